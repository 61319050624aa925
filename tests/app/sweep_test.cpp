// Parameter sweeps: the value grammar, the grid of cases, parallel runs equal to serial ones,
// and the CSV and HDF5 outputs of `liftoff sweep`.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "app/cli.hpp"
#include "app/sweep_command.hpp"
#include "core/error.hpp"
#include "support/scenes.hpp"

using namespace liftoff;

TEST_CASE("sweep: lists, linear and logarithmic ranges", "[app][sweep]") {
  const app::SweepParameter list = app::parse_sweep_parameter("foundation.k=10,100,1e3");
  CHECK(list.key == "foundation.k");
  CHECK(list.values == std::vector<double>{10, 100, 1000});
  const app::SweepParameter lin = app::parse_sweep_parameter("loads[0].value=lin:0:1:5");
  CHECK(lin.values == std::vector<double>{0, 0.25, 0.5, 0.75, 1});
  const app::SweepParameter log = app::parse_sweep_parameter("foundation.k=log:10:1e4:4");
  REQUIRE(log.values.size() == 4);
  for (int i = 0; i < 4; ++i) CHECK(log.values[i] == Approx(std::pow(10.0, i + 1)).epsilon(1e-14));
  for (const char* bad :
       {"foundation.k", "=1,2", "foundation.k=1,x", "foundation.k=log:0:1:3", "foundation.k=lin:0:1:1"})
    CHECK_THROWS_AS(app::parse_sweep_parameter(bad), InputError);
}

TEST_CASE("sweep: every combination, in order, in parallel as in series", "[app][sweep]") {
  const scene::Scene s = test::shipped_scene("seed_beam_end_moments");
  const std::vector<app::SweepParameter> grid{app::parse_sweep_parameter("foundation.k=100,1e4"),
                                              app::parse_sweep_parameter("loads[1].value=0.5,1,2")};
  app::SolveRequest request;
  request.elements = 40;
  int calls = 0;
  const auto serial = app::run_sweep(s, grid, request, 1, [&](int done, int total) {
    ++calls;
    CHECK(total == 6);
    CHECK(done == calls);
  });
  const auto parallel = app::run_sweep(s, grid, request, 3);
  REQUIRE(serial.size() == 6);
  CHECK(calls == 6);
  for (std::size_t i = 0; i < 6; ++i) {
    CHECK(serial[i].values == std::vector<double>{i < 3 ? 100.0 : 1e4, std::vector<double>{0.5, 1, 2}[i % 3]});
    REQUIRE(serial[i].reports.size() == 1);
    CHECK(serial[i].reports[0].foundation_parameter == serial[i].values[0]);
    CHECK(serial[i].reports[0].w_max == parallel[i].reports[0].w_max);
  }
  CHECK_THROWS_AS(app::run_sweep(s, {app::parse_sweep_parameter("loads[7].value=1,2")}, request, 2), InputError);
}

TEST_CASE("sweep: the command writes the CSV and an HDF5 file with every case", "[app][sweep]") {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("liftoff_sweep_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string scene = std::string(LIFTOFF_SOURCE_DIR) + "/verification/scenes/seed_beam_end_moments.toml";
  const std::string h5 = (dir / "sweep.h5").string(), csv = (dir / "sweep.csv").string();
  const char* argv[] = {"liftoff",  "sweep", scene.c_str(), "--set", "foundation.k=1e2,1e4",
                        "--method", "all",   "--elements",  "30",    "--modes",
                        "16",       "-o",    h5.c_str(),    "--csv", csv.c_str()};
  std::ostringstream out, err;
  REQUIRE(app::run_cli(static_cast<int>(std::size(argv)), argv, out, err) == 0);
  CHECK_THAT(err.str(), Catch::Matchers::Contains("2/2"));
  std::ifstream in(csv);
  std::string header, line;
  std::getline(in, header);
  CHECK(header ==
        "foundation.k,method,termination,certified,contact_regions,w_max,w_min,max_reaction,iterations,time_s");
  int rows = 0;
  while (std::getline(in, line)) {
    ++rows;
    CHECK_THAT(line, Catch::Matchers::Contains(",solved,true,") || Catch::Matchers::Contains(",converged,true,"));
  }
  CHECK(rows == 8);  // two cases, four methods each
  const std::string script =
      "import h5py,sys; f=h5py.File(sys.argv[1]); "
      "assert sorted(f['cases']['0001'].keys())==['dual','fast','primal','ritz']; "
      "assert f['cases/0001/ritz/fields/w'].shape[0] > 100; "
      "assert f['cases/0001/fast/certificate'].attrs['passed'] == 1; "
      "assert f['cases/0001/fast/support_reactions'].shape == (2, 3); "
      "assert f.attrs['keys']=='foundation.k'";
  CHECK(std::system(("/usr/bin/python3 -c \"" + script + "\" " + h5).c_str()) == 0);
  // The figures of the sweep, as a user draws them.
  const std::string plot = std::string("/usr/bin/python3 ") + LIFTOFF_SOURCE_DIR +
                           "/verification/plots/plot_sweep.py " + h5 + " --out " + (dir / "fig").string() +
                           " > /dev/null";
  CHECK(std::system(plot.c_str()) == 0);
  CHECK(fs::file_size(dir / "fig_deflection.png") > 10000);
  CHECK(fs::file_size(dir / "fig_reaction.png") > 10000);
  fs::remove_all(dir);
}

TEST_CASE("sweep: --method all keys the HDF5 groups by the method asked for, even after a fallback", "[app][sweep]") {
  // Issue 10: fast falling back to dual Lemke on this beam labelled its answer dual, so the sweep
  // created the group "dual" twice and failed with exit 4.
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("liftoff_sweep_fallback_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path scene = dir / "pinned.toml";
  std::ofstream(scene) << "[structure]\nkind = \"beam\"\nlength = 1.0\nEI = 1.0\n[supports]\nleft = \"pinned\"\n"
                          "right = \"pinned\"\n[foundation]\nk = 1e8\n[[loads]]\nkind = \"moment\"\nat = 0.27\n"
                          "value = 1.0\n[solve]\nelements = 150\n";
  const std::string h5 = (dir / "s.h5").string(), csv = (dir / "s.csv").string(), path = scene.string();
  const char* argv[] = {"liftoff", "sweep",    path.c_str(), "--set",     "loads[0].value=1", "--method", "all",
                        "-o",      h5.c_str(), "--csv",      csv.c_str(), "--modes",          "8"};
  std::ostringstream out, err;
  CHECK(app::run_cli(static_cast<int>(std::size(argv)), argv, out, err) == 0);
  const std::string script =
      "import h5py,sys; f=h5py.File(sys.argv[1]); "
      "assert sorted(f['cases']['0000'].keys())==['dual','fast','primal','ritz']; "
      "assert f['cases/0000/fast'].attrs['method_requested']=='fast'";
  CHECK(std::system(("/usr/bin/python3 -c \"" + script + "\" " + h5).c_str()) == 0);
  fs::remove_all(dir);
}
