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

namespace {

// A restrained beam on k = 100 under a dead load pressing it on (50 on the whole span) and a live
// load lifting its right half (50 lambda upward there): every node in contact at small lambda,
// the right half lifting beyond some lambda.
model::MemberModel lifting_beam(bool tensionless) {
  model::MemberModel m = member(100.0, tensionless, 1e4);
  model::MemberLoad dead, live;
  dead.kind = live.kind = model::LoadKind::uniform;
  dead.value = 50.0, dead.from = 0.0, dead.to = 1.0, dead.load_case = model::LoadCase::dead;
  live.value = -50.0, live.from = 0.5, live.to = 1.0;
  m.loads = {dead, live};
  return m;
}

// w at xi in element e (Hermite), from the nodal w and w'.
double w_at(const fe::Discretisation& d, const VonKarmanResult& r, int e, double xi) {
  const Eigen::Vector4d shape = fe::hermite_cubic(xi, d.mesh.element_size(e)).value;
  return shape[0] * r.w[e] + shape[1] * r.theta[e] + shape[2] * r.w[e + 1] + shape[3] * r.theta[e + 1];
}

}  // namespace

TEST_CASE("von Karman solve: tensionless is bilateral below the first lift-off, and differs beyond it",
          "[contact][von_karman]") {
  const model::MemberModel bilateral_model = lifting_beam(false), tensionless_model = lifting_beam(true);
  const fe::Discretisation bd = fe::discretise(bilateral_model, 32), td = fe::discretise(tensionless_model, 32);
  const VonKarmanSystem bilateral(bilateral_model, bd), tensionless(tensionless_model, td);
  for (double lambda : {0.5, 3.0}) {
    const VonKarmanResult b = bilateral.solve(lambda, VonKarmanOptions{});
    const VonKarmanResult t = tensionless.solve(lambda, VonKarmanOptions{});
    CAPTURE(lambda, b.message, t.message);
    REQUIRE(b.is_usable());
    REQUIRE(t.is_usable());
    CHECK(t.stable);
    const double largest_w = b.w.cwiseAbs().maxCoeff(), largest_r = b.reaction.cwiseAbs().maxCoeff();
    if (b.reaction.minCoeff() > 0.0) {
      // Below the event: the bilateral answer pulls nowhere, so it is the tensionless one (same set,
      // same iterates: equal to round-off).
      CHECK(lambda == 0.5);
      CHECK(std::all_of(t.in_contact.begin(), t.in_contact.end(), [](bool c) { return c; }));
      CHECK((t.x - b.x).lpNorm<Eigen::Infinity>() <= 1e-12 * b.x.lpNorm<Eigen::Infinity>());
      continue;
    }
    CHECK(lambda == 3.0);
    // Beyond it: the bilateral answer pulls; the tensionless one meets every inequality at every
    // reaction node (r >= 0, gap >= 0, r gap = 0 to round-off) and is another answer.
    CHECK(b.reaction.minCoeff() < -1e-3 * largest_r);
    CHECK(std::count(t.in_contact.begin(), t.in_contact.end(), false) >= 4);
    const double r_scale = t.reaction.cwiseAbs().maxCoeff(), w_scale = t.w.cwiseAbs().maxCoeff();
    CHECK(t.reaction.minCoeff() >= -1e-12 * r_scale);
    CHECK(t.gap.minCoeff() >= -1e-12 * w_scale);
    CHECK(t.reaction.cwiseProduct(t.gap).cwiseAbs().maxCoeff() <= 1e-12 * r_scale * w_scale);
    CHECK((t.w - b.w).cwiseAbs().maxCoeff() > 0.02 * largest_w);  // 5 % here, round-off 1e-12
    // At samples: the reaction (hat functions of r >= 0) cannot pull; where an element and its
    // neighbours are lifted (no reaction at their nodes) the beam stays off the foundation, w <= 0.
    int lifted_samples = 0;
    for (int e = 1; e + 1 < td.mesh.elements(); ++e) {
      const auto ends = td.element_reactions(e), before = td.element_reactions(e - 1),
                 after = td.element_reactions(e + 1);
      if (t.reaction[ends[0]] != 0.0 || t.reaction[ends[1]] != 0.0 || t.reaction[before[0]] != 0.0 ||
          t.reaction[after[1]] != 0.0)
        continue;
      for (int k = 0; k <= 8; ++k) {
        CHECK(w_at(td, t, e, k / 8.0) <= 0.0);
        ++lifted_samples;
      }
    }
    CHECK(lifted_samples > 0);
  }
}

TEST_CASE("von Karman solve: small loads reproduce the linear FE answer (`fast`) to O(load^2)",
          "[contact][von_karman]") {
  // A straight restrained beam on a stiff tensionless foundation under a central point force: the
  // deflection's lobes lift off near the ends. Linear theory ignores the membrane; von Karman adds
  // N ~ EA w^2 and a force N w'' ~ w^3: relative differences fall like the load squared.
  model::MemberModel m = member(1e4, true, 1e4);
  model::MemberLoad force;
  force.kind = model::LoadKind::force;
  force.at = 0.5;
  force.value = 1.0;
  m.loads = {force};
  const fe::Discretisation d = fe::discretise(m, 40);
  const VonKarmanSystem system(m, d);
  std::vector<double> departure;
  for (double p : {3.0, 1.5, 0.75}) {
    const contact::ActiveSetResult linear = contact::solve_active_set(d, p * d.load(1.0), contact::ActiveSetOptions{});
    REQUIRE(linear.summary.is_usable());
    const VonKarmanResult r = system.solve(p, VonKarmanOptions{});
    CAPTURE(p, r.message);
    REQUIRE(r.is_usable());
    CHECK(r.in_contact == linear.in_contact);
    CHECK(std::count(r.in_contact.begin(), r.in_contact.end(), false) >= 2);
    const VectorXd w = r.x.head(d.equations);
    departure.push_back((w - linear.state.displacement).lpNorm<Eigen::Infinity>() /
                        linear.state.displacement.lpNorm<Eigen::Infinity>());
  }
  CAPTURE(departure);
  CHECK(departure[0] < 0.05);
  for (std::size_t i = 0; i + 1 < departure.size(); ++i)
    CHECK(std::log2(departure[i] / departure[i + 1]) == Approx(2.0).margin(0.05));
}

namespace {

// The one-mode state w = A sin(pi s) of the arch w0 = -rise sin(pi s) on the unknowns, with the u
// that makes the membrane strain constant: u' = eps - w0' w' - w'^2 / 2 (the element test's).
VectorXd one_mode(const fe::Discretisation& d, const VonKarmanSystem& system, double amplitude, double rise) {
  VectorXd x = VectorXd::Zero(system.unknowns());
  for (int node = 0; node < static_cast<int>(d.mesh.nodes.size()); ++node) {
    const double s = d.mesh.nodes[node];
    const int w = d.equation_of_dof[d.deflection_dof(node)], slope = d.equation_of_dof[d.slope_dof(node)],
              u = system.axial_unknown(node);
    if (w >= 0) x[w] = amplitude * std::sin(pi * s);
    if (slope >= 0) x[slope] = amplitude * pi * std::cos(pi * s);
    if (u >= 0) x[u] = -(pi / 4) * (amplitude * amplitude / 2 - rise * amplitude) * std::sin(2 * pi * s);
  }
  return x;
}

}  // namespace

TEST_CASE("von Karman solve: beyond a limit point the energy line search makes progress where plain Newton does not",
          "[contact][von_karman]") {
  closed_form::ShallowArch arch;  // the arch of the symmetric-path test: limit points, no bifurcation
  arch.axial_stiffness = 1e4;
  arch.rise = 4.0 * arch.radius_of_gyration();
  arch.foundation_modulus = 2.0 * pi4;
  const auto analysis = closed_form::analyse(arch);
  const double lambda_limit = analysis.upper_limit.load;
  const model::MemberModel m = member(arch.foundation_modulus, false, arch.axial_stiffness, arch.rise);
  const fe::Discretisation d = fe::discretise(m, 16);
  const VonKarmanSystem system(m, d);
  VonKarmanOptions plain;
  plain.globalisation = contact::VonKarmanGlobalisation::none;

  SECTION("a load step across the limit point: from the state at 0.99 lambda_L to 1.02 lambda_L") {
    // The only equilibrium at 1.02 lambda_L is the snapped one (one root of the cubic), far from
    // the start; the tangent at the start is nearly singular (the limit point is 1 % away).
    const VonKarmanResult before = system.solve(sine_load(d, system, 0.99 * lambda_limit), VonKarmanOptions{});
    REQUIRE(before.is_usable());
    const double lambda = 1.02 * lambda_limit;
    const std::vector<double> roots = closed_form::symmetric_deflections(arch, lambda);
    REQUIRE(roots.size() == 1);
    const VectorXd load = sine_load(d, system, lambda);
    const VonKarmanResult searched = system.solve(load, VonKarmanOptions{}, before.x);
    const VonKarmanResult newton = system.solve(load, plain, before.x);
    CAPTURE(searched.message, newton.message, searched.history.size(), newton.history.size());
    REQUIRE(searched.is_usable());
    CHECK(searched.stable);
    // The snapped state, to the discretisation's error at n = 16 (order 4: 1e-5 or below here).
    CHECK(std::abs(midspan(searched) - roots.front()) <= 1e-4 * roots.front());
    CHECK(midspan(searched) > 2 * midspan(before));
    // Every step decreased the energy (the line search's guarantee; the Newton steps taken near the
    // answer, where Pi's change is below its round-off, are allowed to leave it equal).
    for (std::size_t i = 0; i + 1 < searched.history.size(); ++i)
      CHECK(searched.history[i + 1].energy <=
            searched.history[i].energy + 1e-13 * std::abs(searched.history[i].energy));
    CHECK(searched.history.size() <= 10);
    // Plain Newton wanders: its full steps overshoot along the near-null direction and come back.
    // Where it ends is chaotic (a last-bit change of the start, e.g. the line search's iterative
    // refinement, turned 100 steps without convergence into 71 steps to the snapped state): the
    // robust claims are that it takes many times the line search's steps, and that it never ends
    // in a wrong `solved` (iteration_limit, or the snapped state).
    CHECK(newton.history.size() >= 5 * searched.history.size());
    if (newton.is_usable()) {
      CHECK(std::abs(midspan(newton) - roots.front()) <= 1e-4 * roots.front());
    } else {
      CHECK(newton.termination == VonKarmanTermination::iteration_limit);
    }
  }

  SECTION("a start at the unstable middle branch: plain Newton stays on it, the line search leaves it") {
    const double lambda = 0.95 * lambda_limit;
    const std::vector<double> roots = closed_form::symmetric_deflections(arch, lambda);
    REQUIRE(roots.size() == 3);
    const VectorXd load = sine_load(d, system, lambda);
    const VectorXd start = one_mode(d, system, roots[1], arch.rise);
    const VonKarmanResult newton = system.solve(load, plain, start);
    const VonKarmanResult searched = system.solve(load, VonKarmanOptions{}, start);
    CAPTURE(newton.message, searched.message, roots[0], roots[1], roots[2], midspan(newton), midspan(searched));
    // Plain Newton converges to the unstable equilibrium and says so (stable = false).
    REQUIRE(newton.is_usable());
    CHECK(std::abs(midspan(newton) - roots[1]) <= 1e-4 * roots[1]);
    CHECK_FALSE(newton.stable);
    // The shifted Newton steps descend off the saddle to a stable state on one of the outer branches.
    REQUIRE(searched.is_usable());
    CHECK(searched.stable);
    const double to_outer =
        std::min(std::abs(midspan(searched) - roots[0]) / roots[0], std::abs(midspan(searched) - roots[2]) / roots[2]);
    CHECK(to_outer <= 1e-4);
    CHECK(std::any_of(searched.history.begin(), searched.history.end(),
                      [](const contact::VonKarmanIteration& it) { return it.shift > 0.0; }));
  }
}

TEST_CASE("von Karman solve: an axially free end carries no membrane force, so the answer is the linear one",
          "[contact][von_karman]") {
  // One end free (N = 0 then, whatever w), or both (u's rigid motion fixed as a gauge): the straight
  // beam is the linear beam, and the tensionless answer is `fast`'s to round-off, with u = -int w'^2 / 2.
  for (const auto& [left, right] : {std::pair{true, false}, std::pair{false, false}}) {
    model::MemberModel m = member(1e4, true, 1e4);
    m.left_axially_restrained = left;
    m.right_axially_restrained = right;
    model::MemberLoad force;
    force.kind = model::LoadKind::force;
    force.at = 0.5;
    force.value = 30.0;  // ten times the largest load of the small-load test: far from linear if restrained
    m.loads = {force};
    const fe::Discretisation d = fe::discretise(m, 40);
    const VonKarmanSystem system(m, d);
    CHECK(system.unknowns() == d.equations + 40);  // 41 nodes, one u fixed: restrained or the gauge
    const VonKarmanResult r = system.solve(1.0, VonKarmanOptions{});
    const contact::ActiveSetResult linear = contact::solve_active_set(d, d.load(1.0), contact::ActiveSetOptions{});
    CAPTURE(left, right, r.message);
    REQUIRE(r.is_usable());
    REQUIRE(linear.summary.is_usable());
    CHECK(r.in_contact == linear.in_contact);
    const double size = linear.state.displacement.lpNorm<Eigen::Infinity>();
    CHECK((r.x.head(d.equations) - linear.state.displacement).lpNorm<Eigen::Infinity>() <= 1e-10 * size);
    for (double n : r.normal_force) CHECK(std::abs(n) <= 1e-8 * 1e4 * size * size);
    CHECK(r.u[0] == 0.0);
    CHECK(r.u[40] < 0.0);  // the free end moves in as the beam bends
  }
}

TEST_CASE("von Karman solve: bad input is refused with a message", "[contact][von_karman]") {
  const model::MemberModel good = member(100.0, true, 1e4);
  const fe::Discretisation d = fe::discretise(good, 8);
  model::MemberModel linear = good;
  linear.theory = model::Theory::linear;
  CHECK_THROWS_AS(VonKarmanSystem(linear, d), std::invalid_argument);
  model::MemberModel no_membrane = good;
  no_membrane.membrane_stiffness = 0.0;
  CHECK_THROWS_AS(VonKarmanSystem(no_membrane, d), std::invalid_argument);
  model::MemberModel axial = good;
  axial.axial_dead = 1.0;
  CHECK_THROWS_AS(VonKarmanSystem(axial, d), std::invalid_argument);
  model::MemberModel arch = good;
  arch.kind = model::StructureKind::arch;
  CHECK_THROWS_AS(VonKarmanSystem(arch, d), std::invalid_argument);
  const VonKarmanSystem system(good, d);
  CHECK_THROWS_AS(system.solve(VectorXd::Zero(3), VonKarmanOptions{}), std::invalid_argument);
  CHECK_THROWS_AS(system.solve(1.0, VonKarmanOptions{}, VectorXd::Zero(2)), std::invalid_argument);
  CHECK_THROWS_AS(system.solve(1.0, VonKarmanOptions{}, {}, std::vector<bool>(2, true)), std::invalid_argument);
  for (auto spoil : std::vector<void (*)(VonKarmanOptions&)>{
           [](VonKarmanOptions& o) { o.max_newton_iterations = 0; },
           [](VonKarmanOptions& o) { o.residual_tolerance = -1.0; }, [](VonKarmanOptions& o) { o.armijo = 0.7; },
           [](VonKarmanOptions& o) { o.sign_tolerance = std::nan(""); },
           [](VonKarmanOptions& o) { o.max_contact_sets = 0; }}) {
    VonKarmanOptions o;
    spoil(o);
    CHECK_THROWS_AS(o.validate(), std::invalid_argument);
    CHECK_THROWS_AS(system.solve(1.0, o), std::invalid_argument);
  }
  CHECK(contact::to_string(VonKarmanTermination::contact_cycling) == "contact_cycling");
}
TEST_CASE("von Karman solve: the primal system's round-off limits the mesh, and a too fine one is not `solved`",
          "[contact][von_karman]") {
  // The error estimate (one more Newton correction) follows the primal K's condition, ~ h^-4:
  // 4e-11 on 200 elements, 1e-7 on 2000, ~4e-2 on 5000 (the answer then wrong in its second
  // digit). The last must end in a termination, never `solved`.
  const model::MemberModel m = lifting_beam(true);
  for (int n : {200, 5000}) {
    const fe::Discretisation d = fe::discretise(m, n);
    const VonKarmanSystem system(m, d);
    const VonKarmanResult r = system.solve(3.0, VonKarmanOptions{});
    CAPTURE(n, r.message, r.error_estimate);
    if (n == 200) {
      REQUIRE(r.is_usable());
      CHECK(r.error_estimate < 1e-9);
    } else {
      CHECK_FALSE(r.is_usable());
    }
  }
}
