#include "continuation/ritz_path.hpp"

// The Ritz load history, one topology at a time:
//  1. start: the topology and limits at lambda_min (from the scene, or from an FE + LCP solution
//     as `liftoff solve --method ritz` takes them), solved by solve_ritz; or a resumed step;
//  2. follow: the arc-length driver on the Ritz model of that topology, with an observer that,
//     between accepted steps, evaluates the event functions (below), locates the first that
//     changed sign to event_tolerance in lambda and stops the driver there;
//  3. switch: the topology the event implies, a first equilibrium in it, and back to 2.
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
// negative length counting negatively), so that a length event is bracketed like any other.
//
// Switching: a vanishing piece is removed at the event itself (its two limits, or the end
// piece's one limit): the same amplitudes solve the new topology there. An opening needs a
// zone of nonzero width: the old topology is continued a little past the event (its solution
// there is the local expansion of the new one, w dipping through zero around the event point),
// the roots of w around the event point give the new limits, and the new topology is solved at
// that lambda.
//
// Units: the path works in fe::MemberModel's nondimensional s and w; steps are reported in the
// user's units through fe::Scales.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "contact/contact_solver.hpp"
#include "continuation/arclength.hpp"
#include "fe/discretisation.hpp"
#include "fe/member_model.hpp"
#include "post/contact_regions.hpp"
#include "ritz/starting_point.hpp"
#include "ritz/ritz_model.hpp"
#include "ritz/ritz_solver.hpp"

namespace liftoff::continuation {

namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;
using ritz::RitzModel;
using ritz::Topology;

constexpr double infinity = std::numeric_limits<double>::infinity();

// No equilibrium to start from: an outcome (solver_failure in the summary), not misuse.
struct StartFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

enum class EventFunction { interior_extreme, end_value, length, limit_at_load };

struct EventSpec {
  EventFunction function;
  EventKind kind;
  int piece = 0;         // interior_extreme, length; end_value: 0 (begin) or last piece (end)
  bool far_end = false;  // end_value: the foundation's end (true) or its begin; with one piece
                         // both ends are piece 0, so the piece cannot tell them apart
  int limit = 0;         // limit_at_load
  double position = 0;   // limit_at_load: the load's s
};

struct EventValue {
  double value = infinity;
  double at = 0.0;  // s
};

// How the new zone is opened after an event: the old topology is continued this far in
// lambda past the event (direction * delta), see switch_topology.
struct Opening {
  double direction = 1.0;
  double delta = 0.0;
};

// What a resumed step carries (see TraceStep::state): topology, x, tangent, next step length;
// and for a step at a switching event, how the switch opens its zone.
struct ResumeState {
  Topology topology;
  PathPoint point;
  double next_step = 0.0;
  std::optional<Opening> at_event;
};

class RitzTracer {
 public:
  RitzTracer(const scene::Scene& scene, const TraceOptions& options, const TraceSink& sink)
      : scene_(scene), options_(options), sink_(sink), member_(fe::make_member_model(scene)) {}

  TraceResult run();

 private:
  ritz::Enrichment choose_enrichment() const {
    const double beta_l = std::pow(member_.foundation_modulus / 4.0, 0.25) * member_.length();
    return member_.kind == fe::StructureKind::beam && beta_l <= 10.0 ? ritz::Enrichment::load_points
                                                                      : ritz::Enrichment::none;
  }
  // Verbs, in the order run() calls them.
  void validate() const;
  ResumeState starting_state();
  PathFollower make_follower(const RitzModel& model) const;
  ArcLengthResult follow(const RitzModel& model, const PathFollower& follower, const PathPoint& start,
                         double first_step);
  bool switch_topology(const PathFollower& follower);

  // Helpers.
  std::vector<EventSpec> event_specs(const RitzModel& model) const;
  EventValue event_value(const RitzModel& model, const VectorXd& x, const EventSpec& spec) const;
  EventValue extreme(const RitzModel& model, const VectorXd& x, double a, double b, bool minimum) const;
  std::vector<EventValue> local_minima(const RitzModel& model, const VectorXd& x, double a, double b,
                                       bool minimum) const;
  double w_scale(const RitzModel& model, const VectorXd& x) const;
  void record_step(const RitzModel& model, const PathPoint& point, int iterations, double next_step,
                   const std::optional<Opening>& at_event = std::nullopt);
  std::vector<EventSpec> without_degenerate_openings(const RitzModel& model, const VectorXd& x,
                                                     std::vector<EventSpec> events) const;
  void record_event(double lambda, EventKind kind, double s, std::string description);
  std::string topology_text(const Topology& t) const {
    return fmt::format("{} {} {}", t.first_in_contact ? 1 : 0, t.limits, modes_);
  }
  int modes_for_trace(const ritz::RitzSolution& start) const;
  bool end_supported(bool left) const;
  double user(double s) const { return member_.user_from_s(s); }

  const scene::Scene& scene_;
  const TraceOptions& options_;
  const TraceSink& sink_;
  fe::MemberModel member_;
  TraceResult result_;
  int modes_ = 0;
  // The load-point enrichment (ritz/basis.hpp) where the foundation leaves a point force's
  // response global (beta L <= 10, beta = (k/4)^(1/4)); on a stiffer one the response is local,
  // the kinked functions' far field must be cancelled by the smooth modes, and Newton stalls.
  ritz::Enrichment enrichment_ = ritz::Enrichment::none;
  std::optional<RitzModel> model_;
  // The event the follow loop stopped at, waiting for a switch.
  struct Pending {
    std::vector<EventSpec> events;  // located together
    PathPoint point;                // at the event
    Opening opening;
    double step = 0.0;              // the step length in use
  };
  std::optional<Pending> pending_;
  std::optional<PathPoint> restart_;  // a non-switching event: go on from here
  double restart_step_ = 0.0;
};

// --------------------------------------------------------------------------------------------
void RitzTracer::validate() const {
  const auto fail = [](const std::string& what) { throw std::invalid_argument("TraceOptions." + what); };
  if (!(std::isfinite(options_.lambda_min) && std::isfinite(options_.lambda_max) &&
        options_.lambda_min < options_.lambda_max))
    fail(fmt::format("lambda_min, lambda_max: expected finite with lambda_min < lambda_max, got {} and {}",
                     options_.lambda_min, options_.lambda_max));
  if (!(options_.event_tolerance > 0)) fail("event_tolerance: expected > 0");
  if (options_.modes < 0) fail(fmt::format("modes: expected >= 0 (0: automatic), got {}", options_.modes));
  if (!(options_.min_step > 0 && options_.min_step <= options_.initial_step &&
        options_.initial_step <= options_.max_step))
    fail(fmt::format("initial_step: expected 0 < min_step <= initial_step <= max_step, got {} <= {} <= {}",
                     options_.min_step, options_.initial_step, options_.max_step));
  const double lo = std::min(scene_.begin(), scene_.end()), hi = std::max(scene_.begin(), scene_.end());
  for (double p : options_.sample_points)
    if (!(p >= lo && p <= hi)) fail(fmt::format("sample_points: expected positions in [{}, {}], got {}", lo, hi, p));
  if (!(options_.monitor >= lo && options_.monitor <= hi))
    fail(fmt::format("monitor: expected a position in [{}, {}], got {}", lo, hi, options_.monitor));
}

int RitzTracer::modes_for_trace(const ritz::RitzSolution& start) const {
  if (options_.modes > 0) return options_.modes;
  if (scene_.ritz.modes > 0) return scene_.ritz.modes;
  // Automatic: what solve_ritz settled on at lambda_min, but at least 32, since limits that do
  // not exist yet at lambda_min (full contact) say nothing about the N they will need.
  return std::max(start.summary.modes, 32);
}

bool RitzTracer::end_supported(bool left) const {
  const double s = left ? member_.foundation_begin : member_.foundation_end;
  const double end = left ? member_.s_begin : member_.s_end;
  if (std::abs(s - end) > 1e-12 * member_.length()) return false;
  return (left ? member_.left : member_.right) != fe::EndSupport::free;
}

// The topology and unknowns at lambda_min (or at the resumed step).
ResumeState RitzTracer::starting_state() {
  ResumeState state;
  if (options_.resume_from) {
    const TraceStep& step = *options_.resume_from;
    std::istringstream text(step.state_topology);
    int first = -1, limits = -1, modes = 0;
    text >> first >> limits >> modes;
    std::string word;
    Opening opening;
    if (text >> word) {
      if (word == "event" && text >> opening.direction >> opening.delta) state.at_event = opening;
      else text.setstate(std::ios::failbit);
    } else if (text.eof()) {
      text.clear();
    }
    const int n2 = static_cast<int>(step.state.size()) - 2;
    if (!text || (first != 0 && first != 1) || limits < 0 || modes < 1 || n2 <= 0 || n2 % 2 != 0)
      throw std::invalid_argument(fmt::format(
          "TraceOptions.resume_from: expected a Ritz step's state (topology \"first_in_contact limits modes\" and "
          "2 n + 2 values), got topology \"{}\" and {} values",
          step.state_topology, step.state.size()));
    const int n = n2 / 2;
    state.topology = {first == 1, limits};
    modes_ = modes;
    if (RitzModel(member_, modes_, state.topology, enrichment_).unknowns() != n)
      throw std::invalid_argument(fmt::format(
          "TraceOptions.resume_from: the state has {} unknowns, but the Ritz model of topology \"{}\" has {}", n,
          step.state_topology, RitzModel(member_, modes_, state.topology, enrichment_).unknowns()));
    const Eigen::Map<const VectorXd> values(step.state.data(), step.state.size());
    state.point.x = values.head(n);
    state.point.tangent_x = values.segment(n, n);
    state.point.tangent_lambda = values(2 * n);
    state.point.lambda = step.load_factor;
    state.next_step = values(2 * n + 1);
    return state;
  }
  // The topology at lambda_min: from the scene, or from the FE + LCP solution there. Without
  // load at lambda_min (no dead load, lambda_min = 0) w vanishes and every topology fits, so
  // the path starts one initial_step later, where the loads define it.
  const bool unloaded = options_.lambda_min == 0.0 &&
                        std::all_of(member_.loads.begin(), member_.loads.end(),
                                    [](const fe::MemberLoad& l) { return l.load_case != fe::LoadCase::dead; });
  const double lambda_start = unloaded ? options_.initial_step : options_.lambda_min;
  ritz::StartingPoint initial;
  if (!scene_.ritz.topology.empty()) {
    initial = ritz::starting_point_from_scene(scene_.ritz, member_);
  } else {
    const fe::Discretisation d = fe::discretise(member_, options_.elements);
    contact::ContactOptions contact_options;
    contact_options.method = scene::Method::fast;
    contact_options.load_factor = lambda_start;
    const contact::ContactSolution fe = contact::solve_contact(d, contact_options);
    if (!fe.summary.is_usable())
      throw StartFailure("the FE + LCP solution at lambda_min that gives the Ritz topology failed: " +
                         fe.summary.message);
    initial = ritz::starting_point_from_regions(post::contact_regions(member_, d, fe.displacement), member_);
  }
  state.topology = initial.topology;
  const std::vector<double>& limits = initial.limits;
  ritz::RitzOptions ritz_options;
  ritz_options.modes = options_.modes > 0 ? options_.modes : scene_.ritz.modes;
  ritz_options.max_modes = scene_.ritz.max_modes;
  ritz_options.mode_tolerance = scene_.ritz.mode_tolerance * member_.length();
  ritz_options.load_factor = lambda_start;
  ritz_options.enrichment = enrichment_;
  ritz::RitzSolution start = ritz::solve_ritz(member_, state.topology, limits, ritz_options);
  modes_ = modes_for_trace(start);
  if (start.summary.modes != modes_) {
    ritz_options.modes = modes_;
    std::vector<double> settled(start.unknowns.data() + start.unknowns.size() - state.topology.limits,
                                start.unknowns.data() + start.unknowns.size());
    if (!start.summary.is_usable()) settled = limits;
    start = ritz::solve_ritz(member_, state.topology, settled, ritz_options);
  }
  if (!start.summary.is_usable())
    throw StartFailure("the Ritz solution at lambda_min failed: " + start.summary.message);
  state.point.x = start.unknowns;
  state.point.lambda = lambda_start;
  state.next_step = options_.initial_step;
  return state;
}

PathFollower RitzTracer::make_follower(const RitzModel& model) const {
  const int n = model.unknowns(), a = model.amplitudes();
  // Typical sizes, from the loads alone (not from x: a resumed trace must take the same steps):
  // forces over the range of lambda, deflections those forces make against the foundation (or
  // against the unit bending stiffness where the foundation is softer).
  const double lambda_size = std::max({std::abs(options_.lambda_min), std::abs(options_.lambda_max), 1.0});
  const double force_scale = std::max(
      model.dead_load().lpNorm<Eigen::Infinity>() + lambda_size * model.live_load().lpNorm<Eigen::Infinity>(), 1e-300);
  const double amplitude_scale = force_scale / std::max(member_.foundation_modulus, 1.0);

  PathProblem problem;
  problem.unknowns = n;
  problem.residual = [&model](const VectorXd& y, double lambda, VectorXd& g) {
    if (!y.allFinite()) return false;
    model.residual(y, lambda, g);
    return true;
  };
  problem.jacobian = [&model](const VectorXd& y, double lambda, MatrixXd& j) {
    model.jacobian(y, lambda, j);
    return true;
  };
  problem.lambda_derivative = [&model](const VectorXd& y, double, VectorXd& g) {
    g = model.residual_lambda_derivative(y);
    return true;
  };
  problem.unknown_scale = VectorXd::Constant(n, 1.0 / amplitude_scale);
  problem.unknown_scale.tail(n - a).setConstant(1.0 / member_.length());
  problem.residual_scale = VectorXd::Constant(n, 1.0 / force_scale);
  problem.residual_scale.tail(n - a).setConstant(1.0 / amplitude_scale);

  ArcLengthOptions o;
  o.control = options_.control;
  o.lambda_min = options_.lambda_min;
  o.lambda_max = options_.lambda_max;
  o.initial_step = options_.initial_step;
  o.min_step = options_.min_step;
  o.max_step = options_.max_step;
  o.max_steps = options_.max_steps;
  o.fold_tolerance = options_.event_tolerance;
  o.locate_folds = false;  // the observer does it, so that fold events reach the sink in order
  return PathFollower(std::move(problem), o);
}

// --------------------------------------------------------------------------------------------
// Events.

std::vector<EventSpec> RitzTracer::event_specs(const RitzModel& model) const {
  std::vector<EventSpec> specs;
  const int pieces = model.limits() + 1;
  bool contact = model.topology().first_in_contact;
  for (int p = 0; p < pieces; ++p, contact = !contact) {
    specs.push_back({EventFunction::interior_extreme,
                     contact ? EventKind::lift_off_opens : EventKind::contact_opens, p, false, 0, 0});
    if (pieces > 1) {
      EventKind kind = contact ? EventKind::region_vanishes : EventKind::lift_off_vanishes;
      if (p == 0 || p == pieces - 1)
        kind = end_supported(p == 0) ? EventKind::limit_at_support : EventKind::limit_at_end;
      specs.push_back({EventFunction::length, kind, p, false, 0, 0});
    }
  }
  // Openings at the foundation's ends (member_ tells which end condition holds w there).
  const auto end_kind = [&](bool begin) {
    return end_supported(begin) ? EventKind::limit_at_support : EventKind::limit_at_end;
  };
  specs.push_back({EventFunction::end_value, end_kind(true), 0, false, 0, 0});
  specs.push_back({EventFunction::end_value, end_kind(false), pieces - 1, true, 0, 0});
  // Limits passing load points.
  std::vector<double> points;
  for (const fe::MemberLoad& load : member_.loads) {
    if (load.kind == fe::LoadKind::uniform) continue;
    if (load.at > member_.foundation_begin && load.at < member_.foundation_end) points.push_back(load.at);
  }
  std::sort(points.begin(), points.end());
  points.erase(std::unique(points.begin(), points.end()), points.end());
  for (int m = 0; m < model.limits(); ++m)
    for (double a : points) specs.push_back({EventFunction::limit_at_load, EventKind::limit_at_load, 0, false, m, a});
  return specs;
}

// The extreme of w strictly inside [a, b]: local extrema (roots of w' refined by safeguarded
// Newton) and the grid values between them.
EventValue RitzTracer::extreme(const RitzModel& model, const VectorXd& x, double a, double b, bool minimum) const {
  EventValue best;
  if (!(b > a)) return best;
  const double sign = minimum ? 1.0 : -1.0;  // minimise sign * w
  const int samples = std::max(16, static_cast<int>(std::ceil(8.0 * modes_ * (b - a) / member_.length())));
  const double h = (b - a) / samples;
  for (int i = 1; i < samples; ++i) {
    const double s = a + i * h;
    const double value = sign * model.w(x, s);
    if (value < best.value) best = {value, s};
  }
  for (const EventValue& local : local_minima(model, x, a, b, minimum))
    if (local.value < best.value) best = local;
  return best;
}

std::vector<EventValue> RitzTracer::local_minima(const RitzModel& model, const VectorXd& x, double a, double b,
                                                 bool minimum) const {
  std::vector<EventValue> minima;
  if (!(b > a)) return minima;
  const double sign = minimum ? 1.0 : -1.0;  // minima of sign * w
  const int samples = std::max(16, static_cast<int>(std::ceil(8.0 * modes_ * (b - a) / member_.length())));
  const double h = (b - a) / samples;
  // Sign changes of the slope from - to + between grid points, refined by safeguarded Newton.
  double s0 = a + 0.5 * h, d0 = sign * model.w(x, s0, 1);
  for (int i = 1; i < samples; ++i) {
    const double s1 = std::min(a + (i + 0.5) * h, b - 0.5 * h);
    const double d1 = sign * model.w(x, s1, 1);
    if (d0 < 0 && d1 >= 0) {
      double lo = s0, hi = s1, s = 0.5 * (s0 + s1);
      for (int k = 0; k < 60; ++k) {
        const double d = sign * model.w(x, s, 1), dd = sign * model.w(x, s, 2);
        (d < 0 ? lo : hi) = s;
        double next = dd > 0 ? s - d / dd : 0.5 * (lo + hi);
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        if (std::abs(next - s) <= 1e-15 * member_.length()) {
          s = next;
          break;
        }
        s = next;
      }
      minima.push_back({sign * model.w(x, s), s});
    }
    s0 = s1, d0 = d1;
  }
  return minima;
}

EventValue RitzTracer::event_value(const RitzModel& model, const VectorXd& x, const EventSpec& spec) const {
  const std::vector<ritz::Piece> pieces = model.pieces(x);
  switch (spec.function) {
    case EventFunction::interior_extreme: {
      const ritz::Piece& p = pieces[spec.piece];
      if (!(p.end > p.begin)) return {infinity, p.begin};  // a piece of negative length: its own event
      // contact: min w > 0; lift-off: -max w > 0.
      return extreme(model, x, p.begin, p.end, p.in_contact);
    }
    case EventFunction::end_value: {
      const bool left = !spec.far_end;
      const ritz::Piece& p = pieces[spec.piece];
      const double s = left ? member_.foundation_begin : member_.foundation_end;
      double value = model.w(x, s);
      if (end_supported(left)) {
        const fe::EndSupport support = left ? member_.left : member_.right;
        // w = 0 at the end: the sign of w just inside comes from w' (pinned) or w'' (clamped).
        value = support == fe::EndSupport::clamped ? model.w(x, s, 2) : (left ? 1.0 : -1.0) * model.w(x, s, 1);
        if (support == fe::EndSupport::clamped) value *= member_.length();
      }
      return {p.in_contact ? value : -value, s};
    }
    case EventFunction::length: {
      const ritz::Piece& p = pieces[spec.piece];
      // Where it vanishes: at the member's end for an end piece, else between its limits.
      const double at = spec.piece == 0                               ? member_.foundation_begin
                        : spec.piece == static_cast<int>(pieces.size()) - 1 ? member_.foundation_end
                                                                       : 0.5 * (p.begin + p.end);
      return {p.end - p.begin, at};
    }
    case EventFunction::limit_at_load: {
      const double t = x[model.limit_offset() + spec.limit];
      return {t - spec.position, spec.position};
    }
  }
  return {};
}

double RitzTracer::w_scale(const RitzModel& model, const VectorXd& x) const {
  double scale = 0.0;
  const int samples = 8 * modes_;
  for (int i = 0; i <= samples; ++i)
    scale = std::max(scale, std::abs(model.w(x, member_.s_begin + member_.length() * i / samples)));
  return scale;
}

// --------------------------------------------------------------------------------------------
// A vanishing piece takes the events of its own degeneracy along (at a shrinking end piece, w
// at the end and the piece's extreme reach zero too): those are no openings. And w at an end
// reaching zero while the end piece is all but gone (shorter than 1e-5 of the member, far
// below what N modes resolve) is that piece vanishing, seen a little early through round-off
// (region_split at 40 modes: w(0) = 0 with the limit 4e-7 L from it, and a contact zone was
// opened at x = 0 instead of the limit removed): its length event replaces the opening.
std::vector<EventSpec> RitzTracer::without_degenerate_openings(const RitzModel& model, const VectorXd& x,
                                                               std::vector<EventSpec> events) const {
  const std::vector<ritz::Piece> pieces = model.pieces(x);
  for (EventSpec& spec : events) {
    if (spec.function != EventFunction::end_value || pieces.size() < 2) continue;
    const ritz::Piece& piece = pieces[spec.piece];
    if (piece.end - piece.begin > 1e-5 * member_.length()) continue;
    for (const EventSpec& length : event_specs(model))
      if (length.function == EventFunction::length && length.piece == spec.piece) spec = length;
  }
  const auto same = [](const EventSpec& a, const EventSpec& b) {
    return a.function == b.function && a.piece == b.piece && a.far_end == b.far_end && a.limit == b.limit &&
           a.position == b.position;
  };
  for (std::size_t i = 0; i < events.size(); ++i)
    for (std::size_t j = events.size(); j-- > i + 1;)
      if (same(events[i], events[j])) events.erase(events.begin() + static_cast<std::ptrdiff_t>(j));
  std::vector<bool> vanishing(model.limits() + 1, false);
  for (const EventSpec& spec : events)
    if (spec.function == EventFunction::length) vanishing[spec.piece] = true;
  std::erase_if(events, [&](const EventSpec& spec) {
    return (spec.function == EventFunction::interior_extreme || spec.function == EventFunction::end_value) &&
           vanishing[spec.piece];
  });
  return events;
}

void RitzTracer::record_step(const RitzModel& model, const PathPoint& point, int iterations, double next_step,
                             const std::optional<Opening>& at_event) {
  TraceStep step;
  step.load_factor = point.lambda;
  const fe::Scales& scales = member_.scales;
  for (const ritz::Piece& piece : model.contact_pieces(point.x))
    if (piece.end > piece.begin) step.contact_regions.push_back({user(piece.begin), user(piece.end)});
  step.monitor_deflection = model.w(point.x, member_.s_from_user(options_.monitor)) * scales.displacement();
  for (double p : options_.sample_points) {
    const double s = member_.s_from_user(p);
    step.deflection.push_back(model.w(point.x, s) * scales.displacement());
    step.reaction.push_back(model.reaction(point.x, s) * scales.force_per_length());
  }
  step.iterations = iterations;
  step.state_topology = topology_text(model.topology());
  if (at_event) step.state_topology += fmt::format(" event {} {}", at_event->direction, at_event->delta);
  const int n = static_cast<int>(point.x.size());
  step.state.resize(2 * n + 2);
  Eigen::Map<VectorXd> state(step.state.data(), 2 * n + 2);
  state.head(n) = point.x;
  state.segment(n, n) = point.tangent_x;
  state(2 * n) = point.tangent_lambda;
  state(2 * n + 1) = next_step;
  if (sink_.on_step) sink_.on_step(step);
  result_.steps.push_back(std::move(step));
  ++result_.summary.steps;
  result_.summary.corrector_iterations += iterations;
  result_.summary.final_load_factor = point.lambda;
}

void RitzTracer::record_event(double lambda, EventKind kind, double s, std::string description) {
  TraceEvent event{lambda, kind, user(s), std::move(description)};
  if (sink_.on_event) sink_.on_event(event);
  result_.events.push_back(std::move(event));
}

// --------------------------------------------------------------------------------------------
ArcLengthResult RitzTracer::follow(const RitzModel& model, const PathFollower& follower, const PathPoint& start,
                                   double first_step) {
  const std::vector<EventSpec> specs = event_specs(model);
  const double tolerance = options_.event_tolerance;
  // Values of the event functions at the last accepted point.
  const auto values_at = [&](const VectorXd& x) {
    std::vector<double> v;
    for (const EventSpec& spec : specs) v.push_back(event_value(model, x, spec).value);
    return v;
  };
  std::vector<double> previous = values_at(start.x);
  double previous_scale = w_scale(model, start.x);

  const auto observer = [&](const PathPoint& from, PathPoint& to) {
    const double ds = to.arclength - from.arclength;
    const std::vector<double> now = values_at(to.x);
    // Which events changed sign (a value that starts at zero, as right after a switch, does not
    // count: it is the event just handled).
    std::vector<std::size_t> changed;
    for (std::size_t i = 0; i < specs.size(); ++i) {
      const bool length_like =
          specs[i].function == EventFunction::length || specs[i].function == EventFunction::limit_at_load;
      const double zero = length_like ? 1e-9 * member_.length() : 1e-9 * previous_scale;
      if (previous[i] > zero && now[i] <= 0.0) changed.push_back(i);
      if (specs[i].function == EventFunction::limit_at_load && previous[i] < -zero && now[i] >= 0.0)
        changed.push_back(i);
    }
    if (!changed.empty()) {
      // Locate each; the earliest wins, and those at the same lambda come along.
      std::optional<PathPoint> first;
      std::vector<std::pair<double, std::size_t>> located;
      for (std::size_t i : changed) {
        const EventSpec spec = specs[i];
        auto point = follower.locate(from, to,
                                     [&](const PathPoint& p) { return event_value(model, p.x, spec).value; },
                                     tolerance);
        if (!point) continue;
        located.emplace_back(point->arclength, i);
        if (!first || point->arclength < first->arclength) first = std::move(point);
      }
      if (first) {
        Pending pending;
        pending.point = *first;
        pending.opening = {to.lambda >= first->lambda ? 1.0 : -1.0,
                           std::max(0.1 * std::abs(to.lambda - first->lambda), 1e3 * options_.event_tolerance)};
        pending.step = ds;
        for (auto [arclength, i] : located)
          if (std::abs(arclength - first->arclength) <= 1e-6 * std::abs(ds) ||
              std::abs(event_value(model, first->x, specs[i]).value) <=
                  1e-7 * (specs[i].function == EventFunction::length ? member_.length() : previous_scale))
            pending.events.push_back(specs[i]);
        pending.events = without_degenerate_openings(model, first->x, std::move(pending.events));
        to = *first;
        bool switches = false;
        for (const EventSpec& spec : pending.events)
          if (spec.function != EventFunction::limit_at_load) switches = true;
        record_step(model, to, to.iterations, ds, switches ? std::optional(pending.opening) : std::nullopt);
        const auto record = [&](const EventSpec& spec, double s) {
          record_event(to.lambda, spec.kind, s,
                       fmt::format("{} at {} = {:.10g} ({})", to_string(spec.kind),
                                   member_.kind == fe::StructureKind::arch ? "theta" : "x", user(s),
                                   to_string(model.topology())));
        };
        for (const EventSpec& spec : pending.events) {
          if (spec.function != EventFunction::interior_extreme) {
            record(spec, event_value(model, to.x, spec).at);
            continue;
          }
          // One event per zone that opens (symmetric loads open several at once).
          const ritz::Piece piece = model.pieces(to.x)[spec.piece];
          const double zero = 1e-6 * w_scale(model, to.x);
          for (const EventValue& local : local_minima(model, to.x, piece.begin, piece.end, piece.in_contact))
            if (local.value <= zero) record(spec, local.at);
        }
        if (switches) {
          pending_ = std::move(pending);
        } else {
          restart_ = to;
          restart_step_ = ds;
        }
        return ObserverVerdict::stop;
      }
    }
    // A fold of the path (a limit point) between from and to.
    if (options_.control == PathControl::arc_length && (from.tangent_lambda > 0) != (to.tangent_lambda > 0) &&
        from.tangent_lambda != 0.0)
      if (auto fold = follower.locate(from, to, [](const PathPoint& p) { return p.tangent_lambda; }, tolerance))
        record_event(fold->lambda, EventKind::limit_point, member_.s_from_user(options_.monitor),
                     fmt::format("limit point: lambda reaches a {} of {:.10g}",
                                 from.tangent_lambda > 0 ? "maximum" : "minimum", fold->lambda));
    record_step(model, to, to.iterations, follower.next_step(ds, to.iterations));
    previous = now;
    previous_scale = w_scale(model, to.x);
    return ObserverVerdict::proceed;
  };
  return follower.follow(start, observer, first_step);
}

// The topology after the pending event(s), and a first equilibrium in it. Returns false (with
// the summary filled) if there is none.
bool RitzTracer::switch_topology(const PathFollower& old_follower) {
  const Pending pending = std::move(*pending_);
  pending_.reset();
  const RitzModel& old = *model_;
  const PathPoint& at = pending.point;

  // 1. What the events change: limits removed with vanishing pieces, zones to open.
  std::vector<double> limits(at.x.data() + old.limit_offset(), at.x.data() + old.unknowns());
  std::vector<bool> remove(limits.size(), false);
  bool flip_first = false;
  std::vector<std::pair<double, int>> openings;  // s; 1 interior (two limits), 0 at the begin, 2 at the end
  for (const EventSpec& spec : pending.events) {
    switch (spec.function) {
      case EventFunction::length: {
        const int p = spec.piece;
        if (p > 0) remove[p - 1] = true;
        if (p < old.limits()) remove[p] = true;
        if (p == 0) flip_first = !flip_first;
        break;
      }
      case EventFunction::interior_extreme: {
        // Every local extreme of the piece that reaches zero here opens a zone (symmetric
        // loads open two at once, and one event function sees only the lower).
        const ritz::Piece piece = old.pieces(at.x)[spec.piece];
        const double zero = 1e-6 * w_scale(old, at.x);
        for (const EventValue& local : local_minima(old, at.x, piece.begin, piece.end, piece.in_contact))
          if (local.value <= zero) openings.emplace_back(local.at, 1);
        break;
      }
      case EventFunction::end_value:
        openings.emplace_back(event_value(old, at.x, spec).at, spec.far_end ? 2 : 0);
        if (!spec.far_end) flip_first = !flip_first;
        break;
      case EventFunction::limit_at_load: break;
    }
  }
  std::vector<double> kept;
  for (std::size_t m = 0; m < limits.size(); ++m)
    if (!remove[m]) kept.push_back(limits[m]);
  int added = 0;
  for (const auto& opening : openings) added += opening.second == 1 ? 2 : 1;
  const Topology topology{old.topology().first_in_contact != flip_first, static_cast<int>(kept.size()) + added};

  // Nothing holds a free-free member that has lifted off everywhere.
  if (!topology.first_in_contact && topology.limits == 0 && member_.left == fe::EndSupport::free &&
      member_.right == fe::EndSupport::free && member_.point_supports.empty()) {
    result_.summary.termination = TraceTermination::no_equilibrium;
    result_.summary.message = fmt::format(
        "no equilibrium beyond lambda = {:.10g}: the member has lifted off the foundation entirely and nothing else "
        "holds it",
        at.lambda);
    return false;
  }

  // 2. A first equilibrium in the new topology. A removal needs none other than the event's
  //    own amplitudes. An opening continues the old topology a little past the event (first a
  //    tenth of the step in use, in lambda); the roots of w around each opening point there
  //    are the new zone's limits. Should Newton fail from there, the opening step shrinks.
  std::string failure;
  double delta = pending.opening.delta;
  for (int attempt = 0; attempt < 8; ++attempt, delta *= 0.1) {
    PathPoint base = at;
    std::vector<double> guess = kept;
    if (!openings.empty()) {
      StepOutcome past = old_follower.step_to_lambda(at, at.lambda + pending.opening.direction * delta);
      if (!past.point) {
        failure = "the old topology could not be continued past the event: " + past.corrector.message;
        continue;
      }
      base = *past.point;
      const std::vector<ritz::Piece> pieces = old.pieces(base.x);
      for (auto [s, where] : openings) {
        // The new zone's sign: w's at an interior opening point; at an end, the opposite of the
        // end piece's state (w there is 0 at a supported end, and its sign noise: a scan keyed
        // on it stops at once and Newton settles on a zone of no width).
        const ritz::Piece& end_piece = where == 0 ? pieces.front() : pieces.back();
        const double w0 = where == 1 ? old.w(base.x, s) : (end_piece.in_contact ? -1.0 : 1.0);
        const auto root = [&](double from, double to) {  // bisection on w
          double a = from, b = to, fa = old.w(base.x, a);
          for (int k = 0; k < 200 && std::abs(b - a) > 1e-15 * member_.length(); ++k) {
            const double m = 0.5 * (a + b), fm = old.w(base.x, m);
            if ((fm > 0) == (fa > 0)) a = m, fa = fm; else b = m;
          }
          return 0.5 * (a + b);
        };
        // From s toward limit_s, the first point where w has left the sign it has at s.
        const auto scan = [&](double limit_s) {
          constexpr int samples = 4096;
          double previous = s;
          for (int i = 1; i <= samples; ++i) {
            const double next = s + (limit_s - s) * i / samples;
            if ((old.w(base.x, next) > 0) != (w0 > 0)) return root(previous, next);
            previous = next;
          }
          return limit_s;
        };
        if (where == 1) {
          double lo = member_.foundation_begin, hi = member_.foundation_end;
          for (const ritz::Piece& p : pieces)
            if (s >= p.begin && s <= p.end) lo = p.begin, hi = p.end;
          guess.push_back(scan(lo));
          guess.push_back(scan(hi));
        } else {
          guess.push_back(scan(where == 0 ? pieces.front().end : pieces.back().begin));
        }
      }
      std::sort(guess.begin(), guess.end());
    }
    RitzModel candidate(member_, modes_, topology, enrichment_);
    VectorXd x(candidate.unknowns());
    x.head(candidate.amplitudes()) = base.x.head(old.amplitudes());
    for (int m = 0; m < topology.limits; ++m) x[candidate.limit_offset() + m] = guess[m];
    const PathFollower follower = make_follower(candidate);
    nonlinear::NewtonSummary newton;
    // The new tangent keeps the old one's sense: its amplitude and lambda parts as the reference.
    PathPoint orientation;
    orientation.tangent_x = VectorXd::Zero(candidate.unknowns());
    orientation.tangent_x.head(candidate.amplitudes()) = at.tangent_x.head(candidate.amplitudes());
    orientation.tangent_lambda = at.tangent_lambda;
    const std::optional<PathPoint> start = follower.start(x, base.lambda, &newton, orientation);
    if (!start) {
      failure = "Newton: " + newton.message;
    } else if (!candidate.admissible(start->x)) {
      failure = "the solution has limits out of order or outside the foundation";
    } else {
      model_.emplace(std::move(candidate));
      if (base.lambda != at.lambda) record_step(*model_, *start, newton.iterations, pending.step);
      restart_ = *start;
      restart_step_ = pending.step;
      return true;
    }
    if (openings.empty()) break;  // nothing to vary
  }
  result_.summary.termination = TraceTermination::solver_failure;
  result_.summary.message = fmt::format("no equilibrium found in the topology {} after the event at lambda = {:.10g}: {}",
                                        to_string(topology), at.lambda, failure);
  return false;
}

TraceResult RitzTracer::run() {
  const auto clock = std::chrono::steady_clock::now();
  result_.summary.path = "ritz";
  validate();
  enrichment_ = choose_enrichment();
  ResumeState state;
  try {
    state = starting_state();
  } catch (const StartFailure& failure) {
    result_.summary.termination = TraceTermination::solver_failure;
    result_.summary.message = failure.what();
    return result_;
  }
  model_.emplace(member_, modes_, state.topology, enrichment_);
  std::optional<PathPoint> start;
  {
    const PathFollower follower = make_follower(*model_);
    if (options_.resume_from) {
      start = state.point;
      if (state.at_event) {
        // Resumed at a switching event: the events are those whose functions vanish here.
        Pending pending;
        pending.point = state.point;
        pending.opening = *state.at_event;
        pending.step = state.next_step;
        const double scale = w_scale(*model_, start->x);
        for (const EventSpec& spec : event_specs(*model_)) {
          if (spec.function == EventFunction::limit_at_load) continue;
          const bool length = spec.function == EventFunction::length;
          if (std::abs(event_value(*model_, start->x, spec).value) <= 1e-7 * (length ? member_.length() : scale))
            pending.events.push_back(spec);
        }
        pending.events = without_degenerate_openings(*model_, start->x, std::move(pending.events));
        pending_ = std::move(pending);
        if (!switch_topology(follower)) {
          result_.summary.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - clock).count();
          return result_;
        }
        start = restart_;
        state.next_step = restart_step_;
        restart_.reset();
      }
    } else {
      nonlinear::NewtonSummary newton;
      start = follower.start(state.point.x, state.point.lambda, &newton);
      if (!start) {
        result_.summary.termination = TraceTermination::solver_failure;
        result_.summary.message = "no equilibrium at lambda_min: " + newton.message;
        return result_;
      }
      record_step(*model_, *start, newton.iterations, state.next_step);
    }
  }
  double step = state.next_step;
  while (true) {
    if (result_.summary.steps >= options_.max_steps) {
      result_.summary.termination = TraceTermination::step_limit;
      result_.summary.message = fmt::format("step limit: max_steps = {} steps recorded", options_.max_steps);
      break;
    }
    const PathFollower follower = make_follower(*model_);
    const ArcLengthResult path = follow(*model_, follower, *start, step);
    result_.summary.rejected_steps += path.rejected_steps;
    if (pending_) {
      if (!switch_topology(follower)) break;
    }
    if (restart_ && path.termination == ArcLengthTermination::stopped_by_observer) {
      start = restart_;
      step = restart_step_;
      restart_.reset();
      continue;
    }
    switch (path.termination) {
      case ArcLengthTermination::completed: result_.summary.termination = TraceTermination::completed; break;
      case ArcLengthTermination::step_too_small: result_.summary.termination = TraceTermination::step_too_small; break;
      case ArcLengthTermination::step_limit: result_.summary.termination = TraceTermination::step_limit; break;
      default: result_.summary.termination = TraceTermination::solver_failure; break;
    }
    result_.summary.message = path.message;
    break;
  }
  result_.summary.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - clock).count();
  return result_;
}

}  // namespace

TraceResult trace_ritz(const scene::Scene& scene, const TraceOptions& options, const TraceSink& sink) {
  RitzTracer tracer(scene, options, sink);
  return tracer.run();
}

}  // namespace liftoff::continuation
