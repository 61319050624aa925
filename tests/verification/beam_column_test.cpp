// The closed form's beam-columns (verification/closed_form, issue 15): a constant axial force P on
// beams on bilateral and tensionless Winkler foundations, against the P = 0 closed form, the
// Fourier series of the bilateral pinned strut, the differential equation and equilibrium.
#include "closed_form/beam_column.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "closed_form/beam_on_foundation.hpp"
#include "closed_form/upheaval.hpp"

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

// ---- critical loads (closed_form/beam_column.hpp) ----------------------------------------------

TEST_CASE("critical loads: the bilateral pinned strut's formula, its mode switches and its long-member limit",
          "[verification][beam_column]") {
  // K = 0: Euler's load, one half-wave.
  const cf::StrutBuckling euler = cf::bilateral_pinned_strut_critical(3.0, 2.0, 0.0);
  CHECK(euler.half_waves == 1);
  CHECK(euler.load == Approx(kPi * kPi * 2.0 / 9.0).epsilon(1e-15));
  // The mode has n half-waves for n^2 (n-1)^2 < K L^4 / (pi^4 EI) < n^2 (n+1)^2 (Timoshenko & Gere 2.10).
  const double L = 2.0, EI = 1.5, unit = std::pow(kPi, 4) * EI / std::pow(L, 4);
  for (const auto& [k, n] : std::vector<std::pair<double, int>>{{3.9, 1}, {4.1, 2}, {35.9, 2}, {36.1, 3}, {143.9, 3}}) {
    const cf::StrutBuckling b = cf::bilateral_pinned_strut_critical(L, EI, k * unit);
    CHECK(b.half_waves == n);
    const double a = std::pow(n * kPi / L, 2);
    CHECK(b.load == Approx(EI * a + k * unit / a).epsilon(1e-15));
  }
  // Long members: 0 <= P_cr(L) - 2 sqrt(K EI) <= pi^2 EI / L^2 (beam_column.hpp), and the excess vanishes.
  const double K = 7.0, limit = cf::long_member_critical(K, EI);
  CHECK(limit == Approx(2.0 * std::sqrt(7.0 * 1.5)).epsilon(1e-15));
  double smallest = INFINITY;
  for (double length : {5.0, 13.7, 50.0, 211.0, 1000.3}) {
    const double excess = cf::bilateral_pinned_strut_critical(length, EI, K).load - limit;
    CHECK(excess >= -1e-14 * limit);
    CHECK(excess <= kPi * kPi * EI / (length * length));
    smallest = std::min(smallest, excess);
  }
  CHECK(smallest <= 1e-5 * limit);
}

TEST_CASE("critical loads: the beam-column closed form has its pole at the bilateral strut's critical load",
          "[verification][beam_column]") {
  // Near P_cr (n = 1) the midspan deflection under q is dominated by 4 q / (pi (pi/L)^2 (P_cr - P)).
  cf::BeamProblem p;
  p.length = 2.0;
  p.bending_stiffness = 1.5;
  p.foundation_modulus = 20.0;
  p.left = p.right = cf::EndCondition::pinned;
  p.uniform_loads = {{0.0, 2.0, 0.8}};
  const cf::StrutBuckling cr = cf::bilateral_pinned_strut_critical(p.length, p.bending_stiffness, 20.0);
  REQUIRE(cr.half_waves == 1);
  const double residue = 4.0 * 0.8 * p.length * p.length / std::pow(kPi, 3);
  for (double delta : {1e-6, -1e-6}) {
    p.axial_force = cr.load * (1.0 - delta);
    const double w = cf::solve_bilateral(p).deflection(1.0);
    // The other terms stay O(q L^4 / EI) = O(1e0), a part 1e-6 of the pole's 1e6 (and round-off ~cond eps).
    CHECK(w * (cr.load - p.axial_force) == Approx(residue).epsilon(1e-5));
  }
}

TEST_CASE("critical loads: a weightless tensionless pinned strut buckles away at pi^2 EI / L^2 for any K",
          "[verification][beam_column]") {
  // The closed form itself: under a tiny upward load the strut lifts off entirely (no contact), so it is
  // the K = 0 strut whatever K; its deflection has the Euler load's pole, below the bilateral critical load.
  const double L = 3.0, EI = 2.0, q = -1e-3, euler = cf::tensionless_pinned_strut_critical(L, EI);
  CHECK(euler == Approx(kPi * kPi * EI / (L * L)).epsilon(1e-15));
  for (double K : {0.0, 10.0, 1e4}) {
    CHECK(cf::bilateral_pinned_strut_critical(L, EI, K).load >= euler * (1.0 - 1e-15));
    if (K > 0.0) CHECK(cf::bilateral_pinned_strut_critical(L, EI, K).load > 1.5 * euler);
    for (double ratio : {0.5, 1.0 - 1e-6}) {
      cf::BeamProblem p;
      p.length = L;
      p.bending_stiffness = EI;
      p.foundation_modulus = K;
      p.left = p.right = cf::EndCondition::pinned;
      p.uniform_loads = {{0.0, L, q}};
      p.axial_force = ratio * euler;
      if (K == 0.0) {
        const cf::BeamSolution s = cf::solve_bilateral(p);
        const double w = s.deflection(0.5 * L), roundoff = 1e-15 * s.condition_estimate() * std::abs(w);
        double tail = 0.0;
        CHECK(std::abs(w - strut_series(L, EI, 0.0, p.axial_force, q, 2001, tail)) <=
              tail + std::max(1e-12 * std::abs(w), roundoff));
        continue;
      }
      const cf::TensionlessResult r = cf::solve_tensionless_auto(p);
      INFO("K = " << K << ", P / P_e = " << ratio << ": " << r.message);
      REQUIRE(r.status == cf::TensionlessStatus::converged);
      CHECK(r.contact.empty());  // lifted off everywhere: the foundation gives no help
      double tail = 0.0;
      const double series = strut_series(L, EI, 0.0, p.axial_force, q, 2001, tail);
      // Round-off: eps times the segment system's condition (~1e6 / (1 - P/P_e) near the pole).
      const double roundoff = 1e-15 * r.solution.condition_estimate() * std::abs(series);
      CHECK(std::abs(r.solution.deflection(0.5 * L) - series) <= tail + std::max(1e-12 * std::abs(series), roundoff));
      if (ratio > 0.9)  // the pole: w (P_e - P) -> 4 q L^2 / pi^3 (the other terms are O(1e-6) of it)
        CHECK(r.solution.deflection(0.5 * L) * (euler - p.axial_force) ==
              Approx(4.0 * q * L * L / std::pow(kPi, 3)).epsilon(1e-5));
    }
  }
}

// ---- localized buckle of a heavy infinite member (closed_form/beam_column.hpp) -------------------

TEST_CASE("critical loads: a free-free member's bilateral critical load tends to the rigid rotation's K L^2 / 12",
          "[beam_column]") {
  // The rigid rotation w = x - L / 2 has the Rayleigh quotient K L^2 / 12 (foundation energy
  // K L^3 / 12 against the axial force's L per unit rotation squared): an upper bound of the least
  // critical load, reached as K L^4 / EI -> 0, where the member's bending is a perturbation of
  // first order in K L^4 / EI (the defect 1 - P / (K L^2 / 12) proportional to it).
  const double L = 2.0, EI = 1.0e7;
  auto defect = [&](double k) {
    const double K = k * EI / std::pow(L, 4);
    const double p = cf::free_free_bilateral_critical(L, EI, K);
    REQUIRE(std::isfinite(p));
    CHECK(p < K * L * L / 12.0);
    return 1.0 - p / (K * L * L / 12.0);
  };
  const double d1 = defect(1e-2), d2 = defect(1e-3), d3 = defect(1.6);
  INFO("defects " << d1 << " " << d2 << " " << d3);
  CHECK(d1 / d2 == Approx(10.0).epsilon(1e-2));
  CHECK(d3 > d1);
  CHECK(std::isnan(cf::free_free_bilateral_critical(L, EI, 0.0)));
}

TEST_CASE("localized buckle: the branch starts at 2 sqrt(K EI) as the lifted length vanishes and descends",
          "[verification][beam_column]") {
  const double K = 1.0, EI = 1.0, q = 1.0, top = cf::long_member_critical(K, EI);
  double previous = top, previous_deficit = 0.0;
  for (double a : {0.8, 0.4, 0.2, 0.1}) {  // a shrinking: P rises to 2 sqrt(K EI)
    const cf::LocalizedBuckle b = cf::localized_buckle(K, EI, q, a);
    INFO("a = " << a << ": " << b.message);
    // Below a ~ 0.5 the slowly decaying tail dips below the ground a wavelength away (beam_column.hpp):
    // the single-zone equations still hold, the lifted zone stays lifted.
    REQUIRE((b.status == cf::BuckleStatus::found || b.status == cf::BuckleStatus::secondary_lift_off));
    if (a >= 0.8) CHECK(b.status == cf::BuckleStatus::found);
    CHECK(b.axial_force < top);
    CHECK(b.uplift > 0.0);
    CHECK(b.amplitude == Approx(-b.uplift - q / K).epsilon(1e-14));
    CHECK(std::abs(b.deflection(a)) <= 1e-12 * (q / K + b.uplift));  // the contact limit w(a) = 0
    const double deficit = top - b.axial_force;
    if (a < 0.8) {
      CHECK(b.axial_force > previous);
      // Observed: the deficit falls like a^6 (rates 5.7, 5.9, 6.0 over the halvings).
      const double rate = std::log2(previous_deficit / deficit);
      INFO("observed rate " << rate);
      CHECK(rate > 5.5);
      CHECK(rate < 6.5);
    }
    previous = b.axial_force;
    previous_deficit = deficit;
  }
  CHECK(top - previous <= 1e-6 * top);
  // Descending: P falls and the uplift grows with the lifted length; admissible there.
  double p_last = top, uplift_last = 0.0;
  for (double a : {0.8, 1.0, 2.0, 4.0, 6.0}) {
    const cf::LocalizedBuckle b = cf::localized_buckle(K, EI, q, a);
    INFO("a = " << a << ": " << b.message);
    REQUIRE(b.status == cf::BuckleStatus::found);
    CHECK(b.axial_force < p_last);
    CHECK(b.uplift > uplift_last);
    p_last = b.axial_force;
    uplift_last = b.uplift;
  }
}

TEST_CASE("localized buckle: as K grows at a fixed lifted length the branch tends to Hobbs' vertical mode",
          "[verification][beam_column]") {
  // Lifted length 2a = 1 with q = EI = 1: P -> 80.763, uplift -> 2.407e-3 at the rate K^(-1/4).
  const cf::UpheavalMode hobbs = cf::hobbs_vertical_mode();
  std::vector<double> load_error, uplift_error, loads, uplifts;
  for (double K : {1e8, 1e9, 1e10, 1e11, 1e12}) {
    const cf::LocalizedBuckle b = cf::localized_buckle(K, 1.0, 1.0, 0.5);
    INFO("K = " << K << ": " << b.message);
    REQUIRE(b.status != cf::BuckleStatus::no_root);
    REQUIRE(b.status != cf::BuckleStatus::inadmissible);
    // The stiff foundation's tail dips by about q/K (beam_column.hpp): negligible against the uplift.
    CHECK(b.tail_dip <= 10.0 * (1.0 / K) / b.uplift);
    loads.push_back(b.axial_force);
    uplifts.push_back(b.uplift);
    load_error.push_back(b.axial_force - hobbs.load_parameter);
    uplift_error.push_back(b.uplift - hobbs.uplift);
  }
  for (std::size_t i = 1; i < loads.size(); ++i) {
    CHECK(load_error[i] < 0.0);  // from below: the soft foundation lets the buckle spread
    CHECK(uplift_error[i] > 0.0);
    const double load_rate = std::log10(load_error[i - 1] / load_error[i]);
    const double uplift_rate = std::log10(uplift_error[i - 1] / uplift_error[i]);
    INFO("K = 1e" << 8 + i << ": observed rates " << load_rate << ", " << uplift_rate);
    CHECK(std::abs(load_rate - 0.25) <= 0.02);  // seen: 0.242, 0.246, 0.247, 0.249
    CHECK(std::abs(uplift_rate - 0.25) <= 0.02);
  }
  // Richardson with the rate 1/4 removes the leading term: the limit is Hobbs' to 2% of the last error.
  const double r = std::pow(10.0, -0.25);
  const double load_limit = loads[4] + (loads[4] - loads[3]) * r / (1.0 - r);
  const double uplift_limit = uplifts[4] + (uplifts[4] - uplifts[3]) * r / (1.0 - r);
  INFO("extrapolated P L^2/EI " << load_limit << ", uplift " << uplift_limit);
  CHECK(std::abs(load_limit - hobbs.load_parameter) <= 0.02 * std::abs(load_error[4]));
  CHECK(std::abs(uplift_limit - hobbs.uplift) <= 0.02 * std::abs(uplift_error[4]));
}

TEST_CASE("localized buckle: the segment solver finds the fixed contact set singular exactly at P(a)",
          "[verification][beam_column]") {
  // Independent of the branch's algebra: a long free member (30 decay lengths each side, its ends on the
  // flat state) with the contact set |x - c| > a. At P(a) the buckle is a neutral mode of this contact set
  // (beam_column.hpp), so the segment system is singular there and regular 1% off.
  const double K = 1.0, EI = 1.0, q = 1.0, a = 2.0;
  const cf::LocalizedBuckle b = cf::localized_buckle(K, EI, q, a);
  REQUIRE(b.status == cf::BuckleStatus::found);
  const double c = a + 10.0 / b.alpha;
  cf::BeamProblem p;
  p.length = 2.0 * c;
  p.bending_stiffness = EI;
  p.foundation_modulus = K;
  p.uniform_loads = {{0.0, p.length, q}};
  const std::vector<cf::Interval> contact = {{0.0, c - a}, {c + a, p.length}};
  auto condition = [&](double axial) {
    p.axial_force = axial;
    try {
      return cf::solve_with_contact(p, contact).condition_estimate();
    } catch (const cf::SingularSystem&) {
      return std::numeric_limits<double>::infinity();
    }
  };
  const double at = condition(b.axial_force), below = condition(0.99 * b.axial_force),
               above = condition(1.01 * b.axial_force);
  INFO("condition " << below << " / " << at << " / " << above);
  CHECK(below < 1e5);
  CHECK(above < 1e5);
  CHECK(at > 1e5 * std::max(below, above));  // seen: 3.6e3, 8.7e9, 3.5e3
}
