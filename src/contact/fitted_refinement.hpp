#pragma once
// Accuracy on demand: limit-fitted solves (fitted_limits.hpp) on meshes n, 2n, 4n, ... until an
// a-posteriori estimate of the error is below a tolerance.
//
// The contact topology comes from the caller (a node-based solve: fast or Lemke); each level
// starts from the previous level's limits. After every level beyond the first the changes from
// the level before are measured:
//  - the contact limits: max |t_k(2n) - t_k(n)|, relative to the member's length (arches: the
//    angular span);
//  - the deflection: max |w_2n - w_n| over 4 points per element of the finer mesh, relative to
//    max |w|;
//  - the foundation's reaction k max(w - g, 0) (g the ground gap, 0 without one): the change of w
//    on the contact elements, relative to the largest w - g there (the continuum reaction is k w; the FE's P1 reaction,
//    an L2 projection of k w on the contact elements, converges only like h^2 and is not what this promises).
// Each change d_j is turned into an error estimate of the finer answer by Richardson's rule at
// the observed order: e = d_j / (2^p - 1), with p = log2(d_{j-1} / d_j) from the two last
// changes, clamped to [1, 4] (4: Hermite cubics with every kink at a node converge at h^4, the
// order fitted_limits_test.cpp asserts; a lower observed order gives a larger, safer estimate;
// with only one change p = 1, e = d, the change itself). Below the round-off of the fitted
// solve a change says nothing: no estimate is below the round-off floor.
//
// The round-off floor of a level: the least error its answer can claim whatever the mesh. w is
// known to eps_w = max(16 eps, the solve's own error estimate) of max |w| (the mixed solve's
// nodal error against the closed form stays at 1e-15 up to 1e6 elements: active_set_system.hpp),
// so a limit, the zero of w - g, to eps_w max |w| / |w'(t_k)| (and to Newton's last step), and the
// reaction k (w - g) to eps_w max |w| / max (w - g) on the contact elements. The largest of the three
// (relative, like the estimates) is the smallest tolerance the sequence can honour; on the seed
// beams 4e-14 (the reaction's: max |w| is 10 times the largest contact w), and the limit error
// against the closed form falls monotonically to 3e-15 L (fitted_refinement_test.cpp).
// The sequence stops when every estimate is <= tolerance (reached), when the next mesh would
// exceed max_elements (cap_reached), when the tolerance is below the round-off floor or the
// changes stop decreasing while still above the tolerance (round_off: doubling no longer
// helps), or when a fitted solve fails (fitted_failed, its message: a topology that the finer
// mesh does not confirm).

#include <string>
#include <string_view>
#include <vector>

#include "contact/fitted_limits.hpp"
#include "model/member_model.hpp"

namespace liftoff::contact {

struct ToleranceOptions {
  double tolerance = 1e-8;  // wanted accuracy, relative (see above); in [1e-13, 0.1]
  // First mesh; 0: max(32, 4 beta L) (beta = (k/4)^(1/4)). Raised, whatever is given, to put four
  // elements on the shortest segment between breakpoints and the initial regions' ends (so that
  // every segment's count doubles with the mesh, and its error shows in the changes).
  int initial_elements = 0;
  int max_elements = 1 << 20;   // the cap: no mesh finer than this
  int samples_per_element = 4;  // of w, for the deflection and reaction changes
  FittedOptions fitted;         // elements is set per level
  void validate() const;        // throws std::invalid_argument naming the field
};

enum class ToleranceTermination {
  reached,        // every estimate <= tolerance
  cap_reached,    // the next mesh would exceed max_elements; estimates above the tolerance
  round_off,      // the tolerance is below the round-off floor, or the changes stopped decreasing above it
  fitted_failed,  // a limit-fitted solve failed (its termination in the message)
};
std::string_view to_string(ToleranceTermination);

struct ToleranceLevel {
  int elements = 0;
  double limit_change = -1.0;  // from the level before (-1 on the first)
  double w_change = -1.0;
  double reaction_change = -1.0;
};

struct ToleranceSummary {
  ToleranceTermination termination = ToleranceTermination::fitted_failed;
  std::string message;
  std::vector<ToleranceLevel> levels;
  double estimated_limit_error = -1.0;     // relative to the length; -1 until estimated
  double estimated_w_error = -1.0;         // relative to max |w|
  double estimated_reaction_error = -1.0;  // relative to the largest reaction k w
  double observed_order = -1.0;            // of the limits (or of w when there are none)
  // The finest level's round-off floor (above): the smallest tolerance it can honour; -1 until
  // a level is solved.
  double round_off_floor = -1.0;
  bool is_usable() const { return termination == ToleranceTermination::reached; }
};

struct ToleranceResult {
  FittedResult answer;  // the finest level's
  ToleranceSummary summary;
};

// The sequence for F = F_dead + load_factor F_live from the contact regions `initial`
// (contact_intervals of a node-based answer).
ToleranceResult refine_to_tolerance(const model::MemberModel& model, double load_factor,
                                    const std::vector<ContactRegion>& initial, const ToleranceOptions& options);

}  // namespace liftoff::contact
