// `liftoff solve` as a library call: what method = auto picks and says, and fields computed
// only when asked for.

#include "app/solve_command.hpp"

#include <algorithm>
#include <catch2/catch.hpp>

#include "support/scenes.hpp"

using namespace liftoff;
using scene::Method;

TEST_CASE("auto: Ritz when the scene gives the contact topology, fast otherwise", "[app][auto]") {
  auto scene = test::shipped_scene("seed_beam_end_moments_central_load");
  app::SolveRequest request;
  request.method = Method::automatic;
  const io::SolveReport small = app::solve_scene(scene, request);
  CHECK(small.method == "fast");
  CHECK(small.method_requested == "auto");
  CHECK_THAT(small.method_reason, Catch::StartsWith("fast:") && Catch::Contains("O(n)"));
  CHECK(small.certified());
  CHECK(small.active_set_iterations > 0);

  scene.ritz.topology = {true, false, true};  // contact, lift-off, contact
  const io::SolveReport ritz = app::solve_scene(scene, request);
  CHECK(ritz.method == "ritz");
  CHECK(ritz.method_requested == "auto");
  CHECK_THAT(ritz.method_reason, Catch::StartsWith("ritz:") && Catch::Contains("[ritz]"));
  CHECK(ritz.usable);
  CHECK(ritz.certified());
}

TEST_CASE("fields are sampled only when asked for; the extremes are the same either way", "[app][fields]") {
  const auto scene = test::shipped_scene("seed_beam_end_moments_central_load");
  app::SolveRequest request;
  request.method = Method::fast;
  const io::SolveReport with_fields = app::solve_scene(scene, request);
  request.fields = false;
  const io::SolveReport without = app::solve_scene(scene, request);
  CHECK(without.fields.w.empty());
  CHECK_FALSE(with_fields.fields.w.empty());
  // The same sample points, the same arithmetic: equal, not merely close.
  CHECK(without.w_max == with_fields.w_max);
  CHECK(without.at_w_max == with_fields.at_w_max);
  CHECK(without.w_min == with_fields.w_min);
  CHECK(without.at_w_min == with_fields.at_w_min);
  CHECK(without.max_reaction == with_fields.max_reaction);
}

namespace {
void check_same_design(const io::DesignTable& a, const io::DesignTable& b) {
  for (auto field : {&io::DesignTable::moment_max, &io::DesignTable::moment_min, &io::DesignTable::shear_max_abs,
                     &io::DesignTable::pressure_max, &io::DesignTable::uplift_max}) {
    CHECK((a.*field).value == (b.*field).value);
    CHECK((a.*field).at == (b.*field).at);
  }
}
}  // namespace

TEST_CASE("design values do not depend on whether the fields are asked for, with a tolerance too", "[app][fields]") {
  // The arch's design values come from sampled fields: a tolerance's answer once took them from
  // the P1 reaction without --output and from the continuum's k (w - g) with it (pressure_max
  // 0.0098227 against 0.0098155 on the seed arch).
  for (const char* name : {"seed_arch_pinned", "seed_beam_end_moments_central_load"}) {
    INFO(name);
    const auto scene = test::shipped_scene(name);
    for (const std::optional<double> tolerance : {std::optional<double>{}, std::optional<double>{1e-6}}) {
      INFO("tolerance " << tolerance.value_or(0.0));
      app::SolveRequest request;
      request.method = Method::fast;
      request.tolerance = tolerance;
      const io::SolveReport with_fields = app::solve_scene(scene, request);
      request.fields = false;
      const io::SolveReport without = app::solve_scene(scene, request);
      CHECK(without.fields.w.empty());
      REQUIRE(with_fields.design);
      REQUIRE(without.design);
      check_same_design(*with_fields.design, *without.design);
    }
  }
}

namespace {
// Issue 10's strip footing (N, m): B = 3, EI = 5.4e8, free-free, K = 3e7, 800 kN and -400 kN m at 1.8.
scene::Scene footing() {
  scene::Scene s = test::beam_scene(3.0, 5.4e8, scene::EndSupport::free, scene::EndSupport::free, 0.0);
  s.source_name = "footing";
  s.foundation.k.reset();
  s.foundation.modulus = 3.0e7;
  s.loads = {test::point_force(1.8, 800e3), test::point_moment(1.8, -400e3)};
  return s;
}
}  // namespace

TEST_CASE("the footing of issue 10: auto and fast certified and right, primal never wrong and solved",
          "[app][footing]") {
  const scene::Scene s = footing();
  app::SolveRequest request;
  request.method = Method::ritz;
  const io::SolveReport ritz = app::solve_scene(s, request);
  REQUIRE(ritz.certified());
  REQUIRE(ritz.contact_regions.size() == 1);
  for (Method method : {Method::automatic, Method::fast}) {
    request.method = method;
    const io::SolveReport r = app::solve_scene(s, request);
    CAPTURE(scene::to_string(method), r.message);
    REQUIRE(r.certified());
    CHECK(r.method == "fast");
    REQUIRE(r.contact_regions.size() == 1);
    // The independent Ritz model agrees within both models' error: the FE limit's error at 200
    // elements is O(h^2) (the certificate's change from 100 elements bounds the fields'; a limit
    // moves by at most an element), the Ritz's its last change between mode counts.
    CHECK(std::abs(r.contact_regions[0].begin - ritz.contact_regions[0].begin) <=
          3.0 / 200 + 3 * ritz.estimated_limit_error);
    CHECK(r.contact_regions[0].end == Approx(3.0).epsilon(1e-12));
    // The foundation carries the whole load (no supports): balance to the certificate's tolerance.
    CHECK(r.certificate_figures.foundation_resultant == Approx(800e3).epsilon(1e-6));
  }
  // Primal Lemke: 3 to 6 s at 200 elements. Its answer there was [0.75, 3.0], 3.5 % out of
  // vertical equilibrium; whatever it returns now, nothing wrong is labelled solved.
  request.method = Method::primal;
  const io::SolveReport primal = app::solve_scene(s, request);
  CHECK(primal.method_requested == "primal");
  if (primal.usable) {
    CHECK(primal.certified());
    REQUIRE(primal.contact_regions.size() == 1);
    CHECK(std::abs(primal.contact_regions[0].begin - ritz.contact_regions[0].begin) <=
          3.0 / 200 + 3 * ritz.estimated_limit_error);
  }
}

TEST_CASE("a free member the loads lift off: no_equilibrium from the resultant, no solver run", "[app][resultant]") {
  scene::Scene s = test::beam_scene(2.0, 1e6, scene::EndSupport::free, scene::EndSupport::free, 100.0);
  s.loads = {test::point_force(1.0, -1000.0)};
  for (Method method : {Method::automatic, Method::fast, Method::primal}) {
    app::SolveRequest request;
    request.method = method;
    const io::SolveReport r = app::solve_scene(s, request);
    CAPTURE(scene::to_string(method));
    CHECK_FALSE(r.usable);
    CHECK(r.termination == "no_equilibrium");
    CHECK_THAT(r.message, Catch::Contains("resultant") && Catch::Contains("no solver was run"));
    CHECK(r.pivots <= 0);
    CHECK(r.active_set_iterations <= 0);
  }
}

TEST_CASE("method all: one column per method asked for, whatever answered", "[app][all]") {
  // Issue 10: fast falling back to dual Lemke labelled its answer dual, so dual appeared twice
  // (pinned-pinned, k = 1e8, a moment at 0.27, 150 elements).
  scene::Scene s = test::beam_scene(1.0, 1.0, scene::EndSupport::pinned, scene::EndSupport::pinned, 1e8);
  s.loads = {test::point_moment(0.27, 1.0)};
  app::SolveRequest request;
  request.elements = 150;
  const std::vector<io::SolveReport> reports = app::solve_all_methods(s, request);
  std::vector<std::string> asked;
  for (const auto& r : reports) asked.push_back(r.method_requested);
  CHECK(asked == std::vector<std::string>{"primal", "dual", "fast", "ritz"});
  for (const auto& r : reports) {
    CAPTURE(r.method_requested, r.method, r.message);
    if (r.usable) CHECK(r.certified());
  }
}

TEST_CASE("a bilinear foundation's reaction in the output is the total, K_t (w - g) where the member lifts",
          "[app][fields][tension]") {
  // The pinned beam of verification/dolfinx/scenes/issue12/tension_k.toml (L = EI = 1, k = 1e4,
  // K_t = 1e3, end moments): its ends lift (w < 0), where only K_t pulls: reaction K_t w < 0 in the
  // nodes table and the fields; in contact the total is k w. Without the Winkler part the output
  // showed 0 on the lifted stretch.
  scene::Scene s = test::beam_scene(1.0, 1.0, scene::EndSupport::pinned, scene::EndSupport::pinned, 1e4);
  s.foundation.tension_k = 1e3;
  s.loads = {test::point_moment(0.0, 1.0), test::point_moment(1.0, 1.0)};
  app::SolveRequest request;
  request.method = Method::fast;
  request.elements = 40;
  const io::SolveReport r = app::solve_scene(s, request);
  REQUIRE(r.certified());
  int lifted = 0, pressed = 0;
  for (std::size_t i = 1; i + 1 < r.nodes.w.size(); ++i) {
    const double w = r.nodes.w[i];
    // Nodal values: in contact the LCP's r_i ~ (k - K_t) w_i plus K_t w_i, ~ k w_i (the P1 reaction
    // follows k w only to the discretisation error, largest next to a limit: 4 % here at 40
    // elements), so the total lies well between K_t w and 1.5 k w; where lifted, r_i = 0 exactly
    // and the total is K_t w (a node next to a limit may be in the contact set with a slightly
    // negative w: not counted).
    if (w < 0.0 && r.nodes.w[i - 1] < 0.0 && r.nodes.w[i + 1] < 0.0) {
      ++lifted;
      CHECK(r.nodes.reaction[i] == Approx(1e3 * w).epsilon(1e-12));
    } else if (w > 0.0 && r.nodes.w[i - 1] > 0.0 && r.nodes.w[i + 1] > 0.0) {
      ++pressed;
      CHECK(r.nodes.reaction[i] > 0.5 * 1e4 * w);
      CHECK(r.nodes.reaction[i] < 1.5 * 1e4 * w);
    }
  }
  CHECK(lifted > 0);
  CHECK(pressed > 0);
  // The fields on lifted elements (both nodes lifted, so both LCP reactions are 0).
  for (std::size_t i = 0; i < r.fields.w.size(); ++i) {
    const auto node = std::upper_bound(r.nodes.coordinate.begin(), r.nodes.coordinate.end(), r.fields.coordinate[i]) -
                      r.nodes.coordinate.begin();
    if (node < 2 || node >= static_cast<long>(r.nodes.w.size()) - 1) continue;
    if (r.nodes.w[node - 2] < 0.0 && r.nodes.w[node - 1] < 0.0 && r.nodes.w[node] < 0.0 && r.nodes.w[node + 1] < 0.0)
      CHECK(r.fields.reaction[i] == Approx(1e3 * r.fields.w[i]).epsilon(1e-12));
  }
}

TEST_CASE("design values: Ritz beams by statics agree with FE; free ends carry nothing", "[app][design]") {
  // The B70 sleeper (free-free, two rail-seat loads): the modal series' own V at the seats
  // does not converge (46.9 kN against 70.0 kN), the statics with its reaction do.
  const auto scene = test::shipped_scene("engineering/sleeper_b70_ballast");
  app::SolveRequest request;
  request.method = Method::ritz;
  const io::SolveReport ritz = app::solve_scene(scene, request);
  request.method = Method::fast;
  const io::SolveReport fine = app::solve_scene(scene, request);
  request.elements = 50;
  const io::SolveReport coarse = app::solve_scene(scene, request);
  REQUIRE(ritz.certified());
  REQUIRE(ritz.design);
  REQUIRE(fine.design);
  REQUIRE(coarse.design);
  CHECK(ritz.design->from_statics);
  // The closure: the answer's imbalance (the certificate's balance) plus the quadrature's rounding
  // over the samples' intervals, each a few eps of its terms.
  double balance = 0.0;
  for (const certify::Check& check : ritz.certificate->checks)
    if (check.name.find("balance") != std::string::npos) balance = std::max(balance, check.value);
  const double tolerance = 4 * std::max(balance, ritz.fields.coordinate.size() * 2.2e-16);
  CHECK(ritz.design->shear_closure <= tolerance);
  CHECK(ritz.design->moment_closure <= tolerance);
  CHECK(std::abs(ritz.fields.shear_force.back()) <= tolerance * 4 * ritz.design->shear_max_abs.value);
  CHECK(std::abs(ritz.fields.shear_force.front()) == 0.0);
  // Ritz against FE within the FE's change from half the mesh, 3 times (the corpus's rule), plus
  // the Ritz w's own difference from FE relative to w (its reaction's error carries into M, V).
  const double w_difference = std::abs(ritz.w_max - fine.w_max) / std::abs(fine.w_max);
  auto agree = [&](const io::DesignValue io::DesignTable::*key) {
    const double r = (*ritz.design.*key).value, f = (*fine.design.*key).value, c = (*coarse.design.*key).value;
    INFO("ritz " << r << " fast " << f << " (" << c << " on half the mesh), w differs by " << w_difference);
    CHECK(std::abs(r - f) <= 3 * std::abs(f - c) + w_difference * std::abs(f));
  };
  agree(&io::DesignTable::moment_max);
  agree(&io::DesignTable::moment_min);
  agree(&io::DesignTable::shear_max_abs);
}
