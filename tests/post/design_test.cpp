// Shear and bending moment by the statics of the free body: zero at free ends to round-off,
// the support reactions entering as jumps, and exact extremes against the infinite beam.
#include "post/design.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "certify/certificate.hpp"
#include "support/scenes.hpp"
#include "support/solve.hpp"

using namespace liftoff;
using contact::Method;
using scene::EndSupport;

namespace {

constexpr double eps = std::numeric_limits<double>::epsilon();

std::vector<post::PointReaction> supports_of(const certify::Certificate& c) {
  std::vector<post::PointReaction> out;
  for (const certify::SupportReaction& s : c.support_reactions) out.push_back({s.at, s.force, s.moment});
  return out;
}

double balance_of(const certify::Certificate& c) {
  double worst = 0.0;
  for (const certify::Check& check : c.checks)
    if (check.name.find("balance") != std::string::npos) worst = std::max(worst, check.value);
  return worst;
}

}  // namespace

TEST_CASE("V and M by statics vanish at free ends to round-off; -w''' does not", "[post][design]") {
  // Issue 10's footing in nondimensional form (free-free, lifting off at the heel), plus a
  // uniform load and a second force so every kind of action enters.
  scene::Scene s = test::beam_scene(1.0, 1.0, EndSupport::free, EndSupport::free, 4.5);
  s.loads = {test::point_force(0.6, 1.0), test::point_moment(0.6, -0.167), test::uniform_load(0.2, 0.9, 0.3),
             test::point_force(0.95, 0.1)};
  const int elements = 200;
  const test::Solved fe = test::solve(s, Method::fast, elements);
  const certify::Certificate c = certify::certify(fe.model, fe.discretisation, fe.solution);
  REQUIRE(c.passed);
  post::Fields f = post::sample_fields(fe.model, fe.discretisation, fe.solution, 8);
  const double derivative_shear_at_end = f.shear_force.back();
  const post::DesignValues d =
      post::recover_beam_statics(fe.model, fe.discretisation, fe.solution, supports_of(c), 1.0, &f);
  REQUIRE(d.from_statics);
  // What closes at the far end is the answer's own imbalance (the certificate's balance, relative
  // to the same kind of terms) plus the integration's rounding: N elements' sums of a few terms
  // each, at most N eps of the terms; 4 times the larger of the two.
  const double tolerance = 4 * std::max(balance_of(c), elements * eps);
  INFO("closure " << d.shear_closure << " " << d.moment_closure << ", tolerance " << tolerance);
  CHECK(d.shear_closure <= tolerance);
  CHECK(d.moment_closure <= tolerance);
  const double peak_shear = d.shear_max_abs.value, peak_moment = std::max(d.moment_max.value, -d.moment_min.value);
  CHECK(f.shear_force.front() == 0.0);  // nothing acts at the left end: nothing integrated yet
  CHECK(f.bending_moment.front() == 0.0);
  CHECK(std::abs(f.shear_force.back()) <= tolerance * peak_shear * 4);
  CHECK(std::abs(f.bending_moment.back()) <= tolerance * peak_moment * 4);
  // The derivative of the cubics fails the same test by orders of magnitude (issue 13: 329 N
  // against a 51 kN peak on a free end).
  CHECK(std::abs(derivative_shear_at_end) > 1e6 * tolerance * peak_shear);
  // The extremes bound every sample and sit where V = 0 or at a node.
  for (std::size_t i = 0; i < f.s.size(); ++i) {
    CHECK(f.bending_moment[i] <= d.moment_max.value + 8 * eps * peak_moment);
    CHECK(f.bending_moment[i] >= d.moment_min.value - 8 * eps * peak_moment);
    CHECK(std::abs(f.shear_force[i]) <= d.shear_max_abs.value + 8 * eps * peak_shear);
  }
}

TEST_CASE("supports enter as jumps: a cantilever's clamp carries the load, its free end nothing", "[post][design]") {
  scene::Scene s = test::beam_scene(1.0, 1.0, EndSupport::clamped, EndSupport::free, 50.0);
  s.loads = {test::point_force(1.0, 2.0), test::uniform_load(0.0, 1.0, 1.0)};
  const int elements = 100;
  const test::Solved fe = test::solve(s, Method::fast, elements);
  const certify::Certificate c = certify::certify(fe.model, fe.discretisation, fe.solution);
  REQUIRE(c.passed);
  REQUIRE(c.support_reactions.size() == 1);
  post::Fields f = post::sample_fields(fe.model, fe.discretisation, fe.solution, 4);
  const post::DesignValues d =
      post::recover_beam_statics(fe.model, fe.discretisation, fe.solution, supports_of(c), 1.0, &f);
  const double tolerance = 4 * std::max(balance_of(c), elements * eps);
  CHECK(d.shear_closure <= tolerance);
  CHECK(d.moment_closure <= tolerance);
  // Right of the clamp: V = its force, M = -its couple (a counterclockwise couple hogs).
  CHECK(f.shear_force.front() == c.support_reactions[0].force);
  CHECK(f.bending_moment.front() == -c.support_reactions[0].moment);
  // The force 2 acts at the free end itself: its jump of -2 leaves 0 past the end, so the last
  // sample (the end, left of the jump) carries V = 2 and M = 0.
  CHECK(std::abs(f.shear_force.back() - 2.0) <= tolerance * 4 * d.shear_max_abs.value);
  CHECK(std::abs(f.bending_moment.back()) <= tolerance * 4 * std::max(d.moment_max.value, -d.moment_min.value));
}

TEST_CASE("moment extremes against the infinite beam on a Winkler foundation", "[post][design]") {
  // Bilateral, free ends beta L / 2 = 20 from a central force P = 1: the ends change M at the
  // load by about e^-20 = 2e-9 of it. Hetenyi: M(x) = P/(4 beta) e^(-beta x)(cos beta x - sin beta x)
  // from the load, largest P / (4 beta) under it, smallest -P/(4 beta) e^(-pi/2) at beta x = pi/2
  // (where V = 0 inside an element: found exactly, not at a sample).
  const double beta = 40.0, k = 4 * std::pow(beta, 4);
  scene::Scene s = test::beam_scene(1.0, 1.0, EndSupport::free, EndSupport::free, k, false);
  s.loads = {test::point_force(0.5, 1.0)};
  const double m_max = 1.0 / (4 * beta), m_min = -m_max * std::exp(-M_PI / 2),
               x_min = 0.5 - M_PI / (2 * beta);  // and its mirror image
  auto design = [&](int n) {
    const test::Solved fe = test::solve(s, Method::fast, n);
    const certify::Certificate c = certify::certify(fe.model, fe.discretisation, fe.solution);
    REQUIRE(c.passed);
    return post::recover_beam_statics(fe.model, fe.discretisation, fe.solution, supports_of(c), 1.0, nullptr);
  };
  const post::DesignValues coarse = design(101), fine = design(202);
  // The error of the finer mesh is at most the change from the coarser (convergence of order
  // >= 1), plus the ends' e^-20.
  const double ends = 4 * std::exp(-beta / 2) * m_max;
  const double change_max = std::abs(fine.moment_max.value - coarse.moment_max.value),
               change_min = std::abs(fine.moment_min.value - coarse.moment_min.value);
  INFO("moment_max " << fine.moment_max.value << " (exact " << m_max << "), change " << change_max);
  INFO("moment_min " << fine.moment_min.value << " at " << *fine.moment_min.s << " (exact " << m_min << " at " << x_min
                     << "), change " << change_min);
  CHECK(std::abs(fine.moment_max.value - m_max) <= change_max + ends);
  CHECK(std::abs(fine.moment_max.value - m_max) < std::abs(coarse.moment_max.value - m_max));
  CHECK(*fine.moment_max.s == Approx(0.5).margin(1e-12));
  CHECK(std::abs(fine.moment_min.value - m_min) <= change_min + ends);
  // Both meshes find the same one of the two mirror-image minima (round-off picks it).
  const double exact_at = *fine.moment_min.s < 0.5 ? x_min : 1.0 - x_min;
  CHECK(std::abs(*fine.moment_min.s - exact_at) <= std::abs(*fine.moment_min.s - *coarse.moment_min.s) + 1e-12);
  // Shear: P/2 either side of the load; pressure: P beta / 2 under it (each within its change
  // from the coarser mesh); a bilateral foundation pulls the member beyond beta x = 3 pi / 4:
  // uplift -w > 0 there.
  CHECK(std::abs(fine.shear_max_abs.value - 0.5) <=
        std::abs(fine.shear_max_abs.value - coarse.shear_max_abs.value) + ends);
  CHECK(std::abs(fine.pressure_max.value - beta / 2) <=
        std::abs(fine.pressure_max.value - coarse.pressure_max.value) + ends * beta);
  REQUIRE(fine.uplift_max.s);
  CHECK(fine.uplift_max.value > 0.0);
}
