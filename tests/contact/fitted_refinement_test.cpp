// Accuracy on demand: the limit-fitted sequence reaches the tolerance against the closed forms
// (independent of liftoff's code), its estimates are honest, and it refuses what it cannot reach.

#include "contact/fitted_refinement.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <limits>

#include "closed_form/beam_on_foundation.hpp"
#include "closed_form/member_problem.hpp"
#include "contact/active_set_solver.hpp"
#include "fe/shape_functions.hpp"
#include "model/from_scene.hpp"
#include "support/scenes.hpp"
#include "support/solve.hpp"

using namespace liftoff;
using scene::EndSupport;

namespace {

// The node-based (fast) contact regions on n elements: where the sequence starts.
std::vector<ContactRegion> fast_intervals(const model::MemberModel& model, int n) {
  const fe::Discretisation d = fe::discretise(model, n);
  const auto fast = contact::solve_active_set(d, d.load(1.0), {});
  REQUIRE(fast.summary.is_usable());
  return contact::contact_intervals(d, fast.state.displacement, fast.in_contact);
}

closed_form::TensionlessResult exact_answer(const model::MemberModel& model) {
  std::vector<closed_form::Interval> guess;
  for (const auto& r : fast_intervals(model, 400)) guess.push_back({r.begin, r.end});
  auto exact = closed_form::solve_tensionless(closed_form::problem_of(model), guess);
  REQUIRE(exact.status == closed_form::TensionlessStatus::converged);
  return exact;
}

// A weightless free-free beam under a central point load, beta L = 6: both ends lift off.
scene::Scene free_beam() {
  auto s = test::beam_scene(1.0, 1.0, EndSupport::free, EndSupport::free, 4.0 * std::pow(6.0, 4));
  s.loads = {test::point_force(0.5, 1.0)};
  return s;
}

struct Errors {
  double limits = 0.0, w = 0.0, reaction = 0.0;
};

// The answer's true errors: limits (relative to the length), w at 8 points per element
// (relative to max |w|), the reaction k max(w, 0) on the contact elements (relative to the
// largest exact reaction).
Errors true_errors(const model::MemberModel& model, const contact::FittedResult& answer,
                   const closed_form::TensionlessResult& exact) {
  Errors e;
  REQUIRE(answer.limits.size() == exact.limits.size());
  for (std::size_t k = 0; k < exact.limits.size(); ++k)
    e.limits = std::max(e.limits, std::abs(answer.limits[k] - exact.limits[k]) / model.length());
  const fe::Discretisation& d = answer.discretisation;
  const Eigen::VectorXd all = d.expand(answer.state.displacement);
  double w_scale = 0.0, r_scale = 0.0, w_error = 0.0, r_error = 0.0;
  for (int el = 0; el < d.mesh.elements(); ++el) {
    const std::vector<int> dofs = d.element_dofs(el);
    const Eigen::Vector4d w_dofs(all[dofs[0]], all[dofs[1]], all[dofs[2]], all[dofs[3]]);
    for (int i = 0; i <= 8; ++i) {
      const double xi = i / 8.0, s = d.mesh.nodes[el] + xi * d.mesh.element_size(el);
      const double w = fe::hermite_cubic(xi, d.mesh.element_size(el)).value.dot(w_dofs);
      const double w_exact = exact.solution.deflection(s);
      w_scale = std::max(w_scale, std::abs(w_exact));
      w_error = std::max(w_error, std::abs(w - w_exact));
      const double r = d.foundation_on_element[el] ? model.k * std::max(w, 0.0) : 0.0;
      const double r_exact = model.k * std::max(w_exact, 0.0);
      r_scale = std::max(r_scale, r_exact);
      r_error = std::max(r_error, std::abs(r - r_exact));
    }
  }
  e.w = w_error / w_scale;
  e.reaction = r_error / r_scale;
  return e;
}

}  // namespace

TEST_CASE("the fitted sequence reaches the tolerance with honest estimates", "[contact][tolerance]") {
  struct Case {
    const char* name;
    scene::Scene scene;
  };
  const Case cases[] = {
      {"seed_beam_end_moments", test::shipped_scene("seed_beam_end_moments")},
      {"seed_beam_end_moments_central_load", test::shipped_scene("seed_beam_end_moments_central_load")},
      {"free beam, central load", free_beam()}};
  for (const auto& [name, s] : cases) {
    CAPTURE(name);
    const model::MemberModel model = model::make_member_model(s);
    const closed_form::TensionlessResult exact = exact_answer(model);
    std::vector<int> elements;
    std::vector<double> limit_errors;
    for (double tolerance : {1e-6, 1e-8, 1e-10}) {
      CAPTURE(tolerance);
      contact::ToleranceOptions options;
      options.tolerance = tolerance;
      const auto result = contact::refine_to_tolerance(model, 1.0, fast_intervals(model, 200), options);
      CAPTURE(result.summary.message);
      REQUIRE(result.summary.is_usable());
      const Errors e = true_errors(model, result.answer, exact);
      std::printf("%s tol %.0e: %d elements, limit error %.1e (estimate %.1e), w %.1e (%.1e), reaction %.1e (%.1e)\n",
                  name, tolerance, result.answer.discretisation.mesh.elements(), e.limits,
                  result.summary.estimated_limit_error, e.w, result.summary.estimated_w_error, e.reaction,
                  result.summary.estimated_reaction_error);
      // The promise: true errors below the tolerance.
      CHECK(e.limits <= tolerance);
      CHECK(e.w <= tolerance);
      CHECK(e.reaction <= tolerance);
      // Honesty: an estimate never more than 3 times below the true error. (Richardson at the
      // observed order, clamped to 4, is exact to O(h) in the asymptotic range; the closed
      // form's own error is ~1e-13 of the length, below every tolerance asked for here.)
      CHECK(result.summary.estimated_limit_error >= e.limits / 3);
      CHECK(result.summary.estimated_w_error >= e.w / 3);
      CHECK(result.summary.estimated_reaction_error >= e.reaction / 3);
      // The sequence's own observed order (from its last two changes, pre-asymptotic on the
      // coarsest meshes: 4.5 between 32, 64 and 128 elements) is at least the element's; above
      // 4 Richardson's rule uses 4, the safer estimate.
      if (result.summary.levels.size() >= 3) CHECK(result.summary.observed_order > 3.5);
      elements.push_back(result.answer.discretisation.mesh.elements());
      limit_errors.push_back(e.limits);
    }
    // The order of the limits against the closed form over the three answers (128 to 1024
    // elements): the element's h^4 (fitted_limits_test.cpp: 4.00 +- 0.05 measured).
    std::vector<double> h;
    for (int n : elements) h.push_back(1.0 / n);
    const double order = test::observed_order(h, limit_errors);
    std::printf("%s: observed order of the limits over the three tolerances %.2f\n", name, order);
    CHECK(order > 3.8);
    CHECK(order < 4.2);
  }
}

TEST_CASE("a tolerance beyond the cap is refused, with a reason", "[contact][tolerance]") {
  const model::MemberModel model = model::make_member_model(test::shipped_scene("seed_beam_end_moments"));
  contact::ToleranceOptions options;
  options.tolerance = 1e-12;
  options.max_elements = 200;
  const auto result = contact::refine_to_tolerance(model, 1.0, fast_intervals(model, 200), options);
  CAPTURE(result.summary.message);
  CHECK_FALSE(result.summary.is_usable());
  CHECK(result.summary.termination == contact::ToleranceTermination::cap_reached);
  CHECK(result.summary.message.find("cap of 200 elements") != std::string::npos);
  CHECK(result.summary.estimated_limit_error > 1e-12);
}

TEST_CASE("tolerance options are validated", "[contact][tolerance]") {
  contact::ToleranceOptions options;
  for (double bad : {0.0, -1e-8, 1e-14, 0.2, std::nan("")}) {
    options.tolerance = bad;
    CHECK_THROWS_AS(options.validate(), std::invalid_argument);
  }
}

TEST_CASE("the seed beams' limit error falls monotonically with the mesh to 1e-10 L and below",
          "[contact][tolerance]") {
  // Limit-fitted solves on 10, 20, ..., 20480 elements, each started from the one before, against
  // the closed form. The limit error falls like h^4 (fitted_limits_test.cpp) from ~1e-5 L at 10
  // elements; doubling divides it by ~16 while it is above the limits' round-off. That floor,
  // estimated: Newton stops when its step is below 1e-14 L (FittedOptions::step_tolerance), and a
  // limit is known to |dw| / |w'(t)| with dw the round-off of w there (a few eps of max |w|, the
  // mixed solve's: active_set_system.hpp), plus the closed form's own error (its Newton on the
  // limits to a residual of ~1e-15 of max |w|, the same ratio). The floor asserted is the larger
  // of 1e-14 L and 64 eps max |w| / |w'(t)|: below 1e-10 L by four orders, so the error must go
  // under 1e-10 L while still halving, and from there stay under 1e-10 L.
  for (const char* name : {"seed_beam_end_moments", "seed_beam_end_moments_central_load"}) {
    CAPTURE(name);
    const model::MemberModel model = model::make_member_model(test::shipped_scene(name));
    const closed_form::TensionlessResult exact = exact_answer(model);
    REQUIRE_FALSE(exact.limits.empty());
    double w_max = 0.0, slope = INFINITY;
    for (int i = 0; i <= 10000; ++i)
      w_max = std::max(w_max, std::abs(exact.solution.deflection(model.length() * i / 10000.0)));
    for (double t : exact.limits) slope = std::min(slope, std::abs(exact.solution.derivative(t, 1)));
    const double floor = std::max(1e-14, 64 * std::numeric_limits<double>::epsilon() * w_max / slope / model.length());
    std::printf("%s: limit round-off floor (estimated) %.1e L\n", name, floor);
    std::vector<ContactRegion> start = fast_intervals(model, 200);
    double previous = INFINITY;
    bool below = false;
    for (int n = 10; n <= 20480; n *= 2) {
      CAPTURE(n);
      contact::FittedOptions options;
      options.elements = n;
      const contact::FittedResult answer = contact::solve_fitted_limits(model, 1.0, start, options);
      REQUIRE(answer.summary.is_usable());
      REQUIRE(answer.limits.size() == exact.limits.size());
      double error = 0.0;
      for (std::size_t k = 0; k < exact.limits.size(); ++k)
        error = std::max(error, std::abs(answer.limits[k] - exact.limits[k]) / model.length());
      std::printf("%s: %6d elements, limit error %.2e L (Newton's last step %.1e L)\n", name, n, error,
                  answer.summary.last_step);
      if (previous > floor) {
        // Above the floor the error falls; asymptotically by 16 a doubling, here at least by 4
        // (the coarsest meshes are pre-asymptotic: beta h up to 2.5 at 10 elements).
        CHECK(error < std::max(previous / 4, floor));
      } else {
        CHECK(error <= floor);  // at the floor it stays there
      }
      below |= error <= 1e-10;
      if (below) CHECK(error <= 1e-10);
      previous = error;
      start = answer.contact;
    }
    CHECK(below);
  }
}
