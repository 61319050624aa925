#include "fe/foundation_element.hpp"

#include <array>
#include <cmath>

#include "fe/shape_functions.hpp"

namespace liftoff::fe::foundation_element {

Eigen::Matrix<double, 2, 4> coupling(double h) {
  Eigen::Matrix<double, 2, 4> c = Eigen::Matrix<double, 2, 4>::Zero();
  for (const GaussPoint& g : gauss5)
    c += (g.weight * h) * reaction_shape(g.xi) * hermite_cubic(g.xi, h).value.transpose();
  return c;
}

Eigen::Matrix2d flexibility(double h, double k) {
  Eigen::Matrix2d t;
  t << 2, 1, 1, 2;
  return t * (h / (6.0 * k));
}

namespace {

// J_1(r) - J_2(r) and J_2(r), with J_n(r) = integral over [0, 1] of xi^n / (1 + r xi), r > -1,
// for k falling or rising from k_0 at xi = 0 to k_1 at xi = 1: r = (k_1 - k_0) / k_0.
// |r| <= 1/2: the series sum over m of (-r)^m / (n + m + 1), whose terms fall below 2^-m (60
// terms: below 1e-18 of the sum). Otherwise the closed form J_0 = log(k_1 / k_0) / r (the ratio
// itself, not 1 + r, which loses the digits of a steep fall), J_n = (1/n - J_(n-1)) / r: for
// |r| > 1/2 each subtraction loses at most a factor 5 (at r = 1/2).
std::array<double, 2> moments(double k_0, double k_1) {
  const double r = (k_1 - k_0) / k_0;
  if (std::abs(r) <= 0.5) {
    double j12 = 0.0, j2 = 0.0, power = 1.0;
    for (int m = 0; m < 60; ++m, power *= -r) {
      j12 += power / ((m + 2.0) * (m + 3.0));  // 1/(m + 2) - 1/(m + 3)
      j2 += power / (m + 3.0);
    }
    return {j12, j2};
  }
  const double j0 = std::log(k_1 / k_0) / r, j1 = (1.0 - j0) / r, j2 = (0.5 - j1) / r;
  return {j1 - j2, j2};
}

}  // namespace

Eigen::Matrix2d flexibility(double h, double k_begin, double k_end) {
  if (k_begin == k_end) return flexibility(h, k_begin);
  // T_11 = h/k_b J_2(k_e/k_b - 1); T_00 is T_11 of the reversed element (xi -> 1 - xi), which
  // spares the cancelling J_0 - 2 J_1 + J_2; T_01, the same both ways, from the softer end (r > 0:
  // near r = -1, J_1 - J_2 cancels).
  const auto forward = moments(k_begin, k_end);
  const auto backward = moments(k_end, k_begin);
  Eigen::Matrix2d t;
  t(0, 0) = h / k_end * backward[1];
  t(1, 1) = h / k_begin * forward[1];
  t(0, 1) = t(1, 0) = k_begin <= k_end ? h / k_begin * forward[0] : h / k_end * backward[0];
  return t;
}

}  // namespace liftoff::fe::foundation_element
