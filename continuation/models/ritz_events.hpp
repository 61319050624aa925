#pragma once
// The Ritz path's event functions and contact checks, for one member and number of modes: what
// the RitzPath model (models/ritz.hpp) looks at along a step of one topology.
//
// Event functions of a topology (each > 0 while the topology holds):
//  - per contact piece: the smallest interior minimum of w (lift_off_opens when it reaches 0),
//    per lift-off piece: minus the largest interior maximum (contact_opens);
//  - at a foundation end that is no limit: w there (free end), +-w' (pinned end: w = 0), w''
//    (clamped end), signed so that it is > 0 while the end piece keeps its state: a new zone
//    opening at the end, a limit leaving it (limit_at_end, or limit_at_support at a supported
//    end, as the FE path names a piece opening or closing at an end);
//  - per piece between two limits: its length (region_vanishes, lift_off_vanishes); per end
//    piece: its length (limit_at_end, or limit_at_support at a supported end);
//  - per limit and load point: t - a (limit_at_load; recorded, no switch).
// The residual accepts crossed limits (the Ritz integrals continue analytically, a piece of
// negative length counting negatively), so that a length event is bracketed like any other;
// but a piece between two limits vanishes at a singular point of the regularised equations
// (vanishes_singularly), which is approached from below instead (approach_vanishing).
//
// A contact solution of the Ritz model (state_failure): limits in order, w >= 0 in contact pieces
// (reaction >= 0), w <= 0 in lift-off pieces on ritz::check_inequalities' grid, to
// inequality_tolerance of max |w| (an event's state: but for the event itself, event_allowance).

#include <Eigen/Dense>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "continuation/arclength.hpp"
#include "continuation/result.hpp"
#include "model/member_model.hpp"
#include "ritz/ritz_model.hpp"

namespace liftoff::continuation {

enum class RitzEventFunction { interior_extreme, end_value, length, limit_at_load };

struct RitzEventSpec {
  RitzEventFunction function;
  EventKind kind;
  int piece = 0;         // interior_extreme, length; end_value: 0 (begin) or last piece (end)
  bool far_end = false;  // end_value: the foundation's end (true) or its begin; with one piece
                         // both ends are piece 0, so the piece cannot tell them apart
  int limit = 0;         // limit_at_load
  double position = 0;   // limit_at_load: the load's s
  bool operator==(const RitzEventSpec&) const = default;
};

struct RitzEventValue {
  double value = std::numeric_limits<double>::infinity();
  double at = 0.0;  // s
};

// The beam-column quantities of a state (TraceStep::amplitude, lifted_length, in user units)
// and the s of the largest lift.
struct RitzBuckle {
  double amplitude = 0.0;
  double lifted_length = 0.0;
  double crown = 0.0;
};

class RitzEvents {
 public:
  // The contact inequalities' tolerance on the check grid, relative to max |w| (as solve_ritz).
  static constexpr double inequality_tolerance = 1e-9;

  RitzEvents(const model::MemberModel& member, int modes) : member_(member), modes_(modes) {}

  std::vector<RitzEventSpec> specs(const ritz::RitzModel& model) const;
  RitzEventValue value(const ritz::RitzModel& model, const Eigen::VectorXd& x, const RitzEventSpec& spec) const;
  // The extreme of w strictly inside [a, b] (minimum, or the maximum with its sign flipped), and
  // every interior local minimum (maximum) of w there.
  RitzEventValue extreme(const ritz::RitzModel& model, const Eigen::VectorXd& x, double a, double b,
                         bool minimum) const;
  std::vector<RitzEventValue> local_minima(const ritz::RitzModel& model, const Eigen::VectorXd& x, double a, double b,
                                           bool minimum) const;
  double w_scale(const ritz::RitzModel& model, const Eigen::VectorXd& x) const;  // max |w| on a grid

  // Of the events located together, those that are openings seen early through a vanishing
  // piece's own degeneracy replaced by its length event (see the definition), without repeats.
  std::vector<RitzEventSpec> without_degenerate_openings(const ritz::RitzModel& model, const Eigen::VectorXd& x,
                                                         std::vector<RitzEventSpec> events) const;
  // What locating these events to event_tolerance leaves of w's wrong sign (relative to max |w|).
  double event_allowance(const ritz::RitzModel& model, const Eigen::VectorXd& x,
                         const std::vector<RitzEventSpec>& events) const;
  // Why a state may not be accepted: limits out of order, or the contact inequalities failing by
  // more than inequality_tolerance + allowance, in words and user units. nullopt: a contact solution.
  std::optional<std::string> state_failure(const ritz::RitzModel& model, const Eigen::VectorXd& x,
                                           double allowance = 0.0) const;
  // Events stepped over between two states of one topology: a limit that passed a local minimum
  // of w in the contact piece it advanced into (or a maximum in a lift-off piece), where a zone
  // must have opened first. nullopt if none.
  std::optional<std::string> stepped_over(const ritz::RitzModel& model, const Eigen::VectorXd& from,
                                          const Eigen::VectorXd& to) const;

  // A piece that vanishes at a singular point (its length event): one between two limits, or an
  // end piece at a pinned end of a beam; how far in lambda (along the path's direction at p) it is
  // from vanishing, estimated at p (infinity if it is not shrinking); the point within `tolerance`
  // of that, approached from `from` by fixed-lambda steps (nullopt if that fails); and the length
  // at or below which such an end piece counts as gone.
  bool vanishes_singularly(const ritz::RitzModel& model, const RitzEventSpec& spec) const;
  double vanishing_gap(const ritz::RitzModel& model, const PathPoint& p, const RitzEventSpec& spec) const;
  std::optional<PathPoint> approach_vanishing(const ritz::RitzModel& model, const PathFollower& follower,
                                              const PathPoint& from, const RitzEventSpec& spec, double tolerance) const;
  double landed(const ritz::RitzModel& model, const RitzEventSpec& spec) const;

  RitzBuckle buckle(const ritz::RitzModel& model, const Eigen::VectorXd& x) const;
  bool end_supported(bool left) const;

 private:
  double degenerate_length(const RitzEventSpec& spec) const;
  bool pinned_beam_end(bool left) const;
  double user(double s) const { return member_.user_from_s(s); }

  const model::MemberModel& member_;
  int modes_ = 0;
};

}  // namespace liftoff::continuation
