#pragma once
// Euler-Bernoulli beam element, nondimensional (EI = 1): Hermite cubic deflection,
// local dofs (w0, w0', w1, w1') with w' = dw/ds.

#include <Eigen/Dense>

namespace liftoff::fe::beam_element {

inline constexpr int dofs = 4;
// Bending stiffness, closed form: integral of N''^T N'' over the element.
Eigen::Matrix4d stiffness(double h);

}  // namespace liftoff::fe::beam_element
