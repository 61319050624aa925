#pragma once
// The Ritz model of a member on a tensionless Winkler foundation with moving contact limits
// (Silveira, Pereira & Goncalves 2008, sec. 4), nondimensional as model::MemberModel.
//
// Displacements w = sum W_i phi_i(s) and, for arches, u = sum U_i psi_i(s) (basis.hpp). The
// foundation's extent [foundation_begin, foundation_end] is cut by the limits t_1 < ... < t_M
// into M + 1 pieces which alternate between contact and lift-off, the first one as the
// Topology says. The unknowns are
//     x = (W_1..W_N, [U_1..U_N for arches], t_1..t_M),
// and the total potential energy (EI = 1, length scale 1, EA_hat = membrane_stiffness) is
//     beam: Pi = 1/2 int w''^2 + k/2 int_contact w^2 - F(lambda).A
//     arch: Pi = 1/2 int (EA_hat (u' - w)^2 + (u' + w'')^2) + k/2 int_contact w^2 - F(lambda).A
// with F(lambda) = F_dead + lambda F_live the work-equivalent load vector: a force P at s does
// work P w(s); a counterclockwise moment M does work -M w'(s) (beam) or -M (u + w')(s) (arch);
// a uniform load q over [from, to] does work q int w. Arch forces act along the radius.
//
// Beams under a compressive axial force N = N_dead + lambda N_live (model::MemberModel::
// axial_force, compression > 0; second-order theory) with a stress-free initial shape w0 (w is
// measured from w0, positive toward the foundation, and the ground follows w0, so the foundation
// term is unchanged) add
//     - N/2 int w'^2 - N int w0' w'      (over the whole member)
// = - N/2 W.K_g W - N f_0.W,  K_g = int phi_i' phi_j',  f_0 = int w0' phi_i' (closed form: w0 is
// piecewise linear, so f_0 sums slope (phi_i(hi) - phi_i(lo)) over its pieces). The first softens
// the stiffness, the second is the load -N w0'' of the imperfection. Neither depends on the
// limits, so the limit equations are those without N. Arches take no axial force (refused).
//
// Beams under von Karman kinematics (model::MemberModel::theory == von_karman) add the membrane
// energy of von_karman_membrane.hpp, Pi_m = EA e(W)^2 / (2 L), to Pi, its gradient to the
// amplitude rows of the residual and its Hessian (EA/L) b b^T + N K_g to the Jacobian, the Hessian
// and the reduced Hessian (so to stability_margin): built from the member's membrane_stiffness,
// its ends' axial restraint and w0 (initial_sine kept exact, as a TrigPolynomial, when it is one
// half sine over the whole member; the initial_shape table otherwise). N comes from the exact
// condensation of u when BOTH ends are axially restrained; with one end free or both, nothing
// holds the member axially, N = 0 and the term vanishes (the answers are linear theory's). It
// does not depend on the limits nor on lambda. Arches under von Karman are refused
// (unsupported_input: their shallow-shell membrane energy is not in this model).
//
// Everything that does not depend on the limits (stiffness, loads) is integrated once, in
// closed form, at construction; the foundation term is integrated exactly over the current
// pieces at every call, through a product table (product_table.hpp) built at construction, so
// that each distinct term of the products phi_i phi_j is integrated once per piece. All
// functions take any x of size unknowns() (std::invalid_argument otherwise); their values
// are those of the formulas above, physically meaningful only where admissible(x). Nothing
// here solves the nonlinear system: that is a Newton solver's job.
//
// The system to solve is the REGULARISED stationarity condition:
//     R_A = dPi/dA = K A + k G(t) W - F(lambda) = 0      (amplitude rows; with N: - N (K_g W + f_0))
//     R_m = w(t_m) = 0                                   (one row per limit)
// in place of dPi/dt_m = sigma_m k/2 w(t_m)^2 = 0 (sigma_m = +1 if t_m ends a contact piece,
// -1 if it starts one), which has a double root. At a solution the amplitude-limit block of
// the Jacobian, sigma_m k phi(t_m) w(t_m), vanishes, so the Jacobian is block triangular and
// nonsingular when K + k G is and w'(t_m) != 0: Newton converges quadratically.

#include <Eigen/Dense>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/contact_region.hpp"
#include "model/member_model.hpp"
#include "ritz/basis.hpp"
#include "ritz/product_table.hpp"

namespace liftoff::ritz {

class VonKarmanMembrane;  // von_karman_membrane.hpp

// Which pieces of the foundation's extent are in contact: the first (from foundation_begin)
// as first_in_contact says, then alternating at each of the `limits` contact limits.
struct Topology {
  bool first_in_contact = true;
  int limits = 0;
  void validate() const;  // throws std::invalid_argument if limits < 0
};
std::string to_string(const Topology&);  // e.g. "contact | lift-off | contact (2 limits)"

// What the moving-boundary model cannot take, found from the member before anything is solved:
// the scene key that brings it in and what the model takes instead. The one list of them, used by
// RitzModel, `solve --method ritz` and the Ritz trace path, so that every refusal names the same
// key. gap_key and tension_key: the keys the user wrote (gap or gap_file, tension_modulus or
// tension_k; scene::Foundation::gap_key()).
struct Unsupported {
  std::string key;   // e.g. "foundation.segments"
  std::string what;  // completes "the moving-boundary model ...", e.g. "takes one foundation piece ..."
  std::string message() const { return "key '" + key + "': the moving-boundary model " + what; }
};
std::optional<Unsupported> unsupported_input(const model::MemberModel& model,
                                             const std::string& gap_key = "foundation.gap",
                                             const std::string& tension_key = "foundation.tension_modulus");

class RitzModel {
 public:
  // Throws std::invalid_argument for what unsupported_input lists, modes < 1, an invalid topology,
  // a bilateral foundation with a topology other than {true, 0}, or a non-finite model value;
  // liftoff::MechanismError for an arch whose u is free at both ends (roller or free ends)
  // loaded by moments: they drive the rigid rotation about the centre, which nothing resists.
  // enrichment: see basis.hpp (modes() then counts the kinked functions too).
  RitzModel(const model::MemberModel& model, int modes, Topology topology, Enrichment enrichment = Enrichment::none);

  // Layout of x.
  int modes() const { return modes_; }            // w functions: the N requested plus the load-point enrichment
  int amplitudes() const { return amplitudes_; }  // N (beam) or 2N (arch)
  int limits() const { return topology_.limits; }
  int unknowns() const { return amplitudes_ + topology_.limits; }
  int w_offset() const { return 0; }
  int u_offset() const { return modes_; }           // arches only
  int limit_offset() const { return amplitudes_; }  // t_m is x[limit_offset() + m], m = 0..M-1
  const Topology& topology() const { return topology_; }
  const Basis& basis() const { return basis_; }
  bool is_arch() const { return arch_; }
  // False for a bilateral foundation: it resists both ways, so w < 0 in contact is no violation.
  bool tensionless() const { return tensionless_; }

  // Limit-independent parts: the stiffness K (amplitudes x amplitudes) and load vectors.
  const Eigen::MatrixXd& stiffness() const { return stiffness_; }
  const Eigen::VectorXd& dead_load() const { return dead_load_; }
  const Eigen::VectorXd& live_load() const { return live_load_; }
  // G(t): integral over the contact pieces of phi_i phi_j (N x N), for the limits in x.
  Eigen::MatrixXd contact_gram(const Eigen::VectorXd& x) const;

  // Pi, dPi/dx (the seed's eq. 4.6) and d2Pi/dx2 (eq. 4.5), all analytic:
  //   d2Pi/dW dt_m = sigma_m k w(t_m) phi(t_m),  d2Pi/dt_m^2 = sigma_m k w(t_m) w'(t_m).
  double energy(const Eigen::VectorXd& x, double lambda) const;
  Eigen::VectorXd gradient(const Eigen::VectorXd& x, double lambda) const;
  Eigen::MatrixXd hessian(const Eigen::VectorXd& x, double lambda) const;

  // The regularised system (see above) and its analytic Jacobian; f and J are resized.
  void residual(const Eigen::VectorXd& x, double lambda, Eigen::VectorXd& f) const;
  void jacobian(const Eigen::VectorXd& x, double lambda, Eigen::MatrixXd& J) const;
  // dR/dlambda = -(F_live + N_live (K_g W + f_0), 0 for the limit rows); it does not depend on
  // lambda (nor on x without a live axial force).
  Eigen::VectorXd residual_lambda_derivative(const Eigen::VectorXd& x) const;

  // Von Karman beams with both ends axially restrained: the membrane term (null otherwise, also
  // when the term is zero because an end is axially free). membrane_force: its N at x (tension
  // > 0; 0 without the term).
  bool has_membrane() const { return membrane_ != nullptr; }
  const VonKarmanMembrane* membrane() const { return membrane_.get(); }
  double membrane_force(const Eigen::VectorXd& x) const;
  // Whether Pi may lose convexity, so that stability is to be checked: an axial force or the
  // membrane term.
  bool can_lose_stability() const { return has_axial_force() || has_membrane(); }

  // Second-order theory (beams): N at lambda, K_g and f_0 (see above; zero without axial force).
  double axial_force(double lambda) const { return axial_dead_ + lambda * axial_live_; }
  bool has_axial_force() const { return axial_dead_ != 0.0 || axial_live_ != 0.0; }
  const Eigen::MatrixXd& geometric_stiffness() const { return geometric_stiffness_; }
  const Eigen::VectorXd& imperfection_load() const { return imperfection_load_; }
  // The Hessian of Pi in the amplitudes at fixed limits, K - N K_g + k G(t): at a solution (w = 0
  // at every limit) the Hessian's amplitude-limit blocks vanish, so this is the stiffness of the
  // state against every perturbation that keeps its contact set. stability_margin: its smallest
  // eigenvalue after scaling by diag(K)^(-1/2) on both sides; > 0: the state is stable (positive
  // definite; lift-off zones pushed into the foundation only stiffen it), <= 0: unstable. NaN if
  // the eigensolver fails.
  Eigen::MatrixXd reduced_hessian(const Eigen::VectorXd& x, double lambda) const;
  double stability_margin(const Eigen::VectorXd& x, double lambda) const;

  // The amplitudes minimising Pi for the given limits (a linear solve of (K + k G) A = F; with an
  // axial force (K - N K_g + k G) W = F + N f_0, stationary rather than minimising if unstable;
  // with the membrane term, its tangent at W = 0, (EA/L) f_0 f_0^T, is added to the matrix),
  // packed with the limits into an x. A starting point for Newton. nullopt if K + k G is
  // singular (a rigid motion that neither the supports nor the contact pieces resist).
  std::optional<Eigen::VectorXd> minimiser_for_limits(const Eigen::VectorXd& limits, double lambda) const;

  // Fields at s: derivative order 0..3 of w, or of u (arches only; std::invalid_argument for
  // beams). The reaction is k w inside a contact piece (ends included), 0 elsewhere.
  double w(const Eigen::VectorXd& x, double s, int derivative = 0) const;
  double u(const Eigen::VectorXd& x, double s, int derivative = 0) const;
  double reaction(const Eigen::VectorXd& x, double s) const;
  // The same with x's contact pieces found once (contact_pieces(x)): for many points.
  double reaction(const Eigen::VectorXd& x, double s, const std::vector<ContactRegion>& pieces) const;
  // w (derivative 0) or w' (1) at the n - 1 interior points a + (b - a) i / n, i = 1..n-1 (values
  // is resized), equal to w(x, s, derivative) there up to round-off but much cheaper (add_on_grid
  // in trig_polynomial.hpp). For checks and scans on dense grids. Throws std::invalid_argument for
  // another derivative.
  void w_on_grid(const Eigen::VectorXd& x, double a, double b, int n, std::vector<double>& values,
                 int derivative = 0) const;

  // The M + 1 pieces of the foundation's extent (s), contact and lift-off alternating, and those in contact.
  std::vector<ContactRegion> pieces(const Eigen::VectorXd& x) const;
  std::vector<ContactRegion> contact_pieces(const Eigen::VectorXd& x) const;
  // Limits finite, strictly increasing and strictly inside (foundation_begin, foundation_end),
  // amplitudes finite.
  bool admissible(const Eigen::VectorXd& x) const;

 private:
  void check_size(const Eigen::VectorXd& x) const;
  double piece_sign(int limit) const;  // sigma_m
  Eigen::VectorXd phi_at(double s, int derivative) const;
  // The basis is smooth between breakpoints (the kinks of basis_.kinked_w): region r is
  // [breakpoint r-1, breakpoint r], the outer ones unbounded.
  int region_of(double s) const;
  // Sum over the regions that [a, b] meets of integrate(r, lo, hi); -(that of [b, a]) if b < a,
  // so that a piece of negative length counts negatively.
  template <class Integrate>
  double split_integral(double a, double b, const Integrate& integrate) const;
  Eigen::VectorXd load(double lambda) const { return dead_load_ + lambda * live_load_; }

  bool arch_ = false;
  bool tensionless_ = true;
  int modes_ = 0;
  int amplitudes_ = 0;
  Topology topology_;
  double k_ = 0.0;
  double foundation_begin_ = 0.0;
  double foundation_end_ = 0.0;
  Basis basis_;
  std::vector<double> breakpoints_;
  std::vector<std::vector<std::vector<TrigPolynomial>>> w_derivatives_;  // [region][order 0..3][i]
  std::vector<std::vector<TrigPolynomial>> u_derivatives_;               // arches
  std::vector<std::vector<TrigTerm>> w_terms_;                           // [region]: every term of every w function
  std::vector<std::vector<int>> w_term_function_;                        // [region]: the function each term is of
  std::vector<std::vector<TrigTerm>> w_slope_terms_;                     // [region]: the same of w'
  std::vector<std::vector<int>> w_slope_term_function_;
  std::vector<ProductTable> w_products_;  // [region]: phi_i phi_j, i <= j
  Eigen::MatrixXd stiffness_;
  double axial_dead_ = 0.0;
  double axial_live_ = 0.0;
  Eigen::MatrixXd geometric_stiffness_;  // modes x modes
  Eigen::VectorXd imperfection_load_;    // modes
  Eigen::VectorXd dead_load_;
  Eigen::VectorXd live_load_;
  std::shared_ptr<const VonKarmanMembrane> membrane_;  // immutable: copies of the model share it
};

}  // namespace liftoff::ritz
