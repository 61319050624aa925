// `liftoff solve` for von Karman arches (issue 16, items 6 and 7): the seed's arch scene
// (verification/scenes/von_karman/seed_arch_pinned_von_karman.toml and _clamped_) against
// the departure study's own figures (verification/seed_arch/, the seed_arch_departure program's
// table verification/report/seed_arch_departure.csv): the same discrete problem reached by another
// route (the study's load history in fixed steps of 0.05 from zero, each solve started from the
// last; solve's adaptive load path), so they agree far within the study's mesh estimate (the change
// of its figures from 200 to 400 elements), which is what the scene's comment promises. And the
// outputs a von Karman answer carries (theory, stable, the membrane force, u, the certificate).

#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "app/solve_command.hpp"
#include "scene/scene_reader.hpp"

using namespace liftoff;

namespace {

const std::string source_dir = LIFTOFF_SOURCE_DIR;

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  REQUIRE(in);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// A row of the departure table: w(0)/R and the half-angle (degrees) under von Karman theory.
struct Departure {
  double crown_deflection = 0.0, half_angle_deg = 0.0;
};
Departure departure(const std::string& ends, int elements) {
  std::istringstream table(read_text(source_dir + "/verification/report/seed_arch_departure.csv"));
  std::string line;
  const std::string key = ends + "," + std::to_string(elements) + ",1.000000,";
  while (std::getline(table, line)) {
    if (line.rfind(key, 0) != 0) continue;
    std::vector<double> columns;  // after the key: w0_linear, w0_vk, half_angle_linear, half_angle_vk, ...
    std::istringstream rest(line.substr(key.size()));
    for (std::string cell; std::getline(rest, cell, ',');) columns.push_back(std::stod(cell));
    REQUIRE(columns.size() >= 4);
    return {columns[1], columns[3]};
  }
  FAIL("no row " << key << " in seed_arch_departure.csv");
  return {};
}

}  // namespace

TEST_CASE("solve von Karman arch: the seed's arch gives the departure study's figures within its mesh estimate",
          "[app][von_karman][arch]") {
  const std::string ends = GENERATE("pinned", "clamped");
  const scene::Scene scene =
      scene::read_scene_file(source_dir + "/verification/scenes/von_karman/seed_arch_" + ends + "_von_karman.toml");
  REQUIRE(scene.solve.elements == 400);
  const io::SolveReport r = app::solve_scene(scene, {});
  CAPTURE(ends, r.message);
  REQUIRE(r.usable);
  REQUIRE(r.certified());
  CHECK(r.theory == "von_karman");
  REQUIRE(r.stable);
  CHECK(*r.stable);

  const Departure study = departure(ends, 400), coarse = departure(ends, 200);
  const double radius = 100.0;
  const double crown = r.w_max / radius;  // the deepest point is the crown (the load's point)
  CHECK(std::abs(r.at_w_max) < 1e-9);
  REQUIRE(r.contact_regions.size() == 1);
  const double half_angle = 0.5 * (r.contact_regions[0].end - r.contact_regions[0].begin);
  const double crown_estimate = std::abs(study.crown_deflection - coarse.crown_deflection),
               angle_estimate = std::abs(study.half_angle_deg - coarse.half_angle_deg);
  CAPTURE(crown, study.crown_deflection, crown_estimate, half_angle, study.half_angle_deg, angle_estimate);
  CHECK(std::abs(crown - study.crown_deflection) <= crown_estimate);
  CHECK(std::abs(half_angle - study.half_angle_deg) <= angle_estimate);
  // The figures the scenes and the report quote: w(0)/R 7.966e-3, 5.857 degrees (pinned);
  // 8.019e-3, 5.945 degrees (clamped).
  CHECK(std::abs(crown - (ends == "pinned" ? 7.966e-3 : 8.019e-3)) < 0.5e-6);
  CHECK(std::abs(half_angle - (ends == "pinned" ? 5.857 : 5.945)) < 0.5e-3);

  // The outputs: the membrane force per element (tension positive: the pinned arch's thrust is
  // gone at this load, report.md section 5), u at the nodes, the thrust among the supports.
  REQUIRE(r.membrane_force.size() == 400);
  REQUIRE(r.nodes.u.size() == 401);
  CHECK(std::abs(r.nodes.u.front()) == 0.0);  // held ends
  CHECK(std::abs(r.nodes.u.back()) == 0.0);
  REQUIRE(r.certificate->support_reactions.size() == 2);
  for (const certify::SupportReaction& support : r.certificate->support_reactions) CHECK(support.tangential != 0.0);
}

TEST_CASE("solve von Karman arch: --method all solves fast and refuses the others keyed structure.theory",
          "[app][von_karman][arch]") {
  const scene::Scene scene =
      scene::read_scene_file(source_dir + "/verification/scenes/von_karman/seed_arch_pinned_von_karman.toml");
  const std::vector<io::SolveReport> reports = app::solve_all_methods(scene, {});
  REQUIRE(reports.size() == 4);
  for (const io::SolveReport& r : reports) {
    CAPTURE(r.method, r.message);
    if (r.method == "fast") {
      CHECK(r.certified());
      CHECK(r.theory == "von_karman");
    } else {
      CHECK(r.outcome == io::SolveOutcome::refused);
      CHECK_THAT(r.message, Catch::Matchers::Contains("key 'structure.theory'") &&
                                Catch::Matchers::Contains("theory = \"von_karman\" on an arch"));
    }
  }
}
