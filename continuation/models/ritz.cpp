#include "continuation/models/ritz.hpp"

#include "continuation/step_state.hpp"

// The Ritz path's start, metric, stability and record. Along a step: ritz_steps.cpp; switches of
// topology and branch: ritz_switch.cpp.
//
// Units: the path works in model::MemberModel's nondimensional s and w; steps are reported in the
// user's units through model::Scales.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include "contact/contact_solver.hpp"
#include "contact/von_karman_solve.hpp"
#include "fe/discretisation.hpp"
#include "post/contact_regions.hpp"

namespace liftoff::continuation {

using Eigen::MatrixXd;
using Eigen::VectorXd;
using ritz::RitzModel;
using ritz::Topology;

namespace {

constexpr double kPi = 3.14159265358979323846;
// Automatic modes aim at resolution_target; any N whose e(N) exceeds resolution_limit is refused.
constexpr double resolution_target = 1e-3;
constexpr double resolution_limit = 1e-2;

// No equilibrium to start from: an outcome (solver_failure in the summary), not misuse.
struct StartFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A resumed step's topology in words, for the messages that refuse it.
std::string describe(const StateTopology& topology) {
  if (const auto* r = std::get_if<RitzTopology>(&topology))
    return fmt::format("{} {} {}{}", r->first_in_contact ? 1 : 0, r->limits, r->modes,
                       r->at_event ? fmt::format(" event {} {}", r->at_event->direction, r->at_event->delta) : "");
  return std::holds_alternative<FeContactSet>(topology) ? "an FE contact set" : "none";
}

}  // namespace

// What a resumed step carries (see TraceStep::state): topology, x, tangent, next step length;
// and for a step at a switching event, how the switch opens its zone.
struct RitzPath::ResumeState {
  Topology topology;
  PathPoint point;
  double next_step = 0.0;
  double amplitude_scale = 0.0;  // 0: not stored (a file of an older liftoff), from the loads
  std::optional<RitzOpening> at_event;
};

// The response to a point force is local, of wavenumber beta = (k/4)^(1/4), and w at the force
// converges like the tail of its modal sum, sum over wavenumbers kappa > N pi / length of
// 1/(kappa^4 + 4 beta^4): relative to the whole sum (the infinite beam's, pi/(8 beta^3)) that is
//     e(N) = 8/(3 pi) (beta length / (pi N))^3      (for N pi > beta length),
// which the relative error of the first lift-off load follows closely (pipeline, beta L = 100:
// e = 0.104, 0.0131 at N = 64, 128; measured 0.096, 0.0126). Without such a force, or with the
// load-point enrichment (N^-8, beta L <= 10), there is nothing to estimate (applies = false).
double RitzResolution::error(int modes) const {
  const double ratio = beta_length / (kPi * modes);
  return ratio >= 1.0 ? 1.0 : 8.0 / (3.0 * kPi) * ratio * ratio * ratio;
}

int RitzResolution::modes_for(double target) const {
  return static_cast<int>(std::ceil(beta_length / kPi * std::cbrt(8.0 / (3.0 * kPi * target))));
}

RitzPath::RitzPath(model::MemberModel member, const TraceOptions& options)
    : member_(std::move(member)), options_(options) {
  // The load-point enrichment (ritz/basis.hpp) where the foundation leaves a point force's
  // response global (beta L <= 10, beta = (k/4)^(1/4)); on a stiffer one the response is local,
  // the kinked functions' far field must be cancelled by the smooth modes, and Newton stalls.
  const double beta_l = std::pow(member_.k / 4.0, 0.25) * member_.length();
  enrichment_ = member_.kind == model::StructureKind::beam && beta_l <= 10.0 ? ritz::Enrichment::load_points
                                                                             : ritz::Enrichment::none;
  resolution_ = resolution();
  foundation_only_ = !fe::discretise(member_, options_.elements).structure_is_stable();
}

RitzResolution RitzPath::resolution() const {
  RitzResolution r;
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

int RitzPath::modes_for_trace(const ritz::RitzSolution& start) const {
  if (options_.ritz.modes > 0) return options_.ritz.modes;
  // Automatic: what solve_ritz settled on at lambda_min, but at least 32, since limits that do
  // not exist yet at lambda_min (full contact) say nothing about the N they will need; and
  // what a point force on the foundation needs (resolution_target), up to max_modes.
  int modes = std::max(start.summary.modes, 32);
  if (resolution_.applies)
    modes = std::max(modes, std::min(resolution_.modes_for(resolution_target), options_.ritz.max_modes));
  return modes;
}

// Refuses (StartFailure) N modes that cannot resolve a point force's local response.
void RitzPath::check_resolution(int modes) const {
  if (!resolution_.applies || resolution_.error(modes) <= resolution_limit) return;
  const bool automatic = options_.ritz.modes == 0;
  throw StartFailure(fmt::format(
      "refused: {} modes resolve the local response to the point force at {} = {:.6g} on this foundation (beta times "
      "the member's length = {:.3g}) only to about {:.0f} % (the smooth modes converge there like (beta length / (pi "
      "N))^3); {} modes are needed for {:.0f} % and {} for {:.1f} %{}: set [ritz] modes{} or use an FE method",
      modes, coordinate(), user(resolution_.at), resolution_.beta_length, 100.0 * resolution_.error(modes),
      resolution_.modes_for(resolution_limit), 100.0 * resolution_limit, resolution_.modes_for(resolution_target),
      100.0 * resolution_target,
      automatic ? fmt::format(" (automatic modes stop at [ritz] max_modes = {})", options_.ritz.max_modes) : "",
      automatic ? " and max_modes" : ""));
}

RitzPath::ResumeState RitzPath::resumed_state(const TraceStep& step) {
  ResumeState state;
  const auto* topology = std::get_if<RitzTopology>(&step.state_topology);
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
  const int unknowns = RitzModel(member_, modes_, state.topology, enrichment_).unknowns();
  if (unknowns != n)
    throw std::invalid_argument(
        fmt::format("TraceOptions.resume_from: the state has {} unknowns, but the Ritz model of topology \"{}\" has {}",
                    n, describe(step.state_topology), unknowns));
  const Eigen::Map<const VectorXd> values(step.state.data(), static_cast<Eigen::Index>(step.state.size()));
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

// The topology at lambda_start: the options', or from the FE solution there.
ritz::StartingPoint RitzPath::start_topology(double lambda_start) const {
  if (!options_.ritz.topology.empty())
    return ritz::starting_point_from_pieces(options_.ritz.topology, options_.ritz.limits, member_);
  const fe::Discretisation d = fe::discretise(member_, options_.elements);
  if (member_.theory == model::Theory::von_karman && member_.kind == model::StructureKind::beam) {
    // Von Karman: the linear solve knows nothing of the membrane (a shallow arch's linear answer
    // at lambda_min is the straight beam's, in contact where the arch has lifted off): the FE von
    // Karman contact solve from zero there gives the topology (the branch that the load path from
    // zero reaches while no fold lies below lambda_min).
    const contact::VonKarmanResult fe = contact::VonKarmanSystem(member_, d).solve(lambda_start, {});
    if (!fe.is_usable())
      throw StartFailure("the FE von Karman contact solution at lambda_min that gives the Ritz topology failed: " +
                         fe.message);
    const VectorXd displacement = d.expand_displacement(fe.x.head(d.equations));
    return ritz::starting_point_from_regions(post::contact_regions(member_, d, displacement), member_);
  }
  contact::ContactOptions contact_options;
  contact_options.method = contact::Method::fast;
  contact_options.load_factor = lambda_start;
  const contact::ContactSolution fe = contact::solve_contact(d, contact_options);
  if (!fe.summary.is_usable())
    throw StartFailure("the FE + LCP solution at lambda_min that gives the Ritz topology failed: " +
                       fe.summary.message);
  return ritz::starting_point_from_regions(post::contact_regions(member_, d, fe.displacement), member_);
}

// The topology and unknowns at lambda_min (or at the resumed step).
RitzPath::ResumeState RitzPath::starting_state() {
  if (options_.resume_from) return resumed_state(*options_.resume_from);
  ResumeState state;
  // Without load at lambda_min (no dead load, lambda_min = 0) w vanishes and every topology fits,
  // so the path starts one initial_step later, where the loads define it.
  const bool unloaded = options_.arc_length.lambda_min == 0.0 &&
                        std::all_of(member_.loads.begin(), member_.loads.end(),
                                    [](const model::MemberLoad& l) { return l.load_case != model::LoadCase::dead; });
  const double lambda_start = unloaded ? options_.arc_length.initial_step : options_.arc_length.lambda_min;
  // Refuse before any work: the given N, or the most automatic modes could take.
  check_resolution(options_.ritz.modes > 0 ? options_.ritz.modes : std::max(options_.ritz.max_modes, 32));
  const ritz::StartingPoint initial = start_topology(lambda_start);
  state.topology = initial.topology;
  ritz::RitzOptions ritz_options;
  ritz_options.modes = options_.ritz.modes;
  ritz_options.max_modes = options_.ritz.max_modes;
  ritz_options.mode_tolerance = options_.ritz.mode_tolerance * member_.length();
  ritz_options.load_factor = lambda_start;
  ritz_options.enrichment = enrichment_;
  ritz::RitzSolution start = ritz::solve_ritz(member_, state.topology, initial.limits, ritz_options);
  modes_ = modes_for_trace(start);
  check_resolution(modes_);
  if (start.summary.modes != modes_) {
    ritz_options.modes = modes_;
    std::vector<double> settled(start.unknowns.data() + start.unknowns.size() - state.topology.limits,
                                start.unknowns.data() + start.unknowns.size());
    if (!start.summary.is_usable()) settled = initial.limits;
    start = ritz::solve_ritz(member_, state.topology, settled, ritz_options);
  }
  if (!start.summary.is_usable())
    throw StartFailure("the Ritz solution at lambda_min failed: " + start.summary.message);
  state.point.x = start.unknowns;
  state.point.lambda = lambda_start;
  state.next_step = options_.arc_length.initial_step;
  return state;
}

PathModel::Start RitzPath::start(const ArcLengthOptions& /*options*/) {
  ResumeState state;
  try {
    state = starting_state();
  } catch (const StartFailure& failure) {
    return {std::nullopt, true, 0.0, TraceTermination::solver_failure, failure.what()};
  }
  events_.emplace(member_, modes_);
  adopt(std::make_shared<const RitzModel>(member_, modes_, state.topology, enrichment_));
  amplitude_scale_ = state.amplitude_scale;
  if (options_.resume_from) {
    if (state.at_event) return resumed_at_event(state);
    if (auto why = events_->state_failure(*model_, state.point.x))
      return {
          std::nullopt, true, 0.0, TraceTermination::solver_failure,
          fmt::format("the resumed state at lambda = {:.10g} is no contact solution: {}", state.point.lambda, *why)};
    return {state.point, false, state.next_step, TraceTermination::solver_failure, ""};
  }
  nonlinear::NewtonSummary newton;
  std::optional<PathPoint> point = follower_for(model_).start(state.point.x, state.point.lambda, &newton);
  if (!point)  // (Newton converged: the path's tangent there is what failed, its bordered system singular)
    return {std::nullopt, true, 0.0, TraceTermination::solver_failure,
            newton.is_usable() ? fmt::format("an equilibrium at lambda = {:.10g} but no tangent to the path there "
                                             "(its bordered system is singular)",
                                             state.point.lambda)
                               : "no equilibrium at lambda_min: " + newton.message};
  if (auto why = events_->state_failure(*model_, point->x))
    return {std::nullopt, true, 0.0, TraceTermination::solver_failure,
            fmt::format("the start at lambda = {:.10g} is no contact solution: {}", point->lambda, *why)};
  point->iterations = newton.iterations;
  rescale(model_, *point);
  vouch(*point);
  return {std::move(point), true, state.next_step, TraceTermination::solver_failure, ""};
}

// Resumed at a switching event: the events are those whose functions vanish here; the switch is
// redone.
PathModel::Start RitzPath::resumed_at_event(const ResumeState& state) {
  Transition transition;
  transition.point = state.point;
  transition.opening = *state.at_event;
  transition.changes_topology = true;
  const double scale = events_->w_scale(*model_, state.point.x);
  for (const RitzEventSpec& spec : specs_) {
    if (spec.function == RitzEventFunction::limit_at_load) continue;
    const bool length = spec.function == RitzEventFunction::length;
    if (std::abs(events_->value(*model_, state.point.x, spec).value) <= 1e-7 * (length ? member_.length() : scale))
      transition.events.push_back(spec);
  }
  transition.events = events_->without_degenerate_openings(*model_, state.point.x, std::move(transition.events));
  const double allowance = events_->event_allowance(*model_, state.point.x, transition.events);
  if (auto why = events_->state_failure(*model_, state.point.x, allowance))
    return {std::nullopt, true, 0.0, TraceTermination::solver_failure,
            fmt::format("the resumed state at lambda = {:.10g} is no contact solution: {}", state.point.lambda, *why)};
  Entry entry = switch_topology(transition);
  if (!entry.point) return {std::nullopt, true, 0.0, entry.failure, entry.why};
  return {std::move(entry.point), entry.record, state.next_step, TraceTermination::solver_failure, ""};
}

double RitzPath::lambda_size() const {
  return std::max({std::abs(options_.arc_length.lambda_min), std::abs(options_.arc_length.lambda_max), 1.0});
}

// Typical sizes: forces over the range of lambda from the loads; deflections those forces make
// against the foundation (or against the unit bending stiffness where the foundation is softer).
double RitzPath::force_scale(const RitzModel& model) const {
  return std::max(
      model.dead_load().lpNorm<Eigen::Infinity>() + lambda_size() * model.live_load().lpNorm<Eigen::Infinity>(),
      1e-300);
}

// What the loads make against the foundation (or the unit bending stiffness): at least 1e-300,
// so that its inverse, the metric's scale, stays finite (a member without loads: w = 0 throughout).
double RitzPath::load_deflection(const RitzModel& model) const {
  return std::max(force_scale(model) / std::max(member_.k, 1.0), 1e-300);
}

PathProblem RitzPath::problem() const { return problem_for(model_); }

PathProblem RitzPath::problem_for(std::shared_ptr<const RitzModel> model) const {
  const int n = model->unknowns(), a = model->amplitudes();
  const double force_scale = this->force_scale(*model);
  const double amplitude_scale = amplitude_scale_ > 0 ? amplitude_scale_ : load_deflection(*model);
  PathProblem problem;
  problem.unknowns = n;
  problem.residual = [model](const VectorXd& y, double lambda, VectorXd& g) {
    if (!y.allFinite()) return false;
    model->residual(y, lambda, g);
    return true;
  };
  problem.jacobian = [model](const VectorXd& y, double lambda, MatrixXd& j) {
    model->jacobian(y, lambda, j);
    return true;
  };
  problem.lambda_derivative = [model](const VectorXd& y, double, VectorXd& g) {
    g = model->residual_lambda_derivative(y);
    return true;
  };
  problem.unknown_scale = VectorXd::Constant(n, 1.0 / amplitude_scale);
  problem.unknown_scale.tail(n - a).setConstant(1.0 / member_.length());
  problem.residual_scale = VectorXd::Constant(n, 1.0 / force_scale);
  problem.residual_scale.tail(n - a).setConstant(1.0 / amplitude_scale);
  return problem;
}

PathFollower RitzPath::follower_for(std::shared_ptr<const RitzModel> model) const {
  ArcLengthOptions o = options_.arc_length;
  o.fold_tolerance = options_.event_tolerance;
  o.locate_folds = false;
  return PathFollower(problem_for(std::move(model)), o);
}

// The amplitudes' scale for the topology that starts at p: at least what the loads make
// against the foundation, and what lambda_size units of lambda make at p (dx/dlambda from p's
// tangent), so that a step ds moves lambda by about ds where the topology starts. Scaled by the
// loads alone, a pipeline whose lifted span deflects 200 times q/K took steps of 7e-4 in lambda
// (10000 steps to lambda = 2.2). The scale is stored with each step, so a resumed trace takes
// the same steps.
void RitzPath::rescale(std::shared_ptr<const RitzModel> model, PathPoint& p) {
  const int a = model->amplitudes();
  double scale = load_deflection(*model);
  // (Beam-columns: only where the path starts; near a fold dx/dlambda grows without bound.)
  if (p.tangent_lambda > 0 && (!model->can_lose_stability() || amplitude_scale_ == 0.0))
    scale = std::max(scale, lambda_size() * p.tangent_x.head(a).lpNorm<Eigen::Infinity>() / p.tangent_lambda);
  if (model->can_lose_stability() && amplitude_scale_ > 0.0) scale = std::max(scale, amplitude_scale_);
  if (!std::isfinite(scale)) return;  // keep the scale in use
  amplitude_scale_ = scale;
  const PathFollower follower = follower_for(std::move(model));
  PathPoint reference = p;
  if (auto t = follower.tangent(p.x, p.lambda, &reference)) {
    p.tangent_x = t->first;
    p.tangent_lambda = t->second;
  }
}

// Deflections that grow much faster than where the topology started (a lifted span lengthening)
// would shrink the steps in lambda: the metric is rescaled and the follower rebuilt. (Beam-columns
// keep the scale they started with: near a fold dx/dlambda grows without bound.)
bool RitzPath::wants_new_problem(PathPoint& point) {
  if (model_->can_lose_stability() || !(point.lambda < options_.arc_length.lambda_max) || !(point.tangent_lambda > 0))
    return false;
  const double rate =
      lambda_size() * point.tangent_x.head(model_->amplitudes()).lpNorm<Eigen::Infinity>() / point.tangent_lambda;
  if (!(rate > 4.0 * amplitude_scale_)) return false;
  rescale(model_, point);
  return true;
}

// The compressive force in user units (TraceStep::axial_force): the given axial force less the
// von Karman membrane force (tension > 0; zero without the term).
double RitzPath::compression(const RitzModel& model, const VectorXd& x, double lambda) const {
  return (model.axial_force(lambda) - model.membrane_force(x)) * member_.scales.force();
}

StabilityMeasure RitzPath::stability_measure() const {
  return model_ && model_->can_lose_stability() ? StabilityMeasure::margin : StabilityMeasure::none;
}

StabilityState RitzPath::stability(const PathPoint& point) const {
  StabilityState s;
  s.margin = model_->can_lose_stability() ? model_->stability_margin(point.x, point.lambda)
                                          : std::numeric_limits<double>::quiet_NaN();
  return s;
}

// At: von Karman members, the monitor (the deflection the load-deflection curve draws, the FE
// path's choice); beam-columns, the buckle's crown where the member has lifted, else the monitor.
double RitzPath::event_position(const PathPoint& point) const {
  if (member_.theory == model::Theory::von_karman) return options_.monitor;
  const RitzBuckle b = events_->buckle(*model_, point.x);
  return b.amplitude > 0.0 ? user(b.crown) : options_.monitor;
}

std::string RitzPath::describe_state(const PathPoint& point) const {
  const RitzBuckle b = events_->buckle(*model_, point.x);
  return fmt::format("axial force {:.6g}, amplitude {:.6g}, lifted length {:.6g}, {}",
                     compression(*model_, point.x, point.lambda), b.amplitude, b.lifted_length,
                     to_string(model_->topology()));
}

double RitzPath::amplitude(const PathPoint& point) const { return events_->buckle(*model_, point.x).amplitude; }

std::optional<std::string> RitzPath::certify(const PathPoint& point) const {
  for (const VectorXd& x : checked_)
    if (x.size() == point.x.size() && x == point.x) return std::nullopt;
  return events_->state_failure(*model_, point.x);
}

// The step of a state in the user's units, with its resumable state.
TraceStep RitzPath::record(const PathPoint& point, const RecordContext& context) const {
  const RitzModel& model = *model_;
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
  step.iterations = point.iterations;
  step.axial_force = compression(model, point.x, point.lambda);
  const RitzBuckle b = events_->buckle(model, point.x);
  step.amplitude = b.amplitude;
  step.lifted_length = b.lifted_length;
  record_ritz_state(step, member_, model, point.x, point.lambda, options_.elements);
  // At a switching event the state carries the opening a resumed trace redoes.
  std::optional<RitzOpening> at_event;
  if (context.crossing) {
    const auto& transition = std::any_cast<const Transition&>(context.crossing->transition);
    if (transition.changes_topology) at_event = transition.opening;
  }
  step.state_topology = RitzTopology{model.topology().first_in_contact, model.topology().limits, modes_, at_event};
  const int n = static_cast<int>(point.x.size());
  step.state.resize(2 * n + 3);
  Eigen::Map<VectorXd> state(step.state.data(), 2 * n + 3);
  state.head(n) = point.x;
  state.segment(n, n) = point.tangent_x;
  state(2 * n) = point.tangent_lambda;
  state(2 * n + 1) = context.next_step;
  state(2 * n + 2) = amplitude_scale_;
  return step;
}

std::string RitzPath::summary_note() const {
  std::string note = fmt::format("{} modes", modes_);
  if (resolution_.applies && modes_ > 0)
    note +=
        fmt::format(", the point force's local response resolved to about {:.1e} (estimated from beta length = {:.3g})",
                    resolution_.error(modes_), resolution_.beta_length);
  if (options_.resume_from)
    note += fmt::format(" after the resumed step at lambda = {:.10g}", options_.resume_from->load_factor);
  return note;
}

TraceResult trace_ritz(const model::MemberModel& member, const TraceOptions& options, const TraceSink& sink) {
  // The member's ends in the user coordinate (x, or theta in degrees, which the round trip through
  // s may round by an ulp: app::trace_options puts the last sample on the scene's end exactly).
  const double begin = member.user_from_s(member.s_begin), end = member.user_from_s(member.s_end);
  const double slack = 1e-12 * std::abs(end - begin);
  options.validate(std::min(begin, end) - slack, std::max(begin, end) + slack);
  RitzPath path(member, options);
  return follow_path(path, options, sink);
}

}  // namespace liftoff::continuation
