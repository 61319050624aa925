#include "fe/beam_element.hpp"

namespace liftoff::fe::beam_element {

Eigen::Matrix4d stiffness(double h) {
  const double h2 = h * h;
  Eigen::Matrix4d k;
  k << 12, 6 * h, -12, 6 * h,         //
      6 * h, 4 * h2, -6 * h, 2 * h2,  //
      -12, -6 * h, 12, -6 * h,        //
      6 * h, 2 * h2, -6 * h, 4 * h2;
  return k / (h2 * h);
}

Eigen::Matrix4d geometric_stiffness(double h) {
  const double h2 = h * h;
  Eigen::Matrix4d k;
  k << 36, 3 * h, -36, 3 * h,      //
      3 * h, 4 * h2, -3 * h, -h2,  //
      -36, -3 * h, 36, -3 * h,     //
      3 * h, -h2, -3 * h, 4 * h2;
  return k / (30.0 * h);
}

Eigen::Matrix<double, 2, 4> stress_coupling(double h) {
  const double two_over_h = 2.0 / h;
  Eigen::Matrix<double, 2, 4> g;
  g << 0.0, -1.0, 0.0, 1.0,  //
      two_over_h, 1.0, -two_over_h, 1.0;
  return g;
}

Eigen::Vector2d compliance(double h) { return {h, h / 3.0}; }

}  // namespace liftoff::fe::beam_element
