#pragma once
// Loads on a circular arch in any direction, as work-equivalent (consistent) nodal forces.
//
// Geometry (src/README.md, "The model", Arch): theta = 0 at the crown, the centre of curvature below it, theta
// increasing to the right. The point at theta sits at R (sin theta, cos theta) from the centre
// (x to the right, y up); the unit tangent toward increasing theta is t = (cos theta, -sin theta)
// and the inward normal n = -(sin theta, cos theta). A load of unit value is the force vector
//   radial      the direction of w > 0 (toward the foundation): n inside, -n outside
//   tangential  t
//   vertical    (0, -1)   downward, gravity
//   horizontal  (1, 0)    to the right
// and its components on the dofs are (f . e_w, f . t), e_w the direction of w > 0. Inside
// (e_w = n) a vertical load has (cos theta, sin theta), a horizontal one (-sin theta, cos theta);
// outside (e_w = -n) the radial parts change sign.
//
// Per unit horizontal projection (per = "projection"): the arch's horizontal projection is
// x = R sin theta, dx = R cos theta dtheta = cos theta ds, so a load q per unit projection is
// q cos theta per unit arc (|theta| <= 90 deg, where cos theta >= 0; the scene reader checks it).
//
// Every distributed arch load (uniform today, piecewise linear or any q(s)) goes through
// arch_element_load, so the FE assembly and every integrator agree on directions.

#include <Eigen/Dense>
#include <functional>

#include "model/member_model.hpp"

namespace liftoff::fe {

// (along w > 0, along t) per unit value and unit arc length at theta (radians). `outside`: the
// foundation lies outside the arch ([foundation] side = "outside"), so w > 0 is outward.
Eigen::Vector2d arch_load_components(model::LoadDirection direction, model::LoadBasis per, double theta, bool outside);

// The consistent nodal forces of a load of value q(s) (per unit arc or per unit projection, as
// `per` says) along `direction` on the arch element [s0, s0 + h]: the integrals of
// q (c_w N_w + c_t N_u) ds on the element's local dofs (arch_element.hpp order: the Hermite w dofs,
// then the quartic u dofs). Five-point Gauss: exact for polynomial q up to degree 5 times the
// shape functions; the trigonometric components add a relative error ~ h^10 / 10!, round-off
// for every h < 0.5 rad.
Eigen::Matrix<double, 9, 1> arch_element_load(double s0, double h, model::LoadDirection direction, model::LoadBasis per,
                                              bool outside, const std::function<double(double)>& q);

}  // namespace liftoff::fe
