#include "fe/arch_element.hpp"

#include "fe/shape_functions.hpp"

namespace liftoff::fe::arch_element {

Row9d membrane_strain_row(double xi, double h) {
  const HermiteCubic w = hermite_cubic(xi, h);
  const LagrangeQuartic u = lagrange_quartic(xi, h);
  Row9d row;
  row << -w.value.transpose(), u.d1.transpose();
  return row;
}

Row9d bending_strain_row(double xi, double h) {
  const HermiteCubic w = hermite_cubic(xi, h);
  const LagrangeQuartic u = lagrange_quartic(xi, h);
  Row9d row;
  row << w.d2.transpose(), u.d1.transpose();
  return row;
}

Matrix9d stiffness(double h, double membrane_stiffness) {
  Matrix9d k = Matrix9d::Zero();
  for (const GaussPoint& g : gauss5) {
    const Row9d eps = membrane_strain_row(g.xi, h);
    const Row9d chi = bending_strain_row(g.xi, h);
    k += (g.weight * h) * (membrane_stiffness * eps.transpose() * eps + chi.transpose() * chi);
  }
  return k;
}

}  // namespace liftoff::fe::arch_element
