// Tests of the independent closed-form reference (verification/closed_form): textbook beams,
// the classical Hetenyi beam, and classical tensionless results.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <functional>
#include <vector>

#include "closed_form/beam_on_foundation.hpp"
#include "support/gauss_legendre.hpp"

namespace cf = liftoff::closed_form;

namespace {

const double kPi = std::acos(-1.0);

// int_0^L f(x) g(x) dx where f is smooth on each segment of the solution (pieces of length
// <= 0.25 / beta or L / 64).
double integrate(const cf::BeamSolution& s, const std::function<double(double)>& f) {
  static const liftoff::test::GaussRule g = liftoff::test::gauss_legendre(12);
  double total = 0.0;
  const auto& bp = s.breakpoints();
  const double piece = s.beta() > 0.0 ? std::min(0.25 / s.beta(), s.length() / 64.0) : s.length() / 64.0;
  for (std::size_t i = 0; i + 1 < bp.size(); ++i) {
    const double h = bp[i + 1] - bp[i];
    const int n = std::max(1, static_cast<int>(std::ceil(h / piece)));
    for (int p = 0; p < n; ++p) {
      const double a = bp[i] + h * p / n, b = bp[i] + h * (p + 1) / n;
      for (std::size_t k = 0; k < g.x.size(); ++k) {
        const double x = 0.5 * (a + b) + 0.5 * (b - a) * g.x[k];
        total += 0.5 * (b - a) * g.w[k] * f(x);
      }
    }
  }
  return total;
}

double reaction_integral(const cf::BeamSolution& s) {
  return integrate(s, [&](double x) { return s.reaction(x); });
}
double reaction_moment(const cf::BeamSolution& s) {
  return integrate(s, [&](double x) { return x * s.reaction(x); });
}

// Infinite beam, unit conventions: w = P beta/(2K) e^{-beta r}(cos beta r + sin beta r).
double infinite_w(double P, double beta, double K, double r) {
  r = std::abs(r);
  return P * beta / (2.0 * K) * std::exp(-beta * r) * (std::cos(beta * r) + std::sin(beta * r));
}

cf::BeamProblem free_free_central(double beta_L, double P, double beta = 1.0, double EI = 1.0) {
  cf::BeamProblem pr;
  pr.bending_stiffness = EI;
  pr.foundation_modulus = 4.0 * EI * std::pow(beta, 4);
  pr.length = beta_L / beta;
  pr.left = pr.right = cf::EndCondition::free;
  pr.forces = {{pr.length / 2.0, P}};
  return pr;
}

// The limit equations' Jacobian for two contact regions against central differences (h = 1e-6):
// the largest |J - J_fd| and the largest |J|.
struct JacobianError {
  double worst = 0.0, scale = 0.0;
};
JacobianError limit_jacobian_error(const cf::BeamProblem& pr, const std::vector<cf::Interval>& regions) {
  const auto eq = cf::limit_equations(pr, regions);
  REQUIRE(eq.limits.size() == 4);
  const double h = 1e-6;
  JacobianError error;
  for (std::size_t j = 0; j < 4; ++j) {
    auto shifted = [&](double d) {
      std::vector<double> t = eq.limits;
      t[j] += d;
      return cf::limit_equations(pr, {{t[0], t[1]}, {t[2], t[3]}}).residuals;
    };
    const auto fp = shifted(h), fm = shifted(-h);
    for (std::size_t k = 0; k < 4; ++k) {
      const double fd = (fp[k] - fm[k]) / (2 * h);
      error.worst = std::max(error.worst, std::abs(fd - eq.jacobian[k][j]));
      error.scale = std::max(error.scale, std::abs(eq.jacobian[k][j]));
    }
  }
  return error;
}

// Minimum of w over [0, L]: grid then golden section around the best sample.
std::pair<double, double> min_deflection(const cf::BeamSolution& s, int n = 8000) {
  const double L = s.length();
  int best = 0;
  double wbest = s.deflection(0.0);
  for (int i = 1; i <= n; ++i) {
    const double w = s.deflection(L * i / n);
    if (w < wbest) {
      wbest = w;
      best = i;
    }
  }
  double a = L * std::max(0, best - 1) / n, b = L * std::min(n, best + 1) / n;
  const double r = 0.5 * (std::sqrt(5.0) - 1.0);
  double c = b - r * (b - a), d = a + r * (b - a);
  double fc = s.deflection(c), fd = s.deflection(d);
  for (int it = 0; it < 200 && b - a > 1e-14 * L; ++it) {
    if (fc < fd) {
      b = d;
      d = c;
      fd = fc;
      c = b - r * (b - a);
      fc = s.deflection(c);
    } else {
      a = c;
      c = d;
      fc = fd;
      d = a + r * (b - a);
      fd = s.deflection(d);
    }
  }
  const double x = 0.5 * (a + b);
  const double w = s.deflection(x);
  if (w < wbest) return {x, w};
  return {L * best / n, wbest};
}

const cf::Interval* region_containing(const std::vector<cf::Interval>& r, double x) {
  for (const auto& i : r)
    if (x >= i.start && x <= i.end) return &i;
  return nullptr;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Textbook beams without foundation: sign of the jump conditions and end conditions.
// ---------------------------------------------------------------------------------------------

TEST_CASE("simply supported beam, central force: P L^3 / (48 EI), positive", "[closed_form]") {
  cf::BeamProblem pr;
  pr.length = 2.0;
  pr.bending_stiffness = 3.0;
  pr.left = pr.right = cf::EndCondition::pinned;
  pr.forces = {{1.0, 5.0}};
  const double exact = 5.0 * 8.0 / (48.0 * 3.0);
  SECTION("K = 0") {
    const auto s = cf::solve_bilateral(pr);
    CHECK(s.deflection(1.0) == Approx(exact).epsilon(1e-13));
    CHECK(s.bending_moment(1.0) == Approx(5.0 * 2.0 / 4.0).epsilon(1e-13));  // sagging > 0
    CHECK(s.shear_force(0.5) == Approx(2.5).epsilon(1e-13));
    CHECK(s.shear_force(1.5) == Approx(-2.5).epsilon(1e-13));
  }
  SECTION("K -> 0 (k = K L^4 / EI = 1e-8)") {
    pr.foundation_modulus = 1e-8 * pr.bending_stiffness / std::pow(pr.length, 4);
    const auto s = cf::solve_bilateral(pr);
    // First-order correction: relative -k * (31/630)/(1/48)... bounded by k.
    CHECK(std::abs(s.deflection(1.0) / exact - 1.0) < 1e-8);
    CHECK(s.deflection(1.0) < exact);
    std::printf("[ss K->0] w(L/2)/(PL^3/48EI) - 1 = %.3e, cond = %.2e\n", s.deflection(1.0) / exact - 1.0,
                s.condition_estimate());
  }
  SECTION("first-order foundation correction, k = 1e-4: -k (17/35)/48") {
    // delta w(L/2) = -K/P int w0^2 dx = -(17/35) K P L^7 / (2304 EI^2).
    const double k = 1e-4;
    pr.foundation_modulus = k * pr.bending_stiffness / std::pow(pr.length, 4);
    const auto s = cf::solve_bilateral(pr);
    CHECK((s.deflection(1.0) / exact - 1.0) == Approx(-k * 17.0 / 35.0 / 48.0).epsilon(2e-4));
  }
}

TEST_CASE("textbook beams: uniform load, cantilever tip force and moment", "[closed_form]") {
  cf::BeamProblem pr;
  pr.length = 3.0;
  pr.bending_stiffness = 2.0;
  SECTION("simply supported uniform load 5 q L^4 / 384 EI") {
    pr.left = pr.right = cf::EndCondition::pinned;
    pr.uniform_loads = {{0.0, 3.0, 1.5}};
    const auto s = cf::solve_bilateral(pr);
    CHECK(s.deflection(1.5) == Approx(5.0 * 1.5 * 81.0 / (384.0 * 2.0)).epsilon(1e-13));
  }
  SECTION("cantilever, tip force P L^3 / 3 EI (down), tip moment -M L^2 / 2 EI (ccw lifts)") {
    // A ccw couple at the free right tip curls the beam up: sagging, M_b = +M everywhere.
    pr.left = cf::EndCondition::clamped;
    pr.right = cf::EndCondition::free;
    pr.forces = {{3.0, 0.7}};
    auto s = cf::solve_bilateral(pr);
    CHECK(s.deflection(3.0) == Approx(0.7 * 27.0 / 6.0).epsilon(1e-13));
    pr.forces.clear();
    pr.moments = {{3.0, 0.4}};
    s = cf::solve_bilateral(pr);
    CHECK(s.deflection(3.0) == Approx(-0.4 * 9.0 / 4.0).epsilon(1e-13));
    CHECK(s.bending_moment(1.0) == Approx(0.4).epsilon(1e-13));
  }
  SECTION("simply supported, end moment M0 (ccw at x = 0): w(x) = M0 x (L-x)(2L-x)/(6 EI L)") {
    // EI w''(0) = M0 (natural condition); ccw at the left end hogs the beam: w < 0.
    pr.left = pr.right = cf::EndCondition::pinned;
    pr.moments = {{0.0, 0.9}};
    const auto s = cf::solve_bilateral(pr);
    const double x = 1.1, L = 3.0;
    CHECK(s.deflection(x) == Approx(-0.9 * x * (L - x) * (2 * L - x) / (6 * 2.0 * L)).epsilon(1e-13));
  }
}

TEST_CASE("Maxwell reciprocity checks the sign of the moment jump", "[closed_form]") {
  // Work conjugate of a moment M is -w'(x0): w_M(x1)/M = -w'_P(x0)/P, for any linear setting
  // (here: foundation on part of the beam, clamped/free ends).
  cf::BeamProblem base;
  base.length = 5.0;
  base.bending_stiffness = 1.3;
  base.foundation_modulus = 2.0;
  base.left = cf::EndCondition::clamped;
  base.right = cf::EndCondition::free;
  const double x0 = 1.7, x1 = 3.9;
  const std::vector<cf::Interval> regions = {{0.8, 2.9}, {3.3, 5.0}};
  cf::BeamProblem pm = base, pf = base;
  pm.moments = {{x0, 1.0}};
  pf.forces = {{x1, 1.0}};
  const auto sm = cf::solve_with_contact(pm, regions);
  const auto sf = cf::solve_with_contact(pf, regions);
  CHECK(sm.deflection(x1) == Approx(-sf.slope(x0)).epsilon(1e-12));
  // Jumps at the moment: EI [w''] = M; at a force: EI [w'''] = P.
  CHECK(pm.bending_stiffness * (sm.derivative(x0, 2, cf::Side::right) - sm.derivative(x0, 2, cf::Side::left)) ==
        Approx(1.0).epsilon(1e-12));
  CHECK(pf.bending_stiffness * (sf.derivative(x1, 3, cf::Side::right) - sf.derivative(x1, 3, cf::Side::left)) ==
        Approx(1.0).epsilon(1e-12));
}

TEST_CASE("segment solver input checks", "[closed_form]") {
  cf::BeamProblem pr = free_free_central(4.0, 1.0);
  CHECK_THROWS_AS(cf::solve_segments(pr, {0.0, pr.length}, {true}), std::invalid_argument);
  CHECK_NOTHROW(cf::solve_segments(pr, cf::load_points(pr), {true, true}));
  CHECK_THROWS_AS(cf::solve_segments(pr, cf::load_points(pr), {false, false}), cf::SingularSystem);
}

// ---------------------------------------------------------------------------------------------
// Bilateral (Hetenyi) beam.
// ---------------------------------------------------------------------------------------------

TEST_CASE("bilateral: long free-free beam matches the infinite beam", "[closed_form]") {
  for (double beta_L : {30.0, 1000.0}) {
    const double beta = 1.7, P = 2.5;
    const auto pr = free_free_central(beta_L, P, beta, 0.8);
    const auto s = cf::solve_bilateral(pr);
    const double x0 = pr.length / 2.0, K = pr.foundation_modulus;
    const double w0 = infinite_w(P, beta, K, 0.0);
    double worst_global = 0.0, worst_local = 0.0;
    // The free ends perturb the infinite-beam field by ~ e^{-beta L/2} e^{-beta d} at distance
    // d from an end: ~1e-11 of w(x0) at beta |x - x0| = 5 for beta L = 30 (3e-10 at 8).
    for (double z : {0.0, 0.25, 0.5, 1.0, 1.5, 2.0, 3.0, 4.0, 5.0}) {
      for (double sgn : {-1.0, 1.0}) {
        const double x = x0 + sgn * z / beta;
        const double wi = infinite_w(P, beta, K, z / beta);
        const double err = std::abs(s.deflection(x) - wi);
        worst_global = std::max(worst_global, err / w0);
        if (z <= 2.0) worst_local = std::max(worst_local, err / std::abs(wi));
      }
    }
    std::printf(
        "[infinite beam] beta L = %g: max |w - w_inf|/w(x0) = %.2e, local (beta r <= 2) "
        "= %.2e, cond = %.2e, residual = %.1e\n",
        beta_L, worst_global, worst_local, s.condition_estimate(), s.relative_residual());
    CHECK(worst_global < 1e-10);
    CHECK(worst_local < 1e-10);
    // Bending moment under the load, infinite beam: P / (4 beta) (sagging).
    CHECK(s.bending_moment(x0) == Approx(P / (4.0 * beta)).epsilon(1e-10));
    // Equilibrium: int r = P.
    CHECK(reaction_integral(s) == Approx(P).epsilon(1e-11));
  }
}

TEST_CASE("bilateral: Hetenyi finite free-free beam under a central force", "[closed_form]") {
  // Derived (half beam, Krylov functions, z = beta L / 2):
  //   w(centre) = P beta/(2K) (cosh bL + cos bL + 2)/(sinh bL + sin bL)
  //   w(end)    = 2 P beta/K cosh(bL/2) cos(bL/2)/(sinh bL + sin bL)
  for (double bL : {0.05, 0.5, 1.0, 2.0, 3.0, kPi, 4.0, 6.0, 10.0, 20.0}) {
    const double P = 3.0, beta = 0.6;
    const auto pr = free_free_central(bL, P, beta, 2.0);
    const double K = pr.foundation_modulus;
    const auto s = cf::solve_bilateral(pr);
    const double wc = P * beta / (2 * K) * (std::cosh(bL) + std::cos(bL) + 2) / (std::sinh(bL) + std::sin(bL));
    const double we = 2 * P * beta / K * std::cosh(bL / 2) * std::cos(bL / 2) / (std::sinh(bL) + std::sin(bL));
    INFO("beta L = " << bL);
    CHECK(s.deflection(pr.length / 2) == Approx(wc).epsilon(1e-11));
    CHECK(std::abs(s.deflection(0.0) - we) < 1e-11 * wc);
    CHECK(std::abs(s.deflection(pr.length) - we) < 1e-11 * wc);
    CHECK(reaction_integral(s) == Approx(P).epsilon(1e-11));
  }
}

TEST_CASE("bilateral: equilibrium of forces and moments with every load kind", "[closed_form]") {
  // Free-free: int r = sum P + int q;  int x r = sum x P + int x q - sum M (M ccw).
  cf::BeamProblem pr;
  pr.length = 6.0;
  pr.bending_stiffness = 1.5;
  pr.foundation_modulus = 12.0;
  pr.forces = {{1.2, 2.0}, {4.4, -0.7}, {6.0, 0.3}};
  pr.moments = {{2.5, 1.1}, {0.0, -0.4}};
  pr.uniform_loads = {{0.5, 3.5, 0.8}};
  const auto s = cf::solve_bilateral(pr);
  const double F = 2.0 - 0.7 + 0.3 + 0.8 * 3.0;
  const double Mx = 1.2 * 2.0 - 4.4 * 0.7 + 6.0 * 0.3 + 0.8 * (3.5 * 3.5 - 0.25) / 2.0 - (1.1 - 0.4);
  CHECK(reaction_integral(s) == Approx(F).epsilon(1e-11));
  CHECK(reaction_moment(s) == Approx(Mx).epsilon(1e-11));
  CHECK(s.relative_residual() < 1e-14);
}

TEST_CASE("bilateral: the end deflection of a free-free beam changes sign at beta L = pi", "[closed_form]") {
  auto w_end = [](double bL) {
    const auto pr = free_free_central(bL, 1.0);
    return cf::solve_bilateral(pr).deflection(0.0);
  };
  double a = 3.0, b = 3.3;
  REQUIRE(w_end(a) > 0.0);
  REQUIRE(w_end(b) < 0.0);
  for (int it = 0; it < 200 && b - a > 1e-15; ++it) {
    const double m = 0.5 * (a + b);
    if (m <= a || m >= b) break;
    (w_end(m) > 0.0 ? a : b) = m;
  }
  const double root = 0.5 * (a + b);
  std::printf("[free-free end sign change] beta L = %.15f, pi = %.15f, diff = %.1e\n", root, kPi, root - kPi);
  CHECK(std::abs(root - kPi) < 1e-10);
  // Below pi the bilateral solution is a valid tensionless one (full contact).
  const auto s = cf::solve_bilateral(free_free_central(3.0, 1.0));
  const auto regions = cf::contact_regions(s);
  REQUIRE(regions.size() == 1);
  CHECK(regions[0].start == 0.0);
  CHECK(regions[0].end == 3.0);
}

// ---------------------------------------------------------------------------------------------
// Tensionless results.
// ---------------------------------------------------------------------------------------------

TEST_CASE("tensionless: exact limit Jacobian against finite differences", "[closed_form]") {
  cf::BeamProblem pr = free_free_central(7.0, 1.0);
  pr.forces.push_back({5.1, 0.4});
  pr.uniform_loads = {{0.0, 7.0, 0.05}};
  const auto [worst, scale] = limit_jacobian_error(pr, {{1.3, 4.6}, {5.5, 6.4}});
  std::printf("[limit Jacobian] max |J - J_fd| / max|J| = %.2e\n", worst / scale);
  CHECK(worst < 1e-7 * scale);
}

TEST_CASE("tensionless: free-free beam, central force, contact length pi / beta", "[closed_form]") {
  for (double bL : {4.0, 7.0}) {
    for (double P : {1.0, 250.0}) {
      const double beta = 1.3;
      const auto pr = free_free_central(bL, P, beta, 0.9);
      const double x0 = pr.length / 2;
      const auto bil = cf::solve_bilateral(pr);
      const auto seed = cf::contact_regions(bil);
      const cf::Interval* c = region_containing(seed, x0);
      REQUIRE(c != nullptr);
      const auto r = cf::solve_tensionless(pr, {*c});
      INFO(r.message);
      REQUIRE(r.status == cf::TensionlessStatus::converged);
      REQUIRE(r.limits.size() == 2);
      const double len = r.limits[1] - r.limits[0];
      std::printf(
          "[free-free tensionless] beta L = %g, P = %g: beta * contact length = %.15f "
          "(pi %+.1e), %d Newton steps, residual %.1e, violation %.1e\n",
          bL, P, beta * len, beta * len - kPi, r.iterations, r.residual, r.max_violation);
      CHECK(std::abs(beta * len - kPi) < 1e-10);
      CHECK(std::abs(r.limits[0] + r.limits[1] - pr.length) < 1e-10 * pr.length);
      CHECK(reaction_integral(r.solution) == Approx(P).epsilon(1e-11));
      // Lifted ends are straight (no moment) and go up (w' (a) <= 0 at the right limit).
      CHECK(std::abs(r.solution.bending_moment(0.5 * r.limits[0])) < 1e-11 * P / beta);
      CHECK(r.solution.slope(r.limits[1]) < 0.0);
    }
  }
}

TEST_CASE("tensionless: long free beam (beta L = 40), central force: beta a = pi / 2", "[closed_form]") {
  const double beta = 0.8, P = 7.0;
  const auto pr = free_free_central(40.0, P, beta, 1.1);
  const double x0 = pr.length / 2;
  const auto seed = cf::contact_regions(cf::solve_bilateral(pr));
  const cf::Interval* c = region_containing(seed, x0);
  REQUIRE(c != nullptr);
  // The bilateral seed: w > 0 for beta|x - x0| < 3 pi / 4. For a long beam this is (up to
  // e^{-beta L}) a critical point of the limit equations: with the contact piece a free-free
  // beam of half-length a, w(a) ~ (2 P beta/K) e^{-beta a} cos(beta a), whose derivative
  // -e^{-z}(cos z + sin z) vanishes at z = 3 pi/4. Plain Newton from it ran off to the
  // inadmissible root beta a = 7 pi/2 (caught by the inequality check); the sign safeguard
  // (physical step when s_k dF_k/dt_k <= 0) brings it back.
  CHECK(beta * (x0 - c->start) == Approx(0.75 * kPi).epsilon(1e-9));
  const auto seeded = cf::solve_tensionless(pr, {*c});
  const auto automatic = cf::solve_tensionless_auto(pr);
  for (const auto* r : {&seeded, &automatic}) {
    INFO(r->message);
    REQUIRE(r->status == cf::TensionlessStatus::converged);
    REQUIRE(r->limits.size() == 2);
    const double ba = beta * (x0 - r->limits[0]), bb = beta * (r->limits[1] - x0);
    std::printf(
        "[long beam tensionless, %s] beta a = %.15f / %.15f (pi/2 %+.1e), %d Newton "
        "steps, %d rounds\n",
        r == &seeded ? "bilateral seed" : "auto", ba, bb, ba - kPi / 2, r->iterations, r->rounds);
    CHECK(std::abs(ba - kPi / 2) < 1e-8);
    CHECK(std::abs(bb - kPi / 2) < 1e-8);
    // Closed form of the contact part (free-free beam of length pi/beta, zero end deflection):
    //   w(x0) = P beta/(2K) (cosh pi + cos pi + 2)/(sinh pi + sin pi) = P beta/(2K) coth(pi/2).
    const double K = pr.foundation_modulus;
    CHECK(r->solution.deflection(x0) == Approx(P * beta / (2 * K) / std::tanh(kPi / 2)).epsilon(1e-11));
    CHECK(reaction_integral(r->solution) == Approx(P).epsilon(1e-11));
  }
}

TEST_CASE("tensionless: very long free beam (beta L = 1000), automatic topology", "[closed_form]") {
  const auto pr = free_free_central(1000.0, 1.0);
  const auto r = cf::solve_tensionless_auto(pr);
  INFO(r.message);
  REQUIRE(r.status == cf::TensionlessStatus::converged);
  REQUIRE(r.limits.size() == 2);
  CHECK(std::abs(r.limits[1] - r.limits[0] - kPi) < 1e-10);
  std::printf("[beta L = 1000 auto] contact length - pi = %.1e, %d rounds, lifted end w = %.6e\n",
              r.limits[1] - r.limits[0] - kPi, r.rounds, r.solution.deflection(0.0));
  // The lifted ends are straight: w(0) = w(t1) + w'(t1)(0 - t1) with w(t1) = 0.
  CHECK(r.solution.deflection(0.0) == Approx(-r.solution.slope(r.limits[0]) * r.limits[0]).epsilon(1e-12));
}

TEST_CASE("bilateral: separation under self-weight plus a central force", "[closed_form]") {
  // Infinite-beam prediction: w = q/K + P beta/(2K) e^{-z}(cos z + sin z), z = beta|x - x0|.
  //   upward force (P < 0): the minimum is at the load point, separation at |P| beta / q = 2;
  //   downward force (P > 0): the minimum is at z = pi, separation at P beta / q = 2 e^pi.
  const double beta = 0.9, EI = 1.4, q = 0.35, bL = 40.0;
  auto problem = [&](double P) {
    auto pr = free_free_central(bL, P, beta, EI);
    pr.uniform_loads = {{0.0, pr.length, q}};
    return pr;
  };
  const double x0 = bL / beta / 2;
  for (double sgn : {-1.0, 1.0}) {
    auto separated = [&](double P) { return min_deflection(cf::solve_bilateral(problem(P))).second <= 0.0; };
    double lo = 0.0, hi = 100.0 * q / beta;
    REQUIRE(!separated(sgn * lo));
    REQUIRE(separated(sgn * hi));
    for (int it = 0; it < 200 && hi - lo > 1e-14 * hi; ++it) {
      const double m = 0.5 * (lo + hi);
      if (m <= lo || m >= hi) break;
      (separated(sgn * m) ? hi : lo) = m;
    }
    const double Pc = 0.5 * (lo + hi);
    const auto where = min_deflection(cf::solve_bilateral(problem(sgn * Pc)));
    const double ratio = Pc * beta / q;
    const double expected = sgn < 0 ? 2.0 : 2.0 * std::exp(kPi);
    std::printf(
        "[weight + %s central force] critical |P| beta / q = %.12f (expected %.12f, "
        "rel %+.1e), first separation at beta|x - x0| = %.9f\n",
        sgn < 0 ? "upward" : "downward", ratio, expected, ratio / expected - 1.0, beta * std::abs(where.first - x0));
    CHECK(ratio == Approx(expected).epsilon(1e-9));
    CHECK(beta * std::abs(where.first - x0) == Approx(sgn < 0 ? 0.0 : kPi).margin(1e-5));
  }
}

TEST_CASE("tensionless: weight plus a large downward force lifts a window on each side", "[closed_form]") {
  const double beta = 1.0, q = 1.0, bL = 40.0;
  auto pr = free_free_central(bL, 80.0 * q / beta, beta, 1.0);  // 80 > 2 e^pi = 46.3
  pr.uniform_loads = {{0.0, pr.length, q}};
  const auto seed = cf::contact_regions(cf::solve_bilateral(pr));
  REQUIRE(seed.size() == 3);
  const auto r = cf::solve_tensionless(pr, seed);
  INFO(r.message);
  REQUIRE(r.status == cf::TensionlessStatus::converged);
  REQUIRE(r.limits.size() == 4);
  std::printf(
      "[weight + force 80 q/beta] limits beta(x - x0) = %.10f %.10f %.10f %.10f, "
      "%d Newton steps\n",
      r.limits[0] - 20, r.limits[1] - 20, r.limits[2] - 20, r.limits[3] - 20, r.iterations);
  CHECK(std::abs(r.limits[0] + r.limits[3] - pr.length) < 1e-9);
  CHECK(std::abs(r.limits[1] + r.limits[2] - pr.length) < 1e-9);
  CHECK(reaction_integral(r.solution) == Approx(80.0 + q * pr.length).epsilon(1e-11));
}

TEST_CASE("tensionless: eccentric force near a free end, contact region touching the end", "[closed_form]") {
  cf::BeamProblem pr = free_free_central(10.0, 2.0);
  pr.forces = {{0.4, 2.0}};
  const auto seed = cf::contact_regions(cf::solve_bilateral(pr));
  REQUIRE(!seed.empty());
  const auto seeded = cf::solve_tensionless(pr, {seed.front()});
  const auto automatic = cf::solve_tensionless_auto(pr);
  for (const auto* r : {&seeded, &automatic}) {
    INFO(r->message);
    REQUIRE(r->status == cf::TensionlessStatus::converged);
    REQUIRE(r->contact.size() == 1);
    CHECK(r->contact[0].start == 0.0);
    std::printf("[eccentric force at beta x = 0.4, %s] contact [0, %.12f] (beta units), %d steps\n",
                r == &seeded ? "bilateral seed" : "auto", r->contact[0].end, r->iterations);
    CHECK(reaction_integral(r->solution) == Approx(2.0).epsilon(1e-11));
    CHECK(reaction_moment(r->solution) == Approx(0.8).epsilon(1e-11));
  }
  CHECK(seeded.limits[0] == Approx(automatic.limits[0]).epsilon(1e-12));
}

TEST_CASE("tensionless: automatic topology, mixed loads, four contact regions", "[closed_form]") {
  cf::BeamProblem pr;
  pr.length = 60.0;
  pr.bending_stiffness = 1.0;
  pr.foundation_modulus = 4.0;
  pr.forces = {{10.0, 3.0}, {35.0, -1.0}, {45.0, 2.0}};
  pr.moments = {{20.0, 4.0}};
  pr.uniform_loads = {{0.0, 60.0, 0.02}};
  for (auto left : {cf::EndCondition::free, cf::EndCondition::clamped}) {
    pr.left = left;
    const auto r = cf::solve_tensionless_auto(pr);
    INFO(r.message);
    REQUIRE(r.status == cf::TensionlessStatus::converged);
    std::printf("[mixed loads, %s left end] %s; contact:", left == cf::EndCondition::free ? "free" : "clamped",
                r.message.c_str());
    for (const auto& i : r.contact) std::printf(" [%.9f, %.9f]", i.start, i.end);
    std::printf("\n");
    CHECK(r.max_violation < 1e-12);
    // Re-solving from the found regions is a fixed point.
    const auto again = cf::solve_tensionless(pr, r.contact);
    REQUIRE(again.status == cf::TensionlessStatus::converged);
    CHECK(again.iterations == 0);
    if (left == cf::EndCondition::free) {
      const double F = 3.0 - 1.0 + 2.0 + 0.02 * 60.0;
      const double Mx = 30.0 - 35.0 + 90.0 + 0.02 * 1800.0 - 4.0;
      CHECK(reaction_integral(r.solution) == Approx(F).epsilon(1e-11));
      CHECK(reaction_moment(r.solution) == Approx(Mx).epsilon(1e-11));
    }
  }
}

TEST_CASE("tensionless: simply supported beam under opposite end moments, k = 1e4", "[closed_form]") {
  // EI = L = 1, K = 1e4 (beta L = 7.07). Opposite senses give symmetric bending.
  cf::BeamProblem pr;
  pr.length = 1.0;
  pr.bending_stiffness = 1.0;
  pr.foundation_modulus = 1e4;
  pr.left = pr.right = cf::EndCondition::pinned;
  const double M = 1.0;

  SECTION("hogging (ccw at the left end, cw at the right): the beam bows up, no contact") {
    pr.moments = {{0.0, M}, {1.0, -M}};
    // Bilateral: w < 0 near the ends, w > 0 in the middle ...
    const auto bil = cf::solve_bilateral(pr);
    const auto seed = cf::contact_regions(bil);
    std::printf("[ss hogging] bilateral w > 0 on");
    for (const auto& i : seed) std::printf(" [%.6f, %.6f]", i.start, i.end);
    std::printf("\n");
    // ... but the tensionless problem is strictly convex with a unique solution, and the
    // foundation-free beam w = -M x (L - x) / (2 EI) < 0 satisfies every condition.
    const auto r = cf::solve_tensionless(pr, {});
    REQUIRE(r.status == cf::TensionlessStatus::converged);
    CHECK(r.solution.deflection(0.3) == Approx(-M * 0.3 * 0.7 / 2).epsilon(1e-13));
    const auto automatic = cf::solve_tensionless_auto(pr);
    REQUIRE(automatic.status == cf::TensionlessStatus::converged);
    CHECK(automatic.contact.empty());
    // Seeded with the bilateral central region, the fixed topology cannot work.
    REQUIRE(seed.size() == 1);
    const auto bad = cf::solve_tensionless(pr, seed);
    std::printf("[ss hogging] seeded with the bilateral central region: %s (%s)\n", cf::to_string(bad.status).c_str(),
                bad.message.c_str());
    CHECK(bad.status != cf::TensionlessStatus::converged);
  }

  SECTION("sagging (cw at the left end, ccw at the right): contact at the ends") {
    pr.moments = {{0.0, -M}, {1.0, M}};
    const auto bil = cf::solve_bilateral(pr);
    const auto seed = cf::contact_regions(bil);
    std::printf("[ss sagging] bilateral w > 0 on");
    for (const auto& i : seed) std::printf(" [%.6f, %.6f]", i.start, i.end);
    std::printf("\n");
    const auto r = cf::solve_tensionless(pr, seed);
    INFO(r.message);
    REQUIRE(r.status == cf::TensionlessStatus::converged);
    std::printf("[ss sagging] tensionless contact:");
    for (const auto& i : r.contact) std::printf(" [%.12f, %.12f]", i.start, i.end);
    std::printf(" (%d Newton steps, residual %.1e, violation %.1e)\n", r.iterations, r.residual, r.max_violation);
    REQUIRE(r.limits.size() == 2);
    CHECK(std::abs(r.limits[0] + r.limits[1] - 1.0) < 1e-10);
    // Equilibrium with the pin forces S0 = EI w'''(0+), SL = -EI w'''(L-) (in +w):
    //   S0 + SL = int r,  L SL - (M0 + ML) = int x r, M0 + ML = 0.
    const auto& s = r.solution;
    const double S0 = s.derivative(0.0, 3, cf::Side::right);
    const double SL = -s.derivative(1.0, 3, cf::Side::left);
    CHECK(S0 + SL == Approx(reaction_integral(s)).epsilon(1e-10));
    CHECK(SL == Approx(reaction_moment(s)).epsilon(1e-10));
    const auto automatic = cf::solve_tensionless_auto(pr);
    REQUIRE(automatic.status == cf::TensionlessStatus::converged);
    REQUIRE(automatic.limits.size() == 2);
    CHECK(automatic.limits[0] == Approx(r.limits[0]).epsilon(1e-12));
  }
}

TEST_CASE("tensionless: status reporting", "[closed_form]") {
  const auto pr = free_free_central(6.0, 1.0);
  CHECK(cf::solve_tensionless(pr, {{1.0, 3.0}, {2.0, 4.0}}).status == cf::TensionlessStatus::invalid_input);
  CHECK(cf::solve_tensionless(pr, {}).status == cf::TensionlessStatus::singular_system);
  // Full contact is not admissible for beta L = 6 > pi: the ends would pull.
  const auto full = cf::solve_tensionless(pr, {{0.0, 6.0}});
  CHECK(full.status == cf::TensionlessStatus::inequalities_violated);
  std::printf("[status] full contact at beta L = 6: %s (%s)\n", cf::to_string(full.status).c_str(),
              full.message.c_str());
}

// ---------------------------------------------------------------------------------------------
// Ground models of issue 12: foundation pieces and voids, an initial gap, linear loads, K_t.
// Units beta = 1, q/K = 1 where a foundation acts: EI = 1, K = 4, q = 4.
// ---------------------------------------------------------------------------------------------

namespace {

cf::BeamProblem heavy_free_beam(double length) {
  cf::BeamProblem pr;
  pr.length = length;
  pr.bending_stiffness = 1.0;
  pr.foundation_modulus = 4.0;
  pr.left = pr.right = cf::EndCondition::free;
  pr.uniform_loads = {{0.0, length, 4.0}};
  return pr;
}

// Lead's trench solution (beta = 1, q/K = 1, X from the trench centre, half-width b): inside
// w = X^4/6 + A X^2 + B, outside w = 1 + e^{-t}(C cos t + D sin t), t = |X| - b.
struct Trench {
  double b, A, B, C, D;
  explicit Trench(double b_) : b(b_) {
    A = -b * (b * b + 3 * b + 3) / (3 * (b + 1));
    B = std::pow(b, 4) / 6 + 2 * std::pow(b, 3) / 3 + b * b + b + 1;
    C = b * (2 * b * b + 6 * b + 3) / (3 * (b + 1));
    D = b * (3 - 2 * b * b) / (3 * (b + 1));
  }
  double w(double X) const {
    X = std::abs(X);
    if (X <= b) return std::pow(X, 4) / 6 + A * X * X + B;
    const double t = X - b;
    return 1 + std::exp(-t) * (C * std::cos(t) + D * std::sin(t));
  }
  // Smallest w outside the trench: at a root of w' = e^{-t}((D - C) cos t - (C + D) sin t),
  // t = atan2(D - C, C + D) + n pi; the first few n cover it (the humps decay like e^{-pi}).
  double outside_min() const {
    double m = 1.0;
    const double t0 = std::atan2(D - C, C + D);
    for (int n = -1; n < 6; ++n) {
      const double t = t0 + n * kPi;
      if (t > 0) m = std::min(m, 1 + std::exp(-t) * (C * std::cos(t) + D * std::sin(t)));
    }
    return m;
  }
};

// The beam of the trench test: free ends 40 / beta beyond each trench edge (the end effects of
// the trench's disturbance are e^{-40} ~ 4e-18 of it: below round-off), no foundation on |X| < b.
cf::BeamProblem trench_beam(double b) {
  const double reach = 40.0, L = 2 * (b + reach);
  cf::BeamProblem pr = heavy_free_beam(L);
  pr.foundation_segments = {{0.0, reach, 4.0}, {L - reach, L, 4.0}};
  return pr;
}

// Bisection for the b at which f(b) changes sign from + to -, on [lo, hi].
double bisect(const std::function<double(double)>& f, double lo, double hi) {
  for (int it = 0; it < 200 && hi - lo > 1e-15 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    (f(mid) > 0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// Smallest w outside the trench of the solved beam (grid over the near humps, then golden section
// via min_deflection's grid restricted by sampling).
double solved_outside_min(const cf::BeamSolution& s, double b) {
  const double xc = 0.5 * s.length();
  double best = 1e300, xb = 0;
  for (int i = 0; i <= 4000; ++i) {
    const double x = xc + b + 8.0 * i / 4000;
    if (s.deflection(x) < best) best = s.deflection(x), xb = x;
  }
  // Newton on w'(x) = 0 from the best sample.
  for (int it = 0; it < 20; ++it) xb -= s.slope(xb) / s.derivative(xb, 2);
  return std::min(best, s.deflection(xb));
}

}  // namespace

TEST_CASE("ground: a linear load and a linear gap are exact particular solutions", "[closed_form]") {
  // A free-free beam on a full foundation under q(x) linear and with g(x) linear: w = g + q/K
  // satisfies the ODE and the free-end conditions (w'' = w''' = 0) exactly, so it is the
  // solution; tensionless too, since w - g = q/K > 0. Round-off: the segment solve is
  // backward stable, |error| ~ 1e-13 max|w|.
  cf::BeamProblem pr = heavy_free_beam(20.0);
  pr.uniform_loads.clear();
  pr.distributed_loads = {{0.0, 20.0, 2.0, 6.0}};
  pr.gap = {{0.0, 20.0}, {0.5, -0.5}};
  const auto r = cf::solve_tensionless_auto(pr);
  INFO(r.message);
  REQUIRE(r.status == cf::TensionlessStatus::converged);
  REQUIRE(r.contact.size() == 1);
  for (double x : {0.0, 3.3, 10.0, 17.1, 20.0}) {
    const double exact = (0.5 - x / 20.0) + (2.0 + 4.0 * x / 20.0) / 4.0;
    CHECK(std::abs(r.solution.deflection(x) - exact) < 1e-12);
    CHECK(std::abs(r.solution.reaction(x) - (2.0 + 4.0 * x / 20.0)) < 1e-11);
  }
}

TEST_CASE("ground: triangular load on a simply supported beam, midspan 5 q L^4 / (768 EI)", "[closed_form]") {
  // Half of the uniform load's 5 q L^4 / (384 EI) by symmetry (the triangle plus its mirror is
  // the uniform load); the quintic particular solution of a lift-off segment carries it.
  cf::BeamProblem pr;
  pr.length = 3.0;
  pr.bending_stiffness = 2.0;
  pr.left = pr.right = cf::EndCondition::pinned;
  pr.distributed_loads = {{0.0, 3.0, 0.0, 5.0}};
  const auto s = cf::solve_bilateral(pr);
  CHECK(s.deflection(1.5) == Approx(5 * 5.0 * std::pow(3.0, 4) / (768 * 2.0)).epsilon(1e-13));
  // The support forces q L / 6 and q L / 3, pushing up (-w): EI w'''(0+) and -EI w'''(L-) in +w.
  CHECK(s.derivative(0.0, 3) * 2.0 == Approx(-5.0 * 3.0 / 6).epsilon(1e-12));
  CHECK(-s.derivative(3.0, 3, cf::Side::left) * 2.0 == Approx(-5.0 * 3.0 / 3).epsilon(1e-12));
}

TEST_CASE("ground: foundation pieces, equilibrium and the one-piece case", "[closed_form]") {
  cf::BeamProblem one = free_free_central(12.0, 3.0);
  cf::BeamProblem two = one;
  two.foundation_segments = {{0.0, 5.0, one.foundation_modulus}, {5.0, 12.0, one.foundation_modulus}};
  const auto a = cf::solve_tensionless_auto(one), b = cf::solve_tensionless_auto(two);
  REQUIRE(a.status == cf::TensionlessStatus::converged);
  REQUIRE(b.status == cf::TensionlessStatus::converged);
  for (double x : {0.0, 2.0, 5.0, 6.0, 9.5, 12.0})
    CHECK(std::abs(a.solution.deflection(x) - b.solution.deflection(x)) < 1e-12 * a.solution.max_abs_deflection());

  // Two soils with a void between them, an eccentric force and a trapezoidal load; bilinear
  // foundation (K_t = K / 10): the foundation carries the loads (free-free: no other support).
  cf::BeamProblem pr;
  pr.length = 10.0;
  pr.bending_stiffness = 1.0;
  pr.foundation_segments = {{0.0, 4.0, 4.0}, {5.0, 10.0, 1.0}};
  pr.forces = {{7.0, 2.0}};
  pr.distributed_loads = {{1.0, 9.0, 1.0, 0.2}};
  pr.gap = {{0.0, 10.0}, {0.0, 0.1}};
  for (double kt : {0.0, 0.4}) {
    pr.tension_modulus = kt;
    const auto r = cf::solve_tensionless_auto(pr);
    INFO(r.message);
    REQUIRE(r.status == cf::TensionlessStatus::converged);
    const auto& s = r.solution;
    const double load = 2.0 + 8.0 * 0.6, moment = 2.0 * 7.0 + (1.0 * 8 * (1 + 8.0 / 3) + 0.2 * 8 * (1 + 16.0 / 3)) / 2;
    // Quadrature on pieces <= 0.25/beta with 12 Gauss points: exact to round-off.
    CHECK(reaction_integral(s) == Approx(load).epsilon(1e-11));
    CHECK(reaction_moment(s) == Approx(moment).epsilon(1e-11));
    CHECK(s.reaction(4.5) == 0.0);  // the void
    std::printf("[two soils, K_t = %.1f] contact:", kt);
    for (const auto& i : r.contact) std::printf(" [%.9f, %.9f]", i.start, i.end);
    std::printf(" (%s)\n", r.message.c_str());
    // Interior limits sit where w = g.
    for (double t : r.limits) CHECK(std::abs(s.deflection(t) - s.gap(t)) < 1e-12 * s.max_abs_deflection());
  }
  // K_t = K: the bilinear foundation is bilateral.
  cf::BeamProblem bil = free_free_central(8.0, 1.0);
  bil.tension_modulus = bil.foundation_modulus;
  const auto full = cf::solve_bilateral(bil);
  const auto r = cf::solve_tensionless(bil, {{2.0, 6.0}});
  REQUIRE(r.status == cf::TensionlessStatus::converged);
  CHECK(std::abs(r.solution.deflection(0.0) - full.deflection(0.0)) < 1e-12 * full.max_abs_deflection());
}

TEST_CASE("ground: heavy beam over a trench, bilateral = tensionless up to beta b = 2.98486", "[closed_form]") {
  // The lead's closed form against the segment solver, at a few half-widths: round-off only
  // (the finite beam's end effects are e^{-40} of the disturbance).
  for (double b : {0.5, 1.7, 2.9}) {
    const Trench exact(b);
    const auto pr = trench_beam(b);
    const auto s = cf::solve_bilateral(pr);
    const double xc = 0.5 * pr.length;
    for (double X : {0.0, 0.3 * b, b, b + 0.4, b + 2.0, b + 5.0})
      for (double sign : {-1.0, 1.0}) CHECK(std::abs(s.deflection(xc + sign * X) - exact.w(X)) < 1e-11 * exact.w(0.0));
  }
  // The threshold from the hand formula and from the solver (bisection on the sign of the
  // smallest w outside the trench; both to ~1e-14 relative in b, the slope d(min w)/db is O(1)).
  const double hand = bisect([](double b) { return Trench(b).outside_min(); }, 2.0, 4.0);
  const double solved =
      bisect([](double b) { return solved_outside_min(cf::solve_bilateral(trench_beam(b)), b); }, 2.0, 4.0);
  std::printf("[trench] threshold beta b: hand %.15f, solver %.15f, lead 2.984859899980781\n", hand, solved);
  CHECK(std::abs(hand - 2.984859899980781) < 1e-12);
  CHECK(std::abs(solved - hand) < 1e-9);
  // Below it the tensionless solution is the bilateral one (full contact on both pieces); above
  // it the bilateral one pulls (w < 0 outside) and the tensionless one lifts a window each side.
  {
    const auto pr = trench_beam(0.99 * hand);
    const auto r = cf::solve_tensionless_auto(pr);
    INFO(r.message);
    REQUIRE(r.status == cf::TensionlessStatus::converged);
    CHECK(r.contact.size() == 2);
    CHECK(r.limits.empty());
    const double xc = 0.5 * pr.length;
    CHECK(std::abs(r.solution.deflection(xc) - Trench(0.99 * hand).w(0.0)) < 1e-11 * Trench(hand).w(0.0));
  }
  {
    const auto pr = trench_beam(1.05 * hand);
    CHECK(solved_outside_min(cf::solve_bilateral(pr), 1.05 * hand) < 0.0);
    const auto r = cf::solve_tensionless_auto(pr);
    INFO(r.message);
    REQUIRE(r.status == cf::TensionlessStatus::converged);
    CHECK(r.contact.size() == 4);
    CHECK(r.limits.size() == 4);
    std::printf("[trench] beta b = %.6f: contact", 1.05 * hand);
    for (const auto& i : r.contact) std::printf(" [%.9f, %.9f]", i.start - 0.5 * pr.length, i.end - 0.5 * pr.length);
    std::printf(" (from the centre)\n");
    CHECK(reaction_integral(r.solution) == Approx(4.0 * pr.length).epsilon(1e-11));
    // The same trench as a deep gap (g = 1e3 q/K over |X| < b) instead of a void.
    cf::BeamProblem gap = heavy_free_beam(pr.length);
    const double xc = 0.5 * pr.length, b = 1.05 * hand;
    gap.gap = {{xc - b, xc - b, xc + b, xc + b}, {0.0, 1e3, 1e3, 0.0}};
    const auto rg = cf::solve_tensionless_auto(gap);
    INFO(rg.message);
    REQUIRE(rg.status == cf::TensionlessStatus::converged);
    for (double X : {0.0, 0.5 * b, b + 1.0, b + 3.0})
      CHECK(std::abs(rg.solution.deflection(xc + X) - r.solution.deflection(xc + X)) < 1e-10 * Trench(b).w(0.0));
  }
}

TEST_CASE("ground: curling strip, end moment M0: lift-off iff Lambda > 1, beta c = sqrt(Lambda) - 1", "[closed_form]") {
  // Hand derivation (beta = 1, q/K = 1, so EI w'''' = 4 off contact): lifted [0, c] has
  // w = x^4/6 - Lambda x^2 + b1 x + w0 (EI w''(0) = -M0, w'''(0) = 0); contact w = 1 +
  // e^{-t}(C cos t + D sin t), t = x - c, w(c) = 0 gives C = -1; continuity of w''' gives
  // D = 2c + 1, of w'' gives Lambda = (c + 1)^2, and of w, w' the edge w0 = -(Lambda^2 - 1)/2.
  // Full contact (Lambda <= 1): w(0) = (q/K)(1 - Lambda) >= 0. The strip: beta L = 40 (the
  // far end's effect e^{-40}), the moment -M0 (clockwise) at the free left end.
  for (double lambda : {0.5, 0.9, 1.5, 2.0, 4.0, 9.0}) {
    cf::BeamProblem pr = heavy_free_beam(40.0);
    const double M0 = lambda * 4.0 / 2.0;  // Lambda = 2 beta^2 M0 / q
    pr.moments = {{0.0, -M0}};
    const auto r = cf::solve_tensionless_auto(pr);
    INFO(r.message);
    REQUIRE(r.status == cf::TensionlessStatus::converged);
    REQUIRE(r.contact.size() == 1);
    const double c = r.contact.front().start, edge = r.solution.deflection(0.0);
    std::printf(
        "[curling] Lambda = %.2f: beta c = %.12f (expected %.12f), edge w = %.12f q/K (expected %.12f; "
        "Westergaard %.3f)\n",
        lambda, c, std::max(0.0, std::sqrt(lambda) - 1), edge, lambda > 1 ? -(lambda * lambda - 1) / 2 : 1 - lambda,
        1 - lambda);
    // Newton stops at |w(c)| <= 1e-13 max|w|, |w'(c)| = O(1): c to ~1e-12; w0 to round-off.
    if (lambda <= 1.0) {
      CHECK(c == 0.0);
      CHECK(std::abs(edge - (1 - lambda)) < 1e-11);
    } else {
      CHECK(std::abs(c - (std::sqrt(lambda) - 1)) < 1e-10);
      CHECK(std::abs(edge + (lambda * lambda - 1) / 2) < 1e-10 * lambda * lambda);
    }
  }
}

TEST_CASE("ground: input checks", "[closed_form]") {
  auto rejects = [](const cf::BeamProblem& pr) {
    CHECK_THROWS_AS(cf::load_points(pr), std::invalid_argument);
    CHECK(cf::solve_tensionless_auto(pr).status == cf::TensionlessStatus::invalid_input);
  };
  cf::BeamProblem pr = heavy_free_beam(10.0);
  cf::BeamProblem bad = pr;
  bad.foundation_segments = {{0.0, 6.0, 4.0}, {5.0, 10.0, 4.0}};  // overlapping
  rejects(bad);
  bad = pr;
  bad.foundation_segments = {{2.0, 11.0, 4.0}};  // outside the beam
  rejects(bad);
  bad = pr;
  bad.foundation_segments = {{2.0, 3.0, -1.0}};  // negative modulus
  rejects(bad);
  bad = pr;
  bad.gap = {{0.0, 5.0, 4.0}, {0.0, 1.0, 0.0}};  // positions decrease
  rejects(bad);
  bad = pr;
  bad.gap = {{0.0, 5.0}, {0.0}};  // sizes differ
  rejects(bad);
  bad = pr;
  bad.distributed_loads = {{5.0, 5.0, 1.0, 1.0}};  // empty range
  rejects(bad);
  bad = pr;
  bad.tension_modulus = -1.0;
  rejects(bad);
}

TEST_CASE("ground: limit Jacobian with a gap, two soils and K_t against finite differences", "[closed_form]") {
  // d(w - g)(t_k)/dt_j = delta_kj (w' - g')(t_k) + s_j (K - K_t)(w - g)(t_j) G(t_k, t_j); central
  // differences with h = 1e-6 carry an O(h^2) truncation and O(1e-16 / h) round-off: 1e-7 of J.
  cf::BeamProblem pr = free_free_central(7.0, 1.0);
  pr.forces.push_back({5.1, 0.4});
  pr.distributed_loads = {{0.0, 7.0, 0.05, 0.12}};
  pr.foundation_segments = {{0.0, 5.0, 4.0}, {5.0, 7.0, 9.0}};
  pr.gap = {{0.0, 3.0, 7.0}, {0.02, -0.01, 0.03}};
  pr.tension_modulus = 0.5;
  const auto [worst, scale] = limit_jacobian_error(pr, {{1.3, 4.6}, {5.5, 6.4}});
  std::printf("[ground limit Jacobian] max |J - J_fd| / max|J| = %.2e\n", worst / scale);
  CHECK(worst < 1e-7 * scale);
}
