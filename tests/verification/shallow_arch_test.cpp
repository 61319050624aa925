// The sinusoidal shallow arch's closed forms (verification/closed_form/shallow_arch.hpp) against
// the continuous energy integrated by quadrature (potential_energy), finite differences, and the
// classical thresholds of the bare arch.
#include "closed_form/shallow_arch.hpp"

#include <catch2/catch.hpp>
#include <cmath>

using namespace liftoff::closed_form;

namespace {

// L = EI = 1, r = 0.01, a = alpha r, k = kappa (pi/L)^4 EI, q0 = 1.
ShallowArch arch_of(double alpha, double kappa) {
  ShallowArch arch;
  const double r = 0.01;
  arch.axial_stiffness = 1.0 / (r * r);
  arch.rise = alpha * r;
  arch.foundation_modulus = kappa * std::pow(M_PI, 4);
  return arch;
}

// The energy in the units of Pihat (shallow_arch.hpp), as a function of xi = A1 / r, eta = A2 / r.
struct Energy {
  ShallowArch arch;
  double lambda;
  bool tensionless = false;
  double operator()(double xi, double eta) const {
    const double r = arch.radius_of_gyration();
    const double unit = arch.length * arch.bending_stiffness * std::pow(M_PI / arch.length, 4) * r * r / 4;
    return potential_energy(arch, lambda, r * xi, r * eta, tensionless) / unit;
  }
  // Central differences, step h = 1e-3: truncation h^2 |Pihat'''| / 6 <= 1e-6 (alpha + 1) for the
  // cubic and quartic terms here, round-off 1e-16 Pihat / h below 1e-9.
  Eigen::Vector2d gradient(double xi, double eta) const {
    const double h = 1e-3;
    return {((*this)(xi + h, eta) - (*this)(xi - h, eta)) / (2 * h),
            ((*this)(xi, eta + h) - (*this)(xi, eta - h)) / (2 * h)};
  }
  // Truncation h^2 |Pihat''''| / 12 = h^2 3 / 12, round-off 1e-16 Pihat / h^2: both below 1e-6.
  Eigen::Matrix2d hessian(double xi, double eta) const {
    const double h = 1e-3;
    const double f = (*this)(xi, eta);
    Eigen::Matrix2d m;
    m(0, 0) = ((*this)(xi + h, eta) - 2 * f + (*this)(xi - h, eta)) / (h * h);
    m(1, 1) = ((*this)(xi, eta + h) - 2 * f + (*this)(xi, eta - h)) / (h * h);
    m(0, 1) = m(1, 0) =
        ((*this)(xi + h, eta + h) - (*this)(xi + h, eta - h) - (*this)(xi - h, eta + h) + (*this)(xi - h, eta - h)) /
        (4 * h * h);
    return m;
  }
};

double det(const Eigen::Matrix2d& m) { return m.determinant(); }

}  // namespace

TEST_CASE("shallow arch: the cubic's roots are equilibria of the continuous energy", "[verification][shallow_arch]") {
  for (double kappa : {0.0, 2.0, 10.0})
    for (double alpha : {1.5, 3.0, 6.0, 9.0}) {
      const ShallowArch arch = arch_of(alpha, kappa);
      const double r = arch.radius_of_gyration();
      for (double p : {0.5, 1.0, 4.0, 20.0, 60.0}) {
        const double lambda = p * arch.load_unit();
        const std::vector<double> roots = symmetric_deflections(arch, lambda);
        REQUIRE(!roots.empty());
        for (double a1 : roots) {
          CHECK(a1 >= 0.0);  // lambda > 0: all in contact
          CHECK(symmetric_load(arch, a1) == Approx(lambda).epsilon(1e-12).margin(1e-12 * arch.load_unit()));
          const Energy energy{arch, lambda};
          const Eigen::Vector2d g = energy.gradient(a1 / r, 0.0);
          CHECK(std::abs(g(0)) <= 1e-5 * (1 + alpha));
          CHECK(std::abs(g(1)) <= 1e-9);
          // The tensionless foundation has the same equilibrium (w >= 0).
          const Eigen::Vector2d gt = Energy{arch, lambda, true}.gradient(a1 / r, 0.0);
          CHECK(std::abs(gt(0)) <= 1e-5 * (1 + alpha));
        }
        // The count of roots: three between the limit loads, else one.
        const ShallowArchAnalysis a = analyse(arch);
        const bool three = a.has_limit_points && lambda < a.upper_limit.load && lambda > a.lower_limit.load;
        CHECK(roots.size() == (three ? 3u : 1u));
      }
    }
}

TEST_CASE("shallow arch: the two-mode solution solves the differential equation pointwise",
          "[verification][shallow_arch]") {
  // EI w'''' - N (w0 + w)'' + k w = q with N from the quadrature of the membrane strain.
  const ShallowArch arch = arch_of(6.0, 3.0);
  const ShallowArchAnalysis a = analyse(arch);
  const double L = arch.length, b = M_PI / L;
  const double a1 = 0.5 * (a.first_bifurcation.deflection + a.second_bifurcation.deflection);
  const double a2 = bifurcated_asymmetry(arch, a1), lambda = bifurcated_load(arch, a1);
  double stretch = 0.0;
  const int n = 20000;  // midpoint rule on a trigonometric polynomial: exact to round-off
  for (int i = 0; i < n; ++i) {
    const double x = L * (i + 0.5) / n;
    const double dw = b * (a1 * std::cos(b * x) + 2 * a2 * std::cos(2 * b * x)), dw0 = -arch.rise * b * std::cos(b * x);
    stretch += (dw0 * dw + 0.5 * dw * dw) * L / n;
  }
  const double N = arch.axial_stiffness / L * stretch;
  CHECK(-N == Approx(thrust(arch, a1, a2)).epsilon(1e-12));
  CHECK(-N == Approx(4 * M_PI * M_PI / (L * L) + arch.foundation_modulus * L * L / (4 * M_PI * M_PI)).epsilon(1e-12));
  for (double x : {0.1, 0.3, 0.5, 0.77}) {
    const double s1 = std::sin(b * x), s2 = std::sin(2 * b * x);
    const double w4 = std::pow(b, 4) * (a1 * s1 + 16 * a2 * s2);
    const double dd = -b * b * (-arch.rise * s1 + a1 * s1 + 4 * a2 * s2);
    const double residual = w4 - N * dd + arch.foundation_modulus * (a1 * s1 + a2 * s2) - lambda * s1;
    CHECK(std::abs(residual) <= 1e-11 * std::abs(lambda));
  }
}

TEST_CASE("shallow arch: limit points are where d lambda / d A1 = 0", "[verification][shallow_arch]") {
  for (double kappa : {0.0, 1.0, 6.0})
    for (double alpha : {3.0, 5.0, 8.0}) {
      const ShallowArch arch = arch_of(alpha, kappa);
      const ShallowArchAnalysis a = analyse(arch);
      REQUIRE(a.has_limit_points == (alpha > 2 * std::sqrt(1 + kappa)));
      if (!a.has_limit_points) continue;
      const double r = arch.radius_of_gyration(), h = 1e-4 * r;
      for (const ArchPoint& p : {a.upper_limit, a.lower_limit}) {
        CHECK(symmetric_load(arch, p.deflection) == Approx(p.load).epsilon(1e-13));
        // lambda is a cubic in A1: the central difference errs by h^2 lambda''' / 6 = h^2 unit / (4 r^3).
        const double slope =
            (symmetric_load(arch, p.deflection + h) - symmetric_load(arch, p.deflection - h)) / (2 * h);
        CHECK(std::abs(slope) <= 1e-8 * arch.load_unit() / r);
      }
      // The upper limit is a maximum, the lower one a minimum.
      const double d = 1e-2 * r;
      CHECK(symmetric_load(arch, a.upper_limit.deflection + d) < a.upper_limit.load);
      CHECK(symmetric_load(arch, a.upper_limit.deflection - d) < a.upper_limit.load);
      CHECK(symmetric_load(arch, a.lower_limit.deflection + d) > a.lower_limit.load);
      CHECK(symmetric_load(arch, a.lower_limit.deflection - d) > a.lower_limit.load);
      CHECK(a.upper_limit.deflection < a.lower_limit.deflection);
    }
}

TEST_CASE("shallow arch: the bifurcation makes the two-mode tangent singular, in the second mode",
          "[verification][shallow_arch]") {
  for (double kappa : {0.0, 2.0, 4.0, 9.0})
    for (double alpha : {5.0, 7.0, 10.0}) {
      const ShallowArch arch = arch_of(alpha, kappa);
      const ShallowArchAnalysis a = analyse(arch);
      REQUIRE(a.has_bifurcation == (alpha * alpha > 16 + kappa));
      if (!a.has_bifurcation) continue;
      const double r = arch.radius_of_gyration();
      for (const ArchPoint& p : {a.first_bifurcation, a.second_bifurcation}) {
        CHECK(symmetric_load(arch, p.deflection) == Approx(p.load).epsilon(1e-12));
        CHECK(p.thrust == Approx(4 * M_PI * M_PI + arch.foundation_modulus / (4 * M_PI * M_PI)).epsilon(1e-12));
        const Eigen::Matrix2d H = Energy{arch, p.load}.hessian(p.deflection / r, 0.0);
        // The determinant vanishes through H_etaeta (the second mode), H_xixi = 2 d p / d xi stays.
        CHECK(std::abs(H(1, 1)) <= 1e-5);
        CHECK(std::abs(H(0, 1)) <= 1e-5);
        CHECK(std::abs(det(H)) <= 1e-5 * std::abs(H(0, 0)));
        CHECK(H(0, 0) == Approx(energy_hessian(arch, p.deflection, 0.0)(0, 0) / (arch.length * std::pow(M_PI, 4) / 4))
                             .epsilon(1e-6));
      }
    }
}

TEST_CASE("shallow arch: the bifurcated branch is in equilibrium, lambda linear in A1, stable iff kappa > 4",
          "[verification][shallow_arch]") {
  for (double kappa : {0.0, 2.0, 4.0, 9.0}) {
    const double alpha = 8.0;
    const ShallowArch arch = arch_of(alpha, kappa);
    const ShallowArchAnalysis a = analyse(arch);
    REQUIRE(a.has_bifurcation);
    const double r = arch.radius_of_gyration();
    CHECK(a.branch_slope * r / arch.load_unit() == Approx(3 * (kappa - 4) / 4).margin(1e-12));
    CHECK(a.branch_stability == (kappa < 4   ? BranchStability::unstable
                                 : kappa > 4 ? BranchStability::stable
                                             : BranchStability::neutral));
    for (double f : {0.1, 0.4, 0.5, 0.9}) {
      const double a1 =
          a.first_bifurcation.deflection + f * (a.second_bifurcation.deflection - a.first_bifurcation.deflection);
      const double a2 = bifurcated_asymmetry(arch, a1), lambda = bifurcated_load(arch, a1);
      REQUIRE(a2 > 0);
      for (double sign : {-1.0, 1.0}) {
        const Energy energy{arch, lambda};
        const Eigen::Vector2d g = energy.gradient(a1 / r, sign * a2 / r);
        CHECK(g.norm() <= 1e-5 * (1 + alpha));
        // Second variation: det H = 24 eta^2 (kappa - 4), H_etaeta = 16 eta^2.
        const Eigen::Matrix2d H = energy.hessian(a1 / r, sign * a2 / r);
        const double eta = a2 / r;
        CHECK(H(1, 1) == Approx(16 * eta * eta).epsilon(1e-6));
        CHECK(det(H) == Approx(24 * eta * eta * (kappa - 4)).margin(1e-4 * H.norm()));
        CHECK((H - energy_hessian(arch, a1, sign * a2) / (arch.length * std::pow(M_PI, 4) / 4)).norm() <=
              1e-5 * H.norm());
        const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(H);
        if (kappa < 4) CHECK(eig.eigenvalues()(0) < 0);
        if (kappa > 4) CHECK(eig.eigenvalues()(0) > 0);
      }
    }
    // The bifurcated line passes through both bifurcation points.
    CHECK(bifurcated_load(arch, a.second_bifurcation.deflection) == Approx(a.second_bifurcation.load).epsilon(1e-12));
    CHECK(bifurcated_asymmetry(arch, a.first_bifurcation.deflection) == Approx(0.0).margin(1e-6 * r));
  }
}

TEST_CASE("shallow arch: the symmetric path's stability from the second variation", "[verification][shallow_arch]") {
  const ShallowArch arch = arch_of(8.0, 1.0);
  const ShallowArchAnalysis a = analyse(arch);
  REQUIRE(a.first == FirstCritical::unstable_bifurcation);
  const double r = arch.radius_of_gyration();
  const auto hessian_at = [&](double a1) { return Energy{arch, symmetric_load(arch, a1)}.hessian(a1 / r, 0.0); };
  // Before the first bifurcation: stable; between the bifurcation points: the second mode is unstable;
  // between the limit points also the first.
  const Eigen::Matrix2d before = hessian_at(0.9 * a.first_bifurcation.deflection);
  CHECK(before(0, 0) > 0);
  CHECK(before(1, 1) > 0);
  const Eigen::Matrix2d between = hessian_at(0.5 * (a.first_bifurcation.deflection + a.upper_limit.deflection));
  CHECK(between(0, 0) > 0);
  CHECK(between(1, 1) < 0);
  const Eigen::Matrix2d middle = hessian_at(arch.rise);
  CHECK(middle(0, 0) < 0);
  CHECK(middle(1, 1) < 0);
  const Eigen::Matrix2d after = hessian_at(1.01 * a.second_bifurcation.deflection);
  CHECK(after(0, 0) > 0);
  CHECK(after(1, 1) > 0);
}

TEST_CASE("shallow arch: the classical thresholds of the bare arch (a/r = 2, 4, sqrt 22 = 4.690)",
          "[verification][shallow_arch]") {
  const ShallowArchAnalysis a = analyse(arch_of(3.0, 0.0));
  CHECK(a.limit_rise == 2.0);
  CHECK(a.bifurcation_rise == 4.0);
  CHECK(std::abs(a.bifurcation_first_rise - 4.690) <= 0.0005);
  CHECK(analyse(arch_of(1.99, 0.0)).first == FirstCritical::none);
  CHECK(analyse(arch_of(2.01, 0.0)).first == FirstCritical::limit_point);
  CHECK(analyse(arch_of(4.5, 0.0)).first == FirstCritical::limit_point);  // bifurcation exists, comes later
  CHECK(analyse(arch_of(4.5, 0.0)).has_bifurcation);
  CHECK(analyse(arch_of(4.68, 0.0)).first == FirstCritical::limit_point);
  CHECK(analyse(arch_of(4.70, 0.0)).first == FirstCritical::unstable_bifurcation);
  // At the threshold the bifurcation and the limit point coincide.
  const ShallowArchAnalysis at = analyse(arch_of(std::sqrt(22.0), 0.0));
  CHECK(at.first_bifurcation.deflection == Approx(at.upper_limit.deflection).epsilon(1e-7));
  CHECK(at.first_bifurcation.load == Approx(at.upper_limit.load).epsilon(1e-12));
  // The bare arch's bifurcation load p = alpha + 3 sqrt(alpha^2 - 16), branch slope dp/dxi = -3.
  const ShallowArch arch = arch_of(6.0, 0.0);
  const ShallowArchAnalysis b = analyse(arch);
  CHECK(b.first_bifurcation.load / arch.load_unit() == Approx(6.0 + 3 * std::sqrt(20.0)).epsilon(1e-13));
  CHECK(b.branch_slope * arch.radius_of_gyration() / arch.load_unit() == Approx(-3.0).epsilon(1e-13));
}

TEST_CASE("shallow arch: with a foundation the thresholds move, and beyond kappa = 4 the bifurcation is stable",
          "[verification][shallow_arch]") {
  // kappa = 2: limit points from a/r = 2 sqrt 3, bifurcation first from sqrt 21.
  CHECK(analyse(arch_of(3.4, 2.0)).first == FirstCritical::none);
  CHECK(analyse(arch_of(3.5, 2.0)).first == FirstCritical::limit_point);
  CHECK(analyse(arch_of(4.58, 2.0)).first == FirstCritical::limit_point);
  CHECK(analyse(arch_of(4.59, 2.0)).first == FirstCritical::unstable_bifurcation);
  // kappa = 8: bifurcation from sqrt 24 = 4.899, limit points only from 6; the branch rises.
  CHECK(analyse(arch_of(4.89, 8.0)).first == FirstCritical::none);
  CHECK(analyse(arch_of(4.91, 8.0)).first == FirstCritical::stable_bifurcation);
  const ShallowArchAnalysis b = analyse(arch_of(7.0, 8.0));
  CHECK(b.has_limit_points);
  CHECK(b.first == FirstCritical::stable_bifurcation);
  CHECK(b.first_bifurcation.deflection < b.upper_limit.deflection);
  CHECK(b.second_bifurcation.deflection > b.lower_limit.deflection);
  CHECK(b.second_bifurcation.load > b.first_bifurcation.load);
  CHECK(analyse(arch_of(7.0, 4.0)).first == FirstCritical::neutral_bifurcation);
  CHECK(b.covered);
}

TEST_CASE("shallow arch: beyond kappa = 36 a higher mode bifurcates first, which is not covered",
          "[verification][shallow_arch]") {
  // The thrust of mode n is EI beta^2 (n^2 + kappa / n^2): n = 2 and 3 tie at kappa = 36.
  CHECK(analyse(arch_of(20.0, 35.0)).critical_mode == 2);
  CHECK(analyse(arch_of(20.0, 35.0)).covered);
  const ShallowArchAnalysis a = analyse(arch_of(20.0, 40.0));
  CHECK(a.critical_mode == 3);
  CHECK(!a.covered);
  CHECK_THAT(a.reason, Catch::StartsWith("not covered: mode 3"));
  CHECK(analyse(arch_of(20.0, 300.0)).critical_mode == 4);  // 16 + 300/16 = 34.75 < 9 + 300/9, 25 + 12
  // Below the least mode's threshold (a/r <= 2 sqrt(9 + 40/9) = 7.33) nothing bifurcates: covered.
  CHECK(analyse(arch_of(7.3, 40.0)).covered);
}

TEST_CASE("shallow arch: tensionless agrees with bilateral up to the first lift-off at an end",
          "[verification][shallow_arch]") {
  for (double kappa : {0.0, 3.0, 9.0}) {
    const double alpha = 10.0;
    const ShallowArch arch = arch_of(alpha, kappa);
    const ShallowArchAnalysis a = analyse(arch);
    REQUIRE(a.has_contact_event == (alpha * alpha >= 2 * (16 + kappa)));
    const double r = arch.radius_of_gyration(), b = M_PI / arch.length;
    const ArchPoint& c = a.first_lift_off;
    CHECK(c.asymmetry == Approx(c.deflection / 2).epsilon(1e-12));
    CHECK(bifurcated_asymmetry(arch, c.deflection) == Approx(c.asymmetry).epsilon(1e-10));
    CHECK(c.load == Approx(bifurcated_load(arch, c.deflection)).epsilon(1e-14));
    CHECK(c.deflection > a.first_bifurcation.deflection);
    CHECK(c.deflection < a.last_lift_off.deflection);
    // With A2 = -A1/2 the deflection touches zero at x = 0 with zero slope, positive elsewhere.
    const auto w = [&](double x) { return c.deflection * std::sin(b * x) - c.asymmetry * std::sin(2 * b * x); };
    for (int i = 1; i < 100; ++i) CHECK(w(arch.length * i / 100) > 0);
    const double slope0 = b * (c.deflection - 2 * c.asymmetry);
    CHECK(std::abs(slope0) <= 1e-12 * b * c.deflection);
    // Up to the event the bilateral branch is a tensionless equilibrium; past it (between the two
    // roots) it pulls on the foundation and is not (unless there is none: kappa = 0).
    const auto tensionless_gradient = [&](double a1) {
      const double a2 = -bifurcated_asymmetry(arch, a1);
      return Energy{arch, bifurcated_load(arch, a1), true}.gradient(a1 / r, a2 / r).norm();
    };
    const double before = 0.5 * (a.first_bifurcation.deflection + c.deflection);
    CHECK(tensionless_gradient(before) <= 1e-5 * (1 + alpha));
    const double past = 0.5 * (c.deflection + a.last_lift_off.deflection);
    if (kappa > 0) CHECK(tensionless_gradient(past) > 1e-2);  // 1.3 at kappa = 3, 2.8 at 9
  }
  // Below sqrt(2 (16 + kappa)) the whole bifurcated branch stays in contact.
  const ShallowArchAnalysis low = analyse(arch_of(5.5, 0.0));
  CHECK(low.has_bifurcation);
  CHECK(!low.has_contact_event);
}

TEST_CASE("shallow arch: answers do not depend on the units", "[verification][shallow_arch]") {
  ShallowArch base = arch_of(7.0, 2.5);
  base.load_amplitude = 3.0;
  // Lengths times c, forces times f: EI f c^2, EA f, k f / c^2, q0 f / c.
  const double c = 37.5, f = 2.0e5;
  ShallowArch scaled = base;
  scaled.length *= c;
  scaled.rise *= c;
  scaled.bending_stiffness *= f * c * c;
  scaled.axial_stiffness *= f;
  scaled.foundation_modulus *= f / (c * c);
  scaled.load_amplitude *= f / c;
  const ShallowArchAnalysis a = analyse(base), s = analyse(scaled);
  CHECK(s.first == a.first);
  const auto same = [&](const ArchPoint& x, const ArchPoint& y) {
    CHECK(y.deflection == Approx(c * x.deflection).epsilon(1e-12));
    CHECK(y.asymmetry == Approx(c * x.asymmetry).epsilon(1e-12).margin(1e-14 * c * base.rise));
    CHECK(y.load == Approx(x.load).epsilon(1e-12));
    CHECK(y.thrust == Approx(f * x.thrust).epsilon(1e-12));
  };
  same(a.upper_limit, s.upper_limit);
  same(a.lower_limit, s.lower_limit);
  same(a.first_bifurcation, s.first_bifurcation);
  same(a.first_lift_off, s.first_lift_off);
  CHECK(s.branch_slope == Approx(a.branch_slope / c).epsilon(1e-12));
  const std::vector<double> ra = symmetric_deflections(base, 0.5 * a.upper_limit.load);
  const std::vector<double> rs = symmetric_deflections(scaled, 0.5 * a.upper_limit.load);
  REQUIRE(ra.size() == rs.size());
  for (std::size_t i = 0; i < ra.size(); ++i) CHECK(rs[i] == Approx(c * ra[i]).epsilon(1e-12));
}

TEST_CASE("shallow arch: invalid input is refused naming the field", "[verification][shallow_arch]") {
  ShallowArch arch = arch_of(3.0, 0.0);
  arch.rise = -1.0;
  CHECK_THROWS_WITH(analyse(arch), Catch::Contains("rise"));
  arch = arch_of(3.0, 0.0);
  arch.foundation_modulus = -1.0;
  CHECK_THROWS_WITH(analyse(arch), Catch::Contains("modulus"));
}

TEST_CASE("shallow arch: under load control the stable state jumps for kappa < 4 and moves on for kappa > 4",
          "[verification][shallow_arch]") {
  // Every equilibrium at lambda (the cubic's roots and the bifurcated branch's point), kept where the
  // closed-form Hessian is positive definite; the state reached from lambda = 0 is followed as the
  // nearest stable one over 4000 load steps. The largest step of A1, relative to the rise: about
  // 1e-3 while the path moves on (the grid's step), of the order of the rise across a snap.
  const auto largest_jump = [](const ShallowArch& arch) {
    const ShallowArchAnalysis a = analyse(arch);
    const double top = 1.2 * std::max(a.first_bifurcation.load, a.second_bifurcation.load);
    double current = 0.0, jump = 0.0;
    const int steps = 4000;
    for (int i = 1; i <= steps; ++i) {
      const double lambda = top * i / steps;
      std::vector<std::pair<double, double>> states;
      for (double a1 : symmetric_deflections(arch, lambda)) states.push_back({a1, 0.0});
      if (a.branch_slope != 0.0) {
        const double a1 = a.first_bifurcation.deflection + (lambda - a.first_bifurcation.load) / a.branch_slope;
        if (bifurcated_asymmetry(arch, a1) > 0) states.push_back({a1, bifurcated_asymmetry(arch, a1)});
      }
      double best = NAN;
      for (const auto& [a1, a2] : states) {
        const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(energy_hessian(arch, a1, a2));
        if (eig.eigenvalues()(0) > 0 && !(std::abs(a1 - current) >= std::abs(best - current))) best = a1;
      }
      REQUIRE(std::isfinite(best));
      jump = std::max(jump, std::abs(best - current));
      current = best;
    }
    return jump / arch.rise;
  };
  CHECK(largest_jump(arch_of(8.0, 2.0)) > 1.0);   // snaps across the crown
  CHECK(largest_jump(arch_of(8.0, 9.0)) < 0.01);  // follows the rising asymmetric branch
}
