#include "fe/foundation_element.hpp"

#include "fe/shape_functions.hpp"

namespace liftoff::fe::foundation_element {

Eigen::Matrix<double, 2, 4> coupling(double h) {
  Eigen::Matrix<double, 2, 4> c = Eigen::Matrix<double, 2, 4>::Zero();
  for (const GaussPoint& g : gauss5)
    c += (g.weight * h) * reaction_shape(g.xi) * hermite_cubic(g.xi, h).value.transpose();
  return c;
}

Eigen::Matrix2d flexibility(double h, double foundation_modulus) {
  Eigen::Matrix2d t;
  t << 2, 1, 1, 2;
  return t * (h / (6.0 * foundation_modulus));
}

}  // namespace liftoff::fe::foundation_element
