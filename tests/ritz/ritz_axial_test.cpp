// The Ritz model under an axial force with an initial shape (issue 15): the P term's analytic
// derivatives against finite differences, its closed-form integrals against the sine basis'
// exact values, the bowed strut's amplitude and the exact piecewise beam-column with lift-off
// (verification/closed_form) with the observed order in modes, and the refusal of an unstable state.
#include <fmt/format.h>

#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <vector>

#include "closed_form/beam_on_foundation.hpp"
#include "ritz/ritz_model.hpp"
#include "ritz/ritz_solver.hpp"

using namespace liftoff;
using namespace liftoff::ritz;
using Eigen::MatrixXd;
using Eigen::VectorXd;
using model::EndSupport;

namespace {

constexpr double pi = std::numbers::pi;

model::MemberLoad load(model::LoadKind kind, double value, double at, model::LoadCase c) {
  model::MemberLoad l;
  l.kind = kind;
  l.value = value;
  l.at = at;
  l.from = 0.0;
  l.to = 1.0;
  l.load_case = c;
  return l;
}

model::MemberModel beam(EndSupport left, EndSupport right, double k, double axial_dead, double axial_live) {
  model::MemberModel m;
  m.kind = model::StructureKind::beam;
  m.left = left;
  m.right = right;
  m.k = k;
  m.axial_dead = axial_dead;
  m.axial_live = axial_live;
  return m;
}

// w0 = amplitude sin(pi s) sampled at n + 1 points (piecewise linear, as a named shape is).
void half_sine_bow(model::MemberModel& m, double amplitude, int n) {
  for (int i = 0; i <= n; ++i) {
    const double s = static_cast<double>(i) / n;
    m.initial_shape_at.push_back(s);
    m.initial_shape_value.push_back(i == 0 || i == n ? 0.0 : amplitude * std::sin(pi * s));
  }
}

double relative(const MatrixXd& a, const MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(b.cwiseAbs().maxCoeff(), 1e-300);
}

}  // namespace

TEST_CASE("Ritz axial: K_g and f_0 are the integrals of phi_i' phi_j' and w0' phi_i'", "[ritz][axial]") {
  // Against Gauss-Legendre (5 points on each piece of w0's table, where w0' is constant): exact
  // for the polynomial parts, 1e-15 for the trig ones on pieces this short.
  model::MemberModel m = beam(EndSupport::pinned, EndSupport::clamped, 10.0, 2.0, 0.0);
  half_sine_bow(m, 0.01, 400);
  const RitzModel r(m, 6, Topology{true, 0});
  const int n = r.modes();
  const double nodes[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831, 0.9061798459386640};
  const double weights[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889, 0.4786286704993665,
                             0.2369268850561891};
  MatrixXd kg = MatrixXd::Zero(n, n);
  VectorXd f0 = VectorXd::Zero(n);
  for (std::size_t p = 0; p + 1 < m.initial_shape_at.size(); ++p) {
    const double a = m.initial_shape_at[p], b = m.initial_shape_at[p + 1];
    const double slope = (m.initial_shape_value[p + 1] - m.initial_shape_value[p]) / (b - a);
    for (int q = 0; q < 5; ++q) {
      const double s = 0.5 * (a + b) + 0.5 * (b - a) * nodes[q], weight = 0.5 * (b - a) * weights[q];
      VectorXd d(n);
      for (int i = 0; i < n; ++i) d[i] = r.w(VectorXd::Unit(r.unknowns(), i), s, 1);
      kg += weight * d * d.transpose();
      f0 += weight * slope * d;
    }
  }
  CHECK(relative(r.geometric_stiffness(), kg) < 1e-12);
  CHECK(relative(r.imperfection_load(), f0) < 1e-12);
}

TEST_CASE("Ritz axial: gradient, Hessian, Jacobian and dR/dlambda match finite differences", "[ritz][axial]") {
  for (const bool enriched : {false, true}) {
    model::MemberModel m = beam(EndSupport::clamped, EndSupport::pinned, 300.0, 3.0, 2.5);
    m.initial_shape_at = {0.0, 0.2, 0.45, 0.6, 1.0};
    m.initial_shape_value = {0.0, -0.01, 0.02, 0.015, 0.0};
    m.loads = {load(model::LoadKind::uniform, 4.0, 0.0, model::LoadCase::dead),
               load(model::LoadKind::force, -7.0, 0.37, model::LoadCase::live)};
    const RitzModel r(m, 7, Topology{true, 2}, enriched ? Enrichment::load_points : Enrichment::none);
    VectorXd x(r.unknowns());
    for (int i = 0; i < r.amplitudes(); ++i) x[i] = 0.01 * std::cos(1.0 + 2.3 * i) / (1 + i);
    x[r.limit_offset()] = 0.31;
    x[r.limit_offset() + 1] = 0.68;
    const double lambda = 0.7;
    REQUIRE(r.axial_force(lambda) == Approx(3.0 + 0.7 * 2.5));
    const int n = r.unknowns();
    VectorXd g_fd(n), g = r.gradient(x, lambda);
    MatrixXd h_fd(n, n), j_fd(n, n), j;
    r.jacobian(x, lambda, j);
    const MatrixXd h = r.hessian(x, lambda);
    for (int i = 0; i < n; ++i) {
      const double step = 1e-6;
      VectorXd plus = x, minus = x;
      plus[i] += step;
      minus[i] -= step;
      g_fd[i] = (r.energy(plus, lambda) - r.energy(minus, lambda)) / (2 * step);
      h_fd.col(i) = (r.gradient(plus, lambda) - r.gradient(minus, lambda)) / (2 * step);
      VectorXd fp, fm;
      r.residual(plus, lambda, fp);
      r.residual(minus, lambda, fm);
      j_fd.col(i) = (fp - fm) / (2 * step);
    }
    // Central differences: truncation ~ step^2 times third derivatives, round-off ~ eps |E| / step.
    INFO("enriched " << enriched);
    CHECK(relative(g, g_fd) < 1e-7);
    CHECK(relative(h, h_fd) < 1e-6);
    CHECK(relative(j, j_fd) < 1e-6);
    VectorXd fp, fm, f;
    r.residual(x, lambda + 1e-5, fp);
    r.residual(x, lambda - 1e-5, fm);
    CHECK(relative(r.residual_lambda_derivative(x), (fp - fm) / 2e-5) < 1e-8);
    // The N terms are there: without them the Jacobian would not depend on lambda.
    MatrixXd j2;
    r.jacobian(x, lambda + 1.0, j2);
    CHECK(relative((j - j2).topLeftCorner(r.modes(), r.modes()), 2.5 * r.geometric_stiffness()) < 1e-12);
    // The reduced Hessian is the Hessian's amplitude block.
    CHECK(relative(r.reduced_hessian(x, lambda), h.topLeftCorner(r.amplitudes(), r.amplitudes())) < 1e-14);
  }
}

TEST_CASE("Ritz axial: a pinned strut bowed into the foundation grows by P a0 / (P_E + K L^2/pi^2 - P)",
          "[ritz][axial]") {
  // Weightless, EI = L = 1, K = 50: P_E = pi^2, critical pi^2 + 50/pi^2 = 14.94 (n = 1). The bow
  // into the foundation keeps the whole member in contact, so the tensionless answer is the
  // bilateral one: w (from w0) = W sin(pi s), W = P a0 / (P_E + K/pi^2 - P).
  for (const bool tensionless : {true, false}) {
    model::MemberModel m = beam(EndSupport::pinned, EndSupport::pinned, 50.0, 10.0, 0.0);
    m.tensionless = tensionless;
    half_sine_bow(m, 0.01, 4000);
    RitzOptions options;
    options.modes = 8;
    const RitzSolution s = solve_ritz(m, Topology{true, 0}, {}, options);
    INFO(s.summary.message);
    REQUIRE(s.summary.is_usable());
    const double exact = 10.0 * 0.01 / (pi * pi + 50.0 / (pi * pi) - 10.0);
    // The table's interpolation error (pi h)^2 / 12 = 5e-8 relative; the other modes vanish.
    CHECK(s.model->w(s.unknowns, 0.5) == Approx(exact).epsilon(2e-7));
    CHECK(std::abs(s.model->w(s.unknowns, 0.25) - exact * std::sin(pi / 4)) < 2e-7 * exact);
    CHECK(s.model->stability_margin(s.unknowns, 1.0) > 0.0);
  }
}

TEST_CASE("Ritz axial: above the critical load the state is refused as unstable", "[ritz][axial]") {
  // Bilateral: critical pi^2 + 50/pi^2 = 14.94 (n = 1), then 4 pi^2 + 50/(4 pi^2) = 40.7 (n = 2).
  // At P = 20 the bowed strut has an equilibrium (K - P K_g + k G is nonsingular) but it is unstable.
  model::MemberModel m = beam(EndSupport::pinned, EndSupport::pinned, 50.0, 20.0, 0.0);
  m.tensionless = false;
  half_sine_bow(m, 0.01, 400);
  RitzOptions options;
  options.modes = 8;
  const RitzSolution s = solve_ritz(m, Topology{true, 0}, {}, options);
  CHECK(s.summary.termination == RitzTermination::unstable_equilibrium);
  CHECK(to_string(s.summary.termination) == "unstable_equilibrium");
  CHECK(s.summary.message.find("critical load") != std::string::npos);
  // Just below the critical load (0.3 % of it): stable, just above: not (the margin changes sign there).
  m.axial_dead = pi * pi + 50.0 / (pi * pi) - 0.05;
  CHECK(solve_ritz(m, Topology{true, 0}, {}, options).summary.is_usable());
  m.axial_dead = pi * pi + 50.0 / (pi * pi) + 0.05;
  CHECK(solve_ritz(m, Topology{true, 0}, {}, options).summary.termination == RitzTermination::unstable_equilibrium);
}

TEST_CASE("Ritz axial: a beam-column with lift-off converges on the exact piecewise solution", "[ritz][axial]") {
  // Pinned-pinned, EI = L = 1, K = 1e4 (beta L = 7.1), a central force, P = 5 (half the Euler
  // load, so every contact set is stable). The exact solution (closed_form::solve_tensionless_auto,
  // independent of liftoff) lifts off near the ends.
  const double k = 1e4, p = 5.0;
  closed_form::BeamProblem exact_problem;
  exact_problem.foundation_modulus = k;
  exact_problem.left = exact_problem.right = closed_form::EndCondition::pinned;
  exact_problem.forces = {{0.5, 1.0}};
  exact_problem.axial_force = p;
  const closed_form::TensionlessResult exact = closed_form::solve_tensionless_auto(exact_problem);
  REQUIRE(exact.status == closed_form::TensionlessStatus::converged);
  REQUIRE(!exact.limits.empty());
  const bool first_in_contact = exact.contact.front().start <= 1e-12;

  model::MemberModel m = beam(EndSupport::pinned, EndSupport::pinned, k, p, 0.0);
  m.loads = {load(model::LoadKind::force, 1.0, 0.5, model::LoadCase::dead)};
  std::vector<double> guess = exact.limits;
  for (double& t : guess) t += 0.01 * (t < 0.5 ? 1 : -1);
  std::vector<double> errors;
  std::vector<int> modes_list = {16, 32, 64, 128};
  for (int modes : modes_list) {
    RitzOptions options;
    options.modes = modes;
    const RitzSolution s = solve_ritz(m, Topology{first_in_contact, static_cast<int>(guess.size())}, guess, options);
    REQUIRE(s.summary.is_usable());
    double error = 0.0;
    for (std::size_t i = 0; i < guess.size(); ++i)
      error = std::max(error, std::abs(s.unknowns[s.model->limit_offset() + static_cast<int>(i)] - exact.limits[i]));
    const double w_error = std::abs(s.model->w(s.unknowns, 0.5) - exact.solution.deflection(0.5)) /
                           std::abs(exact.solution.deflection(0.5));
    fmt::print("beam-column with lift-off, N = {:3d}: limit error {:.3e}, w(L/2) relative error {:.3e}\n", modes, error,
               w_error);
    errors.push_back(std::max(error, 1e-16));
  }
  for (std::size_t i = 1; i < errors.size(); ++i) CHECK(errors[i] < errors[i - 1]);
  const double order = std::log(errors[1] / errors.back()) / std::log(double(modes_list.back()) / modes_list[1]);
  fmt::print("observed order of the limits in modes: {:.2f}\n", order);
  CHECK(order > 2.0);
  CHECK(errors.back() < 1e-4);
}
