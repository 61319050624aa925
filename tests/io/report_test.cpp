// The solve report's outputs: a no_equilibrium answer that a Lemke ray ended carries the ray, its
// certificate, into the JSON and the HDF5 file exactly as the contact solver found it.
#include "io/report.hpp"

#include <hdf5.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>

#include "io/hdf5_writer.hpp"
#include "post/fields.hpp"
#include "support/scenes.hpp"
#include "support/solve.hpp"

using namespace liftoff;
namespace fs = std::filesystem;

namespace {

struct Scratch {
  fs::path dir = fs::temp_directory_path() / ("liftoff_report_test_" + std::to_string(::getpid()));
  Scratch() { fs::create_directories(dir); }
  ~Scratch() { fs::remove_all(dir); }
};

io::SolveReport report_of(const test::Solved& solved, const scene::Scene& s) {
  const post::Fields fields = post::sample_fields(solved.model, solved.discretisation, solved.solution, 2);
  return io::make_report(s, solved.model, solved.discretisation, solved.solution, fields, solved.regions);
}

}  // namespace

TEST_CASE("report: Lemke's ray reaches the JSON and the HDF5 file as the certificate of no equilibrium",
          "[io][certificate]") {
  // A free beam that a load pulls off its tensionless foundation: no equilibrium.
  scene::Scene s = test::beam_scene(1.0, 1.0, scene::EndSupport::free, scene::EndSupport::free, 1e3);
  s.loads = {test::point_force(0.5, -1.0)};
  const test::Solved solved = test::solve(s, contact::Method::primal, 20);
  REQUIRE(solved.solution.summary.termination == contact::ContactTermination::no_equilibrium);
  REQUIRE(solved.solution.no_equilibrium_certificate.has_value());
  const Eigen::VectorXd& ray = solved.solution.no_equilibrium_certificate->ray;
  const io::SolveReport r = report_of(solved, s);

  const nlohmann::json j = io::to_json(r);
  REQUIRE(j.contains("no_equilibrium_certificate"));
  const nlohmann::json& c = j["no_equilibrium_certificate"];
  CHECK(c["kind"] == "lemke_ray");
  CHECK(c["formulation"] == "primal");
  CHECK(c["q_dot_ray"].get<double>() < 0.0);
  const std::vector<double> json_ray = c["ray"];
  REQUIRE(json_ray.size() == static_cast<std::size_t>(ray.size()));
  for (std::size_t i = 0; i < json_ray.size(); ++i) CHECK(json_ray[i] == ray[static_cast<Eigen::Index>(i)]);
  CHECK_THAT(io::text_summary(r), Catch::Contains("Lemke ray of the primal LCP"));

  Scratch scratch;
  const fs::path file = scratch.dir / "lift.h5";
  io::write_hdf5(r, file, "test");
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  REQUIRE(f >= 0);
  const hid_t dataset = H5Dopen2(f, "no_equilibrium_certificate/ray", H5P_DEFAULT);
  REQUIRE(dataset >= 0);
  std::vector<double> stored(static_cast<std::size_t>(ray.size()));
  CHECK(H5Dread(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, stored.data()) >= 0);
  for (std::size_t i = 0; i < stored.size(); ++i) CHECK(stored[i] == ray[static_cast<Eigen::Index>(i)]);
  CHECK(H5Aexists_by_name(f, "no_equilibrium_certificate", "q_dot_ray", H5P_DEFAULT) > 0);
  H5Dclose(dataset);
  H5Fclose(f);

  // An answer carries none.
  s.loads = {test::point_force(0.5, 1.0)};
  const test::Solved pressed = test::solve(s, contact::Method::primal, 20);
  REQUIRE(pressed.solution.summary.is_usable());
  CHECK_FALSE(io::to_json(report_of(pressed, s)).contains("no_equilibrium_certificate"));
}

// A report without an answer: null for every answer field, `method` the solver that ran (null when
// none did), and the evidence of the failure kept.
TEST_CASE("report: a failure's JSON has null answer fields and names only the solvers that ran", "[io][json]") {
  scene::Scene s = test::beam_scene(1.0, 1.0, scene::EndSupport::free, scene::EndSupport::free, 1e3);
  s.loads = {test::point_force(0.5, -1.0)};
  const test::Solved solved = test::solve(s, contact::Method::primal, 20);
  io::SolveReport r = report_of(solved, s);
  REQUIRE_FALSE(r.usable);
  nlohmann::json j = io::to_json(r);
  for (const char* key : io::answer_keys) {
    CAPTURE(key);
    CHECK(j[key].is_null());
  }
  CHECK(j["method"] == "primal");  // Lemke ran and ended on a ray: its certificate stays
  CHECK(j["methods_run"] == nlohmann::json::array({"primal"}));
  CHECK(j.contains("no_equilibrium_certificate"));
  CHECK(j["pivots"].get<int>() > 0);
  CHECK(j["elements"] == 20);

  r.methods_run.clear();  // as when the resultant check decides before any solver
  j = io::to_json(r);
  CHECK(j["method"].is_null());
  CHECK(j["methods_run"] == nlohmann::json::array());

  // An answer keeps its figures and its method, and has no methods_run.
  s.loads = {test::point_force(0.5, 1.0)};
  const test::Solved pressed = test::solve(s, contact::Method::primal, 20);
  REQUIRE(pressed.solution.summary.is_usable());
  j = io::to_json(report_of(pressed, s));
  for (const char* key : io::answer_keys) {
    CAPTURE(key);
    CHECK_FALSE(j[key].is_null());
  }
  CHECK(j["method"] == "primal");
  CHECK_FALSE(j.contains("methods_run"));
}

// A refused method is told by its typed outcome; the outputs spell it "refused" as they always did.
TEST_CASE("report: the solve outcome's names come from one table, refused spelled as the outputs have it") {
  CHECK(io::to_string(io::SolveOutcome::refused) == "refused");
  CHECK(io::to_string(io::SolveOutcome::ran) == "ran");
  for (const io::SolveOutcome outcome : {io::SolveOutcome::ran, io::SolveOutcome::refused})
    CHECK(from_string<io::SolveOutcome>(io::to_string(outcome)) == outcome);
  CHECK_FALSE(from_string<io::SolveOutcome>("no_such_name").has_value());
  CHECK(io::SolveReport{}.outcome == io::SolveOutcome::ran);
}
