// Stress: the foundation stiffness k = K L^4 / EI from 1e-3 (the beam hardly feels the
// foundation) to 1e12 (a nearly rigid one: the beam's decay length 1/beta is a fraction of an
// element). Every answer is checked for equilibrium and the contact conditions from the
// discretisation (answer_check.hpp); condition estimates are printed beside it, and where the
// dual form's accuracy is lost they say why.
#include <catch2/catch.hpp>
#include <cstdio>

#include "answer_check.hpp"
#include "support/scenes.hpp"
#include "support/solve.hpp"

using namespace liftoff;
using contact::Method;
using scene::EndSupport;

namespace {

// The acceptance threshold of contact::solve_contact: an answer is returned as solved only if
// its relative residual is below this, and the check here must confirm it independently.
constexpr double contract = 1e-6;

std::vector<double> decades(double from, double to) {
  std::vector<double> ks;
  for (double k = from; k <= to * 1.0001; k *= 10.0) ks.push_back(k);
  return ks;
}

void check_sweep(scene::Scene s, const std::vector<Method>& methods, int elements) {
  std::printf("%s, %d elements: k, method, termination, checks, cond(K), cond(P), dual cancellation\n",
              s.source_name.c_str(), elements);
  for (double k : decades(1e-3, 1e12)) {
    s.foundation.k = k;
    for (Method method : methods) {
      const test::Solved fe = test::solve(s, method, elements);
      const auto& summary = fe.solution.summary;
      const double cancellation =
          method == Method::dual ? test::dual_cancellation(fe.discretisation, fe.solution, 1.0) : 1.0;
      const test::AnswerCheck check = test::check_answer(fe.discretisation, fe.solution, 1.0, cancellation);
      const double cond_k = fe.discretisation.structure_is_stable()
                                ? test::symmetric_condition(Eigen::MatrixXd(fe.discretisation.stiffness))
                                : INFINITY;
      const double cond_p = fe.discretisation.structure_is_stable()
                                ? test::symmetric_condition(test::dual_matrix(fe.discretisation))
                                : INFINITY;
      std::printf("  k %7.0e %-7s %-17s %s | cond(K) %.1e cond(P) %.1e cancel %.1e\n", k, to_string(method).data(),
                  std::string(contact::to_string(summary.termination)).c_str(), check.report().c_str(), cond_k, cond_p,
                  cancellation);
      CAPTURE(k, to_string(method), summary.message, check.report(), cond_k, cond_p, cancellation);
      // Every method must solve every k here: each answer's round-off floor (gamma |K||u| ...,
      // amplified by the dual's cancellation) stays orders below the 1e-6 contract over this range.
      REQUIRE(summary.is_usable());
      CHECK(check.worst_relative() <= contract);
      // And equilibrium holds to round-off: within the classical gamma_n backward-error bound.
      CHECK(check.equilibrium_ratio <= 1.0);
      CHECK_FALSE(fe.regions.empty());  // the loads press the beam in somewhere at every k
    }
  }
}

}  // namespace

TEST_CASE("stress: k from 1e-3 to 1e12 on the seed beam (pinned ends, end moments)", "[stress][k]") {
  scene::Scene s = test::shipped_scene("seed_beam_end_moments");
  check_sweep(s, test::fe_methods(), 60);
}

TEST_CASE("stress: k from 1e-3 to 1e12 on a free-free beam that only the foundation holds", "[stress][k]") {
  scene::Scene s = test::beam_scene(1.0, 1.0, EndSupport::free, EndSupport::free, 1.0);
  s.source_name = "free-free beam, central force and off-centre moment";
  s.loads = {test::point_force(0.5, 1.0), test::point_moment(0.3, 0.05)};
  check_sweep(s, test::fe_methods(/*stable_structure=*/false), 40);
}
