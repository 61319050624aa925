#include "continuation/ritz_path.hpp"

// The Ritz load history, one topology at a time:
//  1. start: the topology and limits at lambda_min (from the scene, or from an FE + LCP solution
//     as `liftoff solve --method ritz` takes them), solved by solve_ritz; or a resumed step;
//  2. follow: the arc-length driver on the Ritz model of that topology, with an observer that,
//     between accepted steps, evaluates the event functions (below), locates the first that
//     changed sign to event_tolerance in lambda and stops the driver there;
//  3. switch: the topology the event implies, a first equilibrium in it, and back to 2.
// Beam-columns (and von Karman beams, whose membrane term makes the energy non-convex as well)
// also watch, between accepted steps, the sign of t_lambda (a fold: limit_point)
// and of stability_margin without a fold (a bifurcation); at a bifurcation that loses the
// stability the path may leave for the bifurcated branch (switch_branch, below) and go back to 2
// in that branch's topology.
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
// (see follow), which is approached from below instead.
//
// Switching: a vanishing piece is removed at the event itself (its two limits, or the end
// piece's one limit): the same amplitudes solve the new topology there. An opening needs a
// zone of nonzero width: the old topology is continued a little past the event (its solution
// there is the local expansion of the new one, w dipping through zero around the event point),
// the roots of w around the event point give the new limits, and the new topology is solved at
// that lambda; shorter, if the zone so found is not local (it covers another extreme of w).
//
// What is accepted (issue 10: the path once ended `completed` with a reaction of -8426 N/m and
// printed events that skipped back and forth in lambda): every state recorded as a step, the
// start, each event's state and each switch's first state, satisfies the contact inequalities
// on ritz::check_inequalities' grid (as solve_ritz's answers), with lambda growing along the
// path (the linear tensionless problem has one equilibrium per lambda) and no event stepped
// over. A step that fails is retried shorter; at min_step the path stops with solver_failure,
// its message saying which inequality failed where and by how much, and the steps before stay.
//
// Units: the path works in model::MemberModel's nondimensional s and w; steps are reported in the
// user's units through model::Scales.

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <utility>

#include "contact/contact_solver.hpp"
#include "contact/von_karman_solve.hpp"
#include "continuation/arclength.hpp"
#include "continuation/step_state.hpp"
#include "fe/discretisation.hpp"
#include "model/from_scene.hpp"
#include "model/member_model.hpp"
#include "post/contact_regions.hpp"
#include "ritz/from_scene.hpp"
#include "ritz/ritz_model.hpp"
#include "ritz/ritz_solver.hpp"

namespace liftoff::continuation {

namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;
using ritz::RitzModel;
using ritz::Topology;

constexpr double infinity = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;

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
using Opening = continuation::RitzOpening;

// A resumed step's topology in words, for the messages that refuse it.
std::string describe(const continuation::StateTopology& topology) {
  if (const auto* r = std::get_if<continuation::RitzTopology>(&topology))
    return fmt::format("{} {} {}{}", r->first_in_contact ? 1 : 0, r->limits, r->modes,
                       r->at_event ? fmt::format(" event {} {}", r->at_event->direction, r->at_event->delta) : "");
  return std::holds_alternative<continuation::FeContactSet>(topology) ? "an FE contact set" : "none";
}

// What a resumed step carries (see TraceStep::state): topology, x, tangent, next step length;
// and for a step at a switching event, how the switch opens its zone.
struct ResumeState {
  Topology topology;
  PathPoint point;
  double next_step = 0.0;
  double amplitude_scale = 0.0;  // 0: not stored (a file of an older liftoff), from the loads
  std::optional<Opening> at_event;
};

// How well the smooth modes resolve the response to a point force where the member rests on
// the foundation. That response is local, of wavenumber beta = (k/4)^(1/4), and w at the force
// converges like the tail of its modal sum, sum over wavenumbers kappa > N pi / length of
// 1/(kappa^4 + 4 beta^4): relative to the whole sum (the infinite beam's, pi/(8 beta^3)) that is
//     e(N) = 8/(3 pi) (beta length / (pi N))^3      (for N pi > beta length),
// which the relative error of the first lift-off load follows closely (pipeline, beta L = 100:
// e = 0.104, 0.0131 at N = 64, 128; measured 0.096, 0.0126). Without such a force, or with the
// load-point enrichment (N^-8, beta L <= 10), there is nothing to estimate (applies = false).
struct Resolution {
  bool applies = false;
  double beta_length = 0.0;  // beta times the member's length
  double at = 0.0;           // s of the (first) point force it concerns
  double error(int modes) const {
    const double ratio = beta_length / (kPi * modes);
    return ratio >= 1.0 ? 1.0 : 8.0 / (3.0 * kPi) * ratio * ratio * ratio;
  }
  int modes_for(double target) const {
    return static_cast<int>(std::ceil(beta_length / kPi * std::cbrt(8.0 / (3.0 * kPi * target))));
  }
};
// Automatic modes aim at resolution_target; any N whose e(N) exceeds resolution_limit is refused.
constexpr double resolution_target = 1e-3;
constexpr double resolution_limit = 1e-2;
// The contact inequalities' tolerance on the check grid, relative to max |w| (as solve_ritz).
constexpr double inequality_tolerance = 1e-9;

class RitzTracer {
 public:
  RitzTracer(const scene::Scene& scene, model::MemberModel member, const TraceOptions& options, const TraceSink& sink)
      : scene_(scene), options_(options), sink_(sink), member_(std::move(member)) {}

  TraceResult run();

 private:
  ritz::Enrichment choose_enrichment() const {
    const double beta_l = std::pow(member_.k / 4.0, 0.25) * member_.length();
    return member_.kind == model::StructureKind::beam && beta_l <= 10.0 ? ritz::Enrichment::load_points
                                                                        : ritz::Enrichment::none;
  }
  // Verbs, in the order run() calls them.
  void validate() const;
  Resolution resolution() const;
  ResumeState starting_state();
  PathFollower make_follower(const RitzModel& model) const;
  double lambda_size() const {
    return std::max({std::abs(options_.arc_length.lambda_min), std::abs(options_.arc_length.lambda_max), 1.0});
  }
  double force_scale(const RitzModel& model) const;
  // The follower's amplitude scale for a topology that starts at p (see make_follower), and p's
  // tangent in the metric of that scale.
  void rescale(const RitzModel& model, PathPoint& p);
  ArcLengthResult follow(const RitzModel& model, const PathFollower& follower, const PathPoint& start,
                         double first_step);
  bool switch_topology(const PathFollower& follower);
  // Beam-columns: the bifurcated branch at a bifurcation point `at` of `model`'s path (see
  // switch_branch in the definition). nullopt, with why filled, if it is not found.
  // A switched branch that keeps its topology (von Karman, bilateral foundation) is watched for
  // its return to the path it left: the amplitudes' component along the critical mode (unit
  // length) back at its value at the bifurcation point, where the Hessian is singular again.
  struct ReturnWatch {
    VectorXd mode;           // the critical mode's amplitudes, unit length
    double at = 0.0;         // mode . amplitudes at the bifurcation point
    double departure = 0.0;  // the sign of (mode . amplitudes - at) on the branch
    double lambda = 0.0;     // the bifurcation load left from
  };
  struct Branch {
    RitzModel model;
    PathPoint point;
    int iterations = 0;
    std::optional<ReturnWatch> watch;
  };
  std::optional<Branch> switch_branch(const RitzModel& model, const PathPoint& at, std::string& why);
  // The same on a bilateral foundation: the branch in the same topology, along `mode`.
  std::optional<Branch> switch_in_topology(const RitzModel& model, const PathPoint& at, const VectorXd& mode,
                                           std::string& why);
  // The multiple of `mode` the in-topology switch steps off the bifurcation point, and the
  // amplitude it holds there (the one the mode moves most).
  double in_topology_offset(const RitzModel& model, const PathPoint& at, const VectorXd& mode,
                            Eigen::Index& held) const;
  // The crossing point of a switched branch with the path it left, from `near` (the branch's
  // return located on the mode's component, on either path: on the path it rejoins that
  // component vanishes all along, so the locate cannot tell where the crossing is): a secant in
  // lambda on stability_margin, zero at the crossing and linear in lambda beside it, each point
  // solved at fixed lambda from `near` less its mode component. `near` if that does not converge.
  PathPoint refined_crossing(const RitzModel& model, const PathFollower& follower, PathPoint near) const;
  // Both switches' first point: Newton on `model` from (x, lambda) with unknown `held` fixed and
  // lambda free in its place (false if it does not converge), then the follower's first point
  // there, its tangent oriented along +-held (`sense`); nullopt, with why filled, if no tangent.
  bool solve_with_held(const RitzModel& model, int held, const VectorXd& residual_scale, VectorXd& x,
                       double& lambda) const;
  std::optional<Branch> branch_from(RitzModel model, const VectorXd& x, double lambda, int held, double sense,
                                    std::string& why) const;

  // Helpers.
  std::vector<EventSpec> event_specs(const RitzModel& model) const;
  EventValue event_value(const RitzModel& model, const VectorXd& x, const EventSpec& spec) const;
  EventValue extreme(const RitzModel& model, const VectorXd& x, double a, double b, bool minimum) const;
  std::vector<EventValue> local_minima(const RitzModel& model, const VectorXd& x, double a, double b,
                                       bool minimum) const;
  double w_scale(const RitzModel& model, const VectorXd& x) const;
  void record_step(const RitzModel& model, const PathPoint& point, int iterations, double next_step,
                   const std::optional<Opening>& at_event = std::nullopt);
  // The length (relative to the member's) below which a piece's opening event is its vanishing.
  double degenerate_length(const EventSpec& spec) const;
  // A pinned end of a beam on the foundation's end (w = w'' = 0 there; see vanishes_singularly).
  bool pinned_beam_end(bool left) const;
  // The length at or below which a vanishing piece counts as gone: 0, but for an end piece at a
  // pinned end, whose limit equation has the trivial root t = end: a step across the vanishing
  // lands there (seen: 2e-12 of the member), to round-off.
  double landed(const RitzModel& model, const EventSpec& spec) const;
  std::vector<EventSpec> without_degenerate_openings(const RitzModel& model, const VectorXd& x,
                                                     std::vector<EventSpec> events) const;
  void record_event(double lambda, EventKind kind, double s, std::string description);
  // The beam-column quantities of a state (TraceStep::amplitude, lifted_length, in user units)
  // and the s of the largest lift.
  struct Buckle {
    double amplitude = 0.0;
    double lifted_length = 0.0;
    double crown = 0.0;
  };
  Buckle buckle(const RitzModel& model, const VectorXd& x) const;
  // Why a state may not be accepted: limits out of order, or the contact inequalities failing
  // on ritz::check_inequalities' grid by more than inequality_tolerance + allowance (relative to
  // max |w|), in words and user units. nullopt: the state is a contact solution.
  std::optional<std::string> state_failure(const RitzModel& model, const VectorXd& x, double allowance = 0.0) const;
  double event_allowance(const RitzModel& model, const VectorXd& x, const std::vector<EventSpec>& events) const;
  // A piece that vanishes at a singular point (its length event): one between two limits, or an
  // end piece at a pinned end; how far in lambda (along the path's direction at p) it is from
  // vanishing, estimated at p (infinity if it is not shrinking); and the point within
  // event_tolerance of that, approached from `from` by fixed-lambda steps (nullopt if that fails).
  bool vanishes_singularly(const RitzModel& model, const EventSpec& spec) const;
  double vanishing_gap(const RitzModel& model, const PathPoint& p, const EventSpec& spec) const;
  std::optional<PathPoint> approach_vanishing(const RitzModel& model, const PathFollower& follower,
                                              const PathPoint& from, const EventSpec& spec) const;
  // Events stepped over between two states of one topology: a limit that passed a local
  // minimum of w in the contact piece it advanced into (or a maximum in a lift-off piece),
  // where a zone must have opened first. nullopt if none.
  std::optional<std::string> stepped_over(const RitzModel& model, const VectorXd& from, const VectorXd& to) const;
  int modes_for_trace(const ritz::RitzSolution& start) const;
  void check_resolution(int modes) const;
  // ", point forces resolved to about e(N) (estimated)" where that applies, else "".
  std::string resolution_note() const {
    return resolution_.applies ? fmt::format(
                                     ", the point force's local response resolved to about {:.1e} "
                                     "(estimated from beta length = {:.3g})",
                                     resolution_.error(modes_), resolution_.beta_length)
                               : "";
  }
  bool end_supported(bool left) const;
  double user(double s) const { return member_.user_from_s(s); }
  // The compressive force in user units (TraceStep::axial_force): the given axial force less the
  // von Karman membrane force (tension > 0; zero without the term).
  double compression(const RitzModel& model, const VectorXd& x, double lambda) const {
    return (model.axial_force(lambda) - model.membrane_force(x)) * member_.scales.force();
  }

  const scene::Scene& scene_;
  const TraceOptions& options_;
  const TraceSink& sink_;
  model::MemberModel member_;
  TraceResult result_;
  int modes_ = 0;
  Resolution resolution_;
  bool foundation_only_ = false;  // only the foundation holds the member (it can lift off entirely)
  double amplitude_scale_ = 0.0;  // the follower's, see make_follower
  std::string rejection_;         // why the observer last rejected a step
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
    double step = 0.0;  // the step length in use
  };
  std::optional<Pending> pending_;
  std::optional<PathPoint> restart_;  // a non-switching event: go on from here
  double restart_step_ = 0.0;
  bool amplitude_reached_ = false;        // a step reached options_.max_amplitude (stop, completed)
  std::optional<TraceEvent> limit_load_;  // the first limit point (beam-columns), for the message
  int limit_points_ = 0;                  // beam-columns: limit_point and bifurcation events recorded,
  int bifurcations_ = 0;                  // for the message
  std::optional<Branch> branch_;          // a bifurcated branch to continue on (options_.switch_branch)
  double branch_step_ = 0.0;
  std::optional<ReturnWatch> watch_;     // the switched branch being followed, watched for its return
  std::optional<std::string> rejoined_;  // the branch met the path it left: the trace ends (why)
};

// --------------------------------------------------------------------------------------------
void RitzTracer::validate() const { options_.validate(scene_.begin(), scene_.end()); }

int RitzTracer::modes_for_trace(const ritz::RitzSolution& start) const {
  if (options_.modes > 0) return options_.modes;
  if (scene_.ritz.modes > 0) return scene_.ritz.modes;
  // Automatic: what solve_ritz settled on at lambda_min, but at least 32, since limits that do
  // not exist yet at lambda_min (full contact) say nothing about the N they will need; and
  // what a point force on the foundation needs (resolution_target), up to max_modes.
  int modes = std::max(start.summary.modes, 32);
  if (resolution_.applies)
    modes = std::max(modes, std::min(resolution_.modes_for(resolution_target), scene_.ritz.max_modes));
  return modes;
}

Resolution RitzTracer::resolution() const {
  Resolution r;
  if (enrichment_ == ritz::Enrichment::load_points || !member_.tensionless) return r;
  r.beta_length = std::pow(member_.k / 4.0, 0.25) * member_.length();
  for (const model::MemberLoad& load : member_.loads)
    if (load.kind == model::LoadKind::force && load.value != 0.0 && load.at > member_.foundation_begin &&
        load.at < member_.foundation_end) {
      r.applies = true;
      r.at = load.at;
      break;
    }
  return r;
}

// Refuses (StartFailure) N modes that cannot resolve a point force's local response.
void RitzTracer::check_resolution(int modes) const {
  if (!resolution_.applies || resolution_.error(modes) <= resolution_limit) return;
  const bool automatic = options_.modes == 0 && scene_.ritz.modes == 0;
  throw StartFailure(fmt::format(
      "refused: {} modes resolve the local response to the point force at {} = {:.6g} on this foundation (beta times "
      "the member's length = {:.3g}) only to about {:.0f} % (the smooth modes converge there like (beta length / (pi "
      "N))^3); {} modes are needed for {:.0f} % and {} for {:.1f} %{}: set [ritz] modes{} or use an FE method",
      modes, member_.kind == model::StructureKind::arch ? "theta" : "x", user(resolution_.at), resolution_.beta_length,
      100.0 * resolution_.error(modes), resolution_.modes_for(resolution_limit), 100.0 * resolution_limit,
      resolution_.modes_for(resolution_target), 100.0 * resolution_target,
      automatic ? fmt::format(" (automatic modes stop at [ritz] max_modes = {})", scene_.ritz.max_modes) : "",
      automatic ? " and max_modes" : ""));
}

bool RitzTracer::end_supported(bool left) const {
  const double s = left ? member_.foundation_begin : member_.foundation_end;
  const double end = left ? member_.s_begin : member_.s_end;
  if (std::abs(s - end) > 1e-12 * member_.length()) return false;
  return (left ? member_.left : member_.right) != model::EndSupport::free;
}

// The topology and unknowns at lambda_min (or at the resumed step).
ResumeState RitzTracer::starting_state() {
  ResumeState state;
  if (options_.resume_from) {
    const TraceStep& step = *options_.resume_from;
    const auto* topology = std::get_if<continuation::RitzTopology>(&step.state_topology);
    // 2 n + 3 values (x, tangent, next step, amplitude scale), or 2 n + 2 as liftoff wrote them
    // before the scale was stored.
    const bool scaled = step.state.size() % 2 == 1;
    const int n2 = static_cast<int>(step.state.size()) - (scaled ? 3 : 2);
    if (topology == nullptr || topology->limits < 0 || topology->modes < 1 || n2 <= 0 || n2 % 2 != 0)
      throw std::invalid_argument(fmt::format(
          "TraceOptions.resume_from: expected a Ritz step's state (topology \"first_in_contact limits modes\" and "
          "2 n + 3 values), got topology \"{}\" and {} values",
          describe(step.state_topology), step.state.size()));
    if (topology->at_event) state.at_event = *topology->at_event;
    const int n = n2 / 2;
    state.topology = {topology->first_in_contact, topology->limits};
    modes_ = topology->modes;
    if (RitzModel(member_, modes_, state.topology, enrichment_).unknowns() != n)
      throw std::invalid_argument(fmt::format(
          "TraceOptions.resume_from: the state has {} unknowns, but the Ritz model of topology \"{}\" has {}", n,
          describe(step.state_topology), RitzModel(member_, modes_, state.topology, enrichment_).unknowns()));
    const Eigen::Map<const VectorXd> values(step.state.data(), step.state.size());
    state.point.x = values.head(n);
    state.point.tangent_x = values.segment(n, n);
    state.point.tangent_lambda = values(2 * n);
    state.point.lambda = step.load_factor;
    state.next_step = values(2 * n + 1);
    if (scaled) state.amplitude_scale = values(2 * n + 2);
    if (!(std::isfinite(state.amplitude_scale) && state.amplitude_scale >= 0))
      throw std::invalid_argument(
          fmt::format("TraceOptions.resume_from: expected an amplitude scale >= 0, got {}", state.amplitude_scale));
    check_resolution(modes_);
    return state;
  }
  // The topology at lambda_min: from the scene, or from the FE + LCP solution there. Without
  // load at lambda_min (no dead load, lambda_min = 0) w vanishes and every topology fits, so
  // the path starts one initial_step later, where the loads define it.
  const bool unloaded = options_.arc_length.lambda_min == 0.0 &&
                        std::all_of(member_.loads.begin(), member_.loads.end(),
                                    [](const model::MemberLoad& l) { return l.load_case != model::LoadCase::dead; });
  const double lambda_start = unloaded ? options_.arc_length.initial_step : options_.arc_length.lambda_min;
  // Refuse before any work: the given N, or the most automatic modes could take.
  check_resolution(options_.modes > 0      ? options_.modes
                   : scene_.ritz.modes > 0 ? scene_.ritz.modes
                                           : std::max(scene_.ritz.max_modes, 32));
  ritz::StartingPoint initial;
  if (!scene_.ritz.topology.empty()) {
    initial = ritz::starting_point_from_scene(scene_.ritz, member_);
  } else if (member_.theory == model::Theory::von_karman && member_.kind == model::StructureKind::beam) {
    // Von Karman: the linear solve knows nothing of the membrane (a shallow arch's linear answer
    // at lambda_min is the straight beam's, in contact where the arch has lifted off): the FE von
    // Karman contact solve from zero there gives the topology (the branch that the load path from
    // zero reaches while no fold lies below lambda_min).
    const fe::Discretisation d = fe::discretise(member_, options_.elements);
    const contact::VonKarmanResult fe = contact::VonKarmanSystem(member_, d).solve(lambda_start, {});
    if (!fe.is_usable())
      throw StartFailure("the FE von Karman contact solution at lambda_min that gives the Ritz topology failed: " +
                         fe.message);
    const VectorXd displacement = d.expand_displacement(fe.x.head(d.equations));
    initial = ritz::starting_point_from_regions(post::contact_regions(member_, d, displacement), member_);
  } else {
    const fe::Discretisation d = fe::discretise(member_, options_.elements);
    contact::ContactOptions contact_options;
    contact_options.method = contact::Method::fast;
    contact_options.load_factor = lambda_start;
    const contact::ContactSolution fe = contact::solve_contact(d, contact_options);
    if (!fe.summary.is_usable())
      throw StartFailure("the FE + LCP solution at lambda_min that gives the Ritz topology failed: " +
                         fe.summary.message);
    initial = ritz::starting_point_from_regions(post::contact_regions(member_, d, fe.displacement), member_);
  }
  state.topology = initial.topology;
  const std::vector<double>& limits = initial.limits;
  ritz::RitzOptions ritz_options = ritz::ritz_options_from_scene(
      scene_.ritz, member_, options_.modes > 0 ? std::optional<int>(options_.modes) : std::nullopt);
  ritz_options.load_factor = lambda_start;
  ritz_options.enrichment = enrichment_;
  ritz::RitzSolution start = ritz::solve_ritz(member_, state.topology, limits, ritz_options);
  modes_ = modes_for_trace(start);
  check_resolution(modes_);
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
  state.next_step = options_.arc_length.initial_step;
  return state;
}

// Typical sizes: forces over the range of lambda from the loads; deflections those forces make
// against the foundation (or against the unit bending stiffness where the foundation is softer).
double RitzTracer::force_scale(const RitzModel& model) const {
  return std::max(
      model.dead_load().lpNorm<Eigen::Infinity>() + lambda_size() * model.live_load().lpNorm<Eigen::Infinity>(),
      1e-300);
}

// The amplitudes' scale for the topology that starts at p: at least what the loads make
// against the foundation, and what lambda_size units of lambda make at p (dx/dlambda from p's
// tangent), so that a step ds moves lambda by about ds where the topology starts. Scaled by the
// loads alone, a pipeline whose lifted span deflects 200 times q/K took steps of 7e-4 in lambda
// (10000 steps to lambda = 2.2). The scale is stored with each step, so a resumed trace takes
// the same steps.
void RitzTracer::rescale(const RitzModel& model, PathPoint& p) {
  const int a = model.amplitudes();
  double scale = force_scale(model) / std::max(member_.k, 1.0);
  // (Beam-columns: only where the path starts; near a fold dx/dlambda grows without bound.)
  if (p.tangent_lambda > 0 && (!model.can_lose_stability() || amplitude_scale_ == 0.0))
    scale = std::max(scale, lambda_size() * p.tangent_x.head(a).lpNorm<Eigen::Infinity>() / p.tangent_lambda);
  if (model.can_lose_stability() && amplitude_scale_ > 0.0) scale = std::max(scale, amplitude_scale_);
  if (!std::isfinite(scale)) return;  // keep the scale in use
  amplitude_scale_ = scale;
  const PathFollower follower = make_follower(model);
  PathPoint reference = p;
  if (auto t = follower.tangent(p.x, p.lambda, &reference)) {
    p.tangent_x = t->first;
    p.tangent_lambda = t->second;
  }
}

PathFollower RitzTracer::make_follower(const RitzModel& model) const {
  const int n = model.unknowns(), a = model.amplitudes();
  const double force_scale = this->force_scale(model);
  const double amplitude_scale = amplitude_scale_ > 0 ? amplitude_scale_ : force_scale / std::max(member_.k, 1.0);

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

  ArcLengthOptions o = options_.arc_length;
  o.max_steps = std::max(options_.arc_length.max_steps - result_.summary.steps, 1);  // what the whole path has left
  o.fold_tolerance = options_.event_tolerance;
  o.locate_folds = false;  // the observer does it, so that fold events reach the sink in order
  return PathFollower(std::move(problem), o);
}

// --------------------------------------------------------------------------------------------
// Events.

std::vector<EventSpec> RitzTracer::event_specs(const RitzModel& model) const {
  std::vector<EventSpec> specs;
  if (!model.tensionless()) return specs;  // a bilateral foundation never lifts off: no events
  const int pieces = model.limits() + 1;
  bool contact = model.topology().first_in_contact;
  for (int p = 0; p < pieces; ++p, contact = !contact) {
    specs.push_back({EventFunction::interior_extreme, contact ? EventKind::lift_off_opens : EventKind::contact_opens, p,
                     false, 0, 0});
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
  for (const model::MemberLoad& load : member_.loads) {
    if (load.has_extent()) continue;
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
  const std::vector<ContactRegion> pieces = model.pieces(x);
  switch (spec.function) {
    case EventFunction::interior_extreme: {
      const ContactRegion& p = pieces[spec.piece];
      if (!(p.end > p.begin)) return {infinity, p.begin};  // a piece of negative length: its own event
      // contact: min w > 0; lift-off: -max w > 0.
      return extreme(model, x, p.begin, p.end, p.in_contact);
    }
    case EventFunction::end_value: {
      const bool left = !spec.far_end;
      const ContactRegion& p = pieces[spec.piece];
      const double s = left ? member_.foundation_begin : member_.foundation_end;
      double value = model.w(x, s);
      if (end_supported(left)) {
        const model::EndSupport support = left ? member_.left : member_.right;
        // w = 0 at the end: the sign of w just inside comes from w' (pinned) or w'' (clamped).
        value = support == model::EndSupport::clamped ? model.w(x, s, 2) : (left ? 1.0 : -1.0) * model.w(x, s, 1);
        if (support == model::EndSupport::clamped) value *= member_.length();
      }
      return {p.in_contact ? value : -value, s};
    }
    case EventFunction::length: {
      const ContactRegion& p = pieces[spec.piece];
      // Where it vanishes: at the member's end for an end piece, else between its limits.
      const double at = spec.piece == 0                                     ? member_.foundation_begin
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
// opened at x = 0 instead of the limit removed): its length event replaces the opening. So
// does an interior extreme reaching zero in a piece between two limits that is all but gone
// (culvert: the minimum of w in a contact region 6e-6 of the arch wide, w of the order of its
// width squared, reached zero through round-off just before the region vanished).
// At a pinned end (w = w'' = 0) the end's event is w' there, and an end piece's limit lies
// sqrt(-6 w' / w''') from the end: the piece vanishes together with w' (a double root of w, where
// the limit equation w(t) = 0 meets its trivial root t = end, a pitchfork of the Ritz equations),
// its length going like the square root of the distance to the event. Located on w', the piece is
// still ~1e-4 of the member long (the imperfect arch's zone closing at x = L: 1.4e-4 at 32 modes,
// and a contact zone was opened at the end inside the vanishing lift-off zone, whose limits then
// could not be followed): there the bound is the square root of 1e-5.
double RitzTracer::degenerate_length(const EventSpec& spec) const {
  constexpr double regular = 1e-5;
  if (spec.function != EventFunction::end_value) return regular;
  return pinned_beam_end(!spec.far_end) ? std::sqrt(regular) : regular;
}

double RitzTracer::landed(const RitzModel& model, const EventSpec& spec) const {
  const bool end_piece = spec.piece == 0 || spec.piece == model.limits();
  return end_piece && vanishes_singularly(model, spec) ? 1e-9 * member_.length() : 0.0;
}

bool RitzTracer::pinned_beam_end(bool left) const {
  return member_.kind == model::StructureKind::beam && end_supported(left) &&
         (left ? member_.left : member_.right) == model::EndSupport::pinned;
}

std::vector<EventSpec> RitzTracer::without_degenerate_openings(const RitzModel& model, const VectorXd& x,
                                                               std::vector<EventSpec> events) const {
  const std::vector<ContactRegion> pieces = model.pieces(x);
  for (EventSpec& spec : events) {
    const bool degenerate =
        spec.function == EventFunction::end_value ||
        (spec.function == EventFunction::interior_extreme && spec.piece > 0 && spec.piece < model.limits());
    if (!degenerate || pieces.size() < 2) continue;
    const ContactRegion& piece = pieces[spec.piece];
    if (piece.end - piece.begin > degenerate_length(spec) * member_.length()) continue;
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
  const model::Scales& scales = member_.scales;
  for (const ContactRegion& piece : model.contact_pieces(point.x))
    if (piece.end > piece.begin) step.contact_regions.push_back({user(piece.begin), user(piece.end)});
  step.monitor_deflection = model.w(point.x, member_.s_from_user(options_.monitor)) * scales.displacement();
  for (double p : options_.sample_points) {
    const double s = member_.s_from_user(p);
    step.deflection.push_back(model.w(point.x, s) * scales.displacement());
    step.reaction.push_back(model.reaction(point.x, s) * scales.force_per_length());
  }
  step.iterations = iterations;
  step.axial_force = compression(model, point.x, point.lambda);
  const Buckle b = buckle(model, point.x);
  step.amplitude = b.amplitude;
  step.lifted_length = b.lifted_length;
  if (model.can_lose_stability())  // else the energy is convex: stable, unchecked (unknown)
    step.stability =
        model.stability_margin(point.x, point.lambda) > 0.0 ? continuation::Stability::stable : continuation::Stability::unstable;
  record_ritz_state(step, member_, model, point.x, point.lambda, options_.elements);
  step.state_topology =
      continuation::RitzTopology{model.topology().first_in_contact, model.topology().limits, modes_, at_event};
  const int n = static_cast<int>(point.x.size());
  step.state.resize(2 * n + 3);
  Eigen::Map<VectorXd> state(step.state.data(), 2 * n + 3);
  state.head(n) = point.x;
  state.segment(n, n) = point.tangent_x;
  state(2 * n) = point.tangent_lambda;
  state(2 * n + 1) = next_step;
  state(2 * n + 2) = amplitude_scale_;
  if (sink_.on_step) sink_.on_step(step);
  result_.steps.push_back(std::move(step));
  ++result_.summary.steps;
  result_.summary.corrector_iterations += iterations;
  result_.summary.final_load_factor = point.lambda;
}

// The state at an event is a contact solution but for the event itself: w touching zero where
// a zone opens, by what locating it to event_tolerance leaves. That much violation (relative to
// max |w|) is allowed there.
double RitzTracer::event_allowance(const RitzModel& model, const VectorXd& x,
                                   const std::vector<EventSpec>& events) const {
  const double scale = std::max(w_scale(model, x), 1e-300);
  double allowance = 0.0;
  for (const EventSpec& spec : events) {
    if (spec.function != EventFunction::interior_extreme && spec.function != EventFunction::end_value) continue;
    // The value is w, or at a supported end w' (pinned) or w'' length (clamped): w within a
    // length of the end is at most that times the length.
    const bool slope = spec.function == EventFunction::end_value && end_supported(!spec.far_end);
    allowance += std::abs(event_value(model, x, spec).value) * (slope ? member_.length() : 1.0) / scale;
  }
  return allowance;
}

std::optional<std::string> RitzTracer::state_failure(const RitzModel& model, const VectorXd& x,
                                                     double allowance) const {
  if (!model.admissible(x)) return "its contact limits are out of order or outside the foundation";
  const ritz::InequalityCheck check = ritz::check_inequalities(model, x);
  if (check.violation <= inequality_tolerance + allowance) return std::nullopt;
  const model::Scales& scales = member_.scales;
  const std::string where =
      fmt::format("{} = {:.6g}", member_.kind == model::StructureKind::arch ? "theta" : "x", user(check.at));
  if (check.in_contact)
    return fmt::format(
        "w = {:.3e} at {} inside a contact piece: the foundation would pull (reaction {:.3e} force per length), {:.1e} "
        "of max |w|",
        check.w * scales.displacement(), where, member_.k * check.w * scales.force_per_length(), check.violation);
  return fmt::format(
      "w = {:.3e} at {} inside a lift-off piece: the member would penetrate the foundation without "
      "reaction, {:.1e} of max |w|",
      check.w * scales.displacement(), where, check.violation);
}

bool RitzTracer::vanishes_singularly(const RitzModel& model, const EventSpec& spec) const {
  if (spec.function != EventFunction::length) return false;
  if (spec.piece > 0 && spec.piece < model.limits()) return true;
  // An end piece at a pinned end: w = w'' = 0 there, so next to it w = w'(e) (s - e) + w'''(e)
  // (s - e)^3 / 6 and the piece's limit, the root of w, lies sqrt(-6 w'(e) / w'''(e)) from the
  // end: the piece vanishes with w'(e) at a double root of w, approached like a piece between two
  // limits (there the branch folds; here the limit equation meets its trivial root t = e, and
  // steps past it land on the mirror root outside the foundation: the imperfect arch's zone
  // closing at x = L with 16 modes, "contact limits out of order or outside the foundation").
  // At a clamped or free end the limit moves linearly: regular. Beams only: an arch's pinned end
  // is the same singular point, but the culvert's path then fails its fixed 0.1 steps on the
  // approach instead of on turning back (ritz_path_test, issue 10), not examined further.
  return pinned_beam_end(spec.piece == 0);
}

// The piece's width goes like sqrt(c (lambda* - lambda)) as it vanishes (lambda* beyond p in the
// path's direction), so |lambda* - lambda| = width / (2 |d width / d lambda|), from p's tangent.
// Between limits p - 1 and p the width is their difference; an end piece's, its limit's distance
// to the end.
double RitzTracer::vanishing_gap(const RitzModel& model, const PathPoint& p, const EventSpec& spec) const {
  if (!(p.tangent_lambda != 0.0)) return infinity;
  const int offset = model.limit_offset(), pieces = model.limits() + 1;
  double width = 0.0, rate = 0.0;
  if (spec.piece == 0) {
    width = p.x[offset] - member_.foundation_begin, rate = p.tangent_x[offset];
  } else if (spec.piece == pieces - 1) {
    const int last = offset + model.limits() - 1;
    width = member_.foundation_end - p.x[last], rate = -p.tangent_x[last];
  } else {
    const int first = offset + spec.piece - 1;
    width = p.x[first + 1] - p.x[first], rate = p.tangent_x[first + 1] - p.tangent_x[first];
  }
  rate /= p.tangent_lambda;  // d width / d lambda
  const double direction = p.tangent_lambda > 0 ? 1.0 : -1.0;
  if (!(width > 0 && rate * direction < 0)) return infinity;
  return width / (2.0 * std::abs(rate));
}

std::optional<PathPoint> RitzTracer::approach_vanishing(const RitzModel& model, const PathFollower& follower,
                                                        const PathPoint& from, const EventSpec& spec) const {
  PathPoint p = from;
  const double direction = from.tangent_lambda > 0 ? 1.0 : -1.0;
  for (int iteration = 0; iteration < 200; ++iteration) {
    const double gap = vanishing_gap(model, p, spec);
    if (!std::isfinite(gap)) return std::nullopt;
    if (gap <= options_.event_tolerance) return p;
    // Aim short of the estimate (its error is of the order of gap^2 over the model's scale);
    // past lambda* there is no solution of this topology, and a miss shortens the aim.
    bool moved = false;
    for (double fraction = 0.9; fraction > 1e-3 && !moved; fraction *= 0.25) {
      const double lambda = p.lambda + direction * fraction * gap;
      const VectorXd guess = p.x + (lambda - p.lambda) / p.tangent_lambda * p.tangent_x;
      StepOutcome next = follower.step_to_lambda(from, lambda, &guess);
      if (!next.point || !model.admissible(next.point->x) || !(next.point->tangent_lambda * direction > 0) ||
          !(event_value(model, next.point->x, spec).value > landed(model, spec)))
        continue;
      p = std::move(*next.point);
      moved = true;
    }
    if (!moved) return std::nullopt;
  }
  return std::nullopt;
}

std::optional<std::string> RitzTracer::stepped_over(const RitzModel& model, const VectorXd& from,
                                                    const VectorXd& to) const {
  const std::vector<ContactRegion> pieces = model.pieces(from);
  const int offset = model.limit_offset();
  for (int m = 0; m < model.limits(); ++m) {
    const double t0 = from[offset + m], t1 = to[offset + m];
    if (t1 == t0) continue;
    // The limit ends piece m and begins piece m + 1; moving right it advances into piece m + 1.
    const ContactRegion& piece = pieces[t1 > t0 ? m + 1 : m];
    const double lo = std::min(t0, t1), hi = std::max(t0, t1);
    for (const EventValue& e : local_minima(model, from, piece.begin, piece.end, piece.in_contact))
      if (e.at > lo && e.at < hi)
        return fmt::format(
            "the contact limit at {} = {:.6g} moved past a local {} of w at {:.6g} ({} = {:.3e}) in one "
            "step, where a zone must have {} first",
            member_.kind == model::StructureKind::arch ? "theta" : "x", user(t0),
            piece.in_contact ? "minimum" : "maximum", user(e.at), "w",
            model.w(from, e.at) * member_.scales.displacement(), piece.in_contact ? "lifted off" : "come into contact");
  }
  return std::nullopt;
}

// The largest lift off the foundation surface (the ground is at w = 0: the Ritz model takes no
// gap) on a grid of the foundation's extent that resolves the modes, and the lift-off pieces'
// total length.
RitzTracer::Buckle RitzTracer::buckle(const RitzModel& model, const VectorXd& x) const {
  Buckle b;
  const double a = member_.foundation_begin, e = member_.foundation_end;
  std::vector<double> w;
  const int intervals = std::max(400, 16 * model.modes());
  model.w_on_grid(x, a, e, intervals, w);
  double lift = 0.0;
  for (std::size_t i = 0; i < w.size(); ++i)
    if (-w[i] > lift) lift = -w[i], b.crown = a + (e - a) * static_cast<double>(i + 1) / intervals;
  for (double s : {a, e})
    if (-model.w(x, s) > lift) lift = -model.w(x, s), b.crown = s;
  b.amplitude = lift * member_.scales.displacement();
  for (const ContactRegion& piece : model.pieces(x))
    if (!piece.in_contact && piece.end > piece.begin) b.lifted_length += user(piece.end) - user(piece.begin);
  return b;
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
  // Beam-columns: stability_margin at the last accepted point (NaN: none).
  double previous_margin = model.can_lose_stability() ? model.stability_margin(start.x, start.lambda)
                                                      : std::numeric_limits<double>::quiet_NaN();
  const auto reject = [&](std::string why) {
    rejection_ = std::move(why);
    return ObserverVerdict::reject;
  };

  const auto observer = [&](const PathPoint& from, PathPoint& to) {
    const double ds = to.arclength - from.arclength;
    // Von Karman: a shallow arch's path folds twice within a short stretch of x, and a long step
    // near the first fold can land on the far stable branch (the corrector's hyperplane meets it),
    // skipping both folds with t_lambda > 0 at either end. Lambda then moved against both
    // tangents, which no smooth stretch of a branch does: the step is retried shorter.
    if (model.has_membrane() && (from.tangent_lambda > 0) == (to.tangent_lambda > 0) &&
        (to.lambda - from.lambda) * from.tangent_lambda < 0.0)
      return reject(fmt::format(
          "lambda moved from {:.10g} to {:.10g}, against the tangent at both ends: the step jumped across folds",
          from.lambda, to.lambda));
    // A piece between two limits vanishing: its limits meet where lambda is largest, a singular
    // point of the regularised equations (w'(t) -> 0 at both, their rows alike) past which only
    // the mirror image continues (limits swapped, lambda falling). A step across it cannot be
    // trusted (the corrector may land anywhere near it), nor bisected; so a step whose width
    // changed sign, or that turned back in lambda, is replaced by the approach from below
    // (approach_vanishing) and the events are then taken between `from` and that point.
    {
      std::optional<std::size_t> shrinking;
      double earliest = infinity;
      // (Along the path's direction at `from`: past a fold the path falls in lambda.)
      const double direction = from.tangent_lambda < 0 ? -1.0 : 1.0;
      const bool turned = !((to.lambda - from.lambda) * direction > 0) || !(to.tangent_lambda * direction > 0);
      for (std::size_t i = 0; i < specs.size(); ++i) {
        if (!vanishes_singularly(model, specs[i])) continue;
        // (An end piece at a pinned end: a step across its vanishing lands on the trivial root, the
        // limit at the end to round-off, as well as past it.)
        const bool crossed = previous[i] > 0 && event_value(model, to.x, specs[i]).value <= landed(model, specs[i]);
        if (!crossed && !turned) continue;
        const double gap = vanishing_gap(model, from, specs[i]);
        // A step that turned back for another reason (an event of another kind, handled below)
        // is no vanishing: only a piece predicted to vanish within the step's reach is.
        // An end piece (pinned end) only when crossed: its gap estimate runs to zero at a fold,
        // where d lambda / ds does (issue 16's demo scaled to lambda_max = 1 stopped there).
        const bool end_piece = specs[i].piece == 0 || specs[i].piece == model.limits();
        if (!crossed && (end_piece || !(gap <= std::abs(ds)))) continue;
        if (gap < earliest) earliest = gap, shrinking = i;
      }
      if (shrinking) {
        auto near = approach_vanishing(model, follower, from, specs[*shrinking]);
        if (!near)
          return reject(
              fmt::format("a piece vanishing near lambda = {:.10g} (estimated from lambda = {:.10g}, along the path's "
                          "direction) could not be approached",
                          from.lambda + direction * earliest, from.lambda));
        to = std::move(*near);
      }
    }
    // A switched branch back on the path it left (see ReturnWatch): a second bifurcation point,
    // where the branch crosses that path again (the shallow arch's asymmetric branch rejoins the
    // symmetric path at t = +tB, with a fold in lambda there by symmetry). Located on the mode's
    // component down to round-off in the step (lambda_tolerance 0: at the fold a bracket small in
    // lambda says little about the point, and the corrector may land on the crossing path: with
    // event_tolerance the load was 1e-7 off), recorded as a bifurcation and a step, and the trace
    // ends there: beyond it the
    // branch is its own mirror image back to the first point (the path would shuttle between
    // the two), and the path it rejoins is the one a trace without switch_branch follows.
    if (watch_) {
      const auto departure = [&](const PathPoint& p) {
        return watch_->departure * (watch_->mode.dot(p.x.head(model.amplitudes())) - watch_->at);
      };
      if (departure(from) > 0.0 && !(departure(to) > 0.0)) {
        std::optional<PathPoint> back = follower.locate(from, to, departure, 0.0);
        if (!back) return reject("the bifurcated branch's return to the path it left could not be located");
        to = refined_crossing(model, follower, std::move(*back));
        if (auto why = state_failure(model, to.x))
          return reject(fmt::format("at the branch's return at lambda = {:.10g}: {}", to.lambda, *why));
        record_step(model, to, to.iterations, ds);
        const Buckle b = buckle(model, to.x);
        const std::string where = fmt::format(
            "the bifurcated branch left at lambda = {:.10g} meets the path it left again at lambda = {:.10g}, "
            "axial force {:.6g} (the critical mode's amplitude back to its value at the first point; stability "
            "margin {:.3g})",
            watch_->lambda, to.lambda, compression(model, to.x, to.lambda), model.stability_margin(to.x, to.lambda));
        record_event(
            to.lambda, EventKind::bifurcation, b.amplitude > 0.0 ? b.crown : member_.s_from_user(options_.monitor),
            fmt::format("bifurcation: {} ({}); the switched branch ends here", where, to_string(model.topology())));
        ++bifurcations_;
        rejoined_ = "the switched branch ended where it rejoins the path it left (" + where + ")";
        return ObserverVerdict::stop;
      }
    }
    // Beam-columns: a fold (t_lambda changes sign), located on t_lambda and recorded as a
    // limit_point event before the step (or the event) beyond it.
    std::optional<PathPoint> fold;
    // (Von Karman's membrane term, like an axial force, makes the energy non-convex: "axial" below.)
    const bool axial = model.can_lose_stability();
    if (axial && from.tangent_lambda != 0.0 && (from.tangent_lambda > 0) != (to.tangent_lambda > 0))
      fold = follower.locate(
          from, to, [](const PathPoint& p) { return p.tangent_lambda; }, tolerance);
    const auto record_fold = [&] {
      if (!fold) return;
      const Buckle b = buckle(model, fold->x);
      const bool maximum = from.tangent_lambda > 0;
      // At: von Karman members, the monitor (the deflection the load-deflection curve draws, the
      // FE path's choice); beam-columns, the buckle's crown.
      const double at = member_.theory == model::Theory::von_karman ? options_.monitor : user(b.crown);
      TraceEvent event{
          fold->lambda, EventKind::limit_point, at,
          fmt::format("limit_point: lambda reaches a {} at {:.10g}, axial force {:.6g}, amplitude {:.6g}, lifted "
                      "length {:.6g} ({})",
                      maximum ? "maximum" : "minimum", fold->lambda, compression(model, fold->x, fold->lambda),
                      b.amplitude, b.lifted_length, to_string(model.topology()))};
      if (sink_.on_event) sink_.on_event(event);
      if (!limit_load_) limit_load_ = event;
      ++limit_points_;
      result_.events.push_back(std::move(event));
      fold.reset();
    };
    // Beam-columns: a bifurcation, where stability_margin (the smallest eigenvalue of the
    // reduced Hessian at fixed limits) changes sign while t_lambda keeps its own. At a fold the
    // same Hessian turns singular too (the Jacobian is block triangular at a solution, see
    // ritz_model.hpp): that sign change is the fold's, not reported twice.
    std::optional<PathPoint> bifurcation;
    double margin_to = std::numeric_limits<double>::quiet_NaN();
    if (axial) {
      margin_to = model.stability_margin(to.x, to.lambda);
      if (!fold && std::isfinite(previous_margin) && std::isfinite(margin_to) &&
          (previous_margin > 0.0) != (margin_to > 0.0)) {
        bifurcation = follower.locate(
            from, to, [&](const PathPoint& p) { return model.stability_margin(p.x, p.lambda); }, tolerance);
        // A point where t_lambda is all but zero is a fold seen through round-off (its sign and
        // the margin's may disagree next to it): no bifurcation.
        if (bifurcation && !(std::abs(bifurcation->tangent_lambda) > 1e-6)) bifurcation.reset();
      }
    }
    // Returns true if the path switches to the bifurcated branch there (branch_ set; the
    // observer then stops at the bifurcation point).
    const auto record_bifurcation = [&] {
      if (!bifurcation) return false;
      const Buckle b = buckle(model, bifurcation->x);
      const bool losing = previous_margin > 0.0;
      std::string switched;
      if (losing && options_.switch_branch) {
        std::string why;
        branch_ = switch_branch(model, *bifurcation, why);
        switched = branch_ ? fmt::format("; the path switches to the bifurcated branch ({}, lambda = {:.10g})",
                                         to_string(branch_->model.topology()), branch_->point.lambda)
                           : "; the path stays on this branch: no bifurcated branch found (" + why + ")";
      }
      record_event(bifurcation->lambda, EventKind::bifurcation,
                   b.amplitude > 0.0 ? b.crown : member_.s_from_user(options_.monitor),
                   fmt::format("bifurcation: the tangent stiffness on the contact set turns singular ({} to {}) at "
                               "lambda = {:.10g}, axial force {:.6g}: another branch crosses the path (amplitude "
                               "{:.6g}, lifted length {:.6g}, {}){}",
                               losing ? "stable" : "unstable", losing ? "unstable" : "stable", bifurcation->lambda,
                               compression(model, bifurcation->x, bifurcation->lambda), b.amplitude, b.lifted_length,
                               to_string(model.topology()), switched));
      ++bifurcations_;
      bifurcation.reset();
      return branch_.has_value();
    };
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
    // A piece between two limits within event_tolerance of vanishing (see above) vanishes here.
    std::vector<std::size_t> vanishing;
    for (std::size_t i = 0; i < specs.size(); ++i)
      if (vanishes_singularly(model, specs[i]) && previous[i] > 0 && now[i] > 0 &&
          vanishing_gap(model, to, specs[i]) <= tolerance)
        vanishing.push_back(i);
    // The linear tensionless problem has one equilibrium per lambda (its energy is convex and,
    // where it has one at all, strictly so), so the path of contact solutions never turns back
    // in lambda; a step that did has left it, and events cannot be located on it (their
    // functions are not monotone along it): it is retried shorter. But for an end piece
    // vanishing where a member that only the foundation holds lifts off entirely (the last
    // lambda with any equilibrium: a fold), located like any event.
    // Under an axial force the energy is not convex: folds are part of the path (see above).
    const bool turned = !axial && (!(to.lambda > from.lambda) || !(to.tangent_lambda > 0));
    if (turned && !(foundation_only_ && std::any_of(changed.begin(), changed.end(), [&](std::size_t i) {
                      return specs[i].function == EventFunction::length && !vanishes_singularly(model, specs[i]);
                    })))
      return reject(fmt::format(
          "the path turned back in lambda ({}), which no path of tensionless equilibria does: "
          "the topology {} has left it",
          to.lambda > from.lambda ? fmt::format("its tangent at lambda = {:.10g} points to falling lambda", to.lambda)
                                  : fmt::format("from {:.10g} to {:.10g}", from.lambda, to.lambda),
          to_string(model.topology())));
    if (!changed.empty() || !vanishing.empty()) {
      // Locate each; the earliest wins, and those at the same lambda come along.
      std::optional<PathPoint> first;
      std::vector<std::pair<double, std::size_t>> located;
      for (std::size_t i : vanishing) {
        located.emplace_back(to.arclength, i);
        first = to;
      }
      for (std::size_t i : changed) {
        const EventSpec spec = specs[i];
        auto point = follower.locate(
            from, to, [&](const PathPoint& p) { return event_value(model, p.x, spec).value; }, tolerance);
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
        // (An event at `from` itself: a piece found within event_tolerance of vanishing there.)
        if (!axial && !(first->lambda >= from.lambda))
          return reject(fmt::format("the event located at lambda = {:.10g} lies behind the step's start {:.10g}",
                                    first->lambda, from.lambda));
        // The state at the event must be a contact solution but for the event itself. A piece
        // vanishing leaves its limits out of order or its w of the wrong sign by what locating
        // it leaves: the state after the switch is checked instead (switch_topology).
        const bool removes = std::any_of(pending.events.begin(), pending.events.end(),
                                         [](const EventSpec& e) { return e.function == EventFunction::length; });
        if (!removes)
          if (auto why = state_failure(model, first->x, event_allowance(model, first->x, pending.events)))
            return reject(fmt::format("at the event located at lambda = {:.10g}: {}", first->lambda, *why));
        if (auto why = stepped_over(model, from.x, first->x)) return reject(*why);
        if (fold && fold->arclength <= first->arclength) record_fold();
        if (bifurcation && bifurcation->arclength <= first->arclength) {
          const PathPoint at = *bifurcation;
          if (record_bifurcation()) {  // the branch leaves before this event
            to = at;
            branch_step_ = ds;
            return ObserverVerdict::stop;
          }
        }
        to = *first;
        bool switches = false;
        for (const EventSpec& spec : pending.events)
          if (spec.function != EventFunction::limit_at_load) switches = true;
        record_step(model, to, to.iterations, ds, switches ? std::optional(pending.opening) : std::nullopt);
        const auto record = [&](const EventSpec& spec, double s) {
          record_event(to.lambda, spec.kind, s,
                       fmt::format("{} at {} = {:.10g} ({})", to_string(spec.kind),
                                   member_.kind == model::StructureKind::arch ? "theta" : "x", user(s),
                                   to_string(model.topology())));
        };
        for (const EventSpec& spec : pending.events) {
          if (spec.function != EventFunction::interior_extreme) {
            record(spec, event_value(model, to.x, spec).at);
            continue;
          }
          // One event per zone that opens (symmetric loads open several at once).
          const ContactRegion piece = model.pieces(to.x)[spec.piece];
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
    // No event located: the step's end must be a contact solution reached without stepping over
    // one (else it is retried shorter; at min_step the path stops and says why).
    if (auto why = state_failure(model, to.x)) return reject(fmt::format("at lambda = {:.10g}: {}", to.lambda, *why));
    if (auto why = stepped_over(model, from.x, to.x)) return reject(*why);
    // Deflections that grow much faster than where the topology started (a lifted span
    // lengthening) would shrink the steps in lambda: the metric is rescaled (see rescale) and
    // the follow restarted from here.
    const double next = follower.next_step(ds, to.iterations);
    record_fold();
    if (bifurcation) {
      const PathPoint at = *bifurcation;
      if (record_bifurcation()) {
        // (The bifurcation point is no step: a trace resumed from it could not tell the branch
        // it left by; resumed from the step before, it finds the switch again.)
        to = at;
        branch_step_ = next;
        return ObserverVerdict::stop;
      }
    }
    // (Beam-columns keep the scale they started with: near a fold dx/dlambda grows without bound.)
    if (!axial && to.lambda < options_.arc_length.lambda_max && to.tangent_lambda > 0 &&
        lambda_size() * to.tangent_x.head(model.amplitudes()).lpNorm<Eigen::Infinity>() / to.tangent_lambda >
            4.0 * amplitude_scale_) {
      rescale(model, to);
      record_step(model, to, to.iterations, next);
      restart_ = to;
      restart_step_ = next;
      return ObserverVerdict::stop;
    }
    record_step(model, to, to.iterations, next);
    previous = now;
    previous_scale = w_scale(model, to.x);
    previous_margin = margin_to;
    if (options_.max_amplitude && result_.steps.back().amplitude >= *options_.max_amplitude) {
      amplitude_reached_ = true;
      return ObserverVerdict::stop;
    }
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
        const ContactRegion piece = old.pieces(at.x)[spec.piece];
        const double zero = 1e-6 * w_scale(old, at.x);
        for (const EventValue& local : local_minima(old, at.x, piece.begin, piece.end, piece.in_contact))
          if (local.value <= zero) openings.emplace_back(local.at, 1);
        break;
      }
      case EventFunction::end_value:
        openings.emplace_back(event_value(old, at.x, spec).at, spec.far_end ? 2 : 0);
        if (!spec.far_end) flip_first = !flip_first;
        break;
      case EventFunction::limit_at_load:
        break;
    }
  }
  std::vector<double> kept;
  for (std::size_t m = 0; m < limits.size(); ++m)
    if (!remove[m]) kept.push_back(limits[m]);
  int added = 0;
  for (const auto& opening : openings) added += opening.second == 1 ? 2 : 1;
  const Topology topology{old.topology().first_in_contact != flip_first, static_cast<int>(kept.size()) + added};

  // Nothing holds a free-free member that has lifted off everywhere.
  if (!topology.first_in_contact && topology.limits == 0 && member_.left == model::EndSupport::free &&
      member_.right == model::EndSupport::free && member_.point_supports.empty()) {
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
  // A removed piece leaves what w had over it, of the wrong sign for the merged piece (and as
  // small as locating the event left it): that much violation is allowed at the switch.
  double removal_allowance = 0.0;
  {
    const std::vector<ContactRegion> pieces = old.pieces(at.x);
    const double scale = std::max(w_scale(old, at.x), 1e-300);
    for (const EventSpec& spec : pending.events) {
      if (spec.function != EventFunction::length) continue;
      const ContactRegion& p = pieces[spec.piece];
      const double lo = std::min(p.begin, p.end), hi = std::max(p.begin, p.end);
      constexpr int samples = 64;
      for (int i = 0; i <= samples; ++i)
        removal_allowance = std::max(removal_allowance, std::abs(old.w(at.x, lo + (hi - lo) * i / samples)) / scale);
    }
  }
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
      const std::vector<ContactRegion> pieces = old.pieces(base.x);
      std::vector<ContactRegion> zones;  // each new zone (s), for the locality check below
      for (auto [s, where] : openings) {
        // The new zone's sign: w's at an interior opening point; at an end, the opposite of the
        // end piece's state (w there is 0 at a supported end, and its sign noise: a scan keyed
        // on it stops at once and Newton settles on a zone of no width).
        const ContactRegion& end_piece = where == 0 ? pieces.front() : pieces.back();
        const double w0 = where == 1 ? old.w(base.x, s) : (end_piece.in_contact ? -1.0 : 1.0);
        const auto root = [&](double from, double to) {  // bisection on w
          double a = from, b = to, fa = old.w(base.x, a);
          for (int k = 0; k < 200 && std::abs(b - a) > 1e-15 * member_.length(); ++k) {
            const double m = 0.5 * (a + b), fm = old.w(base.x, m);
            if ((fm > 0) == (fa > 0))
              a = m, fa = fm;
            else
              b = m;
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
          for (const ContactRegion& p : pieces)
            if (s >= p.begin && s <= p.end) lo = p.begin, hi = p.end;
          guess.push_back(scan(lo));
          guess.push_back(scan(hi));
          zones.push_back({guess.end()[-2], guess.back(), w0 > 0});
        } else {
          guess.push_back(scan(where == 0 ? pieces.front().end : pieces.back().begin));
          zones.push_back(where == 0 ? ContactRegion{member_.foundation_begin, guess.back(), w0 > 0}
                                     : ContactRegion{guess.back(), member_.foundation_end, w0 > 0});
        }
      }
      std::sort(guess.begin(), guess.end());
      // The zones must open locally: one that already covers another local extreme of w at
      // the event (a minimum in a contact piece, a maximum in a lift-off one) has swallowed the
      // events between (culvert: a zone opened at a pinned end reached past a minimum of w
      // that lifted off first), so the opening step is too long.
      const double zero = 1e-6 * w_scale(old, at.x);
      std::optional<double> swallowed;
      for (const ContactRegion& piece : old.pieces(at.x))
        for (const EventValue& e : local_minima(old, at.x, piece.begin, piece.end, piece.in_contact))
          if (e.value > zero)  // not an opening point itself
            for (const ContactRegion& zone : zones)
              if (e.at > zone.begin && e.at < zone.end) swallowed = e.at;
      if (swallowed) {
        failure = fmt::format(
            "the zone opened {:.3g} past the event in lambda covers another local extreme of w at {} "
            "= {:.6g}",
            delta, member_.kind == model::StructureKind::arch ? "theta" : "x", user(*swallowed));
        continue;
      }
    }
    RitzModel candidate(member_, modes_, topology, enrichment_);
    VectorXd x(candidate.unknowns());
    x.head(candidate.amplitudes()) = base.x.head(old.amplitudes());
    for (int m = 0; m < topology.limits; ++m) x[candidate.limit_offset() + m] = guess[m];
    const PathFollower follower = make_follower(candidate);
    nonlinear::NewtonSummary newton;
    // The new tangent has lambda growing, as every path of contact solutions (see follow). The
    // old tangent cannot tell: at a piece vanishing it is that of a fold (t_lambda = 0), its
    // amplitude part of either sense.
    // Beam-columns may switch on a falling branch: the new tangent keeps the old one's sense.
    std::optional<PathPoint> orientation;
    if (candidate.can_lose_stability()) {
      PathPoint o;
      o.x = x;
      o.lambda = base.lambda;
      o.tangent_x = VectorXd::Zero(candidate.unknowns());
      o.tangent_x.head(candidate.amplitudes()) = base.tangent_x.head(old.amplitudes());
      o.tangent_lambda = base.tangent_lambda;
      orientation = std::move(o);
    }
    const std::optional<PathPoint> start = follower.start(x, base.lambda, &newton, orientation);
    if (!start) {
      failure = "Newton: " + newton.message;
    } else if (auto why = state_failure(candidate, start->x, removal_allowance)) {
      failure = fmt::format("at lambda = {:.10g}: {}", start->lambda, *why);
    } else {
      PathPoint point = *start;
      rescale(candidate, point);
      model_.emplace(std::move(candidate));
      if (base.lambda != at.lambda) record_step(*model_, point, newton.iterations, pending.step);
      restart_ = point;
      restart_step_ = pending.step;
      return true;
    }
    if (openings.empty()) break;  // nothing to vary
  }
  result_.summary.termination = TraceTermination::solver_failure;
  result_.summary.message =
      fmt::format("no equilibrium found in the topology {} after the event at lambda = {:.10g}: {}",
                  to_string(topology), at.lambda, failure);
  return false;
}

// The bifurcated branch at a bifurcation point `at` (lambda_c) where the path loses its
// stability. The critical mode phi (the amplitudes' eigenvector of the reduced Hessian's smallest
// eigenvalue, zero there) solves the fixed-topology equations at lambda_c for any multiple
// added, as far as the contact conditions allow: x + a phi, with a's sign the one that lifts the
// member off first (the least a > 0 at which w + a phi touches zero in a contact piece, away from
// its limits: where the reaction is smallest relative to the mode's lift). A tensionless
// foundation admits that side only once it touches: there a lift-off zone opens (at every point
// that touches at that a), and the branch is that of the topology with the new zones. Its first
// point: w + 1.02 a phi dips below zero near each touching point, whose roots guess the new
// limits; the first zone's one limit held fixed, Newton
// solves the new topology's equations for the other unknowns and lambda (that limit's column of
// the Jacobian replaced by dR/dlambda). The branch is then followed with the zone widening.
// Not handled (why says so): a critical mode that lifts where a lift-off zone already ends (the
// zone would grow in the same topology), one that pushes a lift-off piece into the foundation.
std::optional<RitzTracer::Branch> RitzTracer::switch_branch(const RitzModel& model, const PathPoint& at,
                                                            std::string& why) {
  const int amplitudes = model.amplitudes();
  // 1. The critical mode, scaled as stability_margin scales the Hessian.
  VectorXd scale = model.stiffness().diagonal();
  for (Eigen::Index i = 0; i < scale.size(); ++i) scale[i] = scale[i] > 0.0 ? 1.0 / std::sqrt(scale[i]) : 1.0;
  const Eigen::SelfAdjointEigenSolver<MatrixXd> eigen(scale.asDiagonal() * model.reduced_hessian(at.x, at.lambda) *
                                                      scale.asDiagonal());
  if (eigen.info() != Eigen::Success) {
    why = "the eigensolver failed";
    return std::nullopt;
  }
  VectorXd mode = VectorXd::Zero(model.unknowns());
  mode.head(amplitudes) = scale.asDiagonal() * eigen.eigenvectors().col(0);
  // Von Karman on a bilateral foundation: nothing lifts off, the bifurcated branch keeps the
  // topology (the shallow arch's asymmetric branch). Its first point: the amplitude the mode
  // moves most held a little off the bifurcation point, lambda free; the tangent leads away from
  // the point. (A linear beam-column's branch is at constant lambda: left as it was, no switch.)
  if (!member_.tensionless && member_.theory == model::Theory::von_karman)
    return switch_in_topology(model, at, mode, why);
  // 2. Where and at which amplitude it first lifts the member off, on a grid of the contact
  //    pieces (a foundation end that is free included, the pieces' limits excluded).
  const int samples = std::max(400, 16 * modes_);
  const double h = member_.length() / samples;
  const double w_size = std::max(w_scale(model, at.x), 1e-300);
  double best = infinity, sign = 1.0;
  struct Sample {
    double s, a, sign;
  };
  std::vector<Sample> lifts;  // at each sample, the multiple a of the mode, of the sign that lifts, touching there
  const std::vector<ContactRegion> pieces = model.pieces(at.x);
  for (const ContactRegion& piece : pieces) {
    if (!piece.in_contact) continue;
    const bool begins = piece.begin <= member_.foundation_begin && !end_supported(true);
    const bool ends = piece.end >= member_.foundation_end && !end_supported(false);
    const double lo = begins ? piece.begin : piece.begin + h, hi = ends ? piece.end : piece.end - h;
    const int n = std::max(1, static_cast<int>(std::ceil((hi - lo) / h)));
    for (int i = 0; i <= n && hi >= lo; ++i) {
      const double s = lo + (hi - lo) * i / n;
      const double w = model.w(at.x, s), f = model.w(mode, s);
      if (!(std::abs(f) > 1e-12 * std::abs(w))) continue;
      lifts.push_back({s, w / std::abs(f), f < 0 ? 1.0 : -1.0});
      if (lifts.back().a < best * (1.0 - 1e-12)) best = lifts.back().a, sign = lifts.back().sign;
    }
  }
  // Von Karman on a tensionless foundation: where the mode lifts nothing within ten times the
  // in-topology first point's offset, the branch starts in contact as on a bilateral foundation
  // (the shallow arch's asymmetric branch lifts off at an end only once |A2| = A1 / 2), and its
  // lift-off is a contact event on the branch.
  if (member_.theory == model::Theory::von_karman) {
    Eigen::Index held = 0;
    if (!(best <= 10.0 * in_topology_offset(model, at, mode, held))) return switch_in_topology(model, at, mode, why);
  }
  if (!std::isfinite(best) || !(best > 0.0)) {
    why = "the critical mode lifts no contact piece off";
    return std::nullopt;
  }
  // Every point where it touches at that multiple (to 1e-6: a symmetric mode lifts both ends, or
  // two mirror points, at once), one per cluster of samples.
  std::vector<double> touches;
  for (const Sample& sample : lifts)
    if (sample.sign == sign && sample.a <= best * (1.0 + 1e-6) &&
        (touches.empty() || sample.s - touches.back() > 4.0 * h))
      touches.push_back(sample.s);
  // Next to a limit, the mode would only move it (the zone grows in the same topology).
  for (double touch : touches)
    for (const ContactRegion& piece : pieces)
      for (double t : {piece.begin, piece.end})
        if (t > member_.foundation_begin && t < member_.foundation_end && std::abs(touch - t) < 2.0 * h) {
          why = fmt::format("the critical mode lifts the member first next to the contact limit at {:.6g}", user(t));
          return std::nullopt;
        }
  mode *= sign;
  constexpr double overshoot = 1.02;
  VectorXd base = at.x;
  base.head(amplitudes) += overshoot * best * mode.head(amplitudes);
  for (const ContactRegion& piece : pieces)
    if (!piece.in_contact && extreme(model, base, piece.begin, piece.end, false).value < -1e-9 * w_size) {
      why = "the critical mode pushes a lift-off piece into the foundation";
      return std::nullopt;
    }
  // 3. The new zones' limits: the roots of the base's w around each touching point.
  const auto root = [&](double from, double to) {
    double a = from, b = to, fa = model.w(base, a);
    for (int k = 0; k < 200 && std::abs(b - a) > 1e-15 * member_.length(); ++k) {
      const double m = 0.5 * (a + b), fm = model.w(base, m);
      if ((fm > 0) == (fa > 0))
        a = m, fa = fm;
      else
        b = m;
    }
    return 0.5 * (a + b);
  };
  const auto scan = [&](double touch, double limit_s) {  // from touch toward limit_s, the first w >= 0
    constexpr int steps = 4096;
    double previous = touch;
    for (int i = 1; i <= steps; ++i) {
      const double next = touch + (limit_s - touch) * i / steps;
      if (model.w(base, next) >= 0) return root(previous, next);
      previous = next;
    }
    return limit_s;
  };
  std::vector<double> limits(at.x.data() + model.limit_offset(), at.x.data() + model.unknowns());
  bool first_in_contact = model.topology().first_in_contact;
  // The limit held in the Newton below (the first zone's), and its sense as that zone widens.
  std::optional<double> fixed;
  double widening = 1.0;
  for (double touch : touches) {
    ContactRegion host{member_.foundation_begin, member_.foundation_end, true};
    for (const ContactRegion& piece : pieces)
      if (piece.in_contact && touch >= piece.begin && touch <= piece.end) host = piece;
    double limit = 0.0, sense = -1.0;
    if (touch <= member_.foundation_begin + 0.5 * h) {
      limit = scan(touch, host.end), sense = 1.0;
      first_in_contact = !first_in_contact;
    } else if (touch >= member_.foundation_end - 0.5 * h) {
      limit = scan(touch, host.begin);
    } else {
      limit = scan(touch, host.begin);
      limits.push_back(scan(touch, host.end));
    }
    limits.push_back(limit);
    if (!fixed) fixed = limit, widening = sense;
  }
  std::sort(limits.begin(), limits.end());
  const Topology topology{first_in_contact, static_cast<int>(limits.size())};
  RitzModel candidate(member_, modes_, topology, enrichment_);
  VectorXd x(candidate.unknowns());
  x.head(candidate.amplitudes()) = base.head(amplitudes);
  for (int m = 0; m < topology.limits; ++m) x[candidate.limit_offset() + m] = limits[m];
  const int held =
      candidate.limit_offset() + static_cast<int>(std::find(limits.begin(), limits.end(), *fixed) - limits.begin());
  // 4. Newton with that limit held, lambda free.
  double lambda = at.lambda;
  VectorXd residual_scale = VectorXd::Constant(candidate.unknowns(), 1.0 / force_scale(candidate));
  residual_scale.tail(topology.limits).setConstant(1.0 / w_size);
  if (!solve_with_held(candidate, held, residual_scale, x, lambda) || !candidate.admissible(x)) {
    why = fmt::format("Newton on the topology {} with the limit at {:.6g} held did not converge", to_string(topology),
                      user(*fixed));
    return std::nullopt;
  }
  // 5. The first point of the branch, its tangent widening the zone.
  std::optional<Branch> branch = branch_from(std::move(candidate), x, lambda, held, widening, why);
  if (!branch) return std::nullopt;
  if (auto failure = state_failure(branch->model, branch->point.x)) {
    why = fmt::format("the branch's first point at lambda = {:.10g} is no contact solution: {}", branch->point.lambda,
                      *failure);
    return std::nullopt;
  }
  return branch;
}

std::optional<RitzTracer::Branch> RitzTracer::switch_in_topology(const RitzModel& model, const PathPoint& at,
                                                                 const VectorXd& mode, std::string& why) {
  Eigen::Index held = 0;
  const double offset = in_topology_offset(model, at, mode, held);
  VectorXd x = at.x + offset * mode;
  double lambda = at.lambda;
  const VectorXd residual_scale = VectorXd::Constant(model.unknowns(), 1.0 / force_scale(model));
  if (!solve_with_held(model, static_cast<int>(held), residual_scale, x, lambda)) {
    why = "Newton with the critical mode's amplitude held off the bifurcation point did not converge";
    return std::nullopt;
  }
  std::optional<Branch> branch =
      branch_from(model, x, lambda, static_cast<int>(held), mode[held] > 0.0 ? 1.0 : -1.0, why);
  if (branch) {
    ReturnWatch watch;
    watch.mode = mode.head(model.amplitudes()).normalized();
    watch.at = watch.mode.dot(at.x.head(model.amplitudes()));
    watch.departure = watch.mode.dot(branch->point.x.head(model.amplitudes())) > watch.at ? 1.0 : -1.0;
    watch.lambda = at.lambda;
    branch->watch = std::move(watch);
  }
  return branch;
}

PathPoint RitzTracer::refined_crossing(const RitzModel& model, const PathFollower& follower, PathPoint near) const {
  const int amplitudes = model.amplitudes();
  PathPoint guess = near;
  guess.x.head(amplitudes) -= (watch_->mode.dot(near.x.head(amplitudes)) - watch_->at) * watch_->mode;
  const auto solved = [&](double lambda) { return follower.step_to_lambda(guess, lambda, &guess.x).point; };
  std::optional<PathPoint> a = solved(near.lambda);
  if (!a) return near;
  double margin_a = model.stability_margin(a->x, a->lambda);
  std::optional<PathPoint> b = solved(near.lambda + 1e-6 * lambda_size());
  for (int iteration = 0; b && iteration < 30; ++iteration) {
    const double margin_b = model.stability_margin(b->x, b->lambda);
    if (std::abs(b->lambda - a->lambda) <= 0.1 * options_.event_tolerance || margin_b == 0.0) return *b;
    if (margin_b == margin_a) break;
    const double lambda = b->lambda - margin_b * (b->lambda - a->lambda) / (margin_b - margin_a);
    a = std::move(b);
    margin_a = margin_b;
    b = solved(lambda);
  }
  return near;
}

double RitzTracer::in_topology_offset(const RitzModel& model, const PathPoint& at, const VectorXd& mode,
                                      Eigen::Index& held) const {
  mode.head(model.amplitudes()).cwiseAbs().maxCoeff(&held);
  // A step off the point of 1e-3 of w's size along the mode: small beside the branch's own
  // curvature, large beside Newton's tolerance (1e-12).
  const double w_size = std::max(w_scale(model, at.x), 1e-300);
  return 1e-3 * w_size / std::abs(mode[held]);
}

bool RitzTracer::solve_with_held(const RitzModel& model, int held, const VectorXd& residual_scale, VectorXd& x,
                                 double& lambda) const {
  VectorXd r;
  MatrixXd j;
  for (int iteration = 0; iteration < 50; ++iteration) {
    model.residual(x, lambda, r);
    if (!r.allFinite()) return false;
    if (r.cwiseProduct(residual_scale).lpNorm<Eigen::Infinity>() <= 1e-12) return true;
    model.jacobian(x, lambda, j);
    j.col(held) = model.residual_lambda_derivative(x);
    const VectorXd delta =
        (residual_scale.asDiagonal() * j).colPivHouseholderQr().solve(-residual_scale.cwiseProduct(r));
    if (!delta.allFinite()) return false;
    for (int m = 0; m < model.unknowns(); ++m)
      if (m != held) x[m] += delta[m];
    lambda += delta[held];
  }
  return false;
}

std::optional<RitzTracer::Branch> RitzTracer::branch_from(RitzModel model, const VectorXd& x, double lambda, int held,
                                                          double sense, std::string& why) const {
  const PathFollower follower = make_follower(model);
  PathPoint orientation;
  orientation.x = x;
  orientation.lambda = lambda;
  orientation.tangent_x = VectorXd::Zero(model.unknowns());
  orientation.tangent_x[held] = sense;
  orientation.tangent_lambda = 0.0;
  nonlinear::NewtonSummary newton;
  std::optional<PathPoint> point = follower.start(x, lambda, &newton, orientation);
  if (!point) {
    why = "no tangent at the branch's first point: " + newton.message;
    return std::nullopt;
  }
  return Branch{std::move(model), std::move(*point), newton.iterations, std::nullopt};
}

TraceResult RitzTracer::run() {
  const auto clock = std::chrono::steady_clock::now();
  result_.summary.path = PathKind::ritz;
  validate();
  enrichment_ = choose_enrichment();
  resolution_ = resolution();
  foundation_only_ = !fe::discretise(member_, options_.elements).structure_is_stable();
  const auto finish = [&](TraceTermination termination, std::string message) {
    result_.summary.termination = termination;
    result_.summary.message = std::move(message);
    result_.summary.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - clock).count();
    return result_;
  };
  ResumeState state;
  try {
    state = starting_state();
  } catch (const StartFailure& failure) {
    return finish(TraceTermination::solver_failure, failure.what());
  }
  model_.emplace(member_, modes_, state.topology, enrichment_);
  amplitude_scale_ = state.amplitude_scale;
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
        if (auto why = state_failure(*model_, start->x, event_allowance(*model_, start->x, pending.events)))
          return finish(
              TraceTermination::solver_failure,
              fmt::format("the resumed state at lambda = {:.10g} is no contact solution: {}", start->lambda, *why));
        pending_ = std::move(pending);
        if (!switch_topology(follower)) return finish(result_.summary.termination, result_.summary.message);
        start = restart_;
        state.next_step = restart_step_;
        restart_.reset();
      } else if (auto why = state_failure(*model_, start->x)) {
        return finish(
            TraceTermination::solver_failure,
            fmt::format("the resumed state at lambda = {:.10g} is no contact solution: {}", start->lambda, *why));
      }
    } else {
      nonlinear::NewtonSummary newton;
      start = follower.start(state.point.x, state.point.lambda, &newton);
      if (!start) return finish(TraceTermination::solver_failure, "no equilibrium at lambda_min: " + newton.message);
      if (auto why = state_failure(*model_, start->x))
        return finish(TraceTermination::solver_failure,
                      fmt::format("the start at lambda = {:.10g} is no contact solution: {}", start->lambda, *why));
      rescale(*model_, *start);
      record_step(*model_, *start, newton.iterations, state.next_step);
    }
  }
  double step = state.next_step;
  // The run's own figures (not the last topology's follower's), for every outcome.
  const auto figures = [&] {
    const auto count = [](std::size_t n, const char* what) {
      return fmt::format("{} {}{}", n, what, n == 1 ? "" : "s");
    };
    return fmt::format(
        "{} ({} rejected), {}, {} modes{}{}", count(static_cast<std::size_t>(result_.summary.steps), "step"),
        result_.summary.rejected_steps, count(result_.events.size(), "event"), modes_,
        model_ && model_->can_lose_stability()
            ? fmt::format(", {} limit point(s), {} bifurcation(s)", limit_points_, bifurcations_)
            : "",
        options_.resume_from
            ? fmt::format(" after the resumed step at lambda = {:.10g}", options_.resume_from->load_factor)
            : "");
  };
  // Beam-columns: the limit load found, for the messages.
  const auto limit_note = [&]() -> std::string {
    if (!limit_load_) return "";
    return fmt::format(" (limit point at lambda = {:.10g})", limit_load_->load_factor);
  };
  const auto step_limit = [&] {
    return finish(TraceTermination::step_limit,
                  fmt::format("step limit: max_steps = {} steps recorded, lambda = {:.10g}; {}",
                              options_.arc_length.max_steps, result_.summary.final_load_factor, figures()));
  };
  while (true) {
    if (result_.summary.steps >= options_.arc_length.max_steps) return step_limit();
    const PathFollower follower = make_follower(*model_);
    const ArcLengthResult path = follow(*model_, follower, *start, step);
    result_.summary.rejected_steps += path.rejected_steps;
    if (amplitude_reached_)
      return finish(TraceTermination::completed,
                    fmt::format("amplitude {:.6g} reached (max_amplitude = {:.6g}) at lambda = {:.10g}{}: {}{}",
                                result_.steps.back().amplitude, *options_.max_amplitude,
                                result_.summary.final_load_factor, limit_note(), figures(), resolution_note()));
    if (rejoined_)
      return finish(TraceTermination::completed,
                    fmt::format("{}{}: {}{}", *rejoined_, limit_note(), figures(), resolution_note()));
    if (pending_ && !switch_topology(follower))
      return finish(result_.summary.termination, fmt::format("{}; {}", result_.summary.message, figures()));
    if (branch_) {
      Branch branch = std::move(*branch_);
      branch_.reset();
      model_.emplace(std::move(branch.model));
      watch_ = std::move(branch.watch);
      rescale(*model_, branch.point);
      record_step(*model_, branch.point, branch.iterations, branch_step_);
      start = branch.point;
      step = branch_step_;
      continue;
    }
    if (restart_ && path.termination == ArcLengthTermination::stopped_by_observer) {
      start = restart_;
      step = restart_step_;
      restart_.reset();
      continue;
    }
    switch (path.termination) {
      case ArcLengthTermination::completed:
        return finish(TraceTermination::completed,
                      fmt::format("lambda = {:.10g} reached{}: {}{}", result_.summary.final_load_factor, limit_note(),
                                  figures(), resolution_note()));
      case ArcLengthTermination::step_rejected:
        return finish(
            TraceTermination::solver_failure,
            fmt::format("no contact solution beyond lambda = {:.10g} (the step was refined down to min_step "
                        "= {:.3g}): {}; {}",
                        result_.summary.final_load_factor, options_.arc_length.min_step, rejection_, figures()));
      case ArcLengthTermination::step_too_small:
        return finish(TraceTermination::step_too_small, fmt::format("{}; {}", path.message, figures()));
      case ArcLengthTermination::step_limit:
        return step_limit();
      default:
        return finish(TraceTermination::solver_failure, fmt::format("{}; {}", path.message, figures()));
    }
  }
}

}  // namespace

TraceResult trace_ritz(const scene::Scene& scene, const TraceOptions& options, const TraceSink& sink) {
  RitzTracer tracer(scene, model::make_member_model(scene), options, sink);
  return tracer.run();
}

TraceResult trace_ritz(const scene::Scene& scene, const model::MemberModel& member, const TraceOptions& options,
                       const TraceSink& sink) {
  RitzTracer tracer(scene, member, options, sink);
  return tracer.run();
}

}  // namespace liftoff::continuation
