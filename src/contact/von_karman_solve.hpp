#pragma once
// The FE von Karman beam, or circular arch, on a tensionless foundation at one load factor (issue
// 16, items 1 and 2): the equilibrium
//   f_int(x) + C^T r = F,   gap = T r - C w + c >= 0,  r >= 0,  r.gap = 0,
// with f_int the von Karman elements' internal force (beams fe/von_karman_element.hpp, arches
// fe/arch_von_karman_element.hpp) plus the linear parts of the discretisation (Winkler part of a
// bilinear foundation, springs), C, T, c the foundation of fe::discretise, and F a load on the
// unknowns (F_dead + lambda F_live, or any vector the caller builds). It lives in contact/ beside
// the linear `fast` solver, whose sign checks its outer loop repeats. The element kind enters only
// through the element list (one entry per mesh element: the element, the linear part of it already
// in the discretisation's K, where its local dofs sit); the Newton, line search and contact-set
// loop below are the same for both.
//
// Unknowns x, beams: (the discretisation's equations: Hermite w, w' left free by the supports;
// then the axial u at every node not axially restrained). With neither end restrained, u at the
// first node is fixed as a gauge (no axial load exists, so the axial rigid motion carries no work).
// Arches: the discretisation's equations alone (u is already one of its unknowns); each end's u
// and w are the arch's own supports (model::EndSupport): pinned u = w = 0, clamped also the
// rotation, roller w = 0 with u free (no thrust is taken at the end: N = 0 there), free nothing.
// An arch on two rollers keeps the discretisation's gauge (u = 0 at the crown): under linear
// theory the rotation about the centre is strain free; under this theory it stretches the arch by
// c^2 / 2 (the rollers hold the ends on their tangents while the rotation would move them along
// the circle), so the gauge is no longer free of consequence but it is consistent with a symmetric
// answer, and an asymmetric answer of such an arch is out of reach here.
// Arches: the foundation and the loads act along the undeformed normal (C and F are the linear
// discretisation's), not the current one: the difference is a force of the order of the rotation
// beta times the reaction (or load), tangential, i.e. relative order beta, which the shallow
// (Marguerre/Donnell) approximation drops with beta^2 against 1 in the strain; the reaction's
// tangential component k w beta is dropped the same way. This is the current radial direction
// within the approximation, not beyond it.
//
// Method, and why. For a fixed contact set A (reactions on A bilateral, r = 0 elsewhere) the
// problem is smooth and has a potential,
//   Pi_A(x) = strain energy (bending + membrane + linear parts) + 1/2 g_A^T T_AA^-1 g_A - F.x,
//   g_A = C_A w - c_A  (so that r_A = T_AA^-1 g_A makes gap_A = 0),
// whose gradient is the residual R = f_int + C_A^T r_A - F and whose Hessian S = K_t + C_A^T
// T_AA^-1 C_A. Newton's direction S p = -R comes from the sparse saddle system
// [K_t C_A^T; C_A -T_AA] (p, rho) = (-R, 0), factorised by a symmetric LDL^T whose inertia tells
// whether S is positive definite (Sylvester: S > 0 iff the factor has exactly |A| negative pivots).
// Where it is not (past a limit point, on an unstable branch) K_t is shifted by mu diag|K_t| with
// mu raised tenfold until it is (a modified Newton step, always a descent direction); the step
// length then comes from Armijo backtracking on Pi_A. A direction that is still not a descent
// direction in floating point is replaced by the scaled gradient -D^-1 R (D = diag|K_t|). An
// energy line search rather than KINSOL's: the first step from zero raises |R| (the membrane
// strain w'^2 / 2 is not yet relieved by u) while it lowers the energy, and backtracking on |R|
// crawls there (fe/von_karman_element_test.cpp's note).
// The outer loop over contact sets does what the `fast` solver does
// (contact/active_set_solver.hpp): after the set's equilibrium, reactions that pull are released
// and inactive nodes with a negative gap are added (block steps); a set seen before switches to
// single flips of the worst node, and a set seen again after that ends the solve as
// `contact_cycling`.
//
// What is guaranteed. Per inner step: Pi_A decreases (Armijo), or, for a full unshifted Newton
// step only, |R| halves (near the answer Pi's change falls below its round-off while |R| still
// measures progress); so the inner iteration cannot cycle or run away. Near a solution with S
// positive definite the full step is taken and the convergence is quadratic (the tangent is
// consistent; the history shows it). There is no global guarantee: the energy is not convex, so
// the equilibrium found is a local minimum of Pi_A (a stable state for its set) reached from the
// start, which past a limit point depends on the start (the load path): the path driver passes
// the previous step's answer (`start`, and its contact set). The outer loop has no
// finite-termination proof (the contact problem is no longer an LCP with a P-matrix); it is
// bounded by max_contact_sets and the cycle guard. Every failure is a termination other than
// `solved`, with a reason; `solved` is returned only when the residual is below the tolerance and
// every sign holds. With globalisation = none the inner loop is plain Newton (full steps, no
// shift, a sparse LU): for comparison, and for a caller that wants the equilibrium nearest its
// start, stable or not (VonKarmanResult::stable says which).
//
// Limits. The Newton systems are the primal ones (K_t on w, w', u), whose condition grows like
// h^-4: the answer's error, estimated by one more Newton correction at it, is ~1e-10 on 200
// elements, 1e-7 on 2000 and percents on 5000, where the solve ends `inaccurate` (max_error)
// rather than `solved`. The seed's arch (EA R^2 / EI = 3e6) converges to ~1e-10 on 400 elements and
// 2e-8 on 2000, with one step of iterative refinement of each Newton direction (without it the
// line search stalled at |R| ~ 1e-7 on 400 elements). The linear solvers' mixed form (contact/active_set_system.hpp)
// would lift this; members needing more than ~2000 elements are out of reach here.

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "fe/discretisation.hpp"
#include "fe/element.hpp"
#include "fe/von_karman_element.hpp"
#include "model/member_model.hpp"

namespace liftoff::contact {

enum class VonKarmanGlobalisation { energy_line_search, none };

struct VonKarmanOptions {
  VonKarmanGlobalisation globalisation = VonKarmanGlobalisation::energy_line_search;
  int max_newton_iterations = 100;  // per contact set
  int max_contact_sets = 50;
  // Converged when the componentwise backward error max_i |R_i| / s_i is at most this, s_i the
  // forces summed into R_i in magnitude (|K| |x|, |F|, the membrane's terms, |C_A^T| r_A): a few
  // hundred eps, whatever the mesh (|K| grows like h^-3) and EA.
  double residual_tolerance = 256 * std::numeric_limits<double>::epsilon();
  double armijo = 1e-4;         // sufficient decrease: Pi(x + a p) <= Pi(x) + armijo a R.p
  int max_backtracks = 40;      // halvings of the step
  double initial_shift = 1e-8;  // the first mu tried when S is not positive definite
  int max_shifts = 30;
  // A reaction or gap counts as negative below -sign_tolerance times the largest reaction or
  // C w term (round-off must not flip a node at r = gap = 0).
  double sign_tolerance = 1e-10;
  // The answer's relative error (inf-norm), estimated by one more Newton correction at it, at most
  // this; else the termination is `inaccurate` (the fields are still filled).
  double max_error = 1e-6;
  void validate() const;  // throws std::invalid_argument naming the field
};

enum class VonKarmanTermination {
  solved,              // backward error below tolerance on the set, every reaction >= 0, every gap >= 0,
                       // error_estimate <= max_error
  iteration_limit,     // max_newton_iterations on one set without convergence
  line_search_failed,  // no step of the backtracking decreased the energy enough (round-off floor
                       // above the tolerance, or a non-smooth point)
  diverged,            // plain Newton only: a non-finite or exploding iterate
  singular_system,     // the saddle system could not be factorised even shifted
  contact_cycling,     // a contact set came back after single flips
  contact_set_limit,   // max_contact_sets sets tried
  inaccurate,          // converged and signs hold, but error_estimate > max_error (round-off of the primal
                       // system on a very fine mesh: its condition grows like h^-4)
};
std::string_view to_string(VonKarmanTermination);

struct VonKarmanIteration {
  int contact_set = 0;    // which set (0, 1, ...) the step was taken on
  double residual = 0.0;  // |R|_inf before the step
  double energy = 0.0;    // Pi on the set before the step
  double step = 0.0;      // the step length taken (1: the full Newton step)
  double shift = 0.0;     // mu (0: the Newton step itself)
  bool gradient_step = false;
};

struct VonKarmanResult {
  VonKarmanTermination termination = VonKarmanTermination::iteration_limit;
  std::string message;
  bool is_usable() const { return termination == VonKarmanTermination::solved; }
  Eigen::VectorXd x;  // on the unknowns: the start for the next load factor
  // On the mesh nodes: w (settled supports included), w' and u.
  Eigen::VectorXd w, theta, u;
  Eigen::VectorXd reaction;  // r, one per reaction unknown (0 off the set)
  Eigen::VectorXd gap;       // T r - C w + c
  std::vector<bool> in_contact;
  std::vector<double> normal_force;  // N = EA eps per element (tension positive)
  double energy = 0.0;               // Pi on the final set
  bool stable = false;               // S positive definite at the answer (on its contact set)
  double error_estimate = -1.0;      // |one more Newton correction|_inf / |x|_inf (solved answers)
  std::vector<VonKarmanIteration> history;
  std::vector<double> set_residuals;  // |R|_inf at the end of each contact set's Newton iteration
  int contact_sets = 0;
};

// The selection of one contact set A of a discretisation: its reaction indices, C_A (|A| x the
// discretisation's equations), T_AA and c_A (the ground gap on A; zero where the discretisation
// has none). The solve below and the path driver (continuation/models/fe_member.hpp) build
// their set equations from it.
struct ContactSelection {
  std::vector<bool> in_contact;  // per reaction node
  std::vector<int> members;      // reaction indices on the set
  Eigen::SparseMatrix<double> coupling;
  Eigen::SparseMatrix<double> flexibility;
  Eigen::VectorXd ground_gap;
  int size() const { return static_cast<int>(members.size()); }
};
ContactSelection select_contact_set(const fe::Discretisation& discretisation, std::vector<bool> in_contact);

// The nonlinear system of one member on one mesh. model: a beam or an arch with theory =
// von_karman and membrane_stiffness > 0, no given axial force; discretisation: fe::discretise of
// it (the same kind). Throws std::invalid_argument naming what is wrong otherwise. The
// discretisation must outlive the system.
class VonKarmanSystem {
 public:
  VonKarmanSystem(const model::MemberModel& model, const fe::Discretisation& discretisation);

  int unknowns() const { return discretisation_->equations + static_cast<int>(axial_nodes_.size()); }
  // F_dead + lambda F_live on the unknowns (zero on the axial ones).
  Eigen::VectorXd load(double load_factor) const;
  // Equilibrium under `load` (unknowns()) from `start` (empty: zero) with the first contact set
  // `initial_set` (empty: every node in contact, as the `fast` solver starts; a bilateral
  // foundation keeps every node whatever is given).
  VonKarmanResult solve(const Eigen::VectorXd& load, const VonKarmanOptions& options, const Eigen::VectorXd& start = {},
                        std::vector<bool> initial_set = {}) const;
  VonKarmanResult solve(double load_factor, const VonKarmanOptions& options, const Eigen::VectorXd& start = {},
                        std::vector<bool> initial_set = {}) const {
    return solve(load(load_factor), options, start, std::move(initial_set));
  }

  // The total potential on a contact set, and the per-element normal forces, at x (for tests and
  // the path driver). Beams: N is constant on an element; arches: N = EA eps varies along it, and
  // normal_forces gives its mean over the element (the Gauss rule's), normal_force the value at xi
  // in [0, 1] of element e.
  double energy(const Eigen::VectorXd& x, const Eigen::VectorXd& load, const std::vector<bool>& in_contact) const;
  std::vector<double> normal_forces(const Eigen::VectorXd& x) const;
  double normal_force(const Eigen::VectorXd& x, int element, double xi) const;
  // The axial unknown of a mesh node (-1: restrained or the gauge; always -1 for arches, whose u
  // is a discretisation dof).
  int axial_unknown(int node) const { return axial_unknown_[node]; }
  // The set-free part of the equations, for a path driver that carries the reactions as unknowns
  // itself (continuation/models/fe_member.hpp): f_int(x), the elements' internal force plus the
  // linear parts of the discretisation (no load, no reactions), and its Jacobian K_t. K_t's
  // sparsity pattern does not depend on x (every element's 6 x 6 coupling and K's pattern are
  // stored, zeros included), so a caller may analyse it once.
  Eigen::VectorXd internal_force(const Eigen::VectorXd& x) const;
  Eigen::SparseMatrix<double> tangent_stiffness(const Eigen::VectorXd& x) const;
  const fe::Discretisation& discretisation() const { return *discretisation_; }

  // One mesh element's nonlinear part: the element (through the seam), the linear stiffness of it
  // that the discretisation's K already holds (subtracted from its response), where its local dofs
  // are (dof: the discretisation's dof, read through expand_displacement, or -1; unknown: its
  // index in x, or -1 where fixed), and what the seam does not give (energy, N at xi).
  struct Piece {
    std::shared_ptr<const fe::Element> element;
    Eigen::MatrixXd linear;
    std::vector<int> dof, unknown;
    std::function<double(const Eigen::VectorXd&)> energy;
    std::function<double(const Eigen::VectorXd&, double)> normal_force;
    // The terms summed into the element's force, in magnitude, per local dof (the backward
    // error's scale); empty: |K_t| |q_e| + |f_int| of the nonlinear part. The arch's integrated
    // K hides the cancellation of u' against w at each point (nearly inextensional bending at
    // EA R^2 / EI ~ 1e6), so it sums the points' terms itself.
    std::function<Eigen::VectorXd(const Eigen::VectorXd&)> force_terms;
  };

 private:
  const fe::Discretisation* discretisation_;
  double membrane_stiffness_;
  std::vector<int> axial_nodes_;    // the nodes whose u is unknown
  std::vector<int> axial_unknown_;  // per node
  std::vector<Piece> pieces_;
};

// The circular arch under von Karman theory at one load factor: VonKarmanSystem(model,
// discretisation).solve(load_factor, options, start), for `liftoff solve` and the studies. model:
// an arch with theory = von_karman (else std::invalid_argument); the result as for beams, its u
// the arch's tangential displacement at the nodes and w, theta = w' its radial ones.
VonKarmanResult solve_arch_von_karman(const model::MemberModel& model, const fe::Discretisation& discretisation,
                                      double load_factor, const VonKarmanOptions& options = {},
                                      const Eigen::VectorXd& start = {}, std::vector<bool> initial_set = {});

}  // namespace liftoff::contact
