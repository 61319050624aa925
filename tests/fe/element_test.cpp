// The element seam (fe/element.hpp): every element's tangent is the Jacobian of its internal
// force (central differences), and a linear element's internal force is K_e u.
#include "fe/element.hpp"

#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "fe/arch_element.hpp"
#include "fe/beam_element.hpp"

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
