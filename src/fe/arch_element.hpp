#pragma once
// Circular arch element, linear curved-beam theory, nondimensional (R = 1, EI = 1).
//
// Coordinate s = theta; u tangential (positive toward increasing theta), w radial, positive
// inward (into the foundation). Strains (' = d/dtheta):
//   membrane  eps = u' - w            (normal force  N = EA eps)
//   bending   chi = u' + w''          (moment        M = -EI chi, sagging positive)
// and the cross-section rotation (counterclockwise) is beta = -(u + w').
// Local dofs: (w0, w0', w1, w1') Hermite cubic, then (u0, u_1/4, u_1/2, u_3/4, u1) Lagrange
// quartic. The quartic u is what keeps the element free of membrane locking (see
// shape_functions.hpp).

#include <Eigen/Dense>

namespace liftoff::fe::arch_element {

inline constexpr int dofs = 9;
using Matrix9d = Eigen::Matrix<double, 9, 9>;
using Row9d = Eigen::Matrix<double, 1, 9>;

// Foundation outside the arch ([foundation] side = "outside", `outside` below): w > 0 is then
// outward, into the foundation, so the inward displacement is -w and
//   eps = u' + w,   chi = u' - w'',   rotation = -(u - w')
// (the physical strains, normal force and moment are those of the inside form: N tension
// positive, M > 0 with the intrados in tension). The element flips the sign of its w dofs.
inline double inward_sign(bool outside) { return outside ? -1.0 : 1.0; }

// Rows mapping local dofs to eps and chi at xi.
Row9d membrane_strain_row(double xi, double h, bool outside = false);
Row9d bending_strain_row(double xi, double h, bool outside = false);

// Integral of membrane_stiffness * eps^2 + chi^2 (5-point Gauss, exact).
Matrix9d stiffness(double h, double membrane_stiffness, bool outside = false);

// The same stiffness in mixed (Hellinger-Reissner) form, stiffness = G^T H^-1 G exactly: eps and
// chi are cubics on the element, so their Legendre coefficients (P0..P3 on xi in [0, 1]) carry
// them whole. Rows 0-3 of G are the integrals of P_i eps ds, rows 4-7 those of P_i chi ds; H is
// diagonal, h / ((2i + 1) membrane_stiffness) for eps and h / (2i + 1) for chi. A stiff membrane
// (EA R^2 / EI up to 1e7) becomes a small compliance instead of a large stiffness.
inline constexpr int stresses = 8;
using Matrix89d = Eigen::Matrix<double, 8, 9>;
using Vector8d = Eigen::Matrix<double, 8, 1>;
Matrix89d stress_coupling(double h, bool outside = false);
Vector8d compliance(double h, double membrane_stiffness);

}  // namespace liftoff::fe::arch_element
