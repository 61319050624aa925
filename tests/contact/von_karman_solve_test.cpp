// The FE von Karman beam with tensionless contact at a fixed load (contact/von_karman_solve.hpp):
// closed forms (the flat beam's cubic, the sinusoidal shallow arch's symmetric path) at order 4,
// Newton's quadratic convergence from its history, tensionless against bilateral around the first
// lift-off, the linear `fast` answer as the small-load limit, and a start beyond a limit point.
#include "contact/von_karman_solve.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <vector>

#include "closed_form/shallow_arch.hpp"
#include "contact/active_set_solver.hpp"
#include "fe/discretisation.hpp"
#include "fe/shape_functions.hpp"

using namespace liftoff;
using contact::VonKarmanOptions;
using contact::VonKarmanResult;
using contact::VonKarmanSystem;
using contact::VonKarmanTermination;
using Eigen::VectorXd;

namespace {

const double pi = M_PI, pi4 = M_PI * M_PI * M_PI * M_PI;

// A pinned beam of unit length, both ends axially restrained, von Karman, initial shape
// w0 = -rise sin(pi s) (rise > 0: a hump away from the foundation; 0: straight).
model::MemberModel member(double k, bool tensionless, double membrane_stiffness, double rise = 0.0) {
  model::MemberModel m;
  m.kind = model::StructureKind::beam;
  m.theory = model::Theory::von_karman;
  m.membrane_stiffness = membrane_stiffness;
  m.k = k;
  m.tensionless = tensionless;
  if (rise != 0.0) m.initial_sine = model::MemberModel::InitialSine{-rise, 0.0, 1.0};
  return m;
}

// The consistent load of q0 sin(pi s) on the unknowns (5-point rule per element: error ~ h^10).
VectorXd sine_load(const fe::Discretisation& d, const VonKarmanSystem& system, double q0) {
  VectorXd f = VectorXd::Zero(system.unknowns());
  for (int e = 0; e < d.mesh.elements(); ++e) {
    const double s0 = d.mesh.nodes[e], h = d.mesh.element_size(e);
    const std::vector<int> dofs = d.element_dofs(e);
    for (const fe::GaussPoint& point : fe::gauss5) {
      const Eigen::Vector4d shape = fe::hermite_cubic(point.xi, h).value;
      const double q = q0 * std::sin(pi * (s0 + point.xi * h)) * point.weight * h;
      for (int i = 0; i < 4; ++i)
        if (d.equation_of_dof[dofs[i]] >= 0) f[d.equation_of_dof[dofs[i]]] += q * shape[i];
    }
  }
  return f;
}

// The real root of EA (pi^4 / 4) A^3 + (pi^4 + k) A = q0 (increasing in A: bisection to the last bit).
double flat_amplitude(double ea, double k, double q0) {
  auto f = [&](double a) { return ea * pi4 / 4 * a * a * a + (pi4 + k) * a - q0; };
  double lo = -std::abs(q0) / (pi4 + k), hi = std::abs(q0) / (pi4 + k);
  for (int i = 0; i < 200 && hi - lo > 0; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (mid == lo || mid == hi) break;
    (f(mid) < 0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double midspan(const VonKarmanResult& r) { return r.w[r.w.size() / 2]; }

// Newton's order near the root from a residual history (the last three residuals above the floor).
double final_order(const std::vector<double>& history, double floor) {
  std::vector<double> above;
  for (double r : history)
    if (r > floor) above.push_back(r);
  if (above.size() < 3) return 2.0;
  const double r0 = above[above.size() - 3], r1 = above[above.size() - 2], r2 = above.back();
  return std::log(r2 / r1) / std::log(r1 / r0);
}

// The residuals of the last contact set's Newton iteration, its converged residual last.
std::vector<double> last_set_residuals(const VonKarmanResult& r) {
  std::vector<double> out;
  const int last = r.contact_sets - 1;
  for (const auto& it : r.history)
    if (it.contact_set == last) out.push_back(it.residual);
  out.push_back(r.set_residuals.back());
  return out;
}

}  // namespace

TEST_CASE("von Karman solve: a restrained beam lifted off its tensionless foundation meets the cubic, at order 4",
          "[contact][von_karman]") {
  // The load pulls away from the foundation: every node lifts, and the beam is the flat beam of
  // the element test with k = 0: EA (pi^4 / 4) A^3 + pi^4 A = -q0.
  const double ea = 1e4, k = 100.0, q0 = (2 * pi4) * 2.0 / std::sqrt(ea);
  const double exact = flat_amplitude(ea, 0.0, -q0);
  std::vector<double> errors;
  for (int n : {4, 8, 16, 32}) {
    const model::MemberModel m = member(k, true, ea);
    const fe::Discretisation d = fe::discretise(m, n);
    const VonKarmanSystem system(m, d);
    const VonKarmanResult r = system.solve(sine_load(d, system, -q0), VonKarmanOptions{});
    CAPTURE(n, r.message, r.contact_sets, r.history.size());
    REQUIRE(r.is_usable());
    CHECK(std::none_of(r.in_contact.begin(), r.in_contact.end(), [](bool c) { return c; }));
    CHECK(r.reaction.lpNorm<Eigen::Infinity>() == 0.0);
    CHECK(r.stable);
    // Tension: N = EA pi^2 A^2 / 4 on every element (constant along the member: no locking).
    for (double force : r.normal_force) CHECK(force == Approx(ea * pi * pi * exact * exact / 4).epsilon(1e-2));
    errors.push_back(std::abs(midspan(r) - exact) / std::abs(exact));
  }
  for (std::size_t i = 0; i + 1 < errors.size(); ++i) {
    const double order = std::log2(errors[i] / errors[i + 1]);
    CAPTURE(i, errors[i], errors[i + 1], order);
    CHECK(order > 3.8);
    CHECK(order < 4.2);
  }
}

TEST_CASE("von Karman solve: Newton converges quadratically near the solution (the iteration history)",
          "[contact][von_karman]") {
  const double ea = GENERATE(1e2, 1e4, 1e6);
  const double k = 100.0, q0 = (2 * pi4 + k) * 2.0 / std::sqrt(ea);
  const model::MemberModel m = member(k, false, ea);
  const fe::Discretisation d = fe::discretise(m, 16);
  const VonKarmanSystem system(m, d);
  const VonKarmanResult r = system.solve(sine_load(d, system, q0), VonKarmanOptions{});
  CAPTURE(ea, r.message);
  REQUIRE(r.is_usable());
  // The final residual is the round-off floor; above 1e4 times it the residuals are Newton's own.
  const std::vector<double> residuals = last_set_residuals(r);
  const double floor = 1e4 * residuals.back();
  CAPTURE(residuals);
  CHECK(residuals.size() <= 10);
  CHECK(final_order(residuals, floor) >= 1.5);  // 1.76 here: the last pair is pre-asymptotic
  // |R_{i+1}| <= c |R_i|^2 over the last steps (nondimensional forces, EI = L = 1: c ~ 0.2 here, the
  // same for every EA, since w scales with 1 / sqrt(EA) and the residuals agree); a linear rate of
  // 0.1 from 1e-3 would give c = 100.
  int quadratic_steps = 0;
  for (std::size_t i = 0; i + 1 < residuals.size(); ++i)
    if (residuals[i] < 1e-2 && residuals[i + 1] > floor) {
      CAPTURE(i, residuals[i], residuals[i + 1]);
      CHECK(residuals[i + 1] <= 1.0 * residuals[i] * residuals[i]);
      ++quadratic_steps;
    }
  CHECK(quadratic_steps >= 1);
  // Every step taken near the answer is the full, unshifted Newton step.
  CHECK(r.history.back().step == 1.0);
  CHECK(r.history.back().shift == 0.0);
}

TEST_CASE("von Karman solve: a sinusoidal shallow arch on a bilateral foundation meets the symmetric path, at order 4",
          "[contact][von_karman]") {
  closed_form::ShallowArch arch;
  arch.axial_stiffness = 1e4;  // r = 0.01
  arch.rise = 4.0 * arch.radius_of_gyration();
  arch.foundation_modulus = 2.0 * pi4;  // kappa = 2: limit points (a / r > 2 sqrt 3), no bifurcation (a / r < sqrt 18)
  arch.load_amplitude = 1.0;
  const auto analysis = closed_form::analyse(arch);
  REQUIRE(analysis.has_limit_points);
  REQUIRE_FALSE(analysis.has_bifurcation);
  for (double fraction : {0.3, 0.9}) {
    const double lambda = fraction * analysis.upper_limit.load;
    const double exact = closed_form::symmetric_deflections(arch, lambda).front();
    std::vector<double> errors;
    for (int n : {4, 8, 16, 32}) {
      const model::MemberModel m = member(arch.foundation_modulus, false, arch.axial_stiffness, arch.rise);
      const fe::Discretisation d = fe::discretise(m, n);
      const VonKarmanSystem system(m, d);
      const VonKarmanResult r = system.solve(sine_load(d, system, lambda * arch.load_amplitude), VonKarmanOptions{});
      CAPTURE(fraction, n, r.message, r.history.size());
      REQUIRE(r.is_usable());
      CHECK(r.stable);
      errors.push_back(std::abs(midspan(r) - exact) / exact);
    }
    for (std::size_t i = 0; i + 1 < errors.size(); ++i) {
      const double order = std::log2(errors[i] / errors[i + 1]);
      CAPTURE(fraction, i, errors[i], errors[i + 1], order);
      CHECK(order > 3.8);
      CHECK(order < 4.2);
    }
  }
}
