#pragma once
// Limit-fitted solve: the contact limits become mesh nodes, and unknowns.
//
// A node-based contact set (fast, Lemke) puts each contact limit inside an element, where neither
// the cubic w nor the linear reaction can follow the kink of the solution there (the foundation
// force k max(w, 0) has a kink at the limit): the FE limits converge erratically, at orders
// between 0.7 and 2.7. Here the contact topology is taken as given (from such a solve) and
//  - the member is meshed with a node at every breakpoint (mesh_breakpoints) and at every limit,
//    each segment between them uniform, with the requested total shared in proportion to length;
//  - the foundation acts, bilaterally, on the whole elements of the contact regions and not at
//    all on the lift-off elements (fe::discretise with a foundation mask);
//  - the limits t_k solve w(t_k) = g(t_k) (g the ground gap, MemberModel::ground_gap; 0 without
//    one) by Newton's method with the diagonal Jacobian dF_k/dt_k = w'(t_k) - g'(t_k): moving a
//    limit adds or removes foundation of intensity k (w - g)(t_k), which vanishes at the solution,
//    so the off-diagonal terms and the rest of the diagonal are O(w - g) there and the iteration
//    converges quadratically. Steps are kept inside the neighbouring limits and foundation ends
//    (a limit never passes another). g is linear within elements (its table's points, steps
//    included, are breakpoints). A limit that reaches a step of g (a trench wall) stops there,
//    pinned (not an unknown) while w - g changes sign across the step, and moves on by Newton
//    on the side where it does not;
//  - the gap offset of the discretisation (Discretisation::ground_gap: the gap and the settled
//    supports' -C u_f; their dead load -K u_f is in the dead load) enters every solve;
//  - then the contact inequalities are checked on the answer: w >= g on contact elements and
//    w <= g on lift-off elements (each element's cubic sampled), r >= 0 at contact nodes.
// With no kink inside any element, Hermite elements converge at their full order: the limit
// error falls like h^4 (measured: contact/fitted_limits_test.cpp,
// verification/bench/accuracy_bench.cpp limits), against ~h^2 and erratic with the node-based set.
//
// The number of contact regions is kept: a region that shrinks to nothing, or limits that
// would cross, end the iteration (topology_changed); so does a violated inequality
// (inequalities_violated). Either way the caller keeps its node-based answer.

#include <Eigen/Dense>
#include <string>
#include <string_view>
#include <vector>

#include "contact/active_set_system.hpp"
#include "core/contact_region.hpp"
#include "fe/discretisation.hpp"
#include "model/member_model.hpp"

namespace liftoff::contact {

struct FittedOptions {
  int elements = 200;       // total, shared among the segments between breakpoints and limits
  int max_iterations = 30;  // Newton steps on the limits
  // Converged when every limit step is below step_tolerance times the member's length (the
  // limits are then known to round-off: ~1e-15 relative, times |w| / (|w'| length)).
  double step_tolerance = 1e-14;
  // Wrong-signed w allowed by the inequality check, relative to max |w| (round-off of w).
  double inequality_tolerance = 1e-10;
  int samples_per_element = 8;  // of each element's cubic, for the inequality check
  void validate() const;        // throws std::invalid_argument naming the field
};

enum class FittedTermination {
  solved,                 // the limits solve w(t_k) = g(t_k) to round-off and the inequalities hold
  no_convergence,         // max_iterations steps without the step tolerance
  topology_changed,       // a region shrank to nothing or limits would cross
  inequalities_violated,  // converged, but w or r has the wrong sign somewhere: wrong topology
  singular_system,        // the contact regions leave a rigid motion free
};
std::string_view to_string(FittedTermination);

struct FittedSummary {
  FittedTermination termination = FittedTermination::no_convergence;
  std::string message;
  int iterations = -1;            // Newton steps (one factorisation and solve each)
  double limit_residual = -1.0;   // max |w(t_k) - g(t_k)| / max |w| at the end (pinned limits: 0)
  double last_step = -1.0;        // max |t_k step| / length of the last step: the limits' round-off
  double worst_violation = -1.0;  // largest wrong-signed w (relative to max |w|) or r (to max r)
  bool is_usable() const { return termination == FittedTermination::solved; }
};

struct FittedResult {
  fe::Discretisation discretisation;   // on the fitted mesh, foundation on the contact elements
  ContactState state;                  // u on its equations, r at its reaction nodes
  std::vector<ContactRegion> contact;  // the contact regions (in_contact, s), ends at the limits
  std::vector<double> limits;          // the interior limits t_k (s), increasing
  FittedSummary summary;
};

// The contact regions (in_contact, s) of a node-based answer (fast, Lemke) on `d`: runs of reaction nodes in
// contact, each limit placed at the zero of w's cubic in the element where w turns negative
// beyond the run (or within three elements of it; its middle if w changes sign in none).
// Lifted-off nodes with w > 0 (a weighted gap >= 0 allows it next to the limit) are walked past;
// one with w = 0 (held by a support) or the foundation's end ends the region there: a clamped
// end under weight is in contact up to the end, not a limit one element from it.
// `displacement` on the equations.
std::vector<ContactRegion> contact_intervals(const fe::Discretisation& d, const Eigen::VectorXd& displacement,
                                             const std::vector<bool>& in_contact);
// The same for a member with a ground gap g (MemberModel::ground_gap): the regions where w >= g,
// limits at the zeros of w - g, or at a step of g (a trench wall) where w - g changes sign across it.
std::vector<ContactRegion> contact_intervals(const model::MemberModel& model, const fe::Discretisation& d,
                                             const Eigen::VectorXd& displacement, const std::vector<bool>& in_contact);

// The limit-fitted answer for F = F_dead + load_factor F_live, starting from `initial` (disjoint,
// increasing, inside the foundation's extent; a region end at a foundation end is not a limit).
FittedResult solve_fitted_limits(const model::MemberModel& model, double load_factor,
                                 const std::vector<ContactRegion>& initial, const FittedOptions& options);

}  // namespace liftoff::contact
