// The circular arch element with moderate rotations (fe/arch_von_karman_element.hpp): its tangent
// is the Jacobian of its internal force and its internal force the gradient of its energy (central
// differences, whose truncation error is known exactly: f_int is a cubic, the energy a quartic in
// the dofs), its limits (zero displacement: ArchElement's stiffness to the bit; the rigid rotation
// about the centre), and an assembled pinned shallow arch solved by Newton: small loads reproduce
// the linear arch FE, and the crown deflection agrees with the von Karman beam element on the same
// shallow arch (w_0 the circle segment) to the order of (rise / span)^2.
#include "fe/arch_von_karman_element.hpp"

#include <Eigen/Dense>
#include <Eigen/SparseLU>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "fe/arch_element.hpp"
#include "fe/element.hpp"
#include "fe/shape_functions.hpp"
#include "fe/sparse_assembler.hpp"
#include "fe/von_karman_element.hpp"
#include "support/element_checks.hpp"

using namespace liftoff;
using namespace liftoff::fe;
using Eigen::VectorXd;

namespace {

constexpr double eps = std::numeric_limits<double>::epsilon();
using Vector9d = Eigen::Matrix<double, 9, 1>;
using Matrix9d = Eigen::Matrix<double, 9, 9>;

VectorXd random_displacement(double scale) { return scale * VectorXd::Random(9); }

// Entry-wise bounds on the sizes that round-off acts on, from the element's sums (header) with
// every term taken in absolute value: f_int (force), K_t (tangent), the energy.
struct Sizes {
  Vector9d force = Vector9d::Zero();
  Matrix9d tangent = Matrix9d::Zero();
  double energy = 0.0;
};
Sizes round_off_sizes(double h, double ea, bool outside, const VectorXd& q) {
  Sizes s;
  const Vector9d x = q.cwiseAbs();
  for (const GaussPoint& g : gauss5) {
    const Vector9d a = arch_element::membrane_strain_row(g.xi, h, outside).cwiseAbs().transpose();
    const Vector9d r = arch_von_karman_element::rotation_row(g.xi, h, outside).cwiseAbs().transpose();
    const Vector9d c = arch_element::bending_strain_row(g.xi, h, outside).cwiseAbs().transpose();
    const double beta = r.dot(x), strain = a.dot(x) + 0.5 * beta * beta, chi = c.dot(x);
    const Vector9d b = a + beta * r;
    const double w = g.weight * h;
    s.force += w * (ea * strain * b + chi * c);
    s.tangent += w * (ea * b * b.transpose() + c * c.transpose() + ea * strain * r * r.transpose());
    s.energy += w * 0.5 * (ea * strain * strain + chi * chi);
  }
  return s;
}

// The third derivative of f_int along e_j, exactly: with beta(t) = beta + t r_j,
// eps(t) = eps + t b_j + t^2 r_j^2 / 2 and b(t) = b + t r_j r, so eps b has the cubic term
// t^3 r_j^3 r / 2: f''' = sum_g W_g h EA 3 r_j^3 r^T (the bending part is linear).
Vector9d third_derivative(double h, double ea, bool outside, int j) {
  Vector9d d = Vector9d::Zero();
  for (const GaussPoint& g : gauss5) {
    const arch_element::Row9d r = arch_von_karman_element::rotation_row(g.xi, h, outside);
    d += (g.weight * h * ea * 3.0 * std::pow(r[j], 3)) * r.transpose();
  }
  return d;
}

}  // namespace

TEST_CASE("arch von Karman element: K_t is the Jacobian of f_int, to the exact truncation error of central differences",
          "[fe][element][von_karman][arch]") {
  const double h = GENERATE(0.3, 0.0175);
  const double ea = GENERATE(1e2, 1e6);
  const bool outside = GENERATE(false, true);
  const double scale = GENERATE(1e-3, 0.3);
  CAPTURE(h, ea, outside, scale);
  const ArchVonKarmanElement element(h, ea, outside);
  const ElementState state{random_displacement(scale), 0.5};
  const ElementResponse at = element.evaluate(state);
  const Sizes sizes = round_off_sizes(h, ea, outside, state.displacement);
  // f_int is a cubic in q, so the central difference's error is exactly delta^2 / 6 f''' plus
  // round-off: the observed error is the truncation, not a guess. Two steps a factor 2 apart.
  const double base = std::ldexp(1.0, -8) * std::max(scale, 1e-2);
  const test::JacobianMisfit misfit = test::tangent_misfit(element, state, at.tangent, base, sizes.force, sizes.tangent,
                                                           [&](int j) { return third_derivative(h, ea, outside, j); });
  CAPTURE(misfit.worst, misfit.largest_truncation);
  CHECK(misfit.worst <= 1.0);
  // The check has teeth: somewhere the truncation term is far above the round-off allowance.
  if (ea * scale * scale > 1.0) CHECK(misfit.largest_truncation > 10.0);
}

TEST_CASE("arch von Karman element: K_t symmetric to the last bit, f_int the gradient of the energy",
          "[fe][element][von_karman][arch]") {
  const double h = GENERATE(0.3, 0.0175);
  const double ea = GENERATE(1e2, 1e6);
  const bool outside = GENERATE(false, true);
  CAPTURE(h, ea, outside);
  const ArchVonKarmanElement element(h, ea, outside);
  for (double scale : {1e-3, 0.3}) {
    CAPTURE(scale);
    const VectorXd q = random_displacement(scale);
    const ElementResponse at = element.evaluate(ElementState{q, 0.0});
    CHECK(at.tangent == at.tangent.transpose());
    // The energy is a quartic in q: Richardson's (4 D(delta/2) - D(delta)) / 3 of central
    // differences is exact for it, so it meets f_int to round-off: a few dozen roundings of the
    // energy's size over delta.
    const Sizes sizes = round_off_sizes(h, ea, outside, q);
    const double delta = std::ldexp(1.0, -6) * std::max(scale, 1e-2);
    test::check_energy_gradient(element, q, at.internal_force, delta, sizes.energy, sizes.force);
  }
  // The side of the foundation only flips w: the same physical state stores the same energy.
  const ArchVonKarmanElement inside(h, ea, false), outside_element(h, ea, true);
  VectorXd q = random_displacement(0.1), flipped = q;
  flipped.head<4>() *= -1.0;
  CHECK(outside_element.energy(flipped) == inside.energy(q));
}

TEST_CASE("arch von Karman element: at zero displacement ArchElement's stiffness, to the bit",
          "[fe][element][von_karman][arch]") {
  const double h = GENERATE(0.3, 0.0175, 1e-4);
  const double ea = GENERATE(1e2, 3e6);
  const bool outside = GENERATE(false, true);
  CAPTURE(h, ea, outside);
  const ElementResponse zero = ArchVonKarmanElement(h, ea, outside).evaluate(ElementState{VectorXd::Zero(9), 0.3});
  CHECK(zero.internal_force == Vector9d::Zero());
  // The same sums of the same products; K_t is then made symmetric to the bit, which
  // arch_element::stiffness is not (its (i, j) and (j, i) are rounded apart by an ulp or so), so
  // they agree to that rounding, and the linear element on the seam is the same matrix.
  const Matrix9d linear = arch_element::stiffness(h, ea, outside);
  const double asymmetry = (linear - linear.transpose()).cwiseAbs().maxCoeff();
  CHECK((zero.tangent - linear).cwiseAbs().maxCoeff() <= std::max(asymmetry, 4 * eps * linear.cwiseAbs().maxCoeff()));
  CHECK(Matrix9d(ArchElement(h, ea, outside).stiffness()) == linear);
  CHECK(zero.tangent == zero.tangent.transpose());
}

TEST_CASE("arch von Karman element: the rigid rotation about the centre is strain free to second order",
          "[fe][element][von_karman][arch]") {
  const double h = GENERATE(0.3, 0.0175);
  const bool outside = GENERATE(false, true);
  const double ea = 1e4;
  CAPTURE(h, outside);
  const ArchVonKarmanElement element(h, ea, outside);
  const double sigma = arch_element::inward_sign(outside);
  for (double c : {1e-3, 0.1, 0.5}) {
    CAPTURE(c);
    // First order (u = c R, w = 0): no linear strain, and exactly the stretch beta^2 / 2 = c^2 / 2
    // of an unshortened rotation.
    VectorXd first(9);
    first << 0, 0, 0, 0, c, c, c, c, c;
    // Exact: the point at theta moves to theta + c, so u = sin c along the tangent and 1 - cos c
    // inward (sigma w = 1 - cos c, constant): eps = -(1 - cos c) + sin^2 c / 2 = -(1 - cos c)^2 / 2.
    const double inward = 1.0 - std::cos(c);
    VectorXd exact(9);
    exact << sigma * inward, 0, sigma * inward, 0, std::sin(c), std::sin(c), std::sin(c), std::sin(c), std::sin(c);
    for (const GaussPoint& g : gauss5) {
      // Round-off: u' sums values of size c against shape derivatives of size ~10 / h.
      const double allowance = 64 * eps * (c * (1.0 + 10.0 / h) + c * c);
      CHECK(std::abs(element.membrane_strain(first, g.xi) - 0.5 * c * c) <= allowance);
      CHECK(std::abs(element.rotation(first, g.xi) + c) <= allowance);
      CHECK(std::abs(element.bending_strain(first, g.xi)) <= allowance);
      CHECK(std::abs(element.membrane_strain(exact, g.xi) + 0.5 * inward * inward) <= allowance);
      CHECK(std::abs(element.bending_strain(exact, g.xi)) <= allowance);
    }
    // The exact rotation carries only the O(c^4) force of its O(c^4) strain; the first-order one
    // the force of its c^2 / 2 stretch (the linear element's would be zero).
    const double exact_force = element.evaluate(ElementState{exact, 0.0}).internal_force.cwiseAbs().maxCoeff();
    const Sizes sizes = round_off_sizes(h, ea, outside, exact);
    CHECK(exact_force <= ea * 0.5 * inward * inward * 4.0 + 64 * eps * sizes.force.maxCoeff());
    if (c == 0.1) {  // the ratio is ~ (c^2 / 2) / ((c^2 / 2)^2 / 2) = 4 / c^2
      const double first_force = element.evaluate(ElementState{first, 0.0}).internal_force.cwiseAbs().maxCoeff();
      CHECK(first_force > 100.0 * exact_force);
    }
  }
}

TEST_CASE("arch von Karman element: bad arguments are refused with a message", "[fe][element][von_karman][arch]") {
  CHECK_THROWS_AS(ArchVonKarmanElement(0.0, 1.0), std::invalid_argument);
  CHECK_THROWS_AS(ArchVonKarmanElement(-0.1, 1.0), std::invalid_argument);
  CHECK_THROWS_AS(ArchVonKarmanElement(0.1, 0.0), std::invalid_argument);
  CHECK_THROWS_AS(ArchVonKarmanElement(0.1, std::nan("")), std::invalid_argument);
  CHECK_THROWS_AS(ArchVonKarmanElement(std::numeric_limits<double>::infinity(), 1.0), std::invalid_argument);
  const ArchVonKarmanElement element(0.1, 1.0);
  CHECK_FALSE(element.is_linear());
  CHECK(element.dofs() == 9);
  CHECK_THROWS_AS(element.evaluate(ElementState{VectorXd::Zero(6), 0.0}), std::invalid_argument);
  CHECK_THROWS_AS(element.energy(VectorXd::Zero(10)), std::invalid_argument);
  CHECK_THROWS_AS(element.membrane_strain(VectorXd::Zero(4), 0.5), std::invalid_argument);
  const VectorXd first = random_displacement(0.1);
  const VectorXd second = random_displacement(0.2);
  test::check_response_storage_reused(element, first, second);
}

// ---------------------------------------------------------------------------------------------
// Assembled: a pinned circular arch of half-angle alpha (R = 1, theta in [-alpha, alpha]), the
// foundation inside (w > 0 toward the centre: down at the crown), a bilateral Winkler foundation
// k on the w dofs, a uniform radial pressure p along w > 0 (consistent nodal forces), w and u
// fixed at both ends. Solved from zero by Newton (full steps, a sparse LU per step) over the
// fixed-pattern SparseAssembler.
//
// The equivalent von Karman beam (fe/von_karman_element) on the chord L = 2 sin alpha: the shallow
// arch w_0 = -(height of the circle above the chord) / L (a hump away from the foundation), the
// same pins, k L^4, EA R^2 L^2 (EA R^2 / EI the arch's), the load p L^3 per unit chord (a pressure
// p has the vertical resultant p per unit horizontal projection), its crown deflection times L.
// The two differ by what shallow-arch theory neglects, all of relative order theta^2 <= alpha^2
// ~ 16 (rise / span)^2: cos theta against 1 in the load's and the springs' directions and in
// arc length against chord, the arch's rotation against the slope. Scaling: alpha doubles while
// EA rise^2, k L^4 and p L^4 / rise are kept (so that the shallow-arch problem, in units of the
// rise, is the same), and the relative difference should then grow like (rise / span)^2: 4 times.
// ---------------------------------------------------------------------------------------------
namespace {

struct NewtonResult {
  VectorXd x;
  std::vector<double> residuals;  // |R|_inf at each iterate, the last at the answer
  double floor = 0.0;             // 16 eps max(|K_t| |x| + |F|) at the last iterate: round-off's level
  bool converged = false;
};

// Newton with full steps on R(x) = f_int(x) - F, from x = 0, until the step is below 1e-10 |x|
// (converging quadratically, the error after that step is of the order of its square).
// A linear problem (linear = true) stops after its one exact step.
NewtonResult newton(SparseAssembler& assembler, const std::vector<std::unique_ptr<const Element>>& elements,
                    const std::vector<int>& equation_of_dof, const VectorXd& load, bool linear = false) {
  NewtonResult result{VectorXd::Zero(load.size()), {}, false};
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu;
  VectorXd u_all = VectorXd::Zero(static_cast<Eigen::Index>(equation_of_dof.size()));
  for (int iteration = 0; iteration < 40; ++iteration) {
    for (std::size_t dof = 0; dof < equation_of_dof.size(); ++dof)
      if (equation_of_dof[dof] >= 0) u_all[static_cast<Eigen::Index>(dof)] = result.x[equation_of_dof[dof]];
    assembler.assemble(elements, u_all, 0.0);
    const VectorXd residual = assembler.internal_force() - load;
    result.residuals.push_back(residual.cwiseAbs().maxCoeff());
    result.floor = 16 * eps * (assembler.tangent().cwiseAbs() * result.x.cwiseAbs() + load.cwiseAbs()).maxCoeff();
    if (iteration == 0) lu.analyzePattern(assembler.tangent());
    lu.factorize(assembler.tangent());
    if (lu.info() != Eigen::Success) return result;
    const VectorXd step = lu.solve(-residual);
    result.x += step;
    if (linear || step.cwiseAbs().maxCoeff() <= 1e-10 * result.x.cwiseAbs().maxCoeff()) {
      result.converged = true;
      return result;
    }
  }
  return result;
}

// The order of convergence from the last three residuals r0 > r1 > r2 above the round-off floor:
// p = log(r2 / r1) / log(r1 / r0), quadratic ~2, a wrong tangent ~1; too short a history
// (convergence in two steps) gives 2.
double final_order(const NewtonResult& result) {
  std::vector<double> above;
  for (double r : result.residuals)
    if (r > result.floor) above.push_back(r);
  if (above.size() < 3) return 2.0;
  const double r0 = above[above.size() - 3], r1 = above[above.size() - 2], r2 = above.back();
  return std::log(r2 / r1) / std::log(r1 / r0);
}

// Node i: w (3i), w' (3i + 1), u (3i + 2); the three interior u values of element e after the
// nodes. Fixed: w and u at both ends.
class PinnedArch {
 public:
  PinnedArch(int n, double alpha, double ea, double k, bool nonlinear)
      : n_(n), h_(2.0 * alpha / n), linear_(!nonlinear) {
    const int nodes = n + 1, dofs = 3 * nodes + 3 * n;
    std::vector<std::vector<int>> element_dofs;
    for (int e = 0; e < n; ++e) {
      const int a = 3 * e, b = 3 * (e + 1), interior = 3 * nodes + 3 * e;
      if (nonlinear)
        elements_.push_back(std::make_unique<ArchVonKarmanElement>(h_, ea, false));
      else
        elements_.push_back(std::make_unique<ArchElement>(h_, ea, false));
      element_dofs.push_back({a, a + 1, b, b + 1, a + 2, interior, interior + 1, interior + 2, b + 2});
      elements_.push_back(std::make_unique<WinklerElement>(h_, k));
      element_dofs.push_back({a, a + 1, b, b + 1});
    }
    equation_of_dof_.assign(dofs, -1);
    int equations = 0;
    for (int dof = 0; dof < dofs; ++dof)
      if (dof != 0 && dof != 2 && dof != 3 * n && dof != 3 * n + 2) equation_of_dof_[dof] = equations++;
    assembler_ = std::make_unique<SparseAssembler>(element_dofs, equation_of_dof_);
    unit_load_ = VectorXd::Zero(equations);  // uniform radial pressure 1: int N_w ds per element
    for (int e = 0; e < n; ++e)
      for (const GaussPoint& point : gauss5) {
        const Eigen::Vector4d shape = hermite_cubic(point.xi, h_).value;
        for (int i = 0; i < 4; ++i) {
          const int equation = equation_of_dof_[element_dofs[2 * e][i]];
          if (equation >= 0) unit_load_[equation] += point.weight * h_ * shape[i];
        }
      }
  }
  NewtonResult solve(double p) { return newton(*assembler_, elements_, equation_of_dof_, p * unit_load_, linear_); }
  double crown(const VectorXd& x) const { return x[equation_of_dof_[3 * (n_ / 2)]]; }

 private:
  int n_;
  double h_;
  bool linear_;
  std::vector<std::unique_ptr<const Element>> elements_;
  std::vector<int> equation_of_dof_;
  std::unique_ptr<SparseAssembler> assembler_;
  VectorXd unit_load_;
};

// The von Karman beam on the chord (nondimensional by L): node i w (3i), w' (3i + 1), u (3i + 2).
class ShallowBeam {
 public:
  ShallowBeam(int n, double alpha, double ea_chord, double k_chord) : n_(n) {
    const double h = 1.0 / n, chord = 2.0 * std::sin(alpha);
    // w_0(s) = -(sqrt(1 - (x - L/2)^2) - cos alpha) / L at x = s L, so w_0'(s) = (x - L/2) / sqrt(...).
    auto initial_slope = [chord](double s) {
      const double x = (s - 0.5) * chord;
      return x / std::sqrt(1.0 - x * x);
    };
    std::vector<std::vector<int>> element_dofs;
    for (int e = 0; e < n; ++e) {
      const int a = 3 * e, b = 3 * (e + 1);
      elements_.push_back(std::make_unique<VonKarmanBeamElement>(
          h, ea_chord, von_karman_element::sample_initial_slopes(initial_slope, e * h, h)));
      element_dofs.push_back({a, a + 1, b, b + 1, a + 2, b + 2});
      elements_.push_back(std::make_unique<WinklerElement>(h, k_chord));
      element_dofs.push_back({a, a + 1, b, b + 1});
    }
    const int dofs = 3 * (n + 1);
    equation_of_dof_.assign(dofs, -1);
    int equations = 0;
    for (int dof = 0; dof < dofs; ++dof)
      if (dof != 0 && dof != 2 && dof != 3 * n && dof != 3 * n + 2) equation_of_dof_[dof] = equations++;
    assembler_ = std::make_unique<SparseAssembler>(element_dofs, equation_of_dof_);
    unit_load_ = VectorXd::Zero(equations);
    for (int e = 0; e < n; ++e)
      for (const GaussPoint& point : gauss5) {
        const Eigen::Vector4d shape = hermite_cubic(point.xi, h).value;
        for (int i = 0; i < 4; ++i) {
          const int equation = equation_of_dof_[element_dofs[2 * e][i]];
          if (equation >= 0) unit_load_[equation] += point.weight * h * shape[i];
        }
      }
  }
  NewtonResult solve(double q) { return newton(*assembler_, elements_, equation_of_dof_, q * unit_load_); }
  double midspan(const VectorXd& x) const { return x[equation_of_dof_[3 * (n_ / 2)]]; }

 private:
  int n_;
  std::vector<std::unique_ptr<const Element>> elements_;
  std::vector<int> equation_of_dof_;
  std::unique_ptr<SparseAssembler> assembler_;
  VectorXd unit_load_;
};

// The shallow-arch family: EA rise^2 = lambda, k L^4 = kappa, p L^4 / rise = load.
struct Family {
  double lambda = 20.0, kappa = 100.0, load = 100.0;
};
struct Arch {
  double alpha, rise, chord, ea, k, p;
};
Arch member_of(const Family& f, double alpha) {
  Arch a{alpha, 1.0 - std::cos(alpha), 2.0 * std::sin(alpha), 0, 0, 0};
  a.ea = f.lambda / (a.rise * a.rise);
  a.k = f.kappa / std::pow(a.chord, 4);
  a.p = f.load * a.rise / std::pow(a.chord, 4);
  return a;
}

}  // namespace

TEST_CASE("arch von Karman elements, assembled: small loads reproduce the linear arch FE to O(load^2)",
          "[fe][element][von_karman][arch][newton]") {
  const Arch arch = member_of(Family{}, 0.1);
  const int n = 32;
  PinnedArch nonlinear(n, arch.alpha, arch.ea, arch.k, true), linear(n, arch.alpha, arch.ea, arch.k, false);
  std::vector<double> departure;
  for (double fraction : {1e-2, 1e-3, 1e-4}) {
    const double p = fraction * arch.p;
    const NewtonResult solved = nonlinear.solve(p), reference = linear.solve(p);
    CAPTURE(fraction, solved.residuals.size(), solved.floor);
    REQUIRE(solved.converged);
    REQUIRE(reference.converged);
    CHECK(reference.residuals.size() == 1);  // the linear arch: one exact step
    CHECK(final_order(solved) >= 1.5);
    departure.push_back(std::abs(nonlinear.crown(solved.x) - linear.crown(reference.x)) /
                        std::abs(linear.crown(reference.x)));
  }
  // The relative departure falls like the load (the absolute one like load^2): a factor 10 a decade.
  for (std::size_t i = 0; i + 1 < departure.size(); ++i) {
    CAPTURE(i, departure[i], departure[i + 1]);
    CHECK(std::log10(departure[i] / departure[i + 1]) == Approx(1.0).margin(0.05));
  }
}

TEST_CASE(
    "arch von Karman elements, assembled: the crown deflection of a shallow circular arch meets the von Karman "
    "beam on the circle segment to O((rise / span)^2)",
    "[fe][element][von_karman][arch][newton]") {
  const Family family;
  const int n = 32;
  std::vector<double> difference, slenderness;
  for (double alpha : {0.1, 0.2}) {
    const Arch arch = member_of(family, alpha);
    CAPTURE(alpha, arch.ea, arch.k, arch.p);
    PinnedArch circular(n, alpha, arch.ea, arch.k, true);
    ShallowBeam shallow(n, alpha, arch.ea * arch.chord * arch.chord, arch.k * std::pow(arch.chord, 4));
    const NewtonResult a = circular.solve(arch.p);
    const NewtonResult b = shallow.solve(arch.p * std::pow(arch.chord, 3));
    REQUIRE(a.converged);
    REQUIRE(b.converged);
    CHECK(final_order(a) >= 1.5);
    const double crown_arch = circular.crown(a.x), crown_beam = shallow.midspan(b.x) * arch.chord;
    // Beyond linear theory: the crown moves a sizeable fraction of the rise.
    CAPTURE(crown_arch / arch.rise, crown_beam / arch.rise);
    CHECK(crown_arch / arch.rise > 0.1);
    const double ratio = arch.rise / arch.chord;
    difference.push_back(std::abs(crown_arch - crown_beam) / std::abs(crown_beam));
    slenderness.push_back(ratio);
    CAPTURE(difference.back(), ratio);
    CHECK(difference.back() <= 16.0 * ratio * ratio);
    // The difference is the theories', not the meshes': halving the arch's mesh moves its crown
    // far less (Hermite w: errors ~ h^4).
    PinnedArch coarse(n / 2, alpha, arch.ea, arch.k, true);
    const NewtonResult c = coarse.solve(arch.p);
    REQUIRE(c.converged);
    CHECK(std::abs(coarse.crown(c.x) - crown_arch) <= 1e-3 * std::abs(crown_arch - crown_beam));
    // And the nonlinear terms matter here: the linear arch FE is further off than the beam.
    PinnedArch linear(n, alpha, arch.ea, arch.k, false);
    const double crown_linear = linear.crown(linear.solve(arch.p).x);
    CAPTURE(crown_linear / arch.rise);
    CHECK(std::abs(crown_linear - crown_arch) >= 3.0 * std::abs(crown_arch - crown_beam));
  }
  // The difference grows like (rise / span)^2.
  const double order = std::log(difference[1] / difference[0]) / std::log(slenderness[1] / slenderness[0]);
  CAPTURE(difference[0], difference[1], order);
  CHECK(order == Approx(2.0).margin(0.2));
}
