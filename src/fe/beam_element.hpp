#pragma once
// Euler-Bernoulli beam element, nondimensional (EI = 1): Hermite cubic deflection,
// local dofs (w0, w0', w1, w1') with w' = dw/ds.

#include <Eigen/Dense>

namespace liftoff::fe::beam_element {

inline constexpr int dofs = 4;
// Bending stiffness, closed form: integral of N''^T N'' over the element.
Eigen::Matrix4d stiffness(double h);
// Geometric stiffness, closed form: integral of N'^T N' over the element (the consistent one of the
// Hermite cubics). A compressive axial force N (positive compresses; nondimensional N L^2 / EI)
// lowers the stiffness to stiffness - N geometric_stiffness: the second-order (P-delta) energy
// -N/2 (integral of w'^2) of EI w'''' + N w'' = q.
Eigen::Matrix4d geometric_stiffness(double h);

// The same stiffness in mixed (Hellinger-Reissner) form, stiffness = G^T H^-1 G exactly: the
// curvature w'' (linear on the element) has the Legendre coefficients c = H^-1 G u, with
//   G = [ 0    -1   0    1 ]   (integral of w'' ds          = w1' - w0')
//       [ 2/h   1  -2/h  1 ]   (integral of (2 xi - 1) w'' ds = w1' + w0' - 2 (w1 - w0)/h)
// and H = diag(h, h/3). Every entry is an integer or +-2/h, so the rounded G of an element is
// exactly the G of an element of length 2/fl(2/h): the rigid motions stay in its kernel.
inline constexpr int stresses = 2;
Eigen::Matrix<double, 2, 4> stress_coupling(double h);
Eigen::Vector2d compliance(double h);

}  // namespace liftoff::fe::beam_element
