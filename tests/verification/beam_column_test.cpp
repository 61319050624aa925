// The closed form's beam-columns (verification/closed_form, issue 15): a constant axial force P on
// beams on bilateral and tensionless Winkler foundations, against the P = 0 closed form, the
// Fourier series of the bilateral pinned strut, the differential equation and equilibrium.
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "closed_form/beam_on_foundation.hpp"

namespace cf = liftoff::closed_form;

namespace {

const double kPi = std::acos(-1.0);

// Midspan deflection of a bilateral pinned strut (length L, EI, K, compression P, uniform q) by
// its sine series, odd n <= terms; `tail` bounds the terms left off: for n > N,
// EI (n pi/L)^4 - P (n pi/L)^2 + K >= EI (n pi/L)^4 / 2 when P <= EI (N pi/L)^2 / 2, and
// sum_{odd n > N} n^-5 <= 1/(8 N^4), so |tail| <= 8 q L^4 / (pi^5 EI) / (8 N^4).
double strut_series(double L, double EI, double K, double P, double q, int terms, double& tail) {
  double w = 0.0;
  for (int n = 1; n <= terms; n += 2) {
    const double r = n * kPi / L;
    w += 4.0 * q / (n * kPi * (EI * r * r * r * r - P * r * r + K)) * std::sin(n * kPi / 2.0);
  }
  REQUIRE(P <= 0.5 * EI * std::pow(terms * kPi / L, 2));
  tail = q * std::pow(L, 4) / (std::pow(kPi, 5) * EI * std::pow(terms, 4));
  return w;
}

// w'''' by a central difference of w''' (truncation h^2/6 |w^(6)|), for the equation residual.
double fourth(const cf::BeamSolution& s, double x, double h) {
  return (s.derivative(x + h, 3) - s.derivative(x - h, 3)) / (2.0 * h);
}

}  // namespace

TEST_CASE("beam-column closed form: P -> 0 reproduces the P = 0 closed form to round-off",
          "[verification][beam_column]") {
  // A free beam on a tensionless foundation under an off-centre force and a moment (two contact regions),
  // and a pinned beam on a bilateral foundation with a uniform load.
  cf::BeamProblem p;
  p.length = 10.0;
  p.bending_stiffness = 2.0;
  p.foundation_modulus = 3.0;
  p.forces = {{2.0, 5.0}};
  p.moments = {{6.0, 4.0}};
  p.uniform_loads = {{0.0, 10.0, 0.5}};
  const cf::TensionlessResult plain = cf::solve_tensionless_auto(p);
  REQUIRE(plain.status == cf::TensionlessStatus::converged);
  REQUIRE(plain.contact.size() == 2);
  const double euler = kPi * kPi * p.bending_stiffness / (p.length * p.length);
  for (double ratio : {1e-13, -1e-13}) {  // compression and tension
    cf::BeamProblem c = p;
    c.axial_force = ratio * euler;
    const cf::TensionlessResult col = cf::solve_tensionless_auto(c);
    REQUIRE(col.status == cf::TensionlessStatus::converged);
    REQUIRE(col.limits.size() == plain.limits.size());
    for (std::size_t k = 0; k < col.limits.size(); ++k)
      CHECK(std::abs(col.limits[k] - plain.limits[k]) <= 1e-13 * p.length);
    const double scale = plain.solution.max_abs_deflection();
    double worst[4] = {};
    for (int i = 0; i <= 200; ++i) {
      const double x = p.length * i / 200.0;
      for (int d = 0; d < 4; ++d)
        worst[d] = std::max(worst[d], std::abs(col.solution.derivative(x, d) - plain.solution.derivative(x, d)));
    }
    // Round-off of two different bases plus the O(P/P_e) = 1e-13 change (seen: 9e-15; at
    // P/P_e = 1e-9 the difference is 9e-11, linear in P).
    for (double e : worst) CHECK(e <= 1e-13 * scale);
  }
  cf::BeamProblem b;
  b.length = 3.0;
  b.foundation_modulus = 40.0;
  b.left = b.right = cf::EndCondition::pinned;
  b.uniform_loads = {{0.0, 3.0, 1.0}};
  const cf::BeamSolution ref = cf::solve_bilateral(b);
  b.axial_force = 1e-13;
  const cf::BeamSolution col = cf::solve_bilateral(b);
  CHECK(col.segment_count() > ref.segment_count());  // the beam-column basis really ran
  for (double x : {0.1, 0.75, 1.5, 2.9})
    CHECK(std::abs(col.deflection(x) - ref.deflection(x)) <= 1e-13 * ref.max_abs_deflection());
}

TEST_CASE("beam-column closed form: a bilateral pinned strut's midspan deflection equals its sine series",
          "[verification][beam_column]") {
  cf::BeamProblem p;
  p.length = 2.0;
  p.bending_stiffness = 1.5;
  p.foundation_modulus = 20.0;
  p.left = p.right = cf::EndCondition::pinned;
  p.uniform_loads = {{0.0, 2.0, 0.8}};
  // Critical load min_n (n^2 pi^2 EI / L^2 + K L^2 / (n^2 pi^2)): n = 1, symmetric, seen at midspan.
  double critical = INFINITY;
  for (int n = 1; n < 20; ++n) {
    const double a = n * n * kPi * kPi / (p.length * p.length);
    critical = std::min(critical, p.bending_stiffness * a + p.foundation_modulus / a);
  }
  for (double ratio : {0.3, 0.9}) {
    p.axial_force = ratio * critical;
    const cf::BeamSolution s = cf::solve_bilateral(p);
    double tail = 0.0;
    const double series =
        strut_series(p.length, p.bending_stiffness, p.foundation_modulus, p.axial_force, 0.8, 2001, tail);
    const double w = s.deflection(0.5 * p.length);
    INFO("P/P_cr = " << ratio << ", P_cr = " << critical << ", closed form " << w << ", series " << series
                     << ", tail bound " << tail);
    CHECK(std::abs(w - series) <= tail + 1e-13 * std::abs(series));
    // Near the critical load the first mode's term grows by 1 / (1 - P/P_cr) = 10.
    if (ratio == 0.9) {
      cf::BeamProblem straight = p;
      straight.axial_force = 0.0;
      CHECK(w / cf::solve_bilateral(straight).deflection(1.0) > 8.0);
    }
  }
}

TEST_CASE("beam-column closed form: tensionless solutions meet the equation, equilibrium and the sign conditions",
          "[verification][beam_column]") {
  // A free beam (the free ends' transverse force EI w''' + P w' = 0), a clamped and a pinned one
  // under compression below 2 sqrt(K EI) = 1 on a tensionless foundation, and a free one in tension
  // beyond -2 sqrt(K EI) (four real roots). (Closer to 2 sqrt(K EI) the contact-set driver may find
  // no admissible solution: the lifted member is near its own buckling load.)
  struct Case {
    cf::EndCondition end;
    double axial;
  };
  for (const Case c : {Case{cf::EndCondition::free, 0.6}, Case{cf::EndCondition::free, -2.5},
                       Case{cf::EndCondition::clamped, 1.3}, Case{cf::EndCondition::pinned, 0.5}}) {
    cf::BeamProblem p;
    p.length = 8.0;
    p.foundation_modulus = 0.25;  // 2 sqrt(K EI) = 1
    p.left = p.right = c.end;
    p.forces = {{3.0, 2.0}};
    p.moments = {{1.0, -6.0}};
    p.uniform_loads = {{0.0, 8.0, 0.1}};
    p.axial_force = c.axial;
    const cf::TensionlessResult r = cf::solve_tensionless_auto(p);
    INFO("end " << static_cast<int>(c.end) << ", P = " << c.axial << ": " << r.message);
    REQUIRE(r.status == cf::TensionlessStatus::converged);
    CHECK(!r.limits.empty());  // the beam lifts off somewhere
    const cf::BeamSolution& s = r.solution;
    const double scale = s.max_abs_deflection();
    // EI w'''' + P w'' + k w = q away from the breakpoints; central difference, h = 1e-3.
    double worst = 0.0;
    for (int i = 1; i < 80; ++i) {
      const double x = p.length * (i + 0.37) / 80.0;
      bool near = false;
      for (double b : s.breakpoints()) near = near || std::abs(b - x) < 2e-3;
      if (near) continue;
      const double residual = p.bending_stiffness * fourth(s, x, 1e-3) + p.axial_force * s.derivative(x, 2) +
                              s.acting_modulus(x) * s.deflection(x) - 0.1;
      worst = std::max(worst, std::abs(residual));
    }
    CHECK(worst <= 1e-5 * (0.1 + p.foundation_modulus * scale));  // h^2 / 6 |w^(6)| and round-off / h
    if (c.end == cf::EndCondition::free) {
      // Vertical equilibrium: int K w = q L + F (Simpson on 64 panels per piece, error ~1e-12).
      double total = 0.0;
      const auto& bp = s.breakpoints();
      for (std::size_t i = 0; i + 1 < bp.size(); ++i) {
        const int n = 64;
        const double h = (bp[i + 1] - bp[i]) / n;
        for (int k = 0; k <= n; ++k) {
          const double w = (k == 0 || k == n) ? 1.0 : (k % 2 ? 4.0 : 2.0);
          const double x = bp[i] + k * h;
          total += w * h / 3.0 * s.reaction(x, k == n ? cf::Side::left : cf::Side::right);
        }
      }
      CHECK(total == Approx(0.1 * p.length + 2.0).epsilon(1e-9));
    }
  }
}
