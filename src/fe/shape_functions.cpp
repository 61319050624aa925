#include "fe/shape_functions.hpp"

#include <array>

namespace liftoff::fe {

HermiteCubic hermite_cubic(double xi, double h) {
  const double x2 = xi * xi, x3 = x2 * xi;
  HermiteCubic n;
  n.value << 1 - 3 * x2 + 2 * x3, h * (xi - 2 * x2 + x3), 3 * x2 - 2 * x3, h * (x3 - x2);
  n.d1 << (-6 * xi + 6 * x2) / h, 1 - 4 * xi + 3 * x2, (6 * xi - 6 * x2) / h, 3 * x2 - 2 * xi;
  n.d2 << (-6 + 12 * xi) / (h * h), (-4 + 6 * xi) / h, (6 - 12 * xi) / (h * h), (6 * xi - 2) / h;
  n.d3 << 12 / (h * h * h), 6 / (h * h), -12 / (h * h * h), 6 / (h * h);
  return n;
}

namespace {
// Monomial coefficients c[0] + c[1] xi + ... + c[4] xi^4 of each quartic Lagrange polynomial.
using Coefficients = std::array<std::array<double, 5>, 5>;
Coefficients quartic_coefficients() {
  Coefficients c{};
  for (int k = 0; k < 5; ++k) {
    std::array<double, 5> poly{1, 0, 0, 0, 0};
    double denominator = 1.0;
    for (int m = 0; m < 5; ++m) {
      if (m == k) continue;
      for (int p = 4; p >= 1; --p) poly[p] = poly[p - 1] - quartic_nodes[m] * poly[p];
      poly[0] *= -quartic_nodes[m];
      denominator *= quartic_nodes[k] - quartic_nodes[m];
    }
    for (int p = 0; p < 5; ++p) c[k][p] = poly[p] / denominator;
  }
  return c;
}
}  // namespace

LagrangeQuartic lagrange_quartic(double xi, double h) {
  static const Coefficients c = quartic_coefficients();
  LagrangeQuartic n;
  for (int k = 0; k < 5; ++k) {
    const auto& a = c[k];
    n.value[k] = a[0] + xi * (a[1] + xi * (a[2] + xi * (a[3] + xi * a[4])));
    n.d1[k] = (a[1] + xi * (2 * a[2] + xi * (3 * a[3] + xi * 4 * a[4]))) / h;
    n.d2[k] = (2 * a[2] + xi * (6 * a[3] + xi * 12 * a[4])) / (h * h);
  }
  return n;
}

Eigen::Vector2d reaction_shape(double xi) { return {1.0 - xi, xi}; }

}  // namespace liftoff::fe
