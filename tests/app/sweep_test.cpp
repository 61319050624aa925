// Parameter sweeps: the value grammar, the grid of cases, parallel runs equal to serial ones,
// and the CSV and HDF5 outputs of `liftoff sweep`.
#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "app/cli.hpp"
#include "app/sweep_command.hpp"
#include "core/error.hpp"
#include "support/cli.hpp"
#include "support/scenes.hpp"
#include "support/scratch.hpp"

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
    CHECK(serial[i].reports[0].k == serial[i].values[0]);
    CHECK(serial[i].reports[0].w_max == parallel[i].reports[0].w_max);
  }
  CHECK_THROWS_AS(app::run_sweep(s, {app::parse_sweep_parameter("loads[7].value=1,2")}, request, 2), InputError);
}

TEST_CASE("sweep: the command writes the CSV and an HDF5 file with every case", "[app][sweep]") {
  namespace fs = std::filesystem;
  const test::Scratch scratch("liftoff_sweep_test");
  const fs::path& dir = scratch.dir;
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
        "foundation.k,method,termination,certified,contact_regions,w_max,w_min,max_reaction,iterations,time_s,"
        "moment_max,at_moment_max,moment_min,at_moment_min,shear_max_abs,at_shear_max_abs,pressure_max,"
        "at_pressure_max,uplift_max,at_uplift_max,support_reactions");
  int rows = 0;
  const auto columns = [](const std::string& text) { return std::count(text.begin(), text.end(), ','); };
  while (std::getline(in, line)) {
    ++rows;
    CHECK(columns(line) == columns(header));
    // The design values of a certified answer are filled in (moment_max is the 11th column).
    std::stringstream cells(line);
    std::string cell;
    for (int i = 0; i < 11; ++i) std::getline(cells, cell, ',');
    CHECK_FALSE(cell.empty());
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
}

TEST_CASE("sweep: a grid of more than max_sweep_cases cases is refused before any work", "[app][sweep][errors]") {
  const scene::Scene s = test::shipped_scene("seed_beam_end_moments");
  // 1e10 cases once ended in std::bad_alloc (exit 1): now an InputError naming the counts,
  // thrown before the cases are allocated.
  const std::vector<app::SweepParameter> huge{app::parse_sweep_parameter("foundation.k=lin:1:2:100000"),
                                              app::parse_sweep_parameter("structure.EI=lin:1:2:100000")};
  CHECK_THROWS_WITH(app::run_sweep(s, huge, {}, 1),
                    Catch::Matchers::Contains("--set: the grid has 1e+10 cases (100000 values of foundation.k x "
                                              "100000 values of structure.EI), expected at most 100000"));
  // Just past the bound: 317 x 316 = 100172 cases.
  const std::vector<app::SweepParameter> past{app::parse_sweep_parameter("foundation.k=lin:1:2:317"),
                                              app::parse_sweep_parameter("structure.EI=lin:1:2:316")};
  CHECK_THROWS_AS(app::run_sweep(s, past, {}, 1), InputError);
  CHECK_THROWS_WITH(app::parse_sweep_parameter("foundation.k=lin:1:2:100001"),
                    Catch::Matchers::Contains("n must be an integer in [2, 100000]"));
}

TEST_CASE("sweep: a key swept twice, or one that is no scene key, is refused on one line", "[app][sweep][errors]") {
  const scene::Scene s = test::shipped_scene("seed_beam_end_moments");
  // Twice: the second --set silently replaced the first (the grid had both columns).
  CHECK_THROWS_WITH(
      app::run_sweep(
          s, {app::parse_sweep_parameter("foundation.k=1,2"), app::parse_sweep_parameter("foundation.k=3,4")}, {}, 1),
      "--set: key 'foundation.k' given twice; expected each key once (its values in one --set)");
  // A newline in the key or the values: the message escapes it and stays on one line.
  CHECK_THROWS_WITH(app::parse_sweep_parameter("foundation.k\n=1"),
                    Catch::Matchers::EndsWith("got 'foundation.k\\x0a'"));
  CHECK_THROWS_WITH(app::parse_sweep_parameter("foundation.k=1\n"),
                    Catch::Matchers::StartsWith("--set 'foundation.k=1\\x0a': '1\\x0a' is not a finite number"));
  CHECK_THROWS_AS(app::parse_sweep_parameter("foundation.\"k\"=1"), InputError);
}

TEST_CASE("sweep CLI: bad keys, huge grids and clashing outputs exit 2 and write nothing", "[app][sweep][errors]") {
  namespace fs = std::filesystem;
  const test::Scratch scratch("liftoff_sweep_cli_test");
  const fs::path& dir = scratch.dir;
  const std::string scene = std::string(LIFTOFF_SOURCE_DIR) + "/verification/scenes/seed_beam_end_moments.toml";
  const auto run = [](std::vector<std::string> args, std::string* err_text = nullptr) {
    const test::Run r = test::run_cli(std::move(args));
    if (err_text) *err_text = r.err;
    return r.status;
  };
  std::string err;
  // std::stoi on the index was exit 1.
  CHECK(run({"sweep", scene, "--set", "loads[99999999999].value=1,2"}, &err) == 2);
  CHECK_THAT(err, Catch::Matchers::Contains("key 'loads[99999999999].value'"));
  CHECK(run({"sweep", scene, "--set", "foundation.k=lin:1:2:100000", "--set", "structure.EI=lin:1:2:100000"}, &err) ==
        2);
  CHECK_THAT(err, Catch::Matchers::Contains("expected at most 100000"));
  // One file for --output and --csv: refused before the solve, nothing written.
  const std::string same = (dir / "same.out").string();
  CHECK(run({"sweep", scene, "--set", "foundation.k=1e2,1e4", "--elements", "30", "--output", same, "--csv", same},
            &err) == 2);
  CHECK(err == "liftoff: --csv '" + same + "': the same file as --output '" + same +
                   "'; expected an output that is neither an input nor another output of this run (nothing was "
                   "written)\n");
  // The CSV on the HDF5 file's temporary name, and an output on the scene: likewise.
  CHECK(run({"sweep", scene, "--set", "foundation.k=1e2,1e4", "--output", same, "--csv", same + ".tmp"}) == 2);
  CHECK(fs::is_empty(dir));
  const std::string scene_copy = (dir / "scene.toml").string();
  fs::copy_file(scene, scene_copy);
  CHECK(run({"sweep", scene_copy, "--set", "foundation.k=1e2,1e4", "--csv", scene_copy}) == 2);
  std::ifstream copy(scene_copy), original(scene);
  CHECK(std::string(std::istreambuf_iterator<char>(copy), {}) ==
        std::string(std::istreambuf_iterator<char>(original), {}));
}

TEST_CASE("sweep: --method all keys the HDF5 groups by the method asked for, even after a fallback", "[app][sweep]") {
  // Issue 10: fast falling back to dual Lemke on this beam labelled its answer dual, so the sweep
  // created the group "dual" twice and failed with exit 4.
  namespace fs = std::filesystem;
  const test::Scratch scratch("liftoff_sweep_fallback");
  const fs::path& dir = scratch.dir;
  const fs::path scene =
      scratch.write("pinned.toml",
                    "[structure]\nkind = \"beam\"\nlength = 1.0\nEI = 1.0\n[supports]\nleft = \"pinned\"\n"
                    "right = \"pinned\"\n[foundation]\nk = 1e8\n[[loads]]\nkind = \"moment\"\nat = 0.27\n"
                    "value = 1.0\n[solve]\nelements = 150\n");
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
}
