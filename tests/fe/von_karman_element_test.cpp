// The von Karman beam / shallow-arch element (fe/von_karman_element.hpp): its tangent is the
// Jacobian of its internal force and its internal force the gradient of its energy (central
// differences, whose truncation error is known exactly: f_int is a cubic, the energy a quartic),
// its limits (zero displacement, rigid motions, the condensed quintic u), and an assembled member
// solved by Newton against closed forms: the flat beam in membrane action and the sinusoidal
// shallow arch, small loads reproducing linear shallow-arch theory.
#include "fe/von_karman_element.hpp"

#include <Eigen/Dense>
#include <Eigen/SparseLU>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "fe/beam_element.hpp"
#include "fe/element.hpp"
#include "fe/shape_functions.hpp"
#include "fe/sparse_assembler.hpp"
#include "nonlinear/linear_solver.hpp"
#include "nonlinear/newton.hpp"
#include "support/element_checks.hpp"

using namespace liftoff;
using namespace liftoff::fe;
using Eigen::VectorXd;

namespace {

constexpr double eps = std::numeric_limits<double>::epsilon();
const double pi = M_PI, pi2 = M_PI * M_PI, pi4 = pi2 * pi2;

using Vector6d = Eigen::Matrix<double, 6, 1>;

// An initial shape w_0 = rise sin(pi s) on the element [s0, s0 + h] (a member of unit length).
von_karman_element::InitialSlopes sine_slopes(double rise, double s0, double h) {
  return von_karman_element::sample_initial_slopes([rise](double s) { return rise * pi * std::cos(pi * s); }, s0, h);
}

VectorXd random_displacement(double scale) {
  VectorXd u = scale * VectorXd::Random(6);
  u.tail<2>() *= scale;  // u ~ w^2, as in membrane action
  return u;
}

// Entry-wise bounds on the sizes that round-off acts on: |f| summed without cancellation
// (force_size) and |K_t| likewise (tangent_size), from the element's parts (header):
// f = [K_b w + N (a_0 + K_g w); -N; N], K_t = [K_b + N K_g, 0; 0, 0] + (EA / h) (h b)(h b)^T.
struct Sizes {
  Vector6d force;
  Eigen::Matrix<double, 6, 6> tangent;
  double energy;
};
Sizes round_off_sizes(double h, double ea, const von_karman_element::InitialSlopes& slopes, const VectorXd& u) {
  const Eigen::Matrix4d kb = beam_element::stiffness(h).cwiseAbs(),
                        kg = beam_element::geometric_stiffness(h).cwiseAbs();
  Eigen::Vector4d a0 = Eigen::Vector4d::Zero();
  for (int q = 0; q < 5; ++q)
    a0 += (gauss5[q].weight * h * std::abs(slopes[q])) * hermite_cubic(gauss5[q].xi, h).d1.cwiseAbs();
  const Eigen::Vector4d w = u.head<4>().cwiseAbs();
  const double strain = (std::abs(u[4]) + std::abs(u[5]) + a0.dot(w) + 0.5 * w.dot(kg * w)) / h;
  Vector6d hb;
  hb << a0 + kg * w, 1.0, 1.0;
  Sizes s;
  s.force = ea * strain * hb;
  s.force.head<4>() += kb * w;
  s.tangent = (ea / h) * hb * hb.transpose();
  s.tangent.topLeftCorner<4, 4>() += kb + ea * strain * kg;
  s.energy = 0.5 * w.dot(kb * w) + 0.5 * ea * h * strain * strain;
  return s;
}

// The third derivative of f_int along e_j, exactly: with w dof j, eps(t) = eps + t b_j +
// t^2 (K_g)_jj / (2h) and h b(t) = h b + t K_g e_j, so f''' = 3 EA ((K_g)_jj / h) K_g e_j on the w
// rows; along a u dof f is quadratic (f''' = 0).
Vector6d third_derivative(double h, double ea, int j) {
  Vector6d d = Vector6d::Zero();
  if (j < 4) {
    const Eigen::Matrix4d kg = beam_element::geometric_stiffness(h);
    d.head<4>() = 3.0 * ea * kg(j, j) / h * kg.col(j);
  }
  return d;
}

}  // namespace

TEST_CASE("von Karman element: K_t is the Jacobian of f_int, to the exact truncation error of central differences",
          "[fe][element][von_karman]") {
  const double h = GENERATE(1.0, 0.05);
  const double ea = GENERATE(1e2, 1e6);
  const double rise = GENERATE(0.0, -0.07);
  const double scale = GENERATE(1e-3, 0.3);
  CAPTURE(h, ea, rise, scale);
  const auto slopes = sine_slopes(rise, 0.4, h);
  const VonKarmanBeamElement element(h, ea, slopes);
  const ElementState state{random_displacement(scale), 0.5};
  const ElementResponse at = element.evaluate(state);
  const Sizes sizes = round_off_sizes(h, ea, slopes, state.displacement);
  // Two step sizes a factor 2 apart. f_int is a cubic in u_e, so the central difference's error is
  // exactly delta^2 / 6 f''' plus round-off: the observed error is the truncation, not a guess.
  const double base = std::ldexp(1.0, -8) * std::max(scale, 1e-2);
  const test::JacobianMisfit misfit = test::tangent_misfit(element, state, at.tangent, base, sizes.force, sizes.tangent,
                                                           [&](int j) { return third_derivative(h, ea, j); });
  CAPTURE(misfit.largest_truncation);
  CHECK(misfit.worst <= 1.0);
  // The check has teeth: somewhere the truncation term is far above the round-off allowance, so a
  // tangent missing it (or anything of its size) would fail.
  if (ea * scale * scale > 1.0) CHECK(misfit.largest_truncation > 10.0);
}

TEST_CASE("von Karman element: K_t symmetric to the last bit, f_int the gradient of the energy",
          "[fe][element][von_karman]") {
  const double h = GENERATE(1.0, 0.05);
  const double ea = GENERATE(1e2, 1e6);
  const double rise = GENERATE(0.0, -0.07, 0.2);
  CAPTURE(h, ea, rise);
  const auto slopes = sine_slopes(rise, 0.1, h);
  const VonKarmanBeamElement element(h, ea, slopes);
  for (double scale : {1e-3, 0.3}) {
    CAPTURE(scale);
    const VectorXd u = random_displacement(scale);
    const ElementResponse at = element.evaluate(ElementState{u, 0.0});
    CHECK(at.tangent == at.tangent.transpose());
    // The energy is a quartic in u_e: Richardson's combination (4 D(delta/2) - D(delta)) / 3 of
    // central differences is exact for it (the error term needs the fifth derivative), so it
    // meets f_int to round-off: a few dozen roundings of the energy's size, over delta.
    const Sizes sizes = round_off_sizes(h, ea, slopes, u);
    const double delta = std::ldexp(1.0, -6) * std::max(scale, 1e-2);
    test::check_energy_gradient(element, u, at.internal_force, delta, sizes.energy, sizes.force);
  }
}

TEST_CASE("von Karman element: at zero displacement the linear beam plus the bar, or the linear shallow arch",
          "[fe][element][von_karman]") {
  const double h = GENERATE(1.0, 0.37, 1e-3);
  const double ea = GENERATE(1e2, 1e6);
  CAPTURE(h, ea);
  const ElementResponse flat = VonKarmanBeamElement(h, ea).evaluate(ElementState{VectorXd::Zero(6), 0.3});
  CHECK(flat.internal_force == Vector6d::Zero());
  Eigen::Matrix<double, 6, 6> expected = Eigen::Matrix<double, 6, 6>::Zero();
  expected.topLeftCorner<4, 4>() = beam_element::stiffness(h);
  expected.bottomRightCorner<2, 2>() << ea / h, -ea / h, -ea / h, ea / h;
  CHECK(flat.tangent == expected);  // every entry the same product or a zero added to it

  // With an initial shape: the linear shallow arch, eps = (u1 - u0)/h + (a_0 . w)/h with
  // a_0 = int w_0' N_w' ds. For w_0 = c s^2 (slope 2 c s, degree 1 <= 7: the rule is exact)
  // a_0 is a closed form: int 2 c s N_w'(s) ds = 2 c [s N_w]_0^h - 2 c int N_w ds
  //   = 2 c (0, 0, h, 0) - 2 c (h/2, h^2/12, h/2, -h^2/12) = c h (-1, -h/6, 1, h/6).
  const double c = 0.3;
  const auto slopes = von_karman_element::sample_initial_slopes([c](double s) { return 2 * c * s; }, 0.0, h);
  const ElementResponse arch = VonKarmanBeamElement(h, ea, slopes).evaluate(ElementState{VectorXd::Zero(6), 0.0});
  Vector6d hb;
  hb << -c * h, -c * h * h / 6, c * h, c * h * h / 6, -1, 1;
  expected = (ea / h) * hb * hb.transpose();
  expected.topLeftCorner<4, 4>() += beam_element::stiffness(h);
  CHECK((arch.tangent - expected).cwiseAbs().maxCoeff() <= 64 * eps * expected.cwiseAbs().maxCoeff());
  CHECK(arch.internal_force == Vector6d::Zero());
}

TEST_CASE("von Karman element: rigid motions (with the second-order shortening of a rotation) carry no force",
          "[fe][element][von_karman]") {
  const double h = GENERATE(1.0, 0.05);
  const double ea = GENERATE(1e2, 1e6);
  const double rise = GENERATE(0.0, -0.07);
  CAPTURE(h, ea, rise);
  const auto slopes = sine_slopes(rise, 0.3, h);
  double mean_slope = 0.0;  // of w_0 over the element, by the element's rule
  for (int q = 0; q < 5; ++q) mean_slope += gauss5[q].weight * slopes[q];
  const VonKarmanBeamElement element(h, ea, slopes);
  for (double rotation : {0.0, 1e-3, 0.1}) {
    const double translation = 0.7, axial = -0.2;
    CAPTURE(rotation);
    // w = c + theta s; in von Karman kinematics a rotation theta shortens the chord by
    // theta^2 / 2 per unit length and tilts the initial shape, so u = u0 - (theta w_0' + theta^2/2) s.
    VectorXd u(6);
    u << translation, rotation, translation + rotation * h, rotation, axial,
        axial - h * (rotation * mean_slope + 0.5 * rotation * rotation);
    const ElementResponse response = element.evaluate(ElementState{u, 0.0});
    const Sizes sizes = round_off_sizes(h, ea, slopes, u);
    CHECK((response.internal_force.cwiseAbs() - 64 * eps * sizes.force).maxCoeff() <= 0.0);
    CHECK(std::abs(element.membrane_strain(u)) <= 64 * eps * (std::abs(axial) + 1.0) / h);
  }
  // Without the shortening the rotation stretches the member: eps = theta^2 / 2.
  VectorXd stretched(6);
  stretched << 0.0, 0.1, 0.1 * h, 0.1, 0.0, 0.0;
  if (rise == 0.0) CHECK(VonKarmanBeamElement(h, ea).membrane_strain(stretched) == Approx(0.005).epsilon(1e-13));
}

TEST_CASE("von Karman element: the membrane energy is that of a quintic u with its interior values condensed",
          "[fe][element][von_karman]") {
  // The header's claim, checked from its definition: u a Lagrange quintic on xi = 0, 1/5, ..., 1,
  // the membrane energy EA/2 sum_q W_q h (u'(xi_q) + w_0' w' + w'^2/2)^2 on the 5-point rule,
  // minimised over the four interior values (a linear least-squares problem), equals the
  // element's EA h eps^2 / 2.
  const double h = GENERATE(1.0, 0.05);
  const double rise = GENERATE(0.0, -0.07);
  CAPTURE(h, rise);
  const double ea = 1e4;
  const auto slopes = sine_slopes(rise, 0.2, h);
  const VonKarmanBeamElement element(h, ea, slopes);
  const VectorXd u = random_displacement(0.2);
  // u'(xi_q) = D.row(q) . (nodal values): the derivative of the Lagrange interpolant.
  Eigen::Matrix<double, 6, 6> vandermonde;
  for (int i = 0; i < 6; ++i)
    for (int p = 0; p < 6; ++p) vandermonde(i, p) = std::pow(i / 5.0, p);
  const Eigen::Matrix<double, 6, 6> to_monomial = vandermonde.inverse();
  Eigen::Matrix<double, 5, 6> derivative;
  Eigen::Matrix<double, 5, 1> g, root_weight;
  for (int q = 0; q < 5; ++q) {
    const double xi = gauss5[q].xi;
    Eigen::Matrix<double, 1, 6> monomial_derivative;
    for (int p = 0; p < 6; ++p) monomial_derivative[p] = p == 0 ? 0.0 : p * std::pow(xi, p - 1) / h;
    derivative.row(q) = monomial_derivative * to_monomial;
    const double slope = hermite_cubic(xi, h).d1.dot(u.head<4>());
    g[q] = slopes[q] * slope + 0.5 * slope * slope;
    root_weight[q] = std::sqrt(gauss5[q].weight * h);
  }
  // Residual at the points, weighted: sqrt(W h) (D_ends u_ends + D_interior v + g).
  const Eigen::Matrix<double, 5, 4> interior = root_weight.asDiagonal() * derivative.middleCols<4>(1);
  const Eigen::Matrix<double, 5, 1> fixed =
      root_weight.asDiagonal() * (derivative.col(0) * u[4] + derivative.col(5) * u[5] + g);
  const Eigen::Vector4d v = interior.colPivHouseholderQr().solve(-fixed);
  const double condensed = 0.5 * ea * (interior * v + fixed).squaredNorm();
  const double strain = element.membrane_strain(u);
  CHECK(condensed == Approx(0.5 * ea * h * strain * strain).epsilon(1e-10));
  // And the minimiser makes the strain the same at every point (so N is constant on the element).
  const Eigen::Matrix<double, 5, 1> pointwise = (interior * v + fixed).cwiseQuotient(root_weight);
  CHECK((pointwise.array() - strain).abs().maxCoeff() <= 1e-10 * (std::abs(strain) + g.cwiseAbs().maxCoeff()));
}

TEST_CASE("von Karman element: bad arguments are refused with a message", "[fe][element][von_karman]") {
  CHECK_THROWS_AS(VonKarmanBeamElement(0.0, 1.0), std::invalid_argument);
  CHECK_THROWS_AS(VonKarmanBeamElement(0.1, -1.0), std::invalid_argument);
  CHECK_THROWS_AS(VonKarmanBeamElement(0.1, std::nan("")), std::invalid_argument);
  von_karman_element::InitialSlopes slopes{};
  slopes[2] = std::numeric_limits<double>::infinity();
  CHECK_THROWS_AS(VonKarmanBeamElement(0.1, 1.0, slopes), std::invalid_argument);
  const VonKarmanBeamElement element(0.1, 1.0);
  CHECK_FALSE(element.is_linear());
  CHECK_THROWS_AS(element.evaluate(ElementState{VectorXd::Zero(4), 0.0}), std::invalid_argument);
  CHECK_THROWS_AS(element.energy(VectorXd::Zero(7)), std::invalid_argument);
  const VectorXd first = random_displacement(0.1);
  const VectorXd second = random_displacement(0.2);
  test::check_response_storage_reused(element, first, second);
}

// ---------------------------------------------------------------------------------------------
// An assembled member: n von Karman elements on [0, 1], pinned ends with u restrained, a bilateral
// Winkler foundation k on the w dofs, the initial shape w_0 = rise sin(pi s), the load
// q0 sin(pi s) (consistent load vector), solved from zero by nonlinear::NewtonSolver over the
// fixed-pattern SparseAssembler and a SparseLu: the path the FE nonlinear model will take (KINSOL,
// the sparse seam, the residual history), which a few lines of Eigen would not exercise.
//
// Closed form (derived here, independent of verification/closed_form). With w = A sin(pi s),
// w_0 = rise sin(pi s) = -a sin(pi s), N constant (no axial load) and u(0) = u(1) = 0:
//   eps = int_0^1 (w_0' w' + w'^2 / 2) ds = pi^2 (A^2 - 2 a A) / 4,   N = EA eps,
// and the transverse equilibrium w'''' - N (w_0'' + w'') + k w = q holds for every s with
//   q0 = (pi^4 + k) A + EA (pi^4 / 4) A (A - a) (A - 2 a):
// the one-mode solution is exact (every term is a multiple of sin(pi s); w = w'' = 0 at the pins).
// Flat (a = 0): N = EA A^2 pi^2 / 4 and (pi^4 + k + N pi^2) A = q0, a cubic in A. Linearised
// about w_0 (the linear shallow arch): N = -EA a pi^2 A / 2 and (pi^4 + k + EA a^2 pi^4 / 2) A = q0.
// ---------------------------------------------------------------------------------------------
namespace {

struct Member {
  int elements = 8;
  double membrane_stiffness = 1e4;
  double foundation_modulus = 100.0;
  double rise = 0.0;  // w_0 = rise sin(pi s): < 0 rises away from the foundation
};

// Node i: w (3i), w' (3i + 1), u (3i + 2). Fixed: w and u at both ends.
class AssembledMember {
 public:
  explicit AssembledMember(const Member& m) : member_(m) {
    const int n = m.elements, dofs = 3 * (n + 1);
    const double h = 1.0 / n;
    std::vector<std::vector<int>> element_dofs;
    for (int e = 0; e < n; ++e) {
      const int a = 3 * e, b = 3 * (e + 1);
      elements_.push_back(
          std::make_unique<VonKarmanBeamElement>(h, m.membrane_stiffness, sine_slopes(m.rise, e * h, h)));
      element_dofs.push_back({a, a + 1, b, b + 1, a + 2, b + 2});
      elements_.push_back(std::make_unique<WinklerElement>(h, m.foundation_modulus));
      element_dofs.push_back({a, a + 1, b, b + 1});
    }
    equation_of_dof_.assign(dofs, -1);
    int equations = 0;
    for (int dof = 0; dof < dofs; ++dof)
      if (dof != 0 && dof != 2 && dof != 3 * n && dof != 3 * n + 2) equation_of_dof_[dof] = equations++;
    assembler_ = std::make_unique<SparseAssembler>(element_dofs, equation_of_dof_);
    // The consistent load of sin(pi s): the 5-point rule per element (error ~ h^10, far below the
    // discretisation's).
    unit_load_ = VectorXd::Zero(equations);
    for (int e = 0; e < n; ++e)
      for (const GaussPoint& point : gauss5) {
        const Eigen::Vector4d shape = hermite_cubic(point.xi, h).value;
        const double q = std::sin(pi * (e + point.xi) * h) * point.weight * h;
        for (int i = 0; i < 4; ++i) {
          const int equation = equation_of_dof_[element_dofs[2 * e][i]];
          if (equation >= 0) unit_load_[equation] += q * shape[i];
        }
      }
  }

  int equations() const { return static_cast<int>(unit_load_.size()); }
  VectorXd all_dofs(const VectorXd& x) const {
    VectorXd u_all = VectorXd::Zero(static_cast<Eigen::Index>(equation_of_dof_.size()));
    for (std::size_t dof = 0; dof < equation_of_dof_.size(); ++dof)
      if (equation_of_dof_[dof] >= 0) u_all[static_cast<Eigen::Index>(dof)] = x[equation_of_dof_[dof]];
    return u_all;
  }
  double midspan(const VectorXd& x) const { return all_dofs(x)[3 * (member_.elements / 2)]; }
  SparseAssembler& assemble(const VectorXd& x) {
    assembler_->assemble(elements_, all_dofs(x), 0.0);
    return *assembler_;
  }
  // The one-mode closed form at the nodes, as a typical size for the residual's scale.
  VectorXd one_mode(double amplitude) const {
    const int n = member_.elements;
    const double a = -member_.rise;
    VectorXd u_all(3 * (n + 1));
    for (int i = 0; i <= n; ++i) {
      const double s = static_cast<double>(i) / n;
      u_all[3 * i] = amplitude * std::sin(pi * s);
      u_all[3 * i + 1] = amplitude * pi * std::cos(pi * s);
      // u' = eps - w_0' w' - w'^2 / 2 = -(pi^2 / 2) (A^2 / 2 - a A) cos(2 pi s).
      u_all[3 * i + 2] = -(pi / 4) * (amplitude * amplitude / 2 - a * amplitude) * std::sin(2 * pi * s);
    }
    VectorXd x(equations());
    for (std::size_t dof = 0; dof < equation_of_dof_.size(); ++dof)
      if (equation_of_dof_[dof] >= 0) x[equation_of_dof_[dof]] = u_all[static_cast<Eigen::Index>(dof)];
    return x;
  }

  struct Solution {
    VectorXd x;
    nonlinear::NewtonSummary summary;
  };
  // Newton from zero for the load q0 sin(pi s). The residual is scaled row by row by
  // |K_t| |x_typ| + |F| at the closed form x_typ of amplitude `typical` (a componentwise backward
  // error), so the tolerance is a few hundred eps whatever EA and h.
  Solution solve(double q0, double typical) {
    const VectorXd load = q0 * unit_load_;
    const VectorXd x_typ = one_mode(typical);
    assemble(x_typ);
    const Eigen::SparseMatrix<double> magnitude = assembler_->tangent().cwiseAbs();
    const VectorXd row_size = magnitude * x_typ.cwiseAbs() + load.cwiseAbs();
    nonlinear::SparseLu lu(equations());
    nonlinear::NewtonSolver newton(lu);
    const nonlinear::Residual residual = [&](const VectorXd& x, VectorXd& f) {
      f = assemble(x).internal_force() - load;
      return true;
    };
    const nonlinear::JacobianFill jacobian = [&](const VectorXd&, const VectorXd&) {
      const auto& tangent = assembler_->tangent();
      if (lu.matrix().nonZeros() == 0)
        lu.matrix() = tangent;
      else
        std::copy(tangent.valuePtr(), tangent.valuePtr() + tangent.nonZeros(), lu.matrix().valuePtr());
      return true;
    };
    nonlinear::NewtonOptions options;
    options.residual_tolerance = 256 * eps;
    options.residual_scale = row_size.cwiseInverse();
    options.max_newton_step = 1e3;
    Solution solution{VectorXd::Zero(equations()), {}};
    // Full Newton steps. KINSOL's line search asks |F| to decrease, and the first step from zero
    // (the linear beam's answer, with u = 0) raises it: the membrane strain w'^2 / 2 is not yet
    // relieved by u. Backtracking then crawls (n = 16, EA = 1e2: no convergence in 50 iterations,
    // against 6 full steps); an energy line search would not have this problem.
    options.globalisation = nonlinear::Globalisation::none;
    solution.summary = newton.solve(residual, jacobian, solution.x, options);
    return solution;
  }
  // The linear problem K_t(0) x = F (one sparse LU).
  VectorXd solve_linear(double q0) {
    const Eigen::SparseMatrix<double> tangent = assemble(VectorXd::Zero(equations())).tangent();
    Eigen::SparseLU<Eigen::SparseMatrix<double>> lu(tangent);
    REQUIRE(lu.info() == Eigen::Success);
    return lu.solve(VectorXd(q0 * unit_load_));
  }

 private:
  Member member_;
  std::vector<std::unique_ptr<const Element>> elements_;
  std::vector<int> equation_of_dof_;
  std::unique_ptr<SparseAssembler> assembler_;
  VectorXd unit_load_;
};

// Newton's order of convergence near the root, from the residual history: the last three
// residuals above the round-off floor (1e-13, the tolerance being 256 eps), r0 > r1 > r2, give
// p = log(r2 / r1) / log(r1 / r0) (quadratic: ~2; a wrong tangent: ~1). Histories too short for
// three such residuals (Newton converging in two steps) give 2.
double final_order(const std::vector<double>& history) {
  std::vector<double> above;
  for (double r : history)
    if (r > 1e-13) above.push_back(r);
  if (above.size() < 3) return 2.0;
  const double r0 = above[above.size() - 3], r1 = above[above.size() - 2], r2 = above.back();
  return std::log(r2 / r1) / std::log(r1 / r0);
}

// The real root of EA (pi^4 / 4) A^3 + (pi^4 + k) A - q0 = 0 (one, the cubic being increasing),
// by Cardano without cancellation: A^3 + p A + r = 0 with p > 0, t = cbrt(-r/2 + sqrt(r^2/4 +
// p^3/27)), b = p / (3 t), A = t - b = (t^3 - b^3) / (t^2 + t b + b^2) = -r / (t^2 + p/3 + b^2).
double flat_amplitude(double ea, double k, double q0) {
  const double leading = ea * pi4 / 4, p = (pi4 + k) / leading, r = -q0 / leading;
  const double t = std::cbrt(-r / 2 + std::sqrt(r * r / 4 + p * p * p / 27)), b = p / (3 * t);
  return -r / (t * t + p / 3 + b * b);
}

// The load of the one-mode solution of amplitude A on the arch w_0 = -a sin(pi s).
double arch_load(double ea, double k, double a, double amplitude) {
  return (pi4 + k) * amplitude + ea * pi4 / 4 * amplitude * (amplitude - a) * (amplitude - 2 * a);
}

}  // namespace

TEST_CASE(
    "von Karman elements, assembled: a pinned beam with restrained ends in membrane action meets the closed "
    "form w = A sin(pi s), converging like h^4 whatever EA (no locking)",
    "[fe][element][von_karman][newton]") {
  const double k = 100.0;
  std::vector<std::vector<double>> errors;  // by EA, by n
  for (double ea : {1e2, 1e3, 1e4, 1e5, 1e6}) {
    // The load whose answer has N pi^2 = pi^4 (the tension doubles the bending stiffness): A = 2 /
    // sqrt(EA); the cubic's root must give it back.
    const double target = 2.0 / std::sqrt(ea), q0 = (2 * pi4 + k) * target;
    const double exact = flat_amplitude(ea, k, q0);
    CAPTURE(ea, q0, exact);
    CHECK(std::abs(exact - target) <= 16 * eps * target);
    CHECK(ea * exact * exact * pi2 / 4 == Approx(pi2).epsilon(1e-13));
    std::vector<double> error;
    for (int n : {4, 8, 16, 32}) {
      AssembledMember member({n, ea, k, 0.0});
      const auto solution = member.solve(q0, exact);
      CAPTURE(n, solution.summary.brief_report());
      REQUIRE(solution.summary.is_usable());
      CHECK(solution.summary.iterations <= 8);
      CHECK(final_order(solution.summary.residual_history) >= 1.5);
      error.push_back(std::abs(member.midspan(solution.x) - exact) / exact);
    }
    errors.push_back(error);
  }
  for (std::size_t m = 0; m < errors.size(); ++m)
    for (std::size_t i = 0; i + 1 < errors[m].size(); ++i) {
      const double order = std::log2(errors[m][i] / errors[m][i + 1]);
      CAPTURE(m, i, errors[m][i], errors[m][i + 1], order);
      CHECK(order > 3.8);
      CHECK(order < 4.2);
    }
  // No locking: scaled by A = 2 / sqrt(EA) the discrete problems are the same for every EA (u
  // condenses to one N for the member), so the relative errors agree to the solve's round-off;
  // an element with a locking membrane would see them grow with EA.
  for (std::size_t m = 1; m < errors.size(); ++m)
    for (std::size_t i = 0; i < errors[m].size(); ++i) {
      CAPTURE(m, i, errors[0][i], errors[m][i]);
      CHECK(std::abs(errors[m][i] - errors[0][i]) <= 1e-6 * errors[0][i]);
    }
}

TEST_CASE(
    "von Karman elements, assembled: a sinusoidal shallow arch meets the linear shallow arch at small loads and "
    "the one-mode closed form beyond",
    "[fe][element][von_karman][newton]") {
  const double k = 100.0, ea = 1e4, a = 0.05;  // w_0 = -a sin(pi s): a hump away from the foundation
  // Linear shallow-arch theory: A = q0 / (pi^4 + k + EA a^2 pi^4 / 2).
  const double linear_stiffness = pi4 + k + ea * a * a * pi4 / 2;
  std::vector<double> linear_error, moderate_error;
  for (int n : {4, 8, 16, 32}) {
    CAPTURE(n);
    AssembledMember member({n, ea, k, -a});
    // K_t(0): the FE linear shallow arch, against the closed form.
    const double q_small = 1e-3 * linear_stiffness * a;
    const double linear = member.midspan(member.solve_linear(q_small));
    linear_error.push_back(std::abs(linear - q_small / linear_stiffness) / (q_small / linear_stiffness));
    // Small loads: the nonlinear answer tends to the linear one, the difference falling like the
    // load (the one-mode closed form's first nonlinear term is -3 a EA (pi^4/4) A^2, of relative size
    // ~ A / a).
    std::vector<double> departure;
    for (double fraction : {1e-2, 1e-3, 1e-4}) {
      const double q0 = fraction * linear_stiffness * a;
      const auto solution = member.solve(q0, q0 / linear_stiffness);
      CAPTURE(fraction, solution.summary.brief_report());
      REQUIRE(solution.summary.is_usable());
      const double linear_answer = member.midspan(member.solve_linear(q0));
      departure.push_back(std::abs(member.midspan(solution.x) - linear_answer) / linear_answer);
    }
    for (std::size_t i = 0; i + 1 < departure.size(); ++i) {
      CAPTURE(i, departure[i], departure[i + 1]);
      CHECK(std::log10(departure[i] / departure[i + 1]) == Approx(1.0).margin(0.05));
    }
    // A moderate load, A = a / 5 (well before the limit point, where dq/dA = pi^4 + k - EA pi^4 a^2 / 4 < 0):
    // the one-mode closed form.
    const double amplitude = 0.2 * a, q0 = arch_load(ea, k, a, amplitude);
    const auto solution = member.solve(q0, amplitude);
    CAPTURE(q0, solution.summary.brief_report());
    REQUIRE(solution.summary.is_usable());
    CHECK(final_order(solution.summary.residual_history) >= 1.5);
    moderate_error.push_back(std::abs(member.midspan(solution.x) - amplitude) / amplitude);
  }
  for (const auto* error : {&linear_error, &moderate_error})
    for (std::size_t i = 0; i + 1 < error->size(); ++i) {
      const double order = std::log2((*error)[i] / (*error)[i + 1]);
      CAPTURE(i, (*error)[i], (*error)[i + 1], order);
      CHECK(order > 3.8);
      CHECK(order < 4.2);
    }
}
