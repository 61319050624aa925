#pragma once
// Checks shared by the tests of nonlinear elements (tests/fe/von_karman_element_test.cpp,
// arch_von_karman_element_test.cpp): the tangent against differences of the internal force, the
// energy's gradient against the internal force, and the element seam's storage contract
// (fe/element.hpp).

#include <Eigen/Dense>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "fe/element.hpp"

namespace liftoff::test {

// K_t against the central differences of f_int at `state`, steps `base` and base / 2. f_int is a
// cubic in the dofs, so a difference's error is exactly delta^2 / 6 f''' (third_derivative(j): the
// third derivative along e_j) plus round-off: each f_int a few dozen roundings of force_size
// (within a factor 2 of it at u +- delta e_j), over 2 delta; K_t's own of tangent_size; the
// rounded u_j +- delta moves the step by eps |u_j| per side. Returned in units of that allowance:
// the worst misfit (must be <= 1) and the largest truncation (far above 1: the check has teeth).
struct JacobianMisfit {
  double worst = 0.0, largest_truncation = 0.0;
};

template <class ThirdDerivative>
JacobianMisfit tangent_misfit(const fe::Element& element, const fe::ElementState& state, const Eigen::MatrixXd& tangent,
                              double base, const Eigen::VectorXd& force_size, const Eigen::MatrixXd& tangent_size,
                              ThirdDerivative third_derivative) {
  constexpr double eps = std::numeric_limits<double>::epsilon();
  JacobianMisfit out;
  for (double delta : {base, base / 2}) {
    for (int j = 0; j < state.displacement.size(); ++j) {
      fe::ElementState plus = state, minus = state;
      plus.displacement[j] += delta;
      minus.displacement[j] -= delta;
      const Eigen::VectorXd difference =
          (element.evaluate(plus).internal_force - element.evaluate(minus).internal_force) / (2.0 * delta);
      const Eigen::VectorXd truncation = delta * delta / 6.0 * third_derivative(j);
      const Eigen::VectorXd allowance =
          (64 * eps) * (2.0 * force_size / delta + tangent_size.col(j)) +
          tangent_size.col(j) * (2 * eps * (std::abs(state.displacement[j]) + delta) / delta) +
          Eigen::VectorXd::Constant(force_size.size(), std::numeric_limits<double>::min());
      const Eigen::VectorXd misfit = difference - tangent.col(j) - truncation;
      out.worst = std::max(out.worst, (misfit.cwiseAbs().array() / allowance.array()).maxCoeff());
      out.largest_truncation =
          std::max(out.largest_truncation, (truncation.cwiseAbs().array() / allowance.array()).maxCoeff());
    }
  }
  return out;
}

// f_int = grad energy at `u` for an element whose energy is a quartic in its dofs: Richardson's
// (4 D(delta/2) - D(delta)) / 3 of central differences is exact for it (the error term needs the
// fifth derivative), so it meets f_int to round-off: a few dozen roundings of the energy's size
// (energy_size) over delta, plus of the force's (force_size, entry-wise).
template <class QuarticElement>
void check_energy_gradient(const QuarticElement& element, const Eigen::VectorXd& u,
                           const Eigen::VectorXd& internal_force, double delta, double energy_size,
                           const Eigen::VectorXd& force_size) {
  constexpr double eps = std::numeric_limits<double>::epsilon();
  for (int j = 0; j < u.size(); ++j) {
    auto central = [&](double step) {
      Eigen::VectorXd plus = u, minus = u;
      plus[j] += step;
      minus[j] -= step;
      return (element.energy(plus) - element.energy(minus)) / (2.0 * step);
    };
    const double extrapolated = (4.0 * central(delta / 2) - central(delta)) / 3.0;
    const double allowance = 64 * eps * (4.0 * energy_size / delta + force_size[j]);
    CAPTURE(j, extrapolated, internal_force[j], allowance);
    CHECK(std::abs(extrapolated - internal_force[j]) <= allowance);
  }
}

// The seam's contract: once sized, the response's storage is reused (evaluated at u, then at v).
inline void check_response_storage_reused(const fe::Element& element, const Eigen::VectorXd& u,
                                          const Eigen::VectorXd& v) {
  fe::ElementResponse response;
  element.evaluate(fe::ElementState{u, 0.0}, response);
  const double* force = response.internal_force.data();
  const double* tangent = response.tangent.data();
  element.evaluate(fe::ElementState{v, 0.0}, response);
  CHECK(response.internal_force.data() == force);
  CHECK(response.tangent.data() == tangent);
}

}  // namespace liftoff::test
