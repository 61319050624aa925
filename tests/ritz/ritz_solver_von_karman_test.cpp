// solve_ritz on von Karman beams (issue 16, item 3): the membrane term carried by RitzModel when
// the MemberModel says theory = von_karman, against verification/closed_form/shallow_arch.hpp.
//
// The sinusoidal shallow arch: L = 1, EI = 1, pinned ends axially restrained, w0 = -a sin(pi s)
// (initial_sine over the whole member, kept exact), EA = 1e4 (r = 0.01), a / r = 3.5, so that the
// symmetric path has a limit point and no bifurcation point (a / r < sqrt(16 + kappa)). The load
// q0 sin(pi s) is a sine load (model::LoadKind::sine), integrated exactly into the Ritz load
// vector: q0 on the first mode and round-off on the others, so the Ritz problem is the closed
// form's two-mode problem, and the answers agree to the Newton tolerance and the conditioning
// near the limit point, not to a discretisation error. (It used to be a scaled piecewise linear
// interpolant on 64 pieces, exact to round-off too for fewer than 127 modes by aliasing: the
// tolerances, set by Newton's, do not change.)
#include <Eigen/Dense>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <vector>

#include "closed_form/shallow_arch.hpp"
#include "ritz/ritz_model.hpp"
#include "ritz/ritz_solver.hpp"
#include "ritz/von_karman_membrane.hpp"

using namespace liftoff;
using namespace liftoff::ritz;
using Eigen::VectorXd;
using model::EndSupport;

namespace {

constexpr double pi = std::numbers::pi;
constexpr double membrane_stiffness = 1e4;  // EA l^2 / EI; r = 0.01
constexpr double relative_rise = 3.5;       // a / r
constexpr int modes = 16;

model::MemberLoad uniform(double from, double to, double value, double slope) {
  model::MemberLoad l;
  l.kind = model::LoadKind::uniform;
  l.from = from;
  l.to = to;
  l.value = value;
  l.slope = slope;
  return l;
}

// The sine load q0 sin(pi s) over the member.
std::vector<model::MemberLoad> sine_load(double q0) {
  model::MemberLoad l;
  l.kind = model::LoadKind::sine;
  l.from = 0.0;
  l.to = 1.0;
  l.value = q0;
  return {l};
}

model::MemberModel shallow_arch(double k, bool tensionless, double rise) {
  model::MemberModel m;
  m.kind = model::StructureKind::beam;
  m.left = m.right = EndSupport::pinned;
  m.k = k;
  m.tensionless = tensionless;
  m.theory = model::Theory::von_karman;
  m.membrane_stiffness = membrane_stiffness;
  m.initial_sine = model::MemberModel::InitialSine{-rise, 0.0, 1.0};
  m.loads = sine_load(1.0);
  return m;
}

closed_form::ShallowArch reference(double k) {
  closed_form::ShallowArch arch;
  arch.axial_stiffness = membrane_stiffness;
  arch.rise = relative_rise * std::sqrt(1.0 / membrane_stiffness);
  arch.foundation_modulus = k;
  arch.load_amplitude = 1.0;
  return arch;
}

RitzSolution solve(const model::MemberModel& m, double lambda, int n = modes) {
  RitzOptions options;
  options.modes = n;
  options.load_factor = lambda;
  options.newton.residual_tolerance = 1e-12;
  return solve_ritz(m, Topology{true, 0}, {}, options);
}

}  // namespace

TEST_CASE("von Karman Ritz solve: the shallow arch on a bilateral foundation meets the closed form's symmetric path",
          "[ritz][von_karman]") {
  const double k = pi * pi * pi * pi;  // kappa = k / (EI pi^4) = 1
  const closed_form::ShallowArch arch = reference(k);
  const closed_form::ShallowArchAnalysis analysis = closed_form::analyse(arch);
  REQUIRE(analysis.has_limit_points);
  REQUIRE(!analysis.has_bifurcation);
  const double limit_load = analysis.upper_limit.load;
  const model::MemberModel m = shallow_arch(k, false, arch.rise);
  for (const double fraction : {0.1, 0.5, 0.8, 0.95, 0.99}) {
    const double lambda = fraction * limit_load;
    const RitzSolution solution = solve(m, lambda);
    INFO("lambda = " << lambda << ": " << solution.summary.message);
    REQUIRE(solution.summary.is_usable());
    REQUIRE(solution.model->has_membrane());
    // The loading branch is the smallest root: w = A1 sin(pi s) everywhere (the higher modes are
    // unloaded and stay zero on the symmetric path). Compared as w, not amplitude by amplitude:
    // the pinned-pinned basis carries two end-curvature cubics (basis.hpp) that are all but in the
    // sines' span, so single amplitudes are ill-determined at round-off while w is not.
    const double a1 = closed_form::symmetric_deflections(arch, lambda).front();
    const VectorXd& x = solution.unknowns;
    double error = 0.0;
    for (int i = 0; i <= 64; ++i) {
      const double s = i / 64.0;
      error = std::max(error, std::abs(solution.model->w(x, s) - a1 * std::sin(pi * s)));
    }
    INFO("max |w - A1 sin(pi s)| / A1 = " << error / a1);
    // Conditioning: dA1/dlambda grows like (1 - fraction)^(-1/2) near the limit point, and
    // Newton's scaled residual tolerance is 1e-12 of the load: 1e-10 of A1 covers both with room.
    CHECK(error <= 1e-10 * a1);
    // The thrust -N against the closed form's, and the state stable below the limit point.
    const double thrust = closed_form::thrust(arch, a1, 0.0);
    CHECK(std::abs(-solution.model->membrane_force(x) - thrust) <= 1e-8 * std::abs(thrust));
    CHECK(solution.model->stability_margin(x, lambda) > 0.0);
  }
}

TEST_CASE("von Karman Ritz solve: tensionless equals bilateral on the symmetric path (no contact event there)",
          "[ritz][von_karman]") {
  // On the symmetric path w = A1 sin(pi s) >= 0 for every lambda >= 0 (shallow_arch.hpp, item 3):
  // the tensionless arch stays in full contact, with the bilateral answer, up to the limit point.
  const double k = pi * pi * pi * pi;
  const closed_form::ShallowArch arch = reference(k);
  const double limit_load = closed_form::analyse(arch).upper_limit.load;
  for (const double fraction : {0.3, 0.9, 0.99}) {
    const double lambda = fraction * limit_load;
    const RitzSolution bilateral = solve(shallow_arch(k, false, arch.rise), lambda);
    const RitzSolution tensionless = solve(shallow_arch(k, true, arch.rise), lambda);
    REQUIRE(bilateral.summary.is_usable());
    INFO(tensionless.summary.message);
    REQUIRE(tensionless.summary.is_usable());
    REQUIRE(tensionless.model->tensionless());
    CHECK(tensionless.summary.max_violation == 0.0);
    CHECK((tensionless.unknowns - bilateral.unknowns).cwiseAbs().maxCoeff() <=
          1e-14 * bilateral.unknowns.cwiseAbs().maxCoeff());
  }
}

TEST_CASE("von Karman Ritz solve: small loads reproduce the linear answers to second order", "[ritz][von_karman]") {
  SECTION("a straight restrained beam: linear theory, to O(load^2) relative") {
    // w0 = 0: N = EA/(2L) W.K_g W is O(load^2), so W - W_linear is O(load^3).
    model::MemberModel m;
    m.left = m.right = EndSupport::pinned;
    m.k = 100.0;
    m.tensionless = true;
    m.membrane_stiffness = 1e4;
    m.loads = {uniform(0.0, 1.0, 1.0, 0.0)};
    model::MemberModel linear = m;
    m.theory = model::Theory::von_karman;
    double previous = 0.0;
    for (const double lambda : {1e-2, 5e-3, 2.5e-3}) {
      const RitzSolution vk = solve(m, lambda), lin = solve(linear, lambda);
      REQUIRE(vk.summary.is_usable());
      REQUIRE(lin.summary.is_usable());
      REQUIRE(!lin.model->has_membrane());
      const double difference = (vk.unknowns - lin.unknowns).cwiseAbs().maxCoeff() / lin.unknowns.cwiseAbs().maxCoeff();
      CHECK(difference > 0.0);
      CHECK(difference < 1e-2);
      // Halving the load divides the relative difference by 4 (the next term is O(load^4): 1 %).
      if (previous > 0.0) CHECK(previous / difference == Approx(4.0).epsilon(0.01));
      previous = difference;
    }
  }
  SECTION("the shallow arch: its linearisation at W = 0, to O(load^2)") {
    // Linear theory ignores w0 (no axial force); von Karman's linearisation at W = 0 keeps the
    // arch's membrane stiffness (EA/L) f_0 f_0^T: that is the linear answer it must reproduce.
    // minimiser_for_limits solves exactly that linearised problem.
    const double k = pi * pi * pi * pi;
    const closed_form::ShallowArch arch = reference(k);
    const model::MemberModel m = shallow_arch(k, false, arch.rise);
    double previous = 0.0;
    for (const double lambda : {4e-2, 2e-2, 1e-2}) {
      const RitzSolution vk = solve(m, lambda);
      REQUIRE(vk.summary.is_usable());
      const VectorXd linearised = *vk.model->minimiser_for_limits(VectorXd(0), lambda);
      const double difference = (vk.unknowns - linearised).cwiseAbs().maxCoeff();
      CHECK(difference > 0.0);
      if (previous > 0.0) CHECK(previous / difference == Approx(4.0).epsilon(0.02));
      previous = difference;
    }
  }
}

TEST_CASE("von Karman Ritz solve: an axially free end leaves N = 0, linear theory bit for bit", "[ritz][von_karman]") {
  // Nothing holds the member axially when one end slides: u condenses to N = 0 whatever the
  // other end does, so the membrane term is absent and the answers are linear theory's.
  const double k = pi * pi * pi * pi;
  model::MemberModel m = shallow_arch(k, true, reference(k).rise);
  model::MemberModel linear = m;
  linear.theory = model::Theory::linear;
  for (const bool left_free : {true, false}) {
    m.left_axially_restrained = !left_free;
    m.right_axially_restrained = left_free;
    const RitzSolution vk = solve(m, 3.0), lin = solve(linear, 3.0);
    REQUIRE(vk.summary.is_usable());
    REQUIRE(!vk.model->has_membrane());
    CHECK(vk.model->membrane_force(vk.unknowns) == 0.0);
    CHECK(vk.unknowns == lin.unknowns);
  }
}

TEST_CASE("von Karman Ritz solve: the model's membrane term is VonKarmanMembrane's, with the exact half sine",
          "[ritz][von_karman]") {
  const double k = 50.0;
  const model::MemberModel m = shallow_arch(k, true, 0.02);
  const RitzModel with(m, 8, Topology{true, 2});
  model::MemberModel linear = m;
  linear.theory = model::Theory::linear;
  const RitzModel without(linear, 8, Topology{true, 2});
  MembraneOptions options;
  options.membrane_stiffness = membrane_stiffness;
  options.initial_shape = TrigPolynomial::sine(pi, 0.0, -0.02);
  const VonKarmanMembrane membrane(m, without, options);
  VectorXd x = VectorXd::LinSpaced(with.unknowns(), 0.003, -0.002);
  x.tail(2) << 0.3, 0.7;
  const double lambda = 1.7;
  CHECK(with.energy(x, lambda) == Approx(without.energy(x, lambda) + membrane.energy(x)).epsilon(1e-14));
  VectorXd r_with, r_without;
  with.residual(x, lambda, r_with);
  without.residual(x, lambda, r_without);
  CHECK((r_with - r_without - membrane.gradient(x)).cwiseAbs().maxCoeff() <= 1e-14 * r_with.cwiseAbs().maxCoeff());
  Eigen::MatrixXd j_with, j_without;
  with.jacobian(x, lambda, j_with);
  without.jacobian(x, lambda, j_without);
  CHECK((j_with - j_without - membrane.hessian(x)).cwiseAbs().maxCoeff() <= 1e-14 * j_with.cwiseAbs().maxCoeff());
  CHECK((with.reduced_hessian(x, lambda) - without.reduced_hessian(x, lambda) - membrane.amplitude_hessian(x))
            .cwiseAbs()
            .maxCoeff() <= 1e-14 * with.reduced_hessian(x, lambda).cwiseAbs().maxCoeff());
  CHECK(with.membrane_force(x) == Approx(membrane.normal_force(x)).epsilon(1e-14));
}

TEST_CASE("von Karman Ritz solve: an arch under von Karman is refused with the key", "[ritz][von_karman]") {
  model::MemberModel m;
  m.kind = model::StructureKind::arch;
  m.left = m.right = EndSupport::pinned;
  m.k = 10.0;
  m.membrane_stiffness = 1e4;
  m.theory = model::Theory::von_karman;
  const std::optional<Unsupported> refusal = unsupported_input(m);
  REQUIRE(refusal);
  CHECK(refusal->key == "structure.theory");
  CHECK_THROWS_AS(RitzModel(m, 4, Topology{true, 0}), std::invalid_argument);
}
