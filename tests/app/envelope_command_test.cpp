// `liftoff envelope` as a library call and through the command line: combinations solved (and
// shown not to superpose on a tensionless foundation, to superpose on a bilateral one), a moving
// bogie's envelopes and governing positions, the warm start's answers equal to the cold start's,
// a failed case reported and the envelope marked incomplete (exit 3).

#include "app/envelope_command.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/cli.hpp"
#include "core/error.hpp"
#include "scene/scene_reader.hpp"
#include "support/cli.hpp"
#include "support/scene_text.hpp"
#include "support/scenes.hpp"
#include "support/scratch.hpp"

using namespace liftoff;

using namespace liftoff::test;  // support/: the CLI runner, the scratch directory

namespace {

scene::Scene engineering(const std::string& name) { return test::shipped_scene("engineering/" + name); }

const scene::Combination& combination(const scene::Scene& s, const std::string& name) {
  for (const auto& c : s.combinations)
    if (c.name == name) return c;
  FAIL("no combination " << name);
  throw;
}

io::SolveReport solve_case(const scene::Scene& s, const scene::Combination* c, int elements) {
  app::SolveRequest request;
  request.elements = elements;
  io::SolveReport r = app::solve_scene(app::case_scene(s, c, std::nullopt), request);
  REQUIRE(r.certified());
  return r;
}

double max_of(const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); }

// The footing's ULS solved, against 1.35 G + 1.5 Q of the single-case answers, node by node (the
// three meshes are one: every load is at x = 1.8). Returns max |difference| / max |r_ULS|.
struct Superposition {
  double difference;   // max over nodes of |r_ULS - (1.35 r_G + 1.5 r_Q)| / max r_ULS
  double round_off;    // the three answers' measured round-off (relative), summed
  double peak_solved;  // toe pressure of the solved ULS
  double peak_superposed;
};
Superposition superposition(const scene::Scene& s, int elements) {
  const scene::Combination g{"G", {{"G", 1.0}}}, q{"Q", {{"Q", 1.0}}};
  const io::SolveReport uls = solve_case(s, &combination(s, "ULS"), elements);
  const io::SolveReport rg = solve_case(s, &g, elements), rq = solve_case(s, &q, elements);
  REQUIRE(uls.nodes.coordinate == rg.nodes.coordinate);
  REQUIRE(uls.nodes.coordinate == rq.nodes.coordinate);
  Superposition out{0.0, 0.0, 0.0, 0.0};
  const double scale = max_of(uls.nodes.reaction);
  for (std::size_t i = 0; i < uls.nodes.reaction.size(); ++i) {
    const double sum = 1.35 * rg.nodes.reaction[i] + 1.5 * rq.nodes.reaction[i];
    out.difference = std::max(out.difference, std::abs(uls.nodes.reaction[i] - sum) / scale);
  }
  for (const auto* r : {&uls, &rg, &rq}) out.round_off += std::max(r->certificate->round_off_estimate, 0.0);
  out.peak_solved = uls.nodes.reaction.back();
  out.peak_superposed = 1.35 * rg.nodes.reaction.back() + 1.5 * rq.nodes.reaction.back();
  return out;
}

}  // namespace

TEST_CASE("a combination applies each load with its case's factor, 0 for a case it does not name", "[app][envelope]") {
  const auto s = engineering("footing_eccentric_combinations");
  const scene::Scene uls = app::case_scene(s, &combination(s, "ULS"), std::nullopt);
  REQUIRE(uls.loads.size() == 4);
  CHECK(uls.loads[0].value == 1.35 * 600e3);
  CHECK(uls.loads[2].value == 1.5 * 300e3);
  CHECK(uls.combinations.empty());
  const scene::Scene g = app::case_scene(s, &combination(s, "G"), std::nullopt);
  CHECK(g.loads.size() == 2);  // Q left out
}

TEST_CASE("combinations are solved: on a tensionless footing superposition is wrong, on a bilateral one exact",
          "[app][envelope]") {
  auto s = engineering("footing_eccentric_combinations");
  // Tensionless: the difference against the discretisation error (the ULS toe pressure's change
  // from 100 to 200 elements, an upper bound for the 200-element answer's error at order >= 1).
  const Superposition coarse = superposition(s, 100), fine = superposition(s, 200);
  const double discretisation = std::abs(fine.peak_solved - coarse.peak_solved) / fine.peak_solved;
  CHECK(fine.difference > 100.0 * discretisation);
  // The figures of the scene's comment: superposing overstates the toe pressure by ~10 %.
  CHECK(fine.peak_superposed / fine.peak_solved - 1.0 > 0.05);
  INFO("superposed " << fine.peak_superposed << ", solved " << fine.peak_solved);

  // Bilateral: the problem is linear, the same code must superpose to round-off (each answer's
  // own measured round-off, times 10 for the sum of three and the factors).
  s.foundation.tensionless = false;
  const Superposition linear = superposition(s, 100);
  CHECK(linear.difference <= 10.0 * linear.round_off + 1e-14);
  CHECK(linear.difference < 1e-9);  // and far below the tensionless difference
}

TEST_CASE("envelope over combinations: every case certified, the ULS governs the footing", "[app][envelope]") {
  const auto s = engineering("footing_eccentric_combinations");
  const io::EnvelopeReport r = app::run_envelope(s, {});
  REQUIRE(r.cases.size() == 3);
  CHECK(r.complete());
  CHECK(r.cases[2].label() == "ULS");
  CHECK(r.design.pressure_max.governing == 2);
  CHECK(r.design.pressure_max.at == Approx(3.0));
  CHECK(r.design.moment_max.governing == 2);
  CHECK(r.design.moment_max.at == Approx(1.8));
  // The envelope bounds every case's field at the grid points (it is their max and min).
  const io::FieldTable& uls = r.cases[2].report.fields;
  REQUIRE(!r.coordinate.empty());
  CHECK(max_of(r.pressure_max) <= r.design.pressure_max.value);
  CHECK(max_of(r.pressure_max) >= 0.99 * max_of(uls.reaction));  // the grid misses the peak by < 1 %
  // The contact limit of each combination: G full, SLS and ULS lift off near 0.4 (rigid 0.40, 0.436).
  CHECK(r.cases[0].report.contact_regions.size() == 1);
  CHECK(r.cases[0].report.contact_regions[0].begin == Approx(0.0));
  CHECK(r.cases[1].report.contact_regions[0].begin == Approx(0.40).margin(0.05));
  CHECK(r.cases[2].report.contact_regions[0].begin == Approx(0.436).margin(0.05));
}

TEST_CASE("a moving bogie: envelopes, governing positions, and the warm start changes the work, not the answers",
          "[app][envelope]") {
  auto s = engineering("rail_moving_bogie");
  REQUIRE(s.moving);
  s.moving->positions = {5.1, 5.4, 5.7, 6.0, 6.3, 11.1, 11.4, 21.9, 22.2};
  app::EnvelopeRequest warm;
  const io::EnvelopeReport a = app::run_envelope(s, warm);
  app::EnvelopeRequest cold = warm;
  cold.warm_start = false;
  const io::EnvelopeReport b = app::run_envelope(s, cold);
  REQUIRE(a.complete());
  REQUIRE(b.complete());
  CHECK(a.cases[1].warm_started);
  CHECK_FALSE(a.cases[0].warm_started);
  CHECK_FALSE(b.cases[1].warm_started);
  for (std::size_t k = 0; k < a.cases.size(); ++k) {
    // The same contact set gives the same linear system: answers equal to its round-off.
    const auto& ra = a.cases[k].report.contact_regions;
    const auto& rb = b.cases[k].report.contact_regions;
    REQUIRE(ra.size() == rb.size());
    for (std::size_t i = 0; i < ra.size(); ++i) {
      CHECK(ra[i].begin == Approx(rb[i].begin).epsilon(1e-12));
      CHECK(ra[i].end == Approx(rb[i].end).epsilon(1e-12));
    }
    CHECK(a.cases[k].report.w_max == Approx(b.cases[k].report.w_max).epsilon(1e-9));
  }
  // Consecutive positions 0.3 m apart: the warm start needs fewer contact sets in all.
  CHECK(a.contact_sets() < b.contact_sets());
  // Interior positions (lead 5.1..11.4: both ends > 3 decay lengths away): the hand calculation of
  // the scene's comment, w under a wheel 2.20 mm and M under a wheel 21.8 kN m (the infinite
  // beam's, within the tensionless and finite-length corrections, a few per cent).
  const io::SolveReport& interior = a.cases[5].report;
  CHECK(interior.w_max == Approx(2.20e-3).epsilon(0.03));
  CHECK(max_of(interior.fields.bending_moment) == Approx(21.8e3).epsilon(0.03));
  // The trailing wheel at the free end (lead 22.2) governs the hogging moment, 0.7-0.8 m from the end.
  CHECK(a.design.moment_min.governing == 8);
  CHECK(a.design.moment_min.at == Approx(24.0 - 0.75).margin(0.1));
  CHECK(a.design.moment_min.value == Approx(-34.8e3).epsilon(0.05));
}

TEST_CASE("a tandem axle across a slab: interior positions are Hetenyi's, a joint governs and lifts the slab off",
          "[app][envelope]") {
  const auto s = engineering("slab_moving_tandem");
  REQUIRE(s.moving);
  const io::EnvelopeReport r = app::run_envelope(s, app::EnvelopeRequest{});
  REQUIRE(r.complete());
  REQUIRE(r.cases.size() == 47);
  // The scene's data, for the closed form (N, m; per metre width).
  const double EI = 2.2e7, K = 4.0e7, P = 100e3, s_axles = 1.2, q = 5.0e3, L = 15.0;
  const double beta = std::pow(K / (4 * EI), 0.25);
  const auto eta = [](double u) { return std::exp(-u) * (std::cos(u) + std::sin(u)); };
  const auto mu = [](double u) { return std::exp(-u) * (std::cos(u) - std::sin(u)); };
  // Interior: the lead axle at 6.9 m, both axles 6.9 m from a joint (beta d = 5.7). The slab is in
  // contact everywhere (the wave's trough lifts it by less than the self-weight settles it), so the
  // answer is the bilateral one, which differs from the infinite beam's by the free joints' waves,
  // of relative size e^(-beta d); the mesh (beta h = 0.04, cubic elements) adds far less.
  const io::EnvelopeCase& middle = r.cases[23];
  REQUIRE(middle.position);
  CHECK(*middle.position == Approx(6.9));
  REQUIRE(middle.report.contact_regions.size() == 1);
  CHECK(middle.report.contact_regions[0].begin == Approx(0.0).margin(1e-12));
  CHECK(middle.report.contact_regions[0].end == Approx(L));
  const double end_effect = 4 * std::exp(-beta * 6.9);
  const double w_axle = P * beta / (2 * K) * (1 + eta(beta * s_axles)) + q / K;
  const double m_axle = P / (4 * beta) * (1 + mu(beta * s_axles));
  CAPTURE(w_axle, m_axle, end_effect);
  const auto& nodes = middle.report.nodes;
  const auto axle =
      std::find_if(nodes.coordinate.begin(), nodes.coordinate.end(), [](double x) { return std::abs(x - 6.9) < 1e-9; });
  REQUIRE(axle != nodes.coordinate.end());
  CHECK(nodes.w[axle - nodes.coordinate.begin()] == Approx(w_axle).epsilon(end_effect));
  // The axles are closer than pi / (2 beta): the slab sinks most midway between them.
  const double w_midway = P * beta / K * eta(beta * s_axles / 2) + q / K;
  CHECK(middle.report.w_max == Approx(w_midway).epsilon(end_effect));
  CHECK(max_of(middle.report.fields.bending_moment) == Approx(m_axle).epsilon(end_effect));
  // At a joint the slab is softest: the lead axle on the joint (or the trailing axle on the far
  // one, its mirror image) governs w_max. Bilateral semi-infinite beam, by reciprocity:
  // w(0) = 2 P beta / K (1 + e^(-beta s) cos(beta s)) + q / K; the lift-off 2..4 m in (below)
  // lets the end sink a little more, by a few per cent.
  const double w_joint = 2 * P * beta / K * (1 + std::exp(-beta * s_axles) * std::cos(beta * s_axles)) + q / K;
  CAPTURE(w_joint, r.design.w_max.value);
  const double governing_w = *r.cases[r.design.w_max.governing].position;
  CHECK((governing_w == Approx(0.0) || governing_w == Approx(L - s_axles)));
  CHECK(r.design.w_max.value >= w_joint * (1 - end_effect));
  CHECK(r.design.w_max.value == Approx(w_joint).epsilon(0.05));
  // ... and lifts it off inside the end's negative half-wave, where
  // 2 P beta / K e^(-beta x) cos(beta x) < 0: pi / (2 beta) < x < 3 pi / (2 beta).
  const io::EnvelopeCase& at_joint = r.cases[0];
  REQUIRE(at_joint.report.contact_regions.size() == 2);
  const double gap_from = at_joint.report.contact_regions[0].end, gap_to = at_joint.report.contact_regions[1].begin;
  CAPTURE(gap_from, gap_to);
  CHECK(gap_from > M_PI / (2 * beta));
  CHECK(gap_to < 3 * M_PI / (2 * beta));
  CHECK(gap_to > gap_from);
  // The joints govern the hogging too: beyond the interior's -10.1 kN m (the scene's comment).
  const double governing_m = *r.cases[r.design.moment_min.governing].position;
  CHECK((governing_m < 2 * s_axles || governing_m > L - 3 * s_axles));
  CHECK(r.design.moment_min.value < -10.1e3);
}

TEST_CASE("a case that fails is reported, and the envelope is incomplete (exit 3)", "[app][envelope]") {
  // A free member that only the foundation holds, with a Q moment alone that no compressive
  // foundation can balance: the combination "Q" has no equilibrium.
  const std::string text = test::beam_text("3.0", "5.4e8", "\"free\"", "\"free\"") + R"(modulus = 3.0e7
[[loads]]
kind = "force"
at = 1.5
value = 600e3
case = "G"
[[loads]]
kind = "moment"
at = 1.5
value = -2000e3
case = "Q"
[[combinations]]
name = "G"
factors = { G = 1.0 }
[[combinations]]
name = "Q"
factors = { Q = 1.0 }
)";
  const Scratch scratch;
  const auto& dir = scratch.dir;
  const auto scene_file = dir / "failing.toml";
  std::ofstream(scene_file) << text;
  const io::EnvelopeReport r = app::run_envelope(scene::read_scene_file(scene_file), {});
  REQUIRE(r.cases.size() == 2);
  CHECK(r.cases[0].passed());
  CHECK_FALSE(r.cases[1].passed());
  CHECK_FALSE(r.complete());
  CHECK(r.design.pressure_max.governing == 0);  // the envelope of what was certified

  const auto json_file = dir / "failing.json";
  const Run cli = run_cli({"envelope", scene_file.string(), "--json", json_file.string()});
  CHECK(cli.status == 3);
  CHECK_THAT(cli.out, Catch::Contains("INCOMPLETE") && Catch::Contains("FAILED"));
  CHECK_THAT(cli.err, Catch::Contains("1 of 2 cases not certified"));
  const nlohmann::json j = nlohmann::json::parse(std::ifstream(json_file));
  CHECK(j["complete"] == false);
  CHECK(j["cases"][1]["certified"] == false);
  CHECK(j["exit_code"] == 3);
}

TEST_CASE("cli: envelope writes the summary, JSON and HDF5; refuses a scene with nothing to envelope",
          "[app][envelope]") {
  const Scratch scratch;
  const auto& dir = scratch.dir;
  const std::string scene =
      std::string(LIFTOFF_SOURCE_DIR) + "/verification/scenes/engineering/footing_eccentric_combinations.toml";
  const Run ok = run_cli({"envelope", scene, "--json", (dir / "e.json").string(), "--hdf5", (dir / "e.h5").string()});
  CHECK(ok.status == 0);
  CHECK_THAT(ok.out, Catch::Contains("pressure_max") && Catch::Contains("governed by ULS"));
  const nlohmann::json j = nlohmann::json::parse(std::ifstream(dir / "e.json"));
  CHECK(j["kind"] == "envelope");
  CHECK(j["design"]["pressure_max"]["governing"] == "ULS");
  CHECK(j["cases"].size() == 3);
  CHECK(std::filesystem::exists(dir / "e.h5"));
  CHECK_FALSE(std::filesystem::exists(dir / "e.h5.tmp"));

  const Run none = run_cli(
      {"envelope", std::string(LIFTOFF_SOURCE_DIR) + "/verification/scenes/engineering/footing_eccentric_column.toml"});
  CHECK(none.status == 2);
  CHECK_THAT(none.err, Catch::Contains("key 'combinations'"));
}

TEST_CASE("trace refuses a free load case name with its key", "[app][envelope]") {
  const auto s = engineering("footing_eccentric_combinations");
  const Scratch scratch;
  const auto& dir = scratch.dir;
  std::ofstream(dir / "t.toml") << s.text << "\n[trace]\nlambda_max = 2.0\n";
  const Run r = run_cli({"trace", (dir / "t.toml").string()});
  CHECK(r.status == 2);
  CHECK_THAT(r.err, Catch::Contains("key 'loads[0].case'") && Catch::Contains("\"G\""));
}
