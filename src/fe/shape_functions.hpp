#pragma once
// Shape functions on an element of length h, in the local coordinate xi = (s - s0)/h in [0, 1].
// Derivatives are with respect to s (already divided by powers of h).

#include <Eigen/Dense>

namespace liftoff::fe {

// Hermite cubics for the deflection w, dofs (w0, w0', w1, w1'): C1 across elements.
struct HermiteCubic {
  Eigen::Vector4d value, d1, d2, d3;
};
HermiteCubic hermite_cubic(double xi, double h);

// Lagrange quartic for the tangential displacement u of the arch, nodes at xi = 0, 1/4, 1/2,
// 3/4, 1: C0 across elements. Quartic u makes u' a complete cubic, like w, so the membrane
// strain u' - w can vanish for every inextensional deflection: no membrane locking.
struct LagrangeQuartic {
  Eigen::Matrix<double, 5, 1> value, d1, d2;
};
LagrangeQuartic lagrange_quartic(double xi, double h);
inline constexpr double quartic_nodes[5] = {0.0, 0.25, 0.5, 0.75, 1.0};

// Linear interpolation of the foundation reaction between the element's nodes (the seed's Hb).
Eigen::Vector2d reaction_shape(double xi);

// Gauss-Legendre rule on [0, 1], exact for polynomials of degree 9.
struct GaussPoint {
  double xi;
  double weight;
};
inline constexpr GaussPoint gauss5[5] = {
    {0.5 - 0.5 * 0.9061798459386640, 0.5 * 0.2369268850561891},
    {0.5 - 0.5 * 0.5384693101056831, 0.5 * 0.4786286704993665},
    {0.5, 0.5 * 0.5688888888888889},
    {0.5 + 0.5 * 0.5384693101056831, 0.5 * 0.4786286704993665},
    {0.5 + 0.5 * 0.9061798459386640, 0.5 * 0.2369268850561891},
};

}  // namespace liftoff::fe
