#pragma once
// The circular arch element with moderate rotations (issue 16, item 1): the linear locking-free
// arch element (arch_element.hpp) with the shallow-shell (Marguerre/Donnell) membrane strain, on
// the element seam (element.hpp). Nondimensional like ArchElement: R = 1, EI = 1, s = theta, the
// membrane stiffness EA R^2 / EI.
//
// Kinematics, in the arch element's own convention. u tangential (toward increasing theta), w
// radial, positive toward the foundation; sigma = arch_element::inward_sign(outside) (+1 with the
// foundation inside, -1 outside), so that sigma w is the inward displacement. The cross-section
// rotation (counterclockwise) of the linear element, and the strains (' = d/dtheta):
//   beta = -(u + sigma w')                                   (the linear element's rotation)
//   eps  = u' - sigma w + beta^2 / 2                          (membrane, N = EA eps, tension > 0)
//   chi  = u' + sigma w''                                     (bending, the linear element's)
// and the element's stored energy is  EA/2 int eps^2 ds + 1/2 int chi^2 ds. Derivation: the
// point at theta moves by u t + sigma w n (t the tangent, n the inward normal, R = 1); the
// Green strain of the centre line is e + (e^2 + beta^2) / 2 with e = u' - sigma w the linear
// stretch and beta the rotation of the tangent; moderate rotations drop e^2 against beta^2
// (e ~ beta^2 << beta) and keep the curvature change linear. Donnell's shallow form also drops u
// from beta: in a shallow arch of half-angle alpha a nearly inextensional u (u' = sigma w) is
// ~ alpha w against w' ~ w / alpha, so u / w' ~ alpha^2 ~ 16 (rise / span)^2; keeping it, as here,
// makes the rigid rotation about the centre, u = sin c, sigma w = 1 - cos c, strain free to
// second order: eps = -(1 - cos c)^2 / 2 = O(c^4), chi = 0 (the tests check it), while the
// first-order rotation u = c, w = 0 stretches the arch by exactly eps = c^2 / 2, as a straight
// von Karman beam is stretched by an unshortened rotation.
//
// What the model neglects: rotations are moderate (beta^2 small against 1; the linear stretch's
// square e^2 against beta^2), Euler-Bernoulli (no shear), the curvature change linear; loads and
// the foundation act along the undeformed normal and tangent (the difference from the current
// normal is of the order of beta times the load). The foundation is not part of this element
// (WinklerElement, and the tensionless conditions of the contact problem, act on its first four
// dofs, as for ArchElement).
//
// Interpolation (as ArchElement, so the linear part is free of membrane locking): local dofs
// (w0, w0', w1, w1') Hermite cubic, then (u0, u_1/4, u_1/2, u_3/4, u1) Lagrange quartic. The
// quartic u lets u' - sigma w vanish for every cubic w (inextensional bending stores no membrane
// energy); the nonlinear term beta^2 / 2 (degree 8) is followed by the cubic u' only in its part
// of degree <= 3, so at given deflections the P4 (Legendre) part of beta^2 / 2 on the element
// stays as a spurious membrane strain, ~ (beta'' h^2)^2 / 560 P4(xi) as in the von Karman beam
// with a quartic u (von_karman_element.hpp), falling like h^4 against the physical beta^2 / 2 (the
// test measures the assembled arch against the von Karman beam at EA R^2 / EI = 5e4 and 8e5).
//
// Quadrature: the 5-point Gauss rule of ArchElement. It is exact for the linear part (degree 6);
// for the nonlinear terms (degree up to 16) it defines the energy, off the exact integral by
// h^11 times the integrand's tenth derivative, up to a constant. f_int and K_t are the exact derivatives of that
// energy. With the rows a (eps_lin = a q), r (beta = r q), c (chi = c q) of the local dofs q at each point, and b = a +
// beta r = d eps / d q:
//   f_int = sum_g W_g h (EA eps b^T + chi c^T),
//   K_t   = sum_g W_g h (EA b^T b + c^T c + EA eps r^T r),
// symmetric (f_int has a potential; K_t is symmetrised to the last bit). At q = 0, K_t is
// arch_element::stiffness: the same sums of the same products, then symmetrised (the linear
// matrix's (i, j) and (j, i) differ by an ulp or so of rounding).

#include "fe/arch_element.hpp"
#include "fe/element.hpp"

namespace liftoff::fe {

namespace arch_von_karman_element {
inline constexpr int dofs = arch_element::dofs;
// The row mapping the local dofs to the rotation beta at xi (the linear element's beta).
arch_element::Row9d rotation_row(double xi, double h, bool outside = false);
}  // namespace arch_von_karman_element

class ArchVonKarmanElement final : public Element {
 public:
  // h > 0 (the element's angle, radians), membrane_stiffness = EA R^2 / EI > 0, both finite;
  // foundation_outside as ArchElement. Throws std::invalid_argument naming the argument otherwise.
  ArchVonKarmanElement(double h, double membrane_stiffness, bool foundation_outside = false);

  int dofs() const override { return arch_von_karman_element::dofs; }
  bool is_linear() const override { return false; }
  using Element::evaluate;
  // lambda is not read: the loads stay with the assembly.
  void evaluate(const ElementState& state, ElementResponse& response) const override;

  // At the local dofs (size dofs(), else std::invalid_argument): the membrane strain, rotation and
  // curvature change at xi in [0, 1], and the element's stored energy by its rule.
  double membrane_strain(const Eigen::VectorXd& displacement, double xi) const;
  double rotation(const Eigen::VectorXd& displacement, double xi) const;
  double bending_strain(const Eigen::VectorXd& displacement, double xi) const;
  double energy(const Eigen::VectorXd& displacement) const;

  double length() const { return h_; }
  double membrane_stiffness() const { return membrane_stiffness_; }
  bool foundation_outside() const { return outside_; }

 private:
  void check_size(const Eigen::VectorXd& displacement) const;
  double h_, membrane_stiffness_;
  bool outside_;
};

}  // namespace liftoff::fe
