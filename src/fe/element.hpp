#pragma once
// The element seam: what an assembler asks of every element, linear or not.
//
// Given an element's state, an element returns its internal force vector f_int (the
// derivative of its stored energy with respect to its local dofs, in the element's local
// order) and its tangent stiffness K_t = d f_int / d u_e. A linear element returns K_e u_e and
// K_e. Everything is nondimensional (member_model.hpp); loads are not internal forces and stay
// with the assembly (discretisation.cpp), so the residual of a member is
//   R(u, lambda) = sum over elements of f_int(u_e, lambda) - F_dead - lambda F_live.
//
// What the state holds, and why: a geometrically nonlinear element (issues 15 and 16) needs
//  - the dof values u_e on every local dof, prescribed ones included (a settled support moves
//    the element, and a nonlinear element cannot take that as a load K u_f);
//  - the load factor lambda, for an element whose energy depends on the load parameter itself:
//    a beam-column under a prescribed axial force N = lambda P has
//    f_int = (K_e - lambda P K_g) u_e, K_t = K_e - lambda P K_g.
// A von Karman beam or a shallow arch with its own axial dofs reads u_e only: the membrane strain
// u' + w'^2 / 2 (plus the initial rise's w_0' w') is a function of them. Its reference geometry
// (length, initial rise, side of the foundation) is fixed when the element is built, not state.
// The foundation's contact status is not element state either: the tensionless part stays in
// the complementarity conditions (T, C), which no element here carries.
//
// The contract, which the tests check for every element: K_t is the Jacobian of f_int (central
// differences agree to their truncation and round-off), and K_t is symmetric where f_int has a
// potential (all elements here). evaluate() allocates nothing once `response` has its sizes.

#include <Eigen/Dense>

namespace liftoff::fe {

struct ElementState {
  Eigen::VectorXd displacement;  // u_e, local order, size Element::dofs()
  double load_factor = 0.0;      // lambda
};

struct ElementResponse {
  Eigen::VectorXd internal_force;  // f_int(u_e, lambda)
  Eigen::MatrixXd tangent;         // K_t = d f_int / d u_e
};

class Element {
 public:
  virtual ~Element() = default;
  virtual int dofs() const = 0;
  // Whether K_t is the same at every state (then f_int = K_t u_e): an assembler may then
  // assemble once.
  virtual bool is_linear() const = 0;
  // f_int and K_t at `state` into `response` (resized only if its sizes differ). Throws
  // std::invalid_argument if state.displacement has not dofs() entries.
  virtual void evaluate(const ElementState& state, ElementResponse& response) const = 0;
  ElementResponse evaluate(const ElementState& state) const {
    ElementResponse response;
    evaluate(state, response);
    return response;
  }
};

// An element with a constant stiffness: f_int = K_e u_e, K_t = K_e, whatever lambda.
class LinearElement : public Element {
 public:
  explicit LinearElement(Eigen::MatrixXd stiffness);
  int dofs() const override { return static_cast<int>(stiffness_.rows()); }
  bool is_linear() const override { return true; }
  using Element::evaluate;
  void evaluate(const ElementState& state, ElementResponse& response) const override;
  const Eigen::MatrixXd& stiffness() const { return stiffness_; }

 private:
  Eigen::MatrixXd stiffness_;
};

// The linear elements of this code, each on its local dofs:
// the Euler-Bernoulli beam (beam_element.hpp, 4 dofs, bending only);
class BeamElement final : public LinearElement {
 public:
  explicit BeamElement(double h);
};
// the circular arch (arch_element.hpp, 9 dofs: w Hermite, then u quartic);
class ArchElement final : public LinearElement {
 public:
  ArchElement(double h, double membrane_stiffness, bool foundation_outside);
};
// the beam-column (beam_element.hpp, 4 dofs): the beam under a compressive axial force
// N(lambda) = dead + lambda live (positive compresses, nondimensional N L^2 / EI), second-order
// theory: f_int = (K_e - N K_g) u_e, K_t = K_e - N K_g, with K_g the consistent geometric
// stiffness. Not linear in this seam's sense when live != 0: K_t changes with lambda.
class BeamColumnElement final : public Element {
 public:
  BeamColumnElement(double h, double axial_dead, double axial_live);
  int dofs() const override { return 4; }
  bool is_linear() const override { return axial_live_ == 0.0; }
  using Element::evaluate;
  void evaluate(const ElementState& state, ElementResponse& response) const override;
  double axial_force(double load_factor) const { return axial_dead_ + load_factor * axial_live_; }

 private:
  Eigen::Matrix4d bending_, geometric_;
  double axial_dead_, axial_live_;
};
// the bilateral (Winkler) foundation of parameter K_t on the Hermite dofs of w (4 dofs; the first
// four local dofs of either element above): K_t times the integral of N_w^T N_w, by the 4-point
// rule of foundation_element::winkler_rule (exact). The tensionless part is not an element (see
// above).
class WinklerElement final : public LinearElement {
 public:
  WinklerElement(double h, double tension_k);
};

}  // namespace liftoff::fe
