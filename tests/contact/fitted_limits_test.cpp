// The limit-fitted solve: contact limits at h^4 against the closed forms (where the node-based
// limits converge erratically), the checks that refuse a wrong topology, and arches.

#include "contact/fitted_limits.hpp"

#include <catch2/catch.hpp>

#include "closed_form/beam_on_foundation.hpp"
#include "closed_form/member_problem.hpp"
#include "contact/active_set_solver.hpp"
#include "model/from_scene.hpp"
#include "support/scenes.hpp"
#include "support/solve.hpp"

using namespace liftoff;
using scene::EndSupport;

namespace {

// The fast answer on n elements, as contact intervals: the starting topology of a fitted solve.
std::vector<ContactRegion> fast_intervals(const model::MemberModel& model, int n) {
  const fe::Discretisation d = fe::discretise(model, n);
  const auto fast = contact::solve_active_set(d, d.load(1.0), {}, {}, d.ground_gap);
  REQUIRE(fast.summary.is_usable());
  return contact::contact_intervals(model, d, fast.state.displacement, fast.in_contact);
}

std::vector<double> exact_limits(const model::MemberModel& model) {
  std::vector<closed_form::Interval> guess;
  for (const auto& r : fast_intervals(model, 400)) guess.push_back({r.begin, r.end});
  const auto exact = closed_form::solve_tensionless(closed_form::problem_of(model), guess);
  REQUIRE(exact.status == closed_form::TensionlessStatus::converged);
  return exact.limits;
}

// A weightless free-free beam under a central point load, beta L = 6: both ends lift off.
scene::Scene free_beam() {
  auto s = test::beam_scene(1.0, 1.0, EndSupport::free, EndSupport::free, 4.0 * std::pow(6.0, 4));
  s.loads = {test::point_force(0.5, 1.0)};
  return s;
}

// Issue 10's 500 m pipeline: clamped, K = 2e5, self-weight and a central uplift, beta L = 100.
// Its clamped ends stay in contact (w'' > 0 there): two limits around the central lift-off zone.
scene::Scene pipeline() {
  auto s = test::beam_scene(500.0, 3.12e7, EndSupport::clamped, EndSupport::clamped, 0.0);
  s.foundation.k.reset();
  s.foundation.modulus = 2.0e5;
  s.loads = {test::uniform_load(0.0, 500.0, 1000.0, scene::LoadCase::dead), test::point_force(250.0, -50e3)};
  return s;
}

struct Case {
  const char* name;
  scene::Scene scene;
  int coarsest;  // elements; then x2, x4, x8 (the pipeline needs beta h <= 1/2 to be asymptotic)
};

// Fitted solves on coarsest, 2x, 4x, 8x elements against exact limits: h = 1/n and the largest
// limit error of each, with Newton at round-off (its last step far below the error) and the
// errors decreasing; with max_iterations > 0, Newton takes at most that many iterations.
void fitted_study(const model::MemberModel& model, const std::vector<double>& exact, int coarsest,
                  std::vector<double>& h, std::vector<double>& error, int max_iterations = 0) {
  for (int n : {coarsest, 2 * coarsest, 4 * coarsest, 8 * coarsest}) {
    CAPTURE(n);
    contact::FittedOptions options;
    options.elements = n;
    const auto fitted = contact::solve_fitted_limits(model, 1.0, fast_intervals(model, n), options);
    CAPTURE(fitted.summary.message);
    REQUIRE(fitted.summary.is_usable());
    REQUIRE(fitted.limits.size() == exact.size());
    double e = 0.0;
    for (std::size_t k = 0; k < exact.size(); ++k) e = std::max(e, std::abs(fitted.limits[k] - exact[k]));
    CHECK(fitted.summary.last_step < 1e-3 * e);  // Newton at round-off, far below the error
    if (max_iterations > 0) CHECK(fitted.summary.iterations <= max_iterations);
    if (!error.empty()) CHECK(e < error.back());
    h.push_back(1.0 / n);
    error.push_back(e);
  }
}

}  // namespace

TEST_CASE("fitted limits converge at h^4 to the closed forms", "[contact][fitted]") {
  const Case cases[] = {
      {"seed_beam_end_moments", test::shipped_scene("seed_beam_end_moments"), 40},
      {"seed_beam_end_moments_central_load", test::shipped_scene("seed_beam_end_moments_central_load"), 40},
      {"free beam, central load", free_beam(), 40},
      {"500 m pipeline", pipeline(), 200}};
  for (const auto& [name, s, coarsest] : cases) {
    CAPTURE(name);
    const model::MemberModel model = model::make_member_model(s);
    const std::vector<double> exact = exact_limits(model);
    std::vector<double> h, error;
    fitted_study(model, exact, coarsest, h, error, /*max_iterations=*/6);
    // Hermite elements with no kink inside an element: nodal values, and so the zeros of w at
    // the limit nodes, converge at h^4 (measured 4.00 +- 0.05 between 40 and 2560 elements on
    // all three scenes, verification/bench/accuracy_bench.cpp limits); the node-based limits
    // of the same meshes show orders 0.02 to 4.4.
    const double order = test::observed_order(h, error);
    std::printf("%s: fitted limit error %.2e at %d elements, observed order %.2f\n", name, error.back(), 8 * coarsest,
                order);
    CHECK(order > 3.8);
    CHECK(order < 4.2);
    CHECK(error.back() < 1e-9);  // 8e-11 to 2.2e-10 measured (pipeline ~3e-10)
  }
}

TEST_CASE("a wrong topology is refused, not fitted", "[contact][fitted]") {
  const model::MemberModel model = model::make_member_model(test::shipped_scene("seed_beam_end_moments"));
  contact::FittedOptions options;
  options.elements = 80;
  // The answer has one contact region near the right end; claim a second one on the left,
  // where the beam lifts off.
  std::vector<ContactRegion> wrong = fast_intervals(model, 80);
  REQUIRE(wrong.size() == 1);
  wrong.insert(wrong.begin(), ContactRegion{0.1, 0.3});
  const auto fitted = contact::solve_fitted_limits(model, 1.0, wrong, options);
  CAPTURE(fitted.summary.message);
  CHECK_FALSE(fitted.summary.is_usable());
  CHECK((fitted.summary.termination == contact::FittedTermination::topology_changed ||
         fitted.summary.termination == contact::FittedTermination::inequalities_violated ||
         fitted.summary.termination == contact::FittedTermination::no_convergence));
}

TEST_CASE("fitted limits on an arch converge at the same order", "[contact][fitted][arch]") {
  const model::MemberModel model = model::make_member_model(test::shipped_scene("seed_arch_pinned"));
  auto limits_at = [&](int n) {
    contact::FittedOptions options;
    options.elements = n;
    const auto fitted = contact::solve_fitted_limits(model, 1.0, fast_intervals(model, n), options);
    CAPTURE(n, fitted.summary.message);
    REQUIRE(fitted.summary.is_usable());
    return fitted.limits;
  };
  // No closed form for arches: differences between successive meshes, against the finest.
  const std::vector<double> finest = limits_at(640);
  std::vector<double> h, error;
  for (int n : {40, 80, 160}) {
    const std::vector<double> limits = limits_at(n);
    REQUIRE(limits.size() == finest.size());
    double e = 0.0;
    for (std::size_t k = 0; k < limits.size(); ++k) e = std::max(e, std::abs(limits[k] - finest[k]));
    h.push_back(1.0 / n);
    error.push_back(e);
  }
  const double order = test::observed_order(h, error);
  std::printf("seed_arch_pinned: fitted limit change %.2e from 160 to 640 elements, observed order %.2f\n",
              error.back(), order);
  CHECK(order > 3.5);  // the finest mesh's own error (~1/256 of the 160-element one) biases it little
}

TEST_CASE("node-based limits: a lifted node with w > 0 is walked past to w's zero", "[contact][fitted]") {
  // The weighted gap of a lifted node integrates w over both its elements, so the first lifted
  // node may have w > 0 (the free beam at 1280 elements: +2.4e-7). Its limit is the zero of w
  // beyond that node; taken at the node it was 8.1e-5 of the length off at 1280 and 2560
  // elements (0.10 h and 0.21 h), against 7.8e-7 at 640. The zero of the FE cubic is within the
  // node-based discretisation error of the exact limit (about h^2: 2e-7 here), so 0.01 h (8e-6
  // and 4e-6) separates the two by more than an order of magnitude either way.
  const std::pair<const char*, scene::Scene> cases[] = {
      {"free beam, central load", free_beam()},
      {"seed_beam_end_moments_central_load", test::shipped_scene("seed_beam_end_moments_central_load")}};
  for (const auto& [name, s] : cases) {
    CAPTURE(name);
    const model::MemberModel model = model::make_member_model(s);
    const std::vector<double> exact = exact_limits(model);
    bool walked = false;
    for (int n : {640, 1280, 2560}) {
      CAPTURE(n);
      const fe::Discretisation d = fe::discretise(model, n);
      const auto fast = contact::solve_active_set(d, d.load(1.0), {});
      REQUIRE(fast.summary.is_usable());
      const auto regions = contact::contact_intervals(d, fast.state.displacement, fast.in_contact);
      std::vector<double> limits;
      for (const auto& r : regions) {
        if (r.begin > model.foundation_begin + 1e-12) limits.push_back(r.begin);
        if (r.end < model.foundation_end - 1e-12) limits.push_back(r.end);
      }
      REQUIRE(limits.size() == exact.size());
      for (std::size_t k = 0; k < exact.size(); ++k) CHECK(std::abs(limits[k] - exact[k]) < 0.01 / n);
      // Whether the case is exercised: a lifted node next to a contact node with w > 0.
      const Eigen::VectorXd all = d.expand(fast.state.displacement);
      for (int i = 0; i + 1 < d.reactions(); ++i)
        if (fast.in_contact[i] != fast.in_contact[i + 1])
          walked |= all[d.deflection_dof(d.reaction_nodes[fast.in_contact[i] ? i + 1 : i])] > 0.0;
    }
    if (std::string(name) == "free beam, central load") CHECK(walked);
  }
}

namespace {

scene::Scene issue12_scene(const std::string& name) {
  return scene::read_scene_file(std::string(LIFTOFF_SOURCE_DIR) + "/verification/dolfinx/scenes/issue12/" + name +
                                ".toml");
}

// A pinned-clamped beam under its weight (q/k = 5e-4) over ground sloping linearly from
// g = 1e-4 at x = 0 to 4e-4 at x = 1: it lifts off near both ends (w = 0 < g at the supports)
// and rests on the ground between two limits that solve w = g with g' != 0.
scene::Scene sloping_ground() {
  auto s = test::beam_scene(1.0, 1.0, EndSupport::pinned, EndSupport::clamped, 2.0e3);
  s.foundation.gap_at = {0.0, 1.0};
  s.foundation.gap_value = {1.0e-4, 4.0e-4};
  s.loads = {test::uniform_load(0.0, 1.0, 1.0)};
  return s;
}

// The free-free beam of gap_trench.toml over a deeper trench (walls at 0.35 and 0.6, floor
// g = 1e-3 out of reach): it spans the trench, resting on both banks up to the walls, where w - g
// changes sign across the step (w > 0 on the bank, w < 1e-3 over the trench).
scene::Scene deep_trench() {
  auto s = test::beam_scene(1.0, 1.0, EndSupport::free, EndSupport::free, 1.0e4);
  s.foundation.gap_at = {0.0, 0.35, 0.35, 0.6, 0.6, 1.0};
  s.foundation.gap_value = {0.0, 0.0, 1.0e-3, 1.0e-3, 0.0, 0.0};
  s.loads = {test::uniform_load(0.0, 1.0, 1.0)};
  return s;
}

}  // namespace

TEST_CASE("fitted limits with a ground gap converge at h^4 to the closed form", "[contact][fitted][issue12][gap]") {
  // The sloping ground, and clamped ends settled by 1e-3 under a lifting force (their limits are
  // those of the same beam over a hump g = -1e-3, settlement_clamped_gap.toml, which the closed
  // form takes: settlements and the gap enter the fitted solve through the same offset).
  const model::MemberModel settled = model::make_member_model(issue12_scene("settlement_clamped"));
  const model::MemberModel settled_twin = model::make_member_model(issue12_scene("settlement_clamped_gap"));
  REQUIRE(settled.has_settlements());
  REQUIRE_FALSE(settled.has_ground_gap());
  const model::MemberModel sloping = model::make_member_model(sloping_ground());
  const std::tuple<const char*, const model::MemberModel*, const model::MemberModel*, int> cases[] = {
      {"sloping ground", &sloping, &sloping, 40}, {"settled clamped ends", &settled, &settled_twin, 50}};
  for (const auto& [name, model_ptr, twin, coarsest] : cases) {
    CAPTURE(name);
    const model::MemberModel& model = *model_ptr;
    std::vector<closed_form::Interval> guess;
    for (const auto& r : fast_intervals(*twin, 400)) guess.push_back({r.begin, r.end});
    const auto exact = closed_form::solve_tensionless(closed_form::problem_of(*twin), guess);
    REQUIRE(exact.status == closed_form::TensionlessStatus::converged);
    REQUIRE(exact.limits.size() == 2);
    // Would the test see a solve that ignores the gap (or the settlement)? The same beam without
    // it has other limits, far beyond the errors measured below.
    model::MemberModel plain = *twin;
    plain.ground_gap_at.clear();
    plain.ground_gap_value.clear();
    std::vector<closed_form::Interval> plain_guess;
    for (const auto& r : fast_intervals(plain, 400)) plain_guess.push_back({r.begin, r.end});
    const auto without = closed_form::solve_tensionless(closed_form::problem_of(plain), plain_guess);
    if (without.status == closed_form::TensionlessStatus::converged && without.limits.size() == exact.limits.size()) {
      double shift = 0.0;
      for (std::size_t k = 0; k < exact.limits.size(); ++k)
        shift = std::max(shift, std::abs(without.limits[k] - exact.limits[k]));
      CHECK(shift > 1e-3);
    }
    std::vector<double> h, error;
    fitted_study(model, exact.limits, coarsest, h, error);
    // g is linear within elements and its kinks are nodes, so w - g has no kink inside an
    // element: the Hermite order h^4 of the gap-free cases above (3.8..4.2 there, the same band).
    const double order = test::observed_order(h, error);
    std::printf("%s: fitted limit error %.2e at %d elements, observed order %.2f\n", name, error.back(), 8 * coarsest,
                order);
    CHECK(order > 3.8);
    CHECK(order < 4.2);
  }
}

TEST_CASE("fitted limits on a bilinear foundation converge at h^4 to the closed form",
          "[contact][fitted][issue12][tension]") {
  // tension_k.toml: pinned ends, end moments, k = 1e4, K_t = 1e3; and gap_file_seabed.toml (the
  // surveyed seabed, a hump near x = 0.3) with K_t = 1e3 (K_t's dead load K_t g). The reaction is
  // k (w - g) in contact, K_t (w - g) lifted: a kink at the limit only, where w = g, so the order
  // of the tensionless cases holds.
  const model::MemberModel bilinear = model::make_member_model(issue12_scene("tension_k"));
  REQUIRE(bilinear.has_tension_k());
  scene::Scene seabed = issue12_scene("gap_file_seabed");
  seabed.foundation.tension_k = 1e3;
  const model::MemberModel sloping = model::make_member_model(seabed);
  REQUIRE(sloping.has_ground_gap());
  for (const model::MemberModel* model : {&bilinear, &sloping}) {
    CAPTURE(model->has_ground_gap());
    std::vector<closed_form::Interval> guess;
    for (const auto& r : fast_intervals(*model, 400)) guess.push_back({r.begin, r.end});
    const auto exact = closed_form::solve_tensionless(closed_form::problem_of(*model), guess);
    REQUIRE(exact.status == closed_form::TensionlessStatus::converged);
    REQUIRE_FALSE(exact.limits.empty());
    // Would the test see a solve that drops K_t? Without it the limits move far beyond the errors
    // (checked below).
    model::MemberModel plain = *model;
    plain.tension_k = 0.0;
    const auto without = closed_form::solve_tensionless(closed_form::problem_of(plain), guess);
    const bool comparable =
        without.status == closed_form::TensionlessStatus::converged && without.limits.size() == exact.limits.size();
    const double shift = comparable ? std::abs(without.limits[0] - exact.limits[0]) : 1.0;
    std::vector<double> h, error;
    fitted_study(*model, exact.limits, 40, h, error);
    const double order = test::observed_order(h, error);
    std::printf("bilinear%s: fitted limit error %.2e at 320 elements, observed order %.2f\n",
                model->has_ground_gap() ? " over the seabed" : "", error.back(), order);
    CHECK(shift > 100.0 * error.front());  // even the coarsest fit would see K_t dropped
    CHECK(order > 3.8);                    // the band of the cases above
    CHECK(order < 4.2);
  }
}

TEST_CASE("a limit at a step of the ground gap is pinned at the trench wall", "[contact][fitted][issue12][gap]") {
  const model::MemberModel model = model::make_member_model(deep_trench());
  std::vector<closed_form::Interval> guess{{0.0, 0.35}, {0.6, 1.0}};
  const auto exact = closed_form::solve_tensionless(closed_form::problem_of(model), guess);
  REQUIRE(exact.status == closed_form::TensionlessStatus::converged);
  // From the node-based regions, and from regions that end an element or two short of and
  // beyond the walls: Newton passes onto the wall and stops there.
  const std::vector<std::vector<ContactRegion>> starts = {
      fast_intervals(model, 200), {{0.0, 0.33}, {0.62, 1.0}}, {{0.0, 0.36}, {0.585, 1.0}}};
  for (const auto& start : starts) {
    CAPTURE(start.front().end, start.back().begin);
    contact::FittedOptions options;
    options.elements = 400;
    const auto fitted = contact::solve_fitted_limits(model, 1.0, start, options);
    CAPTURE(fitted.summary.message);
    REQUIRE(fitted.summary.is_usable());
    REQUIRE(fitted.limits.size() == 2);
    // Pinned exactly at the walls (the breakpoints 0.35 and 0.6 of the mesh).
    CHECK(fitted.limits[0] == 0.35);
    CHECK(fitted.limits[1] == 0.6);
    // w at the beam's ends against the closed form: the FE nodal error at 400 elements, about
    // (beta h)^4 of w (beta h = 0.018: 1e-7) -- far below w - g's jump at the walls (1e-3).
    const fe::Discretisation& d = fitted.discretisation;
    const Eigen::VectorXd all = d.expand_displacement(fitted.state.displacement);
    const double w_end = all[d.deflection_dof(0)], exact_end = exact.solution.deflection(0.0);
    CHECK(std::abs(w_end - exact_end) < 1e-6 * std::abs(exact_end));
  }
}
