#pragma once
// The answer certificate: an answer (FE + LCP, or Ritz) checked from its final fields alone,
// independently of the solver that produced it and of the solver's own figures (its residual,
// error estimate, contact set). CERTIFICATE.md is the public contract; in short:
//
//  force_balance, moment_balance (arches: force_balance_x, force_balance_y, moment_balance)
//      applied loads = foundation resultant + support reactions, as the work of every force on
//      each rigid motion of the member (beams: translation, rotation about the begin; arches:
//      two translations, rotation about the centre; under an axial force N the work of its nodal
//      forces -N integral of N_w'^T (w' + w0') counts with the loads: on the rotation it is the
//      moment of N at the displaced ends). FE support reactions are the residual of
//      the element equations (sum of K_e u_e, the foundation's nodal forces and the applied
//      nodal loads) at each dof a support fixes, so the imbalance is the rigid-weighted sum of
//      every other row's residual: K m = 0 cancels K u, and the check does not hide behind
//      |K||u| as a row-wise residual does (the primal footing of issue 10: backward error 2e-8
//      per row, 3.5 % out of vertical equilibrium). Tolerance: the round-off a sound answer may
//      leave: twice the assembly's own imbalance for this u, m.(K u - sum K_e u_e) (the
//      assembled K's entries are rounded sums of two elements', so it annihilates the rigid
//      motions only to round-off), plus rows' residuals of 64 eps each adding up like a random
//      walk (4 times the 2-norm of the rigid-weighted row magnitudes |K||u| + |C^T||r| + |F|),
//      plus 64 eps of the terms, plus, for arches, the computed work of K u on the interpolated
//      rigid motion (not zero in exact arithmetic: O(h^4)).
//      Ritz: the support reactions are the Ritz equations' residual on a test function that
//      moves that support alone (the weak end shear and moment; ritz_certificate.cpp says why
//      not the modal series' own end shear, which never converges at clamped ends), so the
//      imbalance is a truncation error: its tolerance is the change of the balance terms from a
//      solve with half the modes (the model's own convergence estimate), times 4.
//  reaction_sign, penetration, separation, complementarity
//      FE: the seed's discrete conditions r_i >= 0, gap_i >= 0, r_i gap_i = 0 with the weighted
//      gap gap_i = integral of phi_i (r/k - w) recomputed here by quadrature of the element
//      cubics against the P1 reaction (not from the solver's C and T), each relative to the
//      magnitude of its terms; and pointwise on `samples_per_element` + 1 points of every
//      element on the foundation: r >= 0, w <= 0 where r = 0 (penetration), w >= 0 where r > 0
//      (separation). The pointwise conditions hold only in the continuum: inside a limit
//      element (w changes sign in it or in a neighbour, or its two nodes differ in contact) the
//      mixed P1/cubic model violates them by O(h) (measured on the shipped scenes at 50 to 800
//      elements: 1e-3 to 2e-2 of max |w|), reported as `limit_element_defect`, not gated;
//      outside them the shipped scenes show at most 2e-16. Ritz: on a grid of every piece (as
//      ritz_solver's check); complementarity is w at the limits. Tolerances: 8 times the
//      round-off a sound answer carries (FE: the data's share of round_off's measurement plus
//      the solver's share scaled down by how far the backward error exceeds its tolerance, so a
//      spoilt answer cannot excuse itself; at least 16 eps; Ritz: eps times the amplitudes'
//      sum and the Newton tolerance of the limits).
//  backward_error
//      max over the rows of the equations of |K u + C^T r - F| / (|K||u| + |C^T||r| + |F|),
//      recomputed from the element equations. Tolerance 64 eps: a backward-stable solve leaves
//      a few eps, the rows sum at most ~20 terms (fast, bilateral, dual whose u is one more
//      sparse solve); for primal Lemke, whose u and r come from a dense LU of its final basis
//      of n_L = 2n + m unknowns, Wilkinson's n_L eps times a growth factor of 8. Ritz: the
//      amplitude rows against their terms, tolerance the Newton tolerance the solve asked for.
//  round_off
//      FE: the error round-off has left in the answer, measured, not bounded: the residual of
//      the answer's own contact-set system in the mixed form of the element equations (the
//      element stress resultants m = H^-1 G u as extra unknowns, K = G^T H^-1 G; its data are
//      exact data of a nearby mesh, its condition ~N^2) computed in twice the working precision,
//      and one solve of that system for the correction. Against the discretisation error,
//      estimated by the change of the (corrected) answer from a solve on half the elements (the
//      certificate's own, by the fast solver, corrected the same way), at least 1e-6
//      (detail.hpp). An answer whose round-off exceeds it is not solved. Measured on
//      seed_beam_end_moments at 3200 elements: the fast (mixed-form) answer 7e-17 of max |w|;
//      the same contact set solved in the stiffness form (K's condition ~N^4) 2.5e-4, against
//      its error of 1.6e-4 from the closed form. (Measured in the stiffness form, whose rounded
//      K_e do not annihilate the rigid motions exactly, the mixed answers showed a "round-off"
//      of eps N^4: 3.5e-10 at 2048 elements, against their nodal error of 1e-15.)
//      Ritz: eps times the condition of the final (scaled) Jacobian against the change of w
//      from half the modes.
//
// Limit-fitted answers (contact/fitted_limits.hpp: the foundation acts on the contact elements
// only, each limit a node): every element of the foundation's extent is checked pointwise, with
// no limit elements: contact elements must press (w >= 0), lift-off elements must not (w <= 0),
// and complementarity includes |w| at the limit nodes. reaction_sign skips the limit nodes, where
// the P1 reaction (an L2 projection of k w, which vanishes there) is an O(h^2) artefact of either
// sign. round_off is checked against CertifyOptions::discretisation_error when given.
//
// Trace steps: certify() with CertifyOptions::load_factor and round_off = false (the half-mesh
// or half-modes solve costs as much as the step; the round-off is still measured for the sign
// tolerances and reported in round_off_estimate). Ritz: RitzOptions::load_factor as solved.
//
// Certificate figures are nondimensional (model::MemberModel's scales); user_figures() converts.
// Signs: a support reaction's force pushes the member away from the foundation (like the
// foundation's reaction), its moment is counterclockwise; applied forces push toward the
// foundation; moments about the member's begin (arches: the centre) counterclockwise.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "certify/support_reaction.hpp"
#include "contact/contact_solver.hpp"
#include "fe/discretisation.hpp"
#include "model/member_model.hpp"
#include "ritz/ritz_solver.hpp"

namespace liftoff::certify {

// Check names, exactly as the JSON carries them.
namespace check_name {
inline constexpr std::string_view force_balance = "force_balance";
inline constexpr std::string_view force_balance_x = "force_balance_x";
inline constexpr std::string_view force_balance_y = "force_balance_y";
inline constexpr std::string_view moment_balance = "moment_balance";
inline constexpr std::string_view reaction_sign = "reaction_sign";
inline constexpr std::string_view penetration = "penetration";
inline constexpr std::string_view separation = "separation";
inline constexpr std::string_view complementarity = "complementarity";
inline constexpr std::string_view backward_error = "backward_error";
inline constexpr std::string_view round_off = "round_off";
inline constexpr std::string_view settlement = "settlement";
inline constexpr std::string_view membrane_uniform = "membrane_uniform";              // von Karman beams
inline constexpr std::string_view membrane_free_end = "membrane_free_end";            // von Karman beams
inline constexpr std::string_view membrane_compatibility = "membrane_compatibility";  // von Karman beams
}  // namespace check_name

struct Check {
  std::string name;
  double value = 0.0;        // dimensionless, relative to the scale of the terms checked
  double tolerance = 0.0;    // dimensionless
  bool passed = false;       // value <= tolerance (and both finite)
  std::optional<double> at;  // s where the worst value is, if it has a place
};

struct Certificate {
  bool passed = false;
  std::string message;  // "all checks passed" or which check failed by how much
  std::vector<Check> checks;
  std::vector<SupportReaction> support_reactions;
  // Beams: the foundation's resultant (compression positive), its centroid (s), the applied
  // force (toward the foundation) and the applied moment about the begin (counterclockwise).
  // Arches: the components toward the foundation at the crown ("vertical"); the _x fields carry
  // the tangential direction at the crown; centroid = integral of r s / integral of r (s).
  double foundation_resultant = 0.0;
  double foundation_centroid = 0.0;
  double applied_force = 0.0;
  double applied_moment = 0.0;
  double foundation_resultant_x = 0.0;  // arches
  double applied_force_x = 0.0;         // arches
  // FE: the largest pointwise sign defect inside limit elements (relative to max |w|),
  // reported, not gated: the mixed model's O(h) there. -1 when there is none to report.
  double limit_element_defect = -1.0;
  // The answer's round-off, measured (relative, the larger of w and r; -1 if it could not be),
  // and the round_off check in words ("round-off 2e-10 of max |w| against ...").
  double round_off_estimate = -1.0;
  std::string round_off_note;

  const Check* find(std::string_view name) const;
  const Check* first_failure() const;
};

struct CertifyOptions {
  double load_factor = 1.0;     // lambda: F = F_dead + lambda F_live, as the answer was solved
  int samples_per_element = 8;  // FE pointwise checks: points per element (plus the end)
  // The round_off check costs a second, coarser solve (FE: half the elements by the fast
  // solver; Ritz: half the modes). Trace steps may skip it (the check is then absent).
  bool round_off = true;
  // The backward error the answer's producer accepts, where it is not one solve of the answer's
  // own equations (the FE load path combines u_dead + lambda u_live of fixed-set solves updated
  // from set to set, and accepts a relative residual of 1e-8). 0: derived from the solve (64 eps;
  // primal Lemke's dense LU bound). Balance and the contact checks keep their own tolerances.
  double backward_tolerance = 0.0;
  // FE: the sign conditions also pointwise inside the elements (samples_per_element), besides
  // the discrete ones at the nodes. The load path checks its breakpoint states at the nodes only:
  // there a node's gap or reaction is zero by construction and its elements' cubics may cross
  // zero by the path's own accuracy (the culvert's closing lift-off zone: 1.2e-9 of max |w|).
  bool pointwise = true;
  // The least error the sign conditions allow (times the certificate's sign safety factor 8),
  // for a producer whose states are accurate to a tolerance of its own: the load path's states
  // (updated from contact set to contact set, accepted at a relative residual of 1e-8) carry
  // reactions and gaps of about that relative size where they should be zero (region_split at
  // 101 elements: -1.7e-8 of the largest reaction at a node about to leave). 0: the answer's
  // measured round-off alone.
  double sign_floor = 0.0;
  // The nodal gaps relative to the largest node's gap terms instead of each node's own: the
  // load path decides its switches on that scale, where a closing lift-off zone's nodes have
  // terms far below the member's.
  bool global_scale = false;
  // FE: the answer's discretisation error (relative to max |w| and max |r|) when its solver
  // estimated it (a limit-fitted sequence, contact/fitted_refinement.hpp): round_off is checked
  // against it instead of the change from a half-mesh fast solve, which solves another discrete
  // model (node-based limits, O(h^2)) and would allow far more round-off than the answer's
  // accuracy. Negative: the half-mesh solve.
  double discretisation_error = -1.0;
  void validate() const;  // throws std::invalid_argument naming the field
};

// The certificate of an FE + LCP answer (solution.displacement on every dof, solution.reaction
// per reaction node, as contact::solve_contact returns them). An answer without finite fields
// gets a failed certificate saying so.
Certificate certify(const model::MemberModel& model, const fe::Discretisation& discretisation,
                    const contact::ContactSolution& solution, const CertifyOptions& options = {});

// The certificate of a Ritz answer (solution.model and solution.unknowns of the final N).
// `ritz_options`: as the answer was solved (load factor, modes, Newton tolerance, enrichment).
Certificate certify(const model::MemberModel& model, const ritz::RitzSolution& solution,
                    const ritz::RitzOptions& ritz_options, const CertifyOptions& options = {});

// A von Karman beam's or arch's answer on an FE mesh (contact/von_karman_solve.hpp), as it is
// reported: displacement on every dof (w, w'; arches also u; settled supports included), axial the
// u of every node (beams: 0 where held; arches: the tangential dofs again), reaction per reaction
// node, normal_force the reported N of each element (tension positive; arches: its mean over the
// element by the element's Gauss rule, as VonKarmanSystem::normal_forces).
struct VonKarmanAnswer {
  Eigen::VectorXd displacement, axial, reaction;
  std::vector<double> normal_force;
};

// The certificate of a von Karman beam's answer, from its fields alone. Checks (certificate.hpp's
// names, CERTIFICATE.md): backward_error (the transverse and axial rows of the von Karman element
// equations, 512 eps); force_balance and moment_balance (the membrane's nodal forces count on the
// rotation as the thrust's moment at the displaced ends); membrane_uniform (N' = 0: N's spread
// over the elements), membrane_free_end (N = 0 at an axially free end), membrane_compatibility
// (the reported N against EA eps of the fields, and with both ends held its mean against EA/L
// integral of (w0' w' + w'^2 / 2)); reaction_sign, penetration, complementarity at the nodes
// (tolerance: sign_floor, the solver's sign tolerance, times 8). The support reactions' tangential
// is the axial reaction at a held end (along increasing x: the thrust). No round_off check (the
// primal system's round-off is not measured here; the solver's own error estimate is reported).
// Arches (the Marguerre/Donnell element of fe/arch_von_karman_element.hpp, on the circle): the
// element forces recomputed from the strain eps = u' - sigma w + beta^2 / 2, beta = -(u + sigma
// w'), chi = u' + sigma w'' at the element's Gauss points; backward_error on every row the supports
// leave free (w, w', u: 512 eps of the row's terms summed point by point); force_balance_x,
// force_balance_y and moment_balance on the rigid motions of the circle, with the membrane's
// nonlinear nodal forces counted like a load (on the rotation about the centre, -integral of N
// beta: the thrust's moment) and the linear element's O(h^4) work on the interpolated rigid
// translations allowed (as for a linear arch); membrane_compatibility: the reported N of each
// element against the Gauss mean of EA eps of the fields (64 eps of EA times eps's terms), and the
// reported u against the tangential dofs; no membrane_uniform or membrane_free_end (N varies along
// an arch; a roller's N = 0 is a natural condition, met only as the mesh converges); the contact
// checks as for beams. The support reactions: radial force, moment and tangential (the thrust).
Certificate certify(const model::MemberModel& model, const fe::Discretisation& discretisation,
                    const VonKarmanAnswer& answer, const CertifyOptions& options = {});

// In the user's units (forces, moments, positions: x or theta in degrees).
struct UserFigures {
  std::vector<SupportReaction> support_reactions;
  double foundation_resultant = 0.0, foundation_centroid = 0.0, applied_force = 0.0, applied_moment = 0.0;
  double foundation_resultant_x = 0.0, applied_force_x = 0.0;
};
UserFigures user_figures(const Certificate& certificate, const model::MemberModel& model);
// The support reactions alone so (UserFigures::support_reactions).
std::vector<SupportReaction> user_support_reactions(const std::vector<SupportReaction>& reactions,
                                                    const model::MemberModel& model);

// The support reactions of a Ritz state (x of `ritz` at load factor lambda), as its certificate
// computes them (the Ritz equations' residual on a test function that moves one support's dof
// alone), without the certificate's checks (whose balance tolerance costs a second solve with half
// the modes): a load path's step reports them so. Nondimensional.
std::vector<SupportReaction> ritz_support_reactions(const model::MemberModel& member, const ritz::RitzModel& ritz,
                                                    const Eigen::VectorXd& x, double lambda);

}  // namespace liftoff::certify
