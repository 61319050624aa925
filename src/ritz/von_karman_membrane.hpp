#pragma once
// The von Karman membrane energy of a Ritz beam (issue 16, item 3): a term added to RitzModel's
// energy, not a change of it. Nondimensional as model::MemberModel (EI = 1, lengths over the
// length scale); conventions of fe/von_karman_element.hpp: w and the stress-free initial shape w0
// positive toward the foundation, the ground follows w0, u along s, membrane strain
//     eps = u' + w0' w' + w'^2 / 2,   N = EA eps (tension positive, EA = membrane_stiffness).
//
// Axially restrained ends (u = 0 at both): the energy is quadratic in u, so u condenses exactly:
// equilibrium makes N constant along the member, and integrating eps over the member with
// u(s_end) - u(s_begin) = 0 gives
//     N = (EA / L) e(W),   e(W) = int (w0' w' + w'^2 / 2) ds = f_0.W + W.K_g W / 2,
//     Pi_m = L N^2 / (2 EA) = EA e^2 / (2 L),
// with K_g = int phi_i' phi_j' (the modes' derivative table, product_table.hpp, split at the
// kinks of an enriched basis) and f_0 = int w0' phi_i' (w0 piecewise linear as the member's
// table: sum over its pieces of slope (phi_i(hi) - phi_i(lo)), as issue 15's axial term; or a
// TrigPolynomial w0, e.g. the exact half sine, integrated in closed form). Both integrals run over
// the whole member, so the term does NOT depend on the contact limits: its derivatives in the
// limits are zero, and the regularised system of ritz_model.hpp stays what it is with the
// amplitude rows gaining the gradient below (the limit rows w(t_m) = 0 are unchanged). Analytic:
//     dPi_m/dW = N (f_0 + K_g W),   d2Pi_m/dW2 = (EA / L) b b^T + N K_g,   b = f_0 + K_g W,
// the Ritz image of the FE element's f_int and K_t. The Hessian is not positive semidefinite for
// N < 0 (compression): with w0 != 0 the total energy can lose convexity (snap-through).
// At least one end axially free: N = 0, and the term is zero (the beam stays linear in w).
// With an axial force in the RitzModel too (compression N_c, its -N_c (W.K_g W / 2 + f_0.W)),
// the sum is, up to a constant, the restrained beam with a prestrain -N_c / EA (a temperature
// rise): EA/(2L) (e - L N_c / EA)^2 = Pi_m - N_c e + const (with the same w0: the member's table).
// What is neglected is the element's list: moderate rotations, loads and foundation along the
// chord's normal, no shear deformation. Beams only (arches have their own membrane energy).

#include <Eigen/Dense>
#include <optional>

#include "model/member_model.hpp"
#include "ritz/ritz_model.hpp"
#include "ritz/trig_polynomial.hpp"

namespace liftoff::ritz {

enum class AxialEnds {
  restrained,  // u = 0 at both ends: N from the condensation above
  free,        // u free at one end at least: N = 0, no membrane energy
};

struct MembraneOptions {
  double membrane_stiffness = 0.0;  // EA l^2 / EI (l the length scale); > 0 when restrained
  AxialEnds ends = AxialEnds::restrained;
  // Empty: w0 is the member's initial_shape table (piecewise linear; none: straight). Else this
  // function of s over [s_begin, s_end] replaces it (a sinusoidal w0 integrated exactly).
  std::optional<TrigPolynomial> initial_shape;
  void validate() const;  // throws std::invalid_argument naming the field
};

class VonKarmanMembrane {
 public:
  // member: the beam `ritz` was built from (its s range and w0 table). Throws
  // std::invalid_argument for an arch, invalid options, or non-finite w0 values.
  VonKarmanMembrane(const model::MemberModel& member, const RitzModel& ritz, MembraneOptions options);

  const MembraneOptions& options() const { return options_; }
  int unknowns() const { return unknowns_; }
  int modes() const { return modes_; }
  // K_g = int phi_i' phi_j' and f_0 = int w0' phi_i' over the member (modes x modes, modes).
  const Eigen::MatrixXd& derivative_gram() const { return derivative_gram_; }
  const Eigen::VectorXd& initial_coupling() const { return initial_coupling_; }

  // Every function takes x laid out as RitzModel's (size unknowns(), else std::invalid_argument);
  // only the W amplitudes are read.
  double stretch(const Eigen::VectorXd& x) const;       // e = int (w0' w' + w'^2 / 2) ds
  double normal_force(const Eigen::VectorXd& x) const;  // N (tension > 0); 0 when free
  double energy(const Eigen::VectorXd& x) const;        // Pi_m
  // Sized unknowns() (zero in the limit rows) and unknowns() x unknowns() (zero outside the W block).
  Eigen::VectorXd gradient(const Eigen::VectorXd& x) const;
  Eigen::MatrixXd hessian(const Eigen::VectorXd& x) const;
  // The W block of the Hessian (modes x modes), for reduced Hessians and stability.
  Eigen::MatrixXd amplitude_hessian(const Eigen::VectorXd& x) const;
  // Adds the gradient to f's W rows and the Hessian to J's W block: RitzModel's regularised
  // residual and Jacobian become those of the von Karman beam.
  void add_to_residual(const Eigen::VectorXd& x, Eigen::VectorXd& f) const;
  void add_to_jacobian(const Eigen::VectorXd& x, Eigen::MatrixXd& J) const;

 private:
  void check_size(const Eigen::VectorXd& x) const;
  bool active() const { return options_.ends == AxialEnds::restrained; }

  MembraneOptions options_;
  int modes_ = 0;
  int unknowns_ = 0;
  double length_ = 1.0;  // L
  Eigen::MatrixXd derivative_gram_;
  Eigen::VectorXd initial_coupling_;
};

}  // namespace liftoff::ritz
