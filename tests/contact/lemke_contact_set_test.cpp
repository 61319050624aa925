// Lemke's answers (primal and dual LCPs) are contact sets, re-solved by the sparse fixed-set system
// and checked for signs (contact_solver.cpp, settle_contact_set): an answer is fast's exactly, or a
// refusal that says why, never a wrong answer labelled solved (issue 10).
//
// The scenes are the issue's strip footing (units N and m: a stiff member only the foundation
// holds, k = 4.5) at the smallest meshes that showed each failure of the primal LCP before the fix,
// measured with the Lemke of the time:
//  - 80 elements, column moment -400 kN m: the final basis had the right contact set but a u+/u-
//    split of the wrong sign at one slope, so Lemke reported a numerical failure;
//  - 80 elements, moment -600 kN m: a contact set one node wrong (numerical failure then; a
//    refusal with the reason now);
//  - 40 elements: Lemke was right then and must stay so.
// The issue's 100 .. 200 element cases take seconds: tests/stress/primal_lemke_stress_test.cpp.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "support/lemke_answers.hpp"
#include "support/scenes.hpp"
#include "support/solve.hpp"

using namespace liftoff;
using contact::ContactTermination;
using contact::Method;
using scene::EndSupport;

TEST_CASE("primal Lemke on the footing of issue 10: fast's answer or a refusal", "[contact][lcp][primal]") {
  const auto [moment, elements] =
      GENERATE(table<double, int>({{-400e3, 40}, {-400e3, 80}, {-600e3, 80}, {-500e3, 60}, {0.0, 60}}));
  CAPTURE(moment, elements);
  const scene::Scene s = test::issue10_footing(moment);
  const test::Solved primal = test::solve(s, Method::primal, elements);
  const test::Solved fast = test::solve(s, Method::fast, elements);
  test::require_fast_or_refusal(primal, fast);
  // Where Lemke's final contact set was right (all but the one-node miss at -600 kN m, 80
  // elements), the answer is now returned, whatever sign its u+/u- split had.
  if (!(moment == -600e3 && elements == 80)) CHECK(primal.solution.summary.is_usable());
}

TEST_CASE("a wrong final contact set is refused with the node and the sign that fail", "[contact][lcp][primal]") {
  const test::Solved primal = test::solve(test::issue10_footing(-600e3), Method::primal, 80);
  const contact::ContactSummary& summary = primal.solution.summary;
  CAPTURE(summary.message);
  // Before the fix Lemke ended here one node off the answer; should a better Lemke find the right
  // set, the first test case holds it to fast's answer, and this one has nothing left to check.
  if (summary.is_usable())
    SUCCEED("Lemke found the right set");
  else {
    CHECK(summary.termination == ContactTermination::numerical_failure);
    CHECK_THAT(summary.message, Catch::Matchers::Contains("primal LCP's final contact set"));
    CHECK_THAT(summary.message, Catch::Matchers::Contains("node"));
    CHECK(summary.pivots > 0);
  }
}

TEST_CASE("dual Lemke on pinned beams: fast's answer, re-solved", "[contact][lcp][dual]") {
  // The seed beam with end moments, stiffened to k = 1e5 (the hidden case of issue 10).
  scene::Scene s = test::shipped_scene("seed_beam_end_moments");
  s.foundation.k = 1e5;
  const int elements = GENERATE(40, 120);
  const test::Solved dual = test::solve(s, Method::dual, elements);
  const test::Solved fast = test::solve(s, Method::fast, elements);
  test::require_fast_or_refusal(dual, fast);
  CHECK(dual.solution.summary.is_usable());
  CHECK_THAT(dual.solution.summary.message, !Catch::Matchers::Contains("not the answer"));
}

TEST_CASE("the residual of a floating member sees its global balance", "[contact][residual]") {
  // The residual's row-wise backward error is relative to |K||u|, which for this footing is ~1e7
  // times the loads; the balance on the rigid motions is relative to the loads. An answer solved to
  // round-off balances to a few eps times what the rows of K u round to (the stored K annihilates
  // rigid motions only to its own rounding): 1e-10 here, where the wrong primal answer of issue 10
  // was off by 3.5e-2. So the residual of an accepted answer bounds its global balance error.
  const test::Solved fast = test::solve(test::issue10_footing(-400e3), Method::fast, 40);
  REQUIRE(fast.solution.summary.is_usable());
  const fe::Discretisation& d = fast.discretisation;
  const Eigen::VectorXd r = fast.solution.reaction;
  const Eigen::VectorXd f = d.load(1.0);
  Eigen::VectorXd translation = Eigen::VectorXd::Zero(d.equations);
  for (int dof = 0; dof < d.dofs(); ++dof)
    if (d.equation_of_dof[dof] >= 0 && d.role_of_dof(dof) == fe::DofRole::deflection)
      translation[d.equation_of_dof[dof]] = 1.0;
  const Eigen::VectorXd pushed = d.coupling.transpose() * r;
  const Eigen::VectorXd pushed_terms = Eigen::MatrixXd(d.coupling.cwiseAbs()).transpose() * r.cwiseAbs();
  const double unbalanced = std::abs(translation.dot(f - pushed)) / translation.dot(f.cwiseAbs() + pushed_terms);
  CAPTURE(unbalanced, fast.solution.summary.residual);
  CHECK(unbalanced <= fast.solution.summary.residual);
  CHECK(fast.solution.summary.residual <= 1e-6);
}
