#pragma once
// The von Karman beam element (moderate rotations), and with an initial shape the shallow arch of
// any shape (Marguerre): the geometrically nonlinear element of issue 16 on the element seam
// (element.hpp). Nondimensional as the others: EI = 1, lengths by the member's length L, the
// membrane stiffness EA L^2 / EI.
//
// Kinematics. s along the chord; w transverse, positive toward the foundation (as everywhere in
// liftoff); u axial, positive toward increasing s. The initial shape w_0(s) is measured like w
// (positive toward the foundation) and is stress free; the member's shape is w_0 + w. Strains
// (' = d/ds):
//   membrane  eps = u' + w_0' w' + w'^2 / 2     (normal force N = EA eps, tension positive)
//   bending   chi = w''                         (the change of curvature; w_0'' is stress free)
// and the stored energy of an element is  EA/2 int eps^2 ds + 1/2 int w''^2 ds.
// An arch rising *away* from the foundation (a hump on its bedding, loaded toward the foundation,
// q > 0, so that it flattens and snaps toward it) has w_0 < 0: [geometry] initial_shape
// { shape = "half_sine", amplitude = -a } is w_0 = -a sin(pi s), a > 0. A load q > 0 then
// compresses it (N < 0) until the snap. The sign of w_0 enters eps only through w_0' w', so a
// rise toward the foundation (w_0 > 0) stiffens the member against q > 0 in tension instead.
//
// What the model neglects: rotations are moderate (w_0' + w' small against 1, so cos -> 1,
// sin -> tan -> the slope), the axial load and the foundation act along the chord's normal, not
// along the current normal (the difference is of the order of the slope squared), and shear
// deformation (Euler-Bernoulli). The foundation is not part of this element (WinklerElement, and
// the tensionless conditions of the contact problem, act on its first four dofs).
//
// Interpolation, and why it does not lock. w is the Hermite cubic (w', quadratic; w'^2, quartic);
// w_0' is known at the Gauss points (below). Equilibrium without axial loads makes N, hence eps,
// constant along the member; an axial field u whose u' cannot follow the varying part of
// w_0' w' + w'^2 / 2 leaves that part as a spurious strain whose energy grows like EA at a given
// deflection: membrane locking. A linear u leaves all of it, a quadratic u the P2..P4 (Legendre)
// parts (strains ~ (w'' h)^2), a quartic u (the arch element's) only the P4 part of w'^2 / 2,
// (w''' h^2)^2 / 560 P4(xi), small but still EA times h^9 (w''')^4 in energy. Here u is a quintic
// (u' a complete quartic) with its four interior values condensed out, which leaves none. The
// energy is quadratic in u, so the condensation is exact and closed form: with the 5-point Gauss
// rule below (exact for (u' + w_0' w' + w'^2/2)^2 when w_0' has degree <= 2; for any w_0' the rule
// defines the energy), u' takes any values at the 5 points with its integral u1 - u0 fixed, so the
// minimising u' makes eps the same at every point:
//   eps = (u1 - u0) / h + (1/h) int (w_0' w' + w'^2 / 2) ds,       constant on the element,
// as equilibrium asks, however stiff EA. Nothing constrains w but what the physics constrains: no
// locking, and n + 1 axial unknowns on a member of n elements instead of 5n + 1 (the test checks
// the condensation from its definition, and that the assembled member's error does not depend on
// EA from 1e2 to 1e6).
//
// Local dofs (6): (w0, w0', w1, w1') Hermite, then (u0, u1) the end values of u.
// Quadrature: int w'^2 ds = w^T K_g w in closed form (beam_element::geometric_stiffness, exact
// for the quadratic w'), int w_0' w' ds by the 5-point Gauss rule (exact for w_0' of degree <= 7),
// int w''^2 in closed form (beam_element::stiffness). With
//   a_0 = int w_0' N_w' ds,   b = d eps / d q_e = ([a_0 + K_g w] / h, -1/h, 1/h),
// the internal force and the consistent tangent are
//   f_int = [K_b w + N (a_0 + K_g w); -N; N],   K_t = [K_b + N K_g, 0; 0, 0] + EA h b b^T,
// symmetric (f_int has a potential). At q_e = 0 and w_0 = 0, K_t is the linear beam's K_b and the
// bar's EA/h [1 -1; -1 1], uncoupled; with w_0 it is the linear shallow arch's stiffness.

#include <array>
#include <functional>

#include "fe/element.hpp"

namespace liftoff::fe {

namespace von_karman_element {
inline constexpr int dofs = 6;
inline constexpr int quadrature_points = 5;  // gauss5 (shape_functions.hpp)
// The initial slope w_0' at the points of gauss5 on the element (zeros: a straight member).
using InitialSlopes = std::array<double, quadrature_points>;
// w_0' sampled at s0 + xi_q h for each point of gauss5: the slopes of an initial shape on the element
// [s0, s0 + h].
InitialSlopes sample_initial_slopes(const std::function<double(double)>& initial_slope, double s0, double h);
}  // namespace von_karman_element

class VonKarmanBeamElement final : public Element {
 public:
  // h > 0 (the element's length), membrane_stiffness = EA L^2 / EI > 0, the initial slopes finite.
  // Throws std::invalid_argument naming the argument otherwise.
  VonKarmanBeamElement(double h, double membrane_stiffness, von_karman_element::InitialSlopes initial_slopes = {});

  int dofs() const override { return von_karman_element::dofs; }
  bool is_linear() const override { return false; }
  using Element::evaluate;
  // lambda is not read: the loads stay with the assembly.
  void evaluate(const ElementState& state, ElementResponse& response) const override;

  // The (constant) membrane strain of the element, its normal force EA eps, and its stored energy
  // EA h eps^2 / 2 + w^T K_b w / 2, at the local dofs u_e (size dofs(), else std::invalid_argument).
  double membrane_strain(const Eigen::VectorXd& displacement) const;
  double normal_force(const Eigen::VectorXd& displacement) const {
    return membrane_stiffness_ * membrane_strain(displacement);
  }
  double energy(const Eigen::VectorXd& displacement) const;

  double length() const { return h_; }
  double membrane_stiffness() const { return membrane_stiffness_; }

 private:
  double h_, membrane_stiffness_;
  Eigen::Matrix4d bending_, geometric_;  // K_b, K_g
  Eigen::Vector4d initial_coupling_;     // a_0 = int w_0' N_w' ds
};

}  // namespace liftoff::fe
