#pragma once
// Lemke's answers (primal and dual LCPs) against fast's on the same mesh, as issue 10 asks of
// them: the issue's footing, and the check that an answer is fast's to the round-off of the sparse
// re-solve or a refusal naming the failed check (contact_solver.cpp, settle_contact_set).

#include <algorithm>
#include <catch2/catch.hpp>
#include <limits>
#include <vector>

#include "support/scenes.hpp"
#include "support/solve.hpp"

namespace liftoff::test {

// The footing of issue 10: B = 3 m, EI = 5.4e8 N m^2, K = 3e7 N/m^2, a column of 800 kN with a
// moment at x = 1.8 m (clockwise negative).
inline scene::Scene issue10_footing(double moment) {
  scene::Scene s = beam_scene(3.0, 5.4e8, scene::EndSupport::free, scene::EndSupport::free, 0.0);
  s.foundation.k.reset();
  s.foundation.modulus = 3.0e7;
  s.loads = {point_force(1.8, 800e3), point_moment(1.8, moment)};
  return s;
}

inline std::vector<bool> contact_flags(const Solved& s) {
  std::vector<bool> flags;
  for (double r : s.solution.reaction) flags.push_back(r > 0.0);
  return flags;
}

// A Lemke answer against fast's on the same mesh: either a refusal naming the check, or the same
// contact set and the same u and r. Both come from the same sparse system on the same set, so they
// may differ by what iterative refinement leaves: 10 times fast's own error estimate (the margin
// the sign tests use), or a few eps where that is below round-off. Returns whether Lemke solved.
inline bool require_fast_or_refusal(const Solved& lemke, const Solved& fast) {
  constexpr double eps = std::numeric_limits<double>::epsilon();
  const contact::ContactSummary& summary = lemke.solution.summary;
  CAPTURE(summary.brief_report(), summary.message, fast.solution.summary.brief_report());
  REQUIRE(fast.solution.summary.is_usable());
  if (!summary.is_usable()) {
    CHECK(summary.termination == contact::ContactTermination::numerical_failure);
    CHECK_THAT(summary.message, Catch::Matchers::Contains("is not the answer"));
    return false;
  }
  CHECK(contact_flags(lemke) == contact_flags(fast));
  const double tolerance = 10.0 * std::max(fast.solution.summary.error_estimate, 4.0 * eps);
  CHECK(relative_difference(lemke.solution.displacement, fast.solution.displacement) <= tolerance);
  CHECK(relative_difference(lemke.solution.reaction, fast.solution.reaction) <= tolerance);
  REQUIRE(lemke.regions.size() == fast.regions.size());
  // A limit is interpolated from nodal deflections: their relative difference times an element.
  double h = 0.0;
  for (int e = 0; e < lemke.discretisation.mesh.elements(); ++e)
    h = std::max(h, lemke.discretisation.mesh.element_size(e));
  for (std::size_t i = 0; i < lemke.regions.size(); ++i) {
    CHECK(lemke.regions[i].begin == Approx(fast.regions[i].begin).margin(h * tolerance + 4.0 * eps));
    CHECK(lemke.regions[i].end == Approx(fast.regions[i].end).margin(h * tolerance + 4.0 * eps));
  }
  return true;
}

}  // namespace liftoff::test
