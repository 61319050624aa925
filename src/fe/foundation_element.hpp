#pragma once
// The Winkler foundation on one element, in the seed's mixed form (eqs. 3.6 to 3.8): the
// reaction r has its own linear interpolation Hb between the element's nodes, so
//   C_e = integral of Hb^T N_w ds     (2 x 4: reaction nodes x Hermite dofs of w)
//   T_e = integral of Hb^T (1/k) Hb ds (2 x 2 flexibility)
// and the discrete contact conditions read  T r - C u >= 0 (gap), r >= 0, r.(T r - C u) = 0.

#include <Eigen/Dense>

namespace liftoff::fe::foundation_element {

Eigen::Matrix<double, 2, 4> coupling(double h);
Eigen::Matrix2d flexibility(double h, double foundation_modulus);

}  // namespace liftoff::fe::foundation_element
