// The element seam (fe/element.hpp): every element's tangent is the Jacobian of its internal
// force (central differences), and a linear element's internal force is K_e u.
#include "fe/element.hpp"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <vector>

#include "fe/arch_element.hpp"
#include "fe/beam_element.hpp"
#include "fe/shape_functions.hpp"

using namespace liftoff::fe;

namespace {

constexpr double eps = std::numeric_limits<double>::epsilon();

// gamma_n = n eps / (1 - n eps): the bound on the relative error of a sum of n products,
// whatever the order it runs in.
double gamma(int n) { return n * eps / (1.0 - n * eps); }

// The largest misfit of the central difference (f(u + delta e_j) - f(u - delta e_j)) / (2 delta)
// to column j of K_t, each entry divided by its allowance:
//  - round-off: f is a sum of n = dofs() terms, each side's f_i carries up to gamma_n times
//    (|K| (|u| + delta e_j))_i, the difference eps |f+ - f-|_i more; the rounded u_j +- delta
//    moves the step by eps (|u_j| + delta) per side, worth |K_ij| eps (|u_j| + delta) / delta;
//  - truncation: delta^2 / 6 times a bound on |f'''| (`third_derivative`; 0 for linear f).
// A ratio <= 1 passes.
double tangent_misfit(const Element& element, const ElementState& state, double third_derivative = 0.0) {
  const int n = element.dofs();
  const ElementResponse at = element.evaluate(state);
  const Eigen::MatrixXd abs_k = at.tangent.cwiseAbs();
  const double delta = std::ldexp(1.0, -12) * std::max(1.0, state.displacement.lpNorm<Eigen::Infinity>());
  double worst = 0.0;
  for (int j = 0; j < n; ++j) {
    ElementState plus = state, minus = state;
    plus.displacement[j] += delta;
    minus.displacement[j] -= delta;
    const Eigen::VectorXd f_plus = element.evaluate(plus).internal_force;
    const Eigen::VectorXd f_minus = element.evaluate(minus).internal_force;
    const Eigen::VectorXd difference = (f_plus - f_minus) / (2.0 * delta);
    Eigen::VectorXd reach = state.displacement.cwiseAbs();
    reach[j] += delta;
    const Eigen::VectorXd allowance =
        (2.0 * gamma(n) * (abs_k * reach) + eps * (f_plus - f_minus).cwiseAbs()) / (2.0 * delta) +
        abs_k.col(j) * (eps * (std::abs(state.displacement[j]) + delta) / delta) +
        Eigen::VectorXd::Constant(n, delta * delta / 6.0 * third_derivative + std::numeric_limits<double>::min());
    worst = std::max(worst, ((difference - at.tangent.col(j)).cwiseAbs().array() / allowance.array()).maxCoeff());
  }
  return worst;
}

ElementState random_state(int dofs, double scale) { return {scale * Eigen::VectorXd::Random(dofs), 0.75}; }

// f_int(u) = K u to gamma_n |K| |u| entry by entry, and K_t = K exactly.
void check_linear(const Element& element, const Eigen::MatrixXd& stiffness) {
  REQUIRE(element.dofs() == stiffness.rows());
  CHECK(element.is_linear());
  for (double scale : {1.0, 1e-3, 1e4}) {
    CAPTURE(scale);
    const ElementState state = random_state(element.dofs(), scale);
    const ElementResponse response = element.evaluate(state);
    CHECK(response.tangent == stiffness);
    const Eigen::VectorXd bound = gamma(element.dofs()) * (stiffness.cwiseAbs() * state.displacement.cwiseAbs());
    CHECK(((response.internal_force - stiffness * state.displacement).cwiseAbs() - 2.0 * bound).maxCoeff() <= 0.0);
    CHECK(tangent_misfit(element, state) <= 1.0);
  }
}

}  // namespace

TEST_CASE("beam element: f_int = K_e u, and K_t is the Jacobian of f_int", "[fe][element]") {
  const double h = GENERATE(1.0, 0.37, 1e-3);
  CAPTURE(h);
  check_linear(BeamElement(h), beam_element::stiffness(h));
}

TEST_CASE("arch element: f_int = K_e u, and K_t is the Jacobian of f_int", "[fe][element]") {
  const double h = GENERATE(0.1, 0.01);
  const double membrane = GENERATE(10.0, 1e7);
  const bool outside = GENERATE(false, true);
  CAPTURE(h, membrane, outside);
  check_linear(ArchElement(h, membrane, outside), arch_element::stiffness(h, membrane, outside));
}

TEST_CASE("Winkler element: K_t times the consistent matrix of the Hermite cubics", "[fe][element]") {
  const double h = GENERATE(1.0, 0.05);
  const double modulus = GENERATE(1.0, 4e5);
  CAPTURE(h, modulus);
  // Integral of N_w^T N_w over the element, closed form (h / 420 times integers).
  Eigen::Matrix4d exact;
  exact << 156, 22 * h, 54, -13 * h,          //
      22 * h, 4 * h * h, 13 * h, -3 * h * h,  //
      54, 13 * h, 156, -22 * h,               //
      -13 * h, -3 * h * h, -22 * h, 4 * h * h;
  exact *= modulus * h / 420.0;
  const WinklerElement element(h, modulus);
  // Four Gauss points summed: a few dozen roundings of entries up to |exact|.
  CHECK((element.stiffness() - exact).cwiseAbs().maxCoeff() <= 64 * eps * exact.cwiseAbs().maxCoeff());
  check_linear(element, element.stiffness());
}

TEST_CASE("the element contract: sizes checked, the response's storage reused", "[fe][element]") {
  const BeamElement element(0.5);
  CHECK_THROWS_AS(element.evaluate(ElementState{Eigen::VectorXd::Zero(3), 0.0}), std::invalid_argument);
  ElementResponse response;
  element.evaluate(random_state(4, 1.0), response);
  const double* force = response.internal_force.data();
  const double* tangent = response.tangent.data();
  element.evaluate(random_state(4, 2.0), response);
  CHECK(response.internal_force.data() == force);
  CHECK(response.tangent.data() == tangent);
}

namespace {
// A nonlinear element for the check itself: f_i = (K u)_i + c u_i^3, K_t = K + 3 c diag(u^2), so
// |f'''| = 6 |c|. `broken` drops the 3, as a wrong tangent would.
class CubicElement final : public Element {
 public:
  CubicElement(double c, bool broken) : k_(BeamElement(0.5).stiffness()), c_(c), broken_(broken) {}
  int dofs() const override { return 4; }
  bool is_linear() const override { return false; }
  void evaluate(const ElementState& state, ElementResponse& response) const override {
    const Eigen::VectorXd& u = state.displacement;
    response.internal_force = k_ * u + c_ * u.cwiseProduct(u).cwiseProduct(u);
    response.tangent = k_;
    response.tangent.diagonal() += (broken_ ? 1.0 : 3.0) * c_ * u.cwiseProduct(u);
  }

 private:
  Eigen::MatrixXd k_;
  double c_;
  bool broken_;
};
}  // namespace

TEST_CASE("the tangent check passes a nonlinear element and fails a wrong tangent", "[fe][element]") {
  const ElementState state = random_state(4, 0.8);
  CHECK(tangent_misfit(CubicElement(5.0, false), state, 6 * 5.0) <= 1.0);
  // The dropped 3 c u_i^2 - c u_i^2 is ~ 2 c |u|^2, far above the allowance.
  CHECK(tangent_misfit(CubicElement(5.0, true), state, 6 * 5.0) > 1e3);
}

TEST_CASE("beam-column element: K_g is the integral of N'^T N', K_t = K_e - N K_g the Jacobian of f_int",
          "[fe][element]") {
  const double h = GENERATE(1.0, 0.37, 1e-3);
  CAPTURE(h);
  // The consistent geometric stiffness by quadrature (5 Gauss points: exact for N'^T N', degree 4).
  Eigen::Matrix4d quadrature = Eigen::Matrix4d::Zero();
  for (const GaussPoint& point : gauss5) {
    const Eigen::Vector4d slope = hermite_cubic(point.xi, h).d1;
    quadrature += (point.weight * h) * slope * slope.transpose();
  }
  const Eigen::Matrix4d geometric = beam_element::geometric_stiffness(h);
  // Five products summed per entry, each shape derivative a few roundings off.
  CHECK((geometric - quadrature).cwiseAbs().maxCoeff() <= 64 * eps * geometric.cwiseAbs().maxCoeff());
  CHECK((geometric - geometric.transpose()).cwiseAbs().maxCoeff() == 0.0);

  const double dead = 3.0, live = 7.5;
  const BeamColumnElement element(h, dead, live);
  CHECK_FALSE(element.is_linear());
  CHECK(BeamColumnElement(h, dead, 0.0).is_linear());
  for (double scale : {1.0, 1e-3, 1e4}) {
    CAPTURE(scale);
    const ElementState state = random_state(4, scale);  // lambda = 0.75
    const ElementResponse response = element.evaluate(state);
    const Eigen::Matrix4d expected = beam_element::stiffness(h) - (dead + 0.75 * live) * geometric;
    CHECK((response.tangent - expected).cwiseAbs().maxCoeff() <= 4 * eps * expected.cwiseAbs().maxCoeff());
    CHECK(tangent_misfit(element, state) <= 1.0);
  }
  CHECK_THROWS_AS(element.evaluate(ElementState{Eigen::VectorXd::Zero(5), 0.0}), std::invalid_argument);
}

namespace {
// The smallest compressive force P that buckles a pinned-pinned strut of unit length (EI = 1)
// on a bilateral Winkler foundation of modulus k, from n beam-column elements: the smallest P
// with (K + k W - P K_g) v = 0, i.e. 1 / the largest mu of K_g v = mu (K + k W) v.
double strut_buckling_load(int n, double k) {
  const double h = 1.0 / n;
  const int dofs = 2 * (n + 1);
  Eigen::MatrixXd stiffness = Eigen::MatrixXd::Zero(dofs, dofs), geometric = stiffness;
  const Eigen::Matrix4d k_e = BeamElement(h).stiffness() + WinklerElement(h, k).stiffness();
  const Eigen::Matrix4d g_e = beam_element::geometric_stiffness(h);
  for (int e = 0; e < n; ++e) {
    stiffness.block<4, 4>(2 * e, 2 * e) += k_e;
    geometric.block<4, 4>(2 * e, 2 * e) += g_e;
  }
  // Pinned ends: w = 0 at s = 0 (dof 0) and s = 1 (dof 2n); the slopes stay free.
  std::vector<int> free;
  for (int i = 0; i < dofs; ++i)
    if (i != 0 && i != 2 * n) free.push_back(i);
  const auto m = static_cast<Eigen::Index>(free.size());
  Eigen::MatrixXd a(m, m), b(m, m);
  for (Eigen::Index i = 0; i < m; ++i)
    for (Eigen::Index j = 0; j < m; ++j) a(i, j) = geometric(free[i], free[j]), b(i, j) = stiffness(free[i], free[j]);
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(a, b, Eigen::EigenvaluesOnly);
  REQUIRE(solver.info() == Eigen::Success);
  return 1.0 / solver.eigenvalues().maxCoeff();
}
}  // namespace

TEST_CASE(
    "beam-column elements: a pinned strut buckles at pi^2 EI/L^2, on a bilateral foundation at "
    "min over n of n^2 pi^2 + K/(n^2 pi^2), converging like h^4",
    "[fe][element][buckling]") {
  const double pi2 = M_PI * M_PI;
  // k = 0: Euler; k = 1e3: the two-half-wave mode governs (n = 2: 64.81, n = 1: 111.2, n = 3: 100.1).
  for (double k : {0.0, 1e3}) {
    double exact = std::numeric_limits<double>::infinity();
    for (int waves = 1; waves <= 10; ++waves) exact = std::min(exact, waves * waves * pi2 + k / (waves * waves * pi2));
    std::vector<double> error;
    for (int n : {4, 8, 16, 32}) {
      const double p = strut_buckling_load(n, k);
      // The Rayleigh quotient of a conforming approximation bounds the load from above.
      CHECK(p >= exact * (1 - 1e-12));
      error.push_back((p - exact) / exact);
    }
    for (std::size_t i = 0; i + 1 < error.size(); ++i) {
      const double order = std::log2(error[i] / error[i + 1]);
      CAPTURE(k, i, error[i], error[i + 1], order);
      // Cubic Hermite: the energy error is O(h^2) in w'', so the eigenvalue's is O(h^4); the next
      // term of the expansion is h^2 smaller, so the observed order nears 4 from the coarse side.
      CHECK(order > 3.8);
      CHECK(order < 4.2);
    }
  }
}
