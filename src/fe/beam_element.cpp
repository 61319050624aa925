#include "fe/beam_element.hpp"

namespace liftoff::fe::beam_element {

Eigen::Matrix4d stiffness(double h) {
  const double h2 = h * h;
  Eigen::Matrix4d k;
  k << 12, 6 * h, -12, 6 * h,       //
      6 * h, 4 * h2, -6 * h, 2 * h2,  //
      -12, -6 * h, 12, -6 * h,        //
      6 * h, 2 * h2, -6 * h, 4 * h2;
  return k / (h2 * h);
}

}  // namespace liftoff::fe::beam_element
