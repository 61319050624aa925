#include "fe/arch_von_karman_element.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "fe/shape_functions.hpp"

namespace liftoff::fe {

namespace arch_von_karman_element {
arch_element::Row9d rotation_row(double xi, double h, bool outside) {
  const HermiteCubic w = hermite_cubic(xi, h);
  const LagrangeQuartic u = lagrange_quartic(xi, h);
  arch_element::Row9d row;
  row << -arch_element::inward_sign(outside) * w.d1.transpose(), -u.value.transpose();
  return row;
}
}  // namespace arch_von_karman_element

ArchVonKarmanElement::ArchVonKarmanElement(double h, double membrane_stiffness, bool foundation_outside)
    : h_(h), membrane_stiffness_(membrane_stiffness), outside_(foundation_outside) {
  if (!(std::isfinite(h) && h > 0.0))
    throw std::invalid_argument("ArchVonKarmanElement: h must be > 0 and finite, got " + std::to_string(h));
  if (!(std::isfinite(membrane_stiffness) && membrane_stiffness > 0.0))
    throw std::invalid_argument("ArchVonKarmanElement: membrane_stiffness (EA R^2 / EI) must be > 0 and finite, got " +
                                std::to_string(membrane_stiffness));
}

void ArchVonKarmanElement::check_size(const Eigen::VectorXd& displacement) const {
  if (displacement.size() != dofs())
    throw std::invalid_argument("ArchVonKarmanElement: one displacement per local dof (9) expected, got " +
                                std::to_string(displacement.size()));
}

double ArchVonKarmanElement::rotation(const Eigen::VectorXd& displacement, double xi) const {
  check_size(displacement);
  return arch_von_karman_element::rotation_row(xi, h_, outside_).dot(displacement);
}

double ArchVonKarmanElement::membrane_strain(const Eigen::VectorXd& displacement, double xi) const {
  const double beta = rotation(displacement, xi);  // checks the size
  return arch_element::membrane_strain_row(xi, h_, outside_).dot(displacement) + 0.5 * beta * beta;
}

double ArchVonKarmanElement::bending_strain(const Eigen::VectorXd& displacement, double xi) const {
  check_size(displacement);
  return arch_element::bending_strain_row(xi, h_, outside_).dot(displacement);
}

double ArchVonKarmanElement::energy(const Eigen::VectorXd& displacement) const {
  double energy = 0.0;
  for (const GaussPoint& g : gauss5) {
    const double eps = membrane_strain(displacement, g.xi), chi = bending_strain(displacement, g.xi);
    energy += (g.weight * h_) * 0.5 * (membrane_stiffness_ * eps * eps + chi * chi);
  }
  return energy;
}

void ArchVonKarmanElement::evaluate(const ElementState& state, ElementResponse& response) const {
  check_size(state.displacement);
  const Eigen::Matrix<double, 9, 1> q = state.displacement;
  response.internal_force.setZero(dofs());
  response.tangent.setZero(dofs(), dofs());
  for (const GaussPoint& g : gauss5) {
    const arch_element::Row9d a = arch_element::membrane_strain_row(g.xi, h_, outside_);
    const arch_element::Row9d r = arch_von_karman_element::rotation_row(g.xi, h_, outside_);
    const arch_element::Row9d chi_row = arch_element::bending_strain_row(g.xi, h_, outside_);
    const double beta = r.dot(q), chi = chi_row.dot(q);
    const double eps = a.dot(q) + 0.5 * beta * beta;
    const arch_element::Row9d b = a + beta * r;  // d eps / d q
    const double weight = g.weight * h_;
    response.internal_force += weight * (membrane_stiffness_ * eps * b.transpose() + chi * chi_row.transpose());
    // The same expression as arch_element::stiffness, so that K_t(0) is its stiffness up to the
    // symmetrisation below; the initial-stress term EA eps r^T r adds an exact zero there.
    response.tangent += weight * (membrane_stiffness_ * b.transpose() * b + chi_row.transpose() * chi_row);
    response.tangent += (weight * membrane_stiffness_ * eps) * (r.transpose() * r);
  }
  // Symmetric to the last bit (a + b == b + a), in place; a no-op where the sums already are.
  for (int j = 0; j < dofs(); ++j)
    for (int i = 0; i < j; ++i)
      response.tangent(i, j) = response.tangent(j, i) = 0.5 * (response.tangent(i, j) + response.tangent(j, i));
}

}  // namespace liftoff::fe
