// The von Karman membrane term of the Ritz beam (issue 16, item 3): its analytic gradient and
// Hessian against central differences (and zero in the contact limits), its energy against an
// independent quadrature of the continuous functional, the restricted two-mode energy and Hessian
// of the sinusoidal shallow arch against the closed forms (verification/closed_form/shallow_arch),
// the straight restrained beam under a sine load solved by KINSOL against its cubic, a solve with
// moving contact limits on a tensionless foundation, and the free-end (N = 0) branch.
#include <Eigen/Dense>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <tuple>
#include <utility>
#include <vector>

#include "closed_form/shallow_arch.hpp"
#include "nonlinear/newton.hpp"
#include "ritz/ritz_model.hpp"
#include "ritz/ritz_solver.hpp"
#include "ritz/von_karman_membrane.hpp"

using namespace liftoff;
using namespace liftoff::ritz;
using Eigen::MatrixXd;
using Eigen::VectorXd;
using model::EndSupport;

namespace {

constexpr double pi = std::numbers::pi;

const double gauss_x[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831, 0.9061798459386640};
const double gauss_w[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889, 0.4786286704993665,
                           0.2369268850561891};

model::MemberModel beam(EndSupport left, EndSupport right, double k, bool tensionless) {
  model::MemberModel m;
  m.kind = model::StructureKind::beam;
  m.left = left;
  m.right = right;
  m.k = k;
  m.tensionless = tensionless;
  return m;
}

model::MemberLoad point_force(double value, double at) {
  model::MemberLoad l;
  l.kind = model::LoadKind::force;
  l.value = value;
  l.at = at;
  return l;
}

MembraneOptions restrained(double membrane_stiffness) {
  MembraneOptions o;
  o.membrane_stiffness = membrane_stiffness;
  return o;
}

double relative(const MatrixXd& a, const MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(b.cwiseAbs().maxCoeff(), 1e-300);
}

// F_j = q0 int sin(pi s) phi_j: the work-equivalent vector of the sine load (not a MemberModel load).
VectorXd sine_load(const RitzModel& r, double q0) {
  VectorXd f = VectorXd::Zero(r.unknowns());
  const TrigPolynomial q = TrigPolynomial::sine(pi, 0.0, q0);
  for (int j = 0; j < static_cast<int>(r.basis().w.size()); ++j) f[j] = (q * r.basis().w[j]).integral(0.0, 1.0);
  return f;
}

}  // namespace

TEST_CASE("von Karman Ritz: gradient and Hessian match central differences; no limit dependence",
          "[ritz][von_karman]") {
  for (const bool enriched : {false, true}) {
    model::MemberModel m = beam(EndSupport::pinned, EndSupport::clamped, 300.0, true);
    m.initial_shape_at = {0.0, 0.2, 0.45, 0.6, 1.0};
    m.initial_shape_value = {0.0, -0.01, 0.02, 0.015, 0.0};
    m.loads = {point_force(-7.0, 0.37)};
    const RitzModel r(m, 7, Topology{true, 2}, enriched ? Enrichment::load_points : Enrichment::none);
    const VonKarmanMembrane membrane(m, r, restrained(2e4));
    REQUIRE(membrane.unknowns() == r.unknowns());
    VectorXd x(r.unknowns());
    for (int i = 0; i < r.modes(); ++i) x[i] = 0.01 * std::cos(1.0 + 2.3 * i) / (1 + i);
    x[r.limit_offset()] = 0.31;
    x[r.limit_offset() + 1] = 0.68;
    const int n = r.unknowns();
    const double lambda = 0.8;
    auto total_energy = [&](const VectorXd& y) { return r.energy(y, lambda) + membrane.energy(y); };
    auto total_gradient = [&](const VectorXd& y) -> VectorXd { return r.gradient(y, lambda) + membrane.gradient(y); };
    VectorXd g_fd(n), total_g_fd(n);
    MatrixXd h_fd(n, n), total_h_fd(n, n), j_fd(n, n);
    const double step = 1e-7;  // amplitudes ~1e-2: truncation (step/A)^2 ~ 1e-10, round-off eps A/step ~ 1e-11
    for (int i = 0; i < n; ++i) {
      VectorXd plus = x, minus = x;
      plus[i] += step;
      minus[i] -= step;
      g_fd[i] = (membrane.energy(plus) - membrane.energy(minus)) / (2 * step);
      total_g_fd[i] = (total_energy(plus) - total_energy(minus)) / (2 * step);
      h_fd.col(i) = (membrane.gradient(plus) - membrane.gradient(minus)) / (2 * step);
      total_h_fd.col(i) = (total_gradient(plus) - total_gradient(minus)) / (2 * step);
      VectorXd fp, fm;
      r.residual(plus, lambda, fp);
      r.residual(minus, lambda, fm);
      membrane.add_to_residual(plus, fp);
      membrane.add_to_residual(minus, fm);
      j_fd.col(i) = (fp - fm) / (2 * step);
      if (i >= r.limit_offset()) {
        // The membrane term integrates over the whole member: moving a limit changes nothing.
        CHECK(membrane.energy(plus) == membrane.energy(x));
        CHECK(membrane.energy(minus) == membrane.energy(x));
      }
    }
    INFO("enriched " << enriched << ", N = " << membrane.normal_force(x));
    REQUIRE(std::abs(membrane.normal_force(x)) > 1.0);  // the term matters at this x
    const VectorXd g = membrane.gradient(x);
    const MatrixXd h = membrane.hessian(x);
    CHECK(relative(g, g_fd) < 1e-8);
    CHECK(relative(h, h_fd) < 1e-7);
    CHECK(relative(h, h.transpose()) == 0.0);
    CHECK(g.tail(r.limits()).isZero(0.0));
    CHECK(h.rightCols(r.limits()).isZero(0.0));
    CHECK(h.bottomRows(r.limits()).isZero(0.0));
    CHECK(relative(total_gradient(x), total_g_fd) < 1e-8);
    CHECK(relative(r.hessian(x, lambda) + h, total_h_fd) < 1e-7);
    MatrixXd j;
    r.jacobian(x, lambda, j);
    membrane.add_to_jacobian(x, j);
    CHECK(relative(j, j_fd) < 1e-7);
    CHECK(relative(membrane.amplitude_hessian(x), h.topLeftCorner(r.modes(), r.modes())) == 0.0);
  }
}

TEST_CASE("von Karman Ritz: the energy is the continuous functional's, by independent quadrature",
          "[ritz][von_karman]") {
  // N = EA/L int (w0' w' + w'^2/2) by 5-point Gauss on each piece of w0's table cut at the kink
  // (w' from RitzModel::w, the modes' own values, not the product tables): exact for the
  // polynomial parts, ~1e-15 for the trig ones on pieces this short.
  model::MemberModel m = beam(EndSupport::clamped, EndSupport::pinned, 50.0, true);
  for (int i = 0; i <= 40; ++i) {
    const double s = i / 40.0;
    m.initial_shape_at.push_back(s);
    m.initial_shape_value.push_back(-0.03 * std::sin(pi * s) + 0.01 * std::sin(3 * pi * s) * s);
  }
  m.loads = {point_force(3.0, 0.4125)};  // between table points: the kink cuts a piece
  const RitzModel r(m, 9, Topology{false, 1}, Enrichment::load_points);
  REQUIRE(r.basis().kinked_w.size() == 1);
  const double ea = 3e3;
  const VonKarmanMembrane membrane(m, r, restrained(ea));
  VectorXd x(r.unknowns());
  for (int i = 0; i < r.modes(); ++i) x[i] = 0.02 * std::sin(0.7 + 1.9 * i) / (1 + i * i);
  x[r.limit_offset()] = 0.55;

  std::vector<double> cuts = m.initial_shape_at;
  cuts.push_back(0.4125);
  std::sort(cuts.begin(), cuts.end());
  double stretch = 0.0;
  for (std::size_t p = 0; p + 1 < cuts.size(); ++p) {
    const double a = cuts[p], b = cuts[p + 1];
    const double slope = (m.initial_shape(b) - m.initial_shape(a)) / (b - a);
    for (int q = 0; q < 5; ++q) {
      const double s = 0.5 * (a + b) + 0.5 * (b - a) * gauss_x[q], weight = 0.5 * (b - a) * gauss_w[q];
      const double dw = r.w(x, s, 1);
      stretch += weight * (slope * dw + 0.5 * dw * dw);
    }
  }
  const double n = ea * stretch;  // L = 1
  INFO("N = " << n);
  CHECK(membrane.stretch(x) == Approx(stretch).epsilon(1e-13));
  CHECK(membrane.normal_force(x) == Approx(n).epsilon(1e-13));
  CHECK(membrane.energy(x) == Approx(n * n / (2 * ea)).epsilon(1e-13));

  // A TrigPolynomial w0 is integrated exactly: w0 = 0.02 sin(2 pi s) s against Gauss on 64 panels.
  MembraneOptions exact = restrained(ea);
  exact.initial_shape = TrigPolynomial::sine(2 * pi, 0.0, 0.02) * TrigPolynomial::monomial(1);
  const VonKarmanMembrane with_trig(m, r, exact);
  double trig_stretch = 0.0;
  for (int p = 0; p < 64; ++p) {
    double a = p / 64.0, b = (p + 1) / 64.0;
    for (const auto& [lo, hi] : {std::pair{a, std::min(b, 0.4125)}, std::pair{std::max(a, 0.4125), b}}) {
      if (!(hi > lo)) continue;
      for (int q = 0; q < 5; ++q) {
        const double s = 0.5 * (lo + hi) + 0.5 * (hi - lo) * gauss_x[q], weight = 0.5 * (hi - lo) * gauss_w[q];
        const double dw = r.w(x, s, 1);
        const double dw0 = 0.02 * (std::sin(2 * pi * s) + 2 * pi * s * std::cos(2 * pi * s));
        trig_stretch += weight * (dw0 * dw + 0.5 * dw * dw);
      }
    }
  }
  CHECK(with_trig.stretch(x) == Approx(trig_stretch).epsilon(1e-13));
}

TEST_CASE("von Karman Ritz: two sine modes of the sinusoidal shallow arch give the closed form's energy",
          "[ritz][von_karman]") {
  // Pinned, axially restrained, w0 = -a sin(pi s), bilateral foundation, q = lambda q0 sin(pi s):
  // with the sine basis the Ritz energy restricted to (A1, A2) is the closed form's Pi(A1, A2)
  // (shallow_arch.hpp), to round-off.
  closed_form::ShallowArch arch;
  arch.axial_stiffness = 1e4;  // r = 0.01
  arch.rise = 5.0 * arch.radius_of_gyration();
  arch.foundation_modulus = 2.0 * std::pow(pi, 4);  // kappa = 2
  arch.load_amplitude = 30.0;
  const double r_g = arch.radius_of_gyration(), alpha = arch.relative_rise(), kappa = arch.relative_modulus();
  REQUIRE(kappa == Approx(2.0));
  for (const int modes : {2, 6}) {
    const model::MemberModel m = beam(EndSupport::pinned, EndSupport::pinned, arch.foundation_modulus, false);
    const RitzModel r(m, modes, Topology{true, 0});
    MembraneOptions options = restrained(arch.axial_stiffness);
    options.initial_shape = TrigPolynomial::sine(pi, 0.0, -arch.rise);
    const VonKarmanMembrane membrane(m, r, options);
    const VectorXd load = sine_load(r, arch.load_amplitude);
    for (const auto& [a1, a2, lambda] : {std::tuple{0.3, 0.0, 0.5}, std::tuple{2.0, -1.5, 1.0},
                                         std::tuple{5.0, 0.7, 2.0}, std::tuple{-1.0, 3.0, 0.0}}) {
      VectorXd x = VectorXd::Zero(r.unknowns());
      x[0] = a1 * r_g;
      x[1] = a2 * r_g;
      const double ritz = r.energy(x, 0.0) + membrane.energy(x) - lambda * load.dot(x);
      // The closed form's modal algebra: Pi = (L EI beta^4 r^2 / 4) Pihat.
      const double xi = a1, eta = a2, e = xi * xi + 4 * eta * eta - 2 * alpha * xi;
      const double p = lambda * arch.load_amplitude / (std::pow(pi, 4) * r_g);
      const double pihat = (1 + kappa) * xi * xi + (16 + kappa) * eta * eta + e * e / 8 - 2 * p * xi;
      const double pi_closed = std::pow(pi, 4) * r_g * r_g / 4 * pihat;
      INFO("modes " << modes << ", (xi, eta) = (" << xi << ", " << eta << "), lambda " << lambda);
      CHECK(ritz == Approx(pi_closed).epsilon(1e-13));
      CHECK(ritz == Approx(closed_form::potential_energy(arch, lambda, x[0], x[1], false)).epsilon(1e-13));
      CHECK(-membrane.normal_force(x) == Approx(closed_form::thrust(arch, x[0], x[1])).epsilon(1e-13));
      const MatrixXd h = r.reduced_hessian(x, lambda) + membrane.amplitude_hessian(x);
      CHECK(relative(h.topLeftCorner(2, 2), closed_form::energy_hessian(arch, x[0], x[1])) < 1e-13);
      // The higher sine modes are uncoupled from (A1, A2) at A_3.. = 0 (the pinned ends' cubics,
      // basis.hpp, are not: they are no sine modes).
      for (int j = 2; j < modes; ++j) {
        const std::vector<TrigTerm>& terms = r.basis().w[j].terms();
        if (terms.size() == 1 && terms[0].wave == Wave::sine && terms[0].power == 0)
          CHECK(h.block(j, 0, 1, 2).cwiseAbs().maxCoeff() < 1e-13 * h.cwiseAbs().maxCoeff());
      }
    }
  }
}

TEST_CASE("von Karman Ritz: the sampled half sine converges to the exact one at second order", "[ritz][von_karman]") {
  // w0's table (as a named shape is sampled) against its TrigPolynomial: f_0's error ~ h^2.
  const model::MemberModel straight = beam(EndSupport::pinned, EndSupport::clamped, 10.0, true);
  const RitzModel r(straight, 5, Topology{true, 0});
  MembraneOptions exact = restrained(1e3);
  exact.initial_shape = TrigPolynomial::sine(pi, 0.0, -0.05);
  const VectorXd f_exact = VonKarmanMembrane(straight, r, exact).initial_coupling();
  std::vector<double> errors;
  for (const int samples : {64, 128, 256}) {
    model::MemberModel m = straight;
    for (int i = 0; i <= samples; ++i) {
      m.initial_shape_at.push_back(static_cast<double>(i) / samples);
      m.initial_shape_value.push_back(i == 0 || i == samples ? 0.0 : -0.05 * std::sin(pi * i / samples));
    }
    errors.push_back(relative(VonKarmanMembrane(m, r, restrained(1e3)).initial_coupling(), f_exact));
  }
  INFO("errors " << errors[0] << " " << errors[1] << " " << errors[2]);
  CHECK(errors[2] < 1e-4);
  CHECK(std::log2(errors[0] / errors[1]) == Approx(2.0).margin(0.05));
  CHECK(std::log2(errors[1] / errors[2]) == Approx(2.0).margin(0.05));
}

TEST_CASE("von Karman Ritz: KINSOL on the restrained straight beam under a sine load meets the cubic",
          "[ritz][von_karman]") {
  // (pi^4 EI/L^4 + k + N pi^2/L^2) A = q0, N = EA A^2 pi^2 / (4 L^2): A ~ 3 r, so the membrane
  // carries twice what bending does.
  const double ea = 1e4, k = 10.0, q0 = 10.0;
  for (const bool tensionless : {false, true}) {
    const model::MemberModel m = beam(EndSupport::pinned, EndSupport::pinned, k, tensionless);
    const RitzModel r(m, 8, Topology{true, 0});
    const VonKarmanMembrane membrane(m, r, restrained(ea));
    const VectorXd load = sine_load(r, q0);
    // The cubic's one real root (it is increasing), by Newton from the linear answer.
    const double c1 = std::pow(pi, 4) + k, c3 = ea * std::pow(pi, 4) / 4;
    double amplitude = q0 / c1;
    for (int i = 0; i < 100; ++i)
      amplitude -= (c3 * std::pow(amplitude, 3) + c1 * amplitude - q0) / (3 * c3 * amplitude * amplitude + c1);
    REQUIRE(c3 * std::pow(amplitude, 3) + c1 * amplitude == Approx(q0).epsilon(1e-15));

    VectorXd x = *r.minimiser_for_limits(VectorXd(0), 0.0);
    x[0] = q0 / c1;  // the linear answer
    const nonlinear::NewtonSummary summary = nonlinear::solve_newton(
        [&](const VectorXd& y, VectorXd& f) {
          r.residual(y, 0.0, f);
          f -= load;
          membrane.add_to_residual(y, f);
          return true;
        },
        [&](const VectorXd& y, const VectorXd&, MatrixXd& J) {
          r.jacobian(y, 0.0, J);
          membrane.add_to_jacobian(y, J);
          return true;
        },
        x);
    INFO(summary.brief_report());
    REQUIRE(summary.is_usable());
    CHECK(x[0] == Approx(amplitude).epsilon(1e-13));
    CHECK(x.tail(r.modes() - 1).cwiseAbs().maxCoeff() < 1e-13 * amplitude);  // w is the first mode alone
    CHECK(membrane.normal_force(x) == Approx(ea * amplitude * amplitude * pi * pi / 4).epsilon(1e-13));
    CHECK(amplitude < 0.5 * q0 / c1);  // well beyond linear theory
  }
}

TEST_CASE("von Karman Ritz: KINSOL on the sinusoidal shallow arch meets its symmetric path and bifurcated branch",
          "[ritz][von_karman]") {
  // a / r = 5 on kappa = 2 (bilateral): the bifurcation precedes the limit point (a / r > sqrt(21)).
  // At 0.8 times the bifurcation load the first root of the symmetric cubic; at a load on the
  // bifurcated branch (unstable for kappa < 4, but a regular root) its (A1, |A2|). Six modes (the
  // pinned ends' cubics among them): the exact solution lies in the span, so to round-off.
  closed_form::ShallowArch arch;
  arch.axial_stiffness = 1e4;
  arch.rise = 5.0 * arch.radius_of_gyration();
  arch.foundation_modulus = 2.0 * std::pow(pi, 4);
  arch.load_amplitude = 30.0;
  const closed_form::ShallowArchAnalysis analysis = closed_form::analyse(arch);
  REQUIRE(analysis.has_bifurcation);
  REQUIRE(analysis.first == closed_form::FirstCritical::unstable_bifurcation);
  const model::MemberModel m = beam(EndSupport::pinned, EndSupport::pinned, arch.foundation_modulus, false);
  const RitzModel r(m, 6, Topology{true, 0});
  MembraneOptions options = restrained(arch.axial_stiffness);
  options.initial_shape = TrigPolynomial::sine(pi, 0.0, -arch.rise);
  const VonKarmanMembrane membrane(m, r, options);
  const VectorXd load = sine_load(r, arch.load_amplitude);
  auto solve = [&](double lambda, VectorXd& x) {
    return nonlinear::solve_newton(
        [&](const VectorXd& y, VectorXd& f) {
          r.residual(y, 0.0, f);
          f -= lambda * load;
          membrane.add_to_residual(y, f);
          return true;
        },
        [&](const VectorXd& y, const VectorXd&, MatrixXd& J) {
          r.jacobian(y, 0.0, J);
          membrane.add_to_jacobian(y, J);
          return true;
        },
        x);
  };
  {
    const double lambda = 0.8 * analysis.first_bifurcation.load;
    const double a1 = closed_form::symmetric_deflections(arch, lambda).front();
    VectorXd x = VectorXd::Zero(r.unknowns());
    x[0] = 0.8 * a1;
    const nonlinear::NewtonSummary summary = solve(lambda, x);
    INFO(summary.brief_report());
    REQUIRE(summary.is_usable());
    CHECK(x[0] == Approx(a1).epsilon(1e-12));
    CHECK(x.tail(r.modes() - 1).cwiseAbs().maxCoeff() < 1e-12 * a1);
    CHECK(-membrane.normal_force(x) == Approx(closed_form::thrust(arch, a1, 0.0)).epsilon(1e-11));
  }
  {
    const double a1 = 0.5 * (analysis.first_bifurcation.deflection + analysis.second_bifurcation.deflection) -
                      0.3 * (analysis.second_bifurcation.deflection - analysis.first_bifurcation.deflection) / 2;
    const double lambda = closed_form::bifurcated_load(arch, a1), a2 = closed_form::bifurcated_asymmetry(arch, a1);
    REQUIRE(a2 > 0.1 * a1);
    VectorXd x = VectorXd::Zero(r.unknowns());
    x[0] = 1.05 * a1;
    x[1] = 0.9 * a2;
    const nonlinear::NewtonSummary summary = solve(lambda, x);
    INFO(summary.brief_report() << "; A1 " << a1 << ", A2 " << a2 << ", lambda " << lambda);
    REQUIRE(summary.is_usable());
    CHECK(x[0] == Approx(a1).epsilon(1e-12));
    CHECK(x[1] == Approx(a2).epsilon(1e-12));
    CHECK(x.tail(r.modes() - 2).cwiseAbs().maxCoeff() < 1e-12 * a1);
    // The thrust there is the second mode's critical load with the foundation (shallow_arch.hpp).
    CHECK(-membrane.normal_force(x) == Approx(4 * pi * pi + arch.foundation_modulus / (4 * pi * pi)).epsilon(1e-11));
  }
}

TEST_CASE("von Karman Ritz: Newton with moving limits on a tensionless foundation converges quadratically",
          "[ritz][von_karman]") {
  // A pinned beam, axially restrained, on a stiff tensionless foundation under a central force:
  // contact in the middle, lift-off toward the pins. From the linear solution (solve_ritz), the
  // membrane's tension (A ~ 3 r) stiffens the beam: the deflection drops and the limits move.
  model::MemberModel m = beam(EndSupport::pinned, EndSupport::pinned, 1e4, true);
  m.loads = {point_force(20.0, 0.5)};
  RitzOptions linear_options;
  linear_options.modes = 24;
  const RitzSolution linear = solve_ritz(m, Topology{false, 2}, {0.2, 0.8}, linear_options);
  REQUIRE(linear.summary.is_usable());
  const RitzModel& r = *linear.model;
  const double ea = 1e5;
  const VonKarmanMembrane membrane(m, r, restrained(ea));
  VectorXd x = linear.unknowns;
  const double linear_crown = r.w(x, 0.5);
  nonlinear::NewtonOptions options;
  options.residual_tolerance = 1e-11;
  options.residual_scale = VectorXd::Constant(r.unknowns(), 1.0 / 20.0);
  options.residual_scale.tail(r.limits()).setConstant(1.0 / linear_crown);
  const nonlinear::NewtonSummary summary = nonlinear::solve_newton(
      [&](const VectorXd& y, VectorXd& f) {
        if (!r.admissible(y)) return false;
        r.residual(y, 1.0, f);
        membrane.add_to_residual(y, f);
        return true;
      },
      [&](const VectorXd& y, const VectorXd&, MatrixXd& J) {
        r.jacobian(y, 1.0, J);
        membrane.add_to_jacobian(y, J);
        return true;
      },
      x, options);
  INFO(summary.brief_report());
  REQUIRE(summary.is_usable());
  const double crown = r.w(x, 0.5), n = membrane.normal_force(x);
  INFO("linear crown " << linear_crown << ", crown " << crown << ", N " << n << ", limits " << x[r.limit_offset()]
                       << " " << x[r.limit_offset() + 1] << " (linear " << linear.unknowns[r.limit_offset()] << " "
                       << linear.unknowns[r.limit_offset() + 1] << ")");
  CHECK(n > 0.0);
  CHECK(crown < linear_crown);
  CHECK(std::abs(x[r.limit_offset()] - linear.unknowns[r.limit_offset()]) > 1e-3);
  // The limit conditions and the contact inequalities hold; the energy is stationary in the
  // limits too (dPi/dt_m = sigma_m k w(t_m)^2 / 2, 0 here) as the membrane adds nothing there.
  const InequalityCheck check = check_inequalities(r, x);
  CHECK(check.violation < 1e-9);
  const VectorXd g = r.gradient(x, 1.0) + membrane.gradient(x);
  CHECK(g.cwiseAbs().maxCoeff() < 1e-9 * 20.0);
  // Quadratic: the last ratios log(r2/r1)/log(r1/r0) above round-off.
  std::vector<double> h;
  for (double value : summary.residual_history)
    if (value > 1e-13) h.push_back(value);
  REQUIRE(h.size() >= 3);
  const std::size_t k = h.size();
  const double order = std::log(h[k - 1] / h[k - 2]) / std::log(h[k - 2] / h[k - 3]);
  INFO("order " << order);
  CHECK(order > 1.7);
}

TEST_CASE("von Karman Ritz: with RitzModel's axial force it is the restrained beam with a prestrain",
          "[ritz][von_karman]") {
  // RitzModel's -N_c e plus Pi_m = EA/(2L) (e - L N_c/EA)^2 - L N_c^2/(2 EA): a temperature rise
  // N_c = EA alpha T on restrained ends, as the header says.
  model::MemberModel plain = beam(EndSupport::clamped, EndSupport::pinned, 80.0, true);
  plain.initial_shape_at = {0.0, 0.3, 0.7, 1.0};
  plain.initial_shape_value = {0.0, -0.02, -0.01, 0.0};
  model::MemberModel heated = plain;
  heated.axial_dead = 6.0;
  const RitzModel r_plain(plain, 8, Topology{true, 1}), r_heated(heated, 8, Topology{true, 1});
  const double ea = 5e3;
  const VonKarmanMembrane membrane(heated, r_heated, restrained(ea));
  VectorXd x(r_heated.unknowns());
  for (int i = 0; i < r_heated.modes(); ++i) x[i] = 0.015 * std::cos(0.3 + 1.7 * i) / (1 + i);
  x[r_heated.limit_offset()] = 0.45;
  const double e = membrane.stretch(x), nc = heated.axial_dead;
  const double expected = r_plain.energy(x, 0.0) + 0.5 * ea * std::pow(e - nc / ea, 2) - nc * nc / (2 * ea);  // L = 1
  CHECK(r_heated.energy(x, 0.0) + membrane.energy(x) == Approx(expected).epsilon(1e-13));
}

TEST_CASE("von Karman Ritz: axially free ends carry no membrane force", "[ritz][von_karman]") {
  model::MemberModel m = beam(EndSupport::pinned, EndSupport::free, 40.0, true);
  m.initial_shape_at = {0.0, 1.0};
  m.initial_shape_value = {0.0, -0.1};
  const RitzModel r(m, 6, Topology{true, 1});
  MembraneOptions options;
  options.ends = AxialEnds::free;
  const VonKarmanMembrane membrane(m, r, options);  // no stiffness needed
  VectorXd x = VectorXd::Constant(r.unknowns(), 0.05);
  x[r.limit_offset()] = 0.4;
  CHECK(membrane.stretch(x) != 0.0);
  CHECK(membrane.normal_force(x) == 0.0);
  CHECK(membrane.energy(x) == 0.0);
  CHECK(membrane.gradient(x).isZero(0.0));
  CHECK(membrane.hessian(x).isZero(0.0));
}

TEST_CASE("von Karman Ritz: bad input is refused with a reason", "[ritz][von_karman]") {
  const model::MemberModel m = beam(EndSupport::pinned, EndSupport::pinned, 10.0, true);
  const RitzModel r(m, 4, Topology{true, 0});
  CHECK_THROWS_WITH(VonKarmanMembrane(m, r, MembraneOptions{}), Catch::Contains("membrane_stiffness"));
  CHECK_THROWS_WITH(VonKarmanMembrane(m, r, restrained(-1.0)), Catch::Contains("membrane_stiffness"));
  const VonKarmanMembrane membrane(m, r, restrained(1.0));
  CHECK_THROWS_WITH(membrane.energy(VectorXd::Zero(3)), Catch::Contains("expected 4"));
}
