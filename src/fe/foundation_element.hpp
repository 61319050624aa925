#pragma once
// The Winkler foundation on one element, in the seed's mixed form (eqs. 3.6 to 3.8): the
// reaction r has its own linear interpolation Hb between the element's nodes, so
//   C_e = integral of Hb^T N_w ds     (2 x 4: reaction nodes x Hermite dofs of w)
//   T_e = integral of Hb^T (1/k) Hb ds (2 x 2 flexibility)
// and the discrete contact conditions read  T r - C u >= 0 (gap), r >= 0, r.(T r - C u) = 0.
//
// k may vary linearly along the element (a foundation piece with a modulus given at both ends):
// T_e is then integrated exactly (logarithms, or their series where k varies little over the
// element, so that nothing cancels); it is within a few eps of the constant form as k_end -> k_begin.

#include <Eigen/Dense>

namespace liftoff::fe::foundation_element {

Eigen::Matrix<double, 2, 4> coupling(double h);
// k constant on the element.
Eigen::Matrix2d flexibility(double h, double foundation_modulus);
// k linear from k_begin (xi = 0) to k_end (xi = 1), both > 0.
Eigen::Matrix2d flexibility(double h, double k_begin, double k_end);

}  // namespace liftoff::fe::foundation_element
