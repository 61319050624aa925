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
Eigen::Matrix2d flexibility(double h, double k);
// k linear from k_begin (xi = 0) to k_end (xi = 1), both > 0.
Eigen::Matrix2d flexibility(double h, double k_begin, double k_end);

// The bilateral (Winkler) part K_t of a bilinear foundation in mixed form: one stress unknown per
// point of a 4-point Gauss rule, sigma_q = K_t W_q w(xi_q) with W_q = weight_q h, so that
//   G_q = N_w(xi_q) (1 x 4, the Hermite dofs of w),  H_q = 1 / (K_t W_q),
// and sum_q G_q^T H_q^-1 G_q = integral of K_t N_w^T N_w ds exactly (degree 6 <= 7).
struct WinklerPoint {
  double xi;
  double weight;
};
inline constexpr int winkler_points = 4;
inline constexpr WinklerPoint winkler_rule[winkler_points] = {
    {0.5 - 0.5 * 0.8611363115940526, 0.5 * 0.3478548451374538},
    {0.5 - 0.5 * 0.3399810435848563, 0.5 * 0.6521451548625461},
    {0.5 + 0.5 * 0.3399810435848563, 0.5 * 0.6521451548625461},
    {0.5 + 0.5 * 0.8611363115940526, 0.5 * 0.3478548451374538},
};

}  // namespace liftoff::fe::foundation_element
