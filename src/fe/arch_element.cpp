#include "fe/arch_element.hpp"

#include "fe/shape_functions.hpp"

namespace liftoff::fe::arch_element {

Row9d membrane_strain_row(double xi, double h, bool outside) {
  const HermiteCubic w = hermite_cubic(xi, h);
  const LagrangeQuartic u = lagrange_quartic(xi, h);
  Row9d row;
  row << -inward_sign(outside) * w.value.transpose(), u.d1.transpose();
  return row;
}

Row9d bending_strain_row(double xi, double h, bool outside) {
  const HermiteCubic w = hermite_cubic(xi, h);
  const LagrangeQuartic u = lagrange_quartic(xi, h);
  Row9d row;
  row << inward_sign(outside) * w.d2.transpose(), u.d1.transpose();
  return row;
}

Matrix9d stiffness(double h, double membrane_stiffness, bool outside) {
  Matrix9d k = Matrix9d::Zero();
  for (const GaussPoint& g : gauss5) {
    const Row9d eps = membrane_strain_row(g.xi, h, outside);
    const Row9d chi = bending_strain_row(g.xi, h, outside);
    k += (g.weight * h) * (membrane_stiffness * eps.transpose() * eps + chi.transpose() * chi);
  }
  return k;
}

namespace {
// Legendre polynomials P0..P3 shifted to [0, 1].
Eigen::Vector4d legendre(double xi) {
  const double t = 2.0 * xi - 1.0;
  return {1.0, t, 0.5 * (3.0 * t * t - 1.0), 0.5 * t * (5.0 * t * t - 3.0)};
}
}  // namespace

Matrix89d stress_coupling(double h, bool outside) {
  Matrix89d g = Matrix89d::Zero();
  for (const GaussPoint& q : gauss5) {  // degree 3 + 3: exact
    const Eigen::Vector4d p = legendre(q.xi) * (q.weight * h);
    g.topRows<4>() += p * membrane_strain_row(q.xi, h, outside);
    g.bottomRows<4>() += p * bending_strain_row(q.xi, h, outside);
  }
  return g;
}

Vector8d compliance(double h, double membrane_stiffness) {
  Vector8d c;
  for (int i = 0; i < 4; ++i) {
    c[i] = h / ((2 * i + 1) * membrane_stiffness);
    c[4 + i] = h / (2 * i + 1);
  }
  return c;
}

}  // namespace liftoff::fe::arch_element
