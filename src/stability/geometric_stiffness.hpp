#pragma once
// The geometric stiffness K_g of a discretised beam on its equations: the sum over the mesh's
// elements of beam_element::geometric_stiffness(h) (the integral of N'^T N', closed form) on the
// element's dofs, the dofs fixed by supports or the gauge left out, so that a constant compressive
// axial force N (positive compresses, nondimensional N L^2 / EI) lowers the stiffness to
// K - N K_g. K_g is symmetric and positive semidefinite: its kernel holds w = const.
//
// One function, so that a K_g the discretisation itself assembles (the axial loads' issue may add
// one to fe::Discretisation) can take its place without touching the stability solver.

#include <Eigen/Sparse>

#include "fe/discretisation.hpp"

namespace liftoff::stability {

// Throws std::invalid_argument for an arch (no geometric stiffness is defined for it here).
Eigen::SparseMatrix<double> geometric_stiffness(const fe::Discretisation& discretisation);

}  // namespace liftoff::stability
