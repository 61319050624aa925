// The Ritz path along a step of one topology: what it rejects (screen) and the events it locates
// on it (crossing). The checks that depend on a located event are made at that event.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "continuation/models/ritz.hpp"

namespace liftoff::continuation {

using Eigen::VectorXd;
using ritz::RitzModel;

namespace {
constexpr double infinity = std::numeric_limits<double>::infinity();
}  // namespace

std::vector<double> RitzPath::event_values(const VectorXd& x) const {
  for (const auto& [at, values] : values_cache_)
    if (at.size() == x.size() && at == x) return values;
  std::vector<double> values;
  for (const RitzEventSpec& spec : specs_) values.push_back(events_->value(*model_, x, spec).value);
  if (values_cache_.size() >= 4) values_cache_.erase(values_cache_.begin());
  values_cache_.emplace_back(x, std::move(values));
  return values_cache_.back().second;
}

Screening RitzPath::screen(const PathPoint& from, PathPoint& to, const PathFollower& follower) {
  checked_.clear();
  if (auto why = jumped_folds(from, to)) return {Screening::Verdict::reject, *why};
  if (std::optional<Screening> approach = approach_vanishing(from, to, follower)) return *approach;
  if (auto why = turned_back(from, to)) return {Screening::Verdict::reject, *why};
  return {};
}

// Von Karman: a shallow arch's path folds twice within a short stretch of x, and a long step
// near the first fold can land on the far stable branch (the corrector's hyperplane meets it),
// skipping both folds with t_lambda > 0 at either end. Lambda then moved against both tangents,
// which no smooth stretch of a branch does: the step is retried shorter.
std::optional<std::string> RitzPath::jumped_folds(const PathPoint& from, const PathPoint& to) const {
  if (model_->has_membrane() && (from.tangent_lambda > 0) == (to.tangent_lambda > 0) &&
      (to.lambda - from.lambda) * from.tangent_lambda < 0.0)
    return fmt::format(
        "lambda moved from {:.10g} to {:.10g}, against the tangent at both ends: the step jumped across folds",
        from.lambda, to.lambda);
  return std::nullopt;
}

// A piece between two limits vanishing: its limits meet where lambda is largest, a singular point
// of the regularised equations (w'(t) -> 0 at both, their rows alike) past which only the mirror
// image continues (limits swapped, lambda falling). A step across it cannot be trusted (the
// corrector may land anywhere near it), nor bisected; so a step whose width changed sign, or that
// turned back in lambda, is replaced by the approach from below (RitzEvents::approach_vanishing)
// and the events are then taken between `from` and that point. nullopt: go on (with `to`
// replaced where it was approached).
std::optional<Screening> RitzPath::approach_vanishing(const PathPoint& from, PathPoint& to,
                                                      const PathFollower& follower) {
  const RitzModel& model = *model_;
  const std::vector<double> previous = event_values(from.x);
  const double ds = to.arclength - from.arclength;
  std::optional<std::size_t> shrinking;
  double earliest = infinity;
  // (Along the path's direction at `from`: past a fold the path falls in lambda.)
  const double direction = from.tangent_lambda < 0 ? -1.0 : 1.0;
  const bool turned = !((to.lambda - from.lambda) * direction > 0) || !(to.tangent_lambda * direction > 0);
  for (std::size_t i = 0; i < specs_.size(); ++i) {
    if (!events_->vanishes_singularly(model, specs_[i])) continue;
    // (An end piece at a pinned end: a step across its vanishing lands on the trivial root, the
    // limit at the end to round-off, as well as past it.)
    const bool crossed =
        previous[i] > 0 && events_->value(model, to.x, specs_[i]).value <= events_->landed(model, specs_[i]);
    if (!crossed && !turned) continue;
    const double gap = events_->vanishing_gap(model, from, specs_[i]);
    // A step that turned back for another reason (an event of another kind, handled below) is no
    // vanishing: only a piece predicted to vanish within the step's reach is. An end piece (pinned
    // end) only when crossed: its gap estimate runs to zero at a fold, where d lambda / ds does
    // (issue 16's demo scaled to lambda_max = 1 stopped there).
    const bool end_piece = specs_[i].piece == 0 || specs_[i].piece == model.limits();
    if (!crossed && (end_piece || !(gap <= std::abs(ds)))) continue;
    if (gap < earliest) earliest = gap, shrinking = i;
  }
  if (!shrinking) return std::nullopt;
  std::optional<PathPoint> near =
      events_->approach_vanishing(model, follower, from, specs_[*shrinking], options_.event_tolerance);
  if (!near)
    return Screening{Screening::Verdict::reject,
                     fmt::format("a piece vanishing near lambda = {:.10g} (estimated from lambda = {:.10g}, along the "
                                 "path's direction) could not be approached",
                                 from.lambda + direction * earliest, from.lambda)};
  to = std::move(*near);
  return std::nullopt;
}

// Which events changed sign between the two states (a value that starts at zero, as right after
// a switch, does not count: it is the event just handled).
std::vector<std::size_t> RitzPath::changed_events(const PathPoint& from, const PathPoint& to) const {
  const std::vector<double> previous = event_values(from.x);
  const std::vector<double> now = event_values(to.x);
  const double previous_scale = events_->w_scale(*model_, from.x);
  std::vector<std::size_t> changed;
  for (std::size_t i = 0; i < specs_.size(); ++i) {
    const bool length_like =
        specs_[i].function == RitzEventFunction::length || specs_[i].function == RitzEventFunction::limit_at_load;
    const double zero = length_like ? 1e-9 * member_.length() : 1e-9 * previous_scale;
    if (previous[i] > zero && now[i] <= 0.0) changed.push_back(i);
    if (specs_[i].function == RitzEventFunction::limit_at_load && previous[i] < -zero && now[i] >= 0.0)
      changed.push_back(i);
  }
  return changed;
}

// The linear tensionless problem has one equilibrium per lambda (its energy is convex and, where
// it has one at all, strictly so), so the path of contact solutions never turns back in lambda; a
// step that did has left it, and events cannot be located on it (their functions are not
// monotone along it): it is retried shorter. But for an end piece vanishing where a member that
// only the foundation holds lifts off entirely (the last lambda with any equilibrium: a fold),
// located like any event. Under an axial force the energy is not convex: folds are part of the path.
std::optional<std::string> RitzPath::turned_back(const PathPoint& from, const PathPoint& to) const {
  if (model_->can_lose_stability() || ((to.lambda > from.lambda) && (to.tangent_lambda > 0))) return std::nullopt;
  if (foundation_only_) {
    const std::vector<std::size_t> changed = changed_events(from, to);
    if (std::any_of(changed.begin(), changed.end(), [&](std::size_t i) {
          return specs_[i].function == RitzEventFunction::length && !events_->vanishes_singularly(*model_, specs_[i]);
        }))
      return std::nullopt;
  }
  return fmt::format(
      "the path turned back in lambda ({}), which no path of tensionless equilibria does: the topology {} has left it",
      to.lambda > from.lambda ? fmt::format("its tangent at lambda = {:.10g} points to falling lambda", to.lambda)
                              : fmt::format("from {:.10g} to {:.10g}", from.lambda, to.lambda),
      to_string(model_->topology()));
}

CrossingSearch RitzPath::crossing(const PathPoint& from, const PathPoint& to, const PathFollower& follower,
                                  bool /*may_take*/) {
  std::vector<std::size_t> changed = changed_events(from, to);
  CrossingSearch search = located_events(from, to, follower, changed);
  if (search.reject || !search.crossings.empty()) return search;
  // No event located: the step's end must be a contact solution reached without stepping over
  // one (else it is retried shorter; at min_step the path stops and says why).
  if (auto why = no_contact_solution(from, to)) return {{}, why, std::nullopt};
  vouch(to);
  return {};
}

std::optional<std::string> RitzPath::no_contact_solution(const PathPoint& from, const PathPoint& to) const {
  if (auto why = events_->state_failure(*model_, to.x)) return fmt::format("at lambda = {:.10g}: {}", to.lambda, *why);
  return events_->stepped_over(*model_, from.x, to.x);
}

// Each changed event located; the earliest wins, and those at the same point come along. A piece
// between two limits within event_tolerance of vanishing (see approach_vanishing) vanishes at `to`.
CrossingSearch RitzPath::located_events(const PathPoint& from, const PathPoint& to, const PathFollower& follower,
                                        const std::vector<std::size_t>& changed) {
  const RitzModel& model = *model_;
  const double tolerance = options_.event_tolerance, ds = to.arclength - from.arclength;
  const std::vector<double> now = event_values(to.x);
  const std::vector<double> previous = event_values(from.x);
  std::optional<PathPoint> first;
  std::vector<std::pair<double, std::size_t>> located;
  for (std::size_t i = 0; i < specs_.size(); ++i)
    if (events_->vanishes_singularly(model, specs_[i]) && previous[i] > 0 && now[i] > 0 &&
        events_->vanishing_gap(model, to, specs_[i]) <= tolerance) {
      located.emplace_back(to.arclength, i);
      first = to;
    }
  for (std::size_t i : changed) {
    const RitzEventSpec spec = specs_[i];
    auto point = follower.locate(
        from, to, [&](const PathPoint& p) { return events_->value(model, p.x, spec).value; }, tolerance);
    if (!point) continue;
    located.emplace_back(point->arclength, i);
    if (!first || point->arclength < first->arclength) first = std::move(point);
  }
  if (!first) return {};
  const double previous_scale = events_->w_scale(model, from.x);
  Transition transition;
  transition.point = *first;
  transition.opening = {to.lambda >= first->lambda ? 1.0 : -1.0,
                        std::max(0.1 * std::abs(to.lambda - first->lambda), 1e3 * tolerance)};
  for (auto [arclength, i] : located)
    if (std::abs(arclength - first->arclength) <= 1e-6 * std::abs(ds) ||
        std::abs(events_->value(model, first->x, specs_[i]).value) <=
            1e-7 * (specs_[i].function == RitzEventFunction::length ? member_.length() : previous_scale))
      transition.events.push_back(specs_[i]);
  transition.events = events_->without_degenerate_openings(model, first->x, std::move(transition.events));
  // (An event at `from` itself: a piece found within event_tolerance of vanishing there.)
  if (!model.can_lose_stability() && !(first->lambda >= from.lambda))
    return {{},
            fmt::format("the event located at lambda = {:.10g} lies behind the step's start {:.10g}", first->lambda,
                        from.lambda),
            std::nullopt};
  // The state at the event must be a contact solution but for the event itself. A piece vanishing
  // leaves its limits out of order or its w of the wrong sign by what locating it leaves: the
  // state after the switch is checked instead (switch_topology).
  const bool removes = std::any_of(transition.events.begin(), transition.events.end(),
                                   [](const RitzEventSpec& e) { return e.function == RitzEventFunction::length; });
  if (!removes)
    if (auto why =
            events_->state_failure(model, first->x, events_->event_allowance(model, first->x, transition.events)))
      return {{}, fmt::format("at the event located at lambda = {:.10g}: {}", first->lambda, *why), std::nullopt};
  if (auto why = events_->stepped_over(model, from.x, first->x)) return {{}, why, std::nullopt};
  transition.changes_topology =
      std::any_of(transition.events.begin(), transition.events.end(),
                  [](const RitzEventSpec& e) { return e.function != RitzEventFunction::limit_at_load; });
  vouch(*first);
  Crossing c;
  c.point = *first;
  c.events = describe_events(transition);
  c.switches = true;  // (a limit passing a load point: the follower goes on from the event, enter)
  c.transition = std::move(transition);
  CrossingSearch search;
  search.crossings.push_back(std::move(c));
  return search;
}

// One event per function, at its own position; one per zone that opens (symmetric loads open
// several at once).
std::vector<TraceEvent> RitzPath::describe_events(const Transition& transition) const {
  const RitzModel& model = *model_;
  const PathPoint& at = transition.point;
  std::vector<TraceEvent> events;
  const auto add = [&](const RitzEventSpec& spec, double s) {
    events.push_back({at.lambda, spec.kind, user(s),
                      fmt::format("{} at {} = {:.10g} ({})", to_string(spec.kind), coordinate(), user(s),
                                  to_string(model.topology()))});
  };
  for (const RitzEventSpec& spec : transition.events) {
    if (spec.function != RitzEventFunction::interior_extreme) {
      add(spec, events_->value(model, at.x, spec).at);
      continue;
    }
    const ContactRegion piece = model.pieces(at.x)[spec.piece];
    const double zero = 1e-6 * events_->w_scale(model, at.x);
    for (const RitzEventValue& local : events_->local_minima(model, at.x, piece.begin, piece.end, piece.in_contact))
      if (local.value <= zero) add(spec, local.at);
  }
  return events;
}

}  // namespace liftoff::continuation
