#include "continuation/engine.hpp"

// Why things are done the way they are:
//  - Everything found inside a step is located first and then taken in the order of arclength, up
//    to the first thing that ends the follower's run (a configuration change, a branch switch, the
//    end of the trace): what lies beyond it belongs to another configuration and is found again
//    there. A fold or a load asked for does not end the run.
//  - The stability of the step's start is kept from the step before (one factorisation a step
//    less), and recomputed where a run starts.
//  - A run continues a new configuration with the step length the old one had reached: the
//    contact set of an FE member changes at every node a limit passes, and restarting each set at
//    initial_step made the step count grow with the mesh.

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <utility>

namespace liftoff::continuation {

Stability StabilityState::verdict() const {
  if (negative_eigenvalues == 0) return Stability::stable;
  if (negative_eigenvalues > 0) return Stability::unstable;
  if (std::isfinite(margin)) return margin > 0.0 ? Stability::stable : Stability::unstable;
  return Stability::unknown;
}

namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

// Something located inside a step, in the order the engine takes it.
struct Found {
  enum class Kind { branch_return, crossing, fold, bifurcation, requested, amplitude };
  Found(Kind k, PathPoint p) : kind(k), point(std::move(p)), lambda(point.lambda) {}
  Kind kind;
  PathPoint point;
  double lambda = 0.0;  // the event's lambda (a bifurcation's bracket midpoint; else point.lambda)
  std::optional<Crossing> crossing;
  StabilityState before, after;
  bool maximum = false;  // a fold: lambda reaches a maximum (else a minimum)
  bool refined = true;   // a branch's return: on the crossing (false: where its amplitude vanished)
  bool ends_run() const {
    return kind == Kind::branch_return || kind == Kind::amplitude || (kind == Kind::crossing && crossing->switches);
  }
};

// What ended a follower's run, for the outer loop to act on.
struct Pending {
  std::optional<Crossing> enter;      // a configuration change at the run's last point
  std::optional<BranchStart> branch;  // a switch onto a bifurcated branch
  bool restart = false;               // a new follower on the model's (changed) problem, same point,
  double restart_step = 0.0;          // at this step length
};

class Engine {
 public:
  Engine(PathModel& model, const TraceOptions& options, const TraceSink& sink)
      : model_(model), options_(options), sink_(sink) {}
  TraceResult run();

 private:
  ArcLengthOptions follower_options() const;
  // Certifies and records a point (the sink, the result); false if its certificate fails (the
  // trace then ends: finished_).
  bool keep(const PathPoint& point, const Crossing* crossing = nullptr, bool requested = false,
            std::optional<StabilityState> stability = std::nullopt, double next_step = 0.0);
  void event(TraceEvent e);
  ObserverVerdict observe(const PathFollower& follower, const PathPoint& from, PathPoint& to);
  Screening screen_stability(const PathPoint& from, const PathPoint& to);
  // The stages of detection, each adding what it located to `found`.
  std::optional<std::string> detect(const PathFollower& follower, const PathPoint& from, const PathPoint& to,
                                    std::vector<Found>& found);
  // (A return that cannot be located on the step: why the step is retried shorter.)
  std::optional<std::string> detect_return(const PathFollower& follower, const PathPoint& from, const PathPoint& to,
                                           std::vector<Found>& found);
  void detect_fold(const PathFollower& follower, const PathPoint& from, const PathPoint& to, std::vector<Found>& found);
  void detect_bifurcation(const PathFollower& follower, const PathPoint& from, const PathPoint& to,
                          std::vector<Found>& found);
  void detect_requested(const PathFollower& follower, const PathPoint& from, const PathPoint& to,
                        std::vector<Found>& found);
  void detect_amplitude(const PathFollower& follower, const PathPoint& from, const PathPoint& to,
                        std::vector<Found>& found);
  // Takes one located thing: records it, and says whether the run ends there. step: the step
  // length in use (what a run continued from the point takes, and what its record says).
  bool take(const PathFollower& follower, Found& f, double step);
  TraceResult finish(TraceTermination termination, std::string message);
  std::string counts() const;

  PathModel& model_;
  const TraceOptions& options_;
  const TraceSink& sink_;
  TraceResult result_;
  std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();

  StabilityState stability_;          // at the last accepted point
  StabilityState candidate_;          // at the step's end being looked at
  std::optional<BranchStart> watch_;  // the switched branch, watched for its return
  double peak_ = 0.0;                 // the largest amplitude it reached at an accepted point
  bool switched_ = false;             // the path has left onto a bifurcated branch (once per trace)
  Pending pending_;
  std::optional<std::pair<TraceTermination, std::string>> finished_;
  std::string rejection_;  // why the last step was rejected
  int limit_points_ = 0, bifurcations_ = 0;
};

ArcLengthOptions Engine::follower_options() const {
  ArcLengthOptions o = options_.arc_length;
  o.locate_folds = false;  // located here, in order with the other events
  o.fold_tolerance = options_.event_tolerance;
  o.max_steps = std::max(1, options_.arc_length.max_steps - result_.summary.steps + 1);
  return o;
}

bool Engine::keep(const PathPoint& point, const Crossing* crossing, bool requested,
                  std::optional<StabilityState> stability, double next_step) {
  if (std::optional<std::string> why = model_.certify(point)) {
    finished_ = {TraceTermination::solver_failure,
                 fmt::format("the state at lambda = {:.10g} failed its certificate: {}", point.lambda, *why)};
    return false;
  }
  TraceStep step = model_.record(point, {crossing, next_step});
  step.requested = requested;
  if (options_.physical_load) step.load = options_.physical_load->at(step.load_factor);
  if (model_.stability_measure() != StabilityMeasure::none)
    step.stability = (stability  ? *stability
                      : crossing ? model_.stability_at_crossing(point, *crossing)
                                 : model_.stability(point))
                         .verdict();
  if (sink_.on_step) sink_.on_step(step);
  result_.summary.final_load_factor = step.load_factor;
  result_.steps.push_back(std::move(step));
  ++result_.summary.steps;
  return true;
}

void Engine::event(TraceEvent e) {
  if (sink_.on_event) sink_.on_event(e);
  result_.events.push_back(std::move(e));
}

// A step holding a fold and a change of stability, or two changes, is retried shorter (down to
// 100 min_step), so that each is located on its own (they are told apart by their own sides).
Screening Engine::screen_stability(const PathPoint& from, const PathPoint& to) {
  if (model_.stability_measure() != StabilityMeasure::count) return {};
  const bool fold = from.tangent_lambda != 0.0 && (from.tangent_lambda > 0) != (to.tangent_lambda > 0);
  const int before = stability_.negative_eigenvalues, after = candidate_.negative_eigenvalues;
  const int changes = std::abs(after - before) - (fold ? 1 : 0);
  if (before >= 0 && after >= 0 && changes >= 1 + (fold ? 0 : 1) &&
      to.arclength - from.arclength > 100 * options_.arc_length.min_step)
    return {Screening::Verdict::reject,
            fmt::format("a limit point and a change of stability, or two changes, between lambda = {:.10g} and "
                        "{:.10g}",
                        from.lambda, to.lambda)};
  return {};
}

std::optional<std::string> Engine::detect_return(const PathFollower& follower, const PathPoint& from,
                                                 const PathPoint& to, std::vector<Found>& found) {
  if (!watch_ || !watch_->amplitude) return std::nullopt;
  peak_ = std::max(peak_, watch_->amplitude(from));
  const double zero = watch_->return_accuracy * peak_;
  const auto amplitude = [&](const PathPoint& p) { return watch_->amplitude(p) - zero; };
  if (!(amplitude(from) > 0.0) || amplitude(to) > 0.0) return std::nullopt;
  std::optional<PathPoint> located = follower.locate(from, to, amplitude, watch_->return_tolerance);
  if (!located)  // (a long step across the crossing's fold, whose corrector solves fail: shorter)
    return fmt::format(
        "the bifurcated branch's return to the path it left could not be located between lambda = "
        "{:.10g} and {:.10g}",
        from.lambda, to.lambda);
  std::optional<PathPoint> refined = model_.refine_return(*located, peak_, follower);
  Found f(Found::Kind::branch_return, refined ? *refined : model_.refine(*located, false));
  f.refined = refined.has_value();
  f.lambda = f.point.lambda;
  found.push_back(std::move(f));
  return std::nullopt;
}

void Engine::detect_fold(const PathFollower& follower, const PathPoint& from, const PathPoint& to,
                         std::vector<Found>& found) {
  // (Under load control lambda is monotone by construction: the tangent turning there is the path
  // approaching a fold it cannot pass, where the corrector then fails.)
  if (options_.arc_length.control == PathControl::load) return;
  if (!(from.tangent_lambda != 0.0 && (from.tangent_lambda > 0) != (to.tangent_lambda > 0))) return;
  const auto t_lambda = [](const PathPoint& p) { return p.tangent_lambda; };
  std::optional<PathPoint> located = follower.locate(from, to, t_lambda, options_.event_tolerance);
  if (!located) return;
  Found f(Found::Kind::fold, model_.refine(*located, false));
  f.lambda = f.point.lambda;
  f.maximum = from.tangent_lambda > 0;
  found.push_back(std::move(f));
}

void Engine::detect_bifurcation(const PathFollower& follower, const PathPoint& from, const PathPoint& to,
                                std::vector<Found>& found) {
  const StabilityMeasure measure = model_.stability_measure();
  if (measure == StabilityMeasure::none) return;
  if (from.tangent_lambda != 0.0 && (from.tangent_lambda > 0) != (to.tangent_lambda > 0)) return;  // the fold's
  const StabilityState before = stability_, after = candidate_;
  Found f(Found::Kind::bifurcation, to);
  f.before = before, f.after = after;
  if (measure == StabilityMeasure::count) {
    if (before.negative_eigenvalues < 0 || after.negative_eigenvalues < 0 ||
        before.negative_eigenvalues == after.negative_eigenvalues)
      return;
    // Bisection on the count, to event_tolerance in lambda.
    double lo = 0.0, hi = to.arclength - from.arclength;
    PathPoint lo_point = from, hi_point = to;
    for (int it = 0; it < 200 && std::abs(hi_point.lambda - lo_point.lambda) > options_.event_tolerance; ++it) {
      const double mid = 0.5 * (lo + hi);
      if (!(mid > lo && mid < hi)) break;
      StepOutcome outcome = follower.step(from, mid);
      if (!outcome.point) break;
      if (model_.stability(*outcome.point).negative_eigenvalues == before.negative_eigenvalues)
        lo = mid, lo_point = std::move(*outcome.point);
      else
        hi = mid, hi_point = std::move(*outcome.point);
    }
    f.point = model_.refine_bifurcation(lo_point);  // the last point with the count of before
    f.lambda = f.point.lambda == lo_point.lambda ? 0.5 * (lo_point.lambda + hi_point.lambda) : f.point.lambda;
  } else {
    if (!std::isfinite(before.margin) || !std::isfinite(after.margin) || (before.margin > 0.0) == (after.margin > 0.0))
      return;
    const auto margin = [&](const PathPoint& p) { return model_.stability(p).margin; };
    std::optional<PathPoint> located = follower.locate(from, to, margin, options_.event_tolerance);
    // A point where t_lambda is all but zero is a fold seen through round-off: no bifurcation.
    if (!located || !(std::abs(located->tangent_lambda) > 1e-6)) return;
    f.point = *located;
    f.lambda = located->lambda;
  }
  found.push_back(std::move(f));
}

void Engine::detect_requested(const PathFollower& follower, const PathPoint& from, const PathPoint& to,
                              std::vector<Found>& found) {
  for (double target : options_.report_at) {
    const double a = from.lambda - target, b = to.lambda - target;
    if (!(a != 0.0 && (b == 0.0 || (a > 0) != (b > 0)))) continue;
    // Located on the step (a folding path may pass the value more than once, each on its own
    // step), then landed on it exactly by a fixed-lambda correction from there.
    std::optional<PathPoint> at = follower.locate(
        from, to, [target](const PathPoint& p) { return p.lambda - target; }, options_.event_tolerance, false);
    if (!at) continue;
    if (at->lambda != target) {
      StepOutcome landed = follower.step_to_lambda(*at, target);
      if (!landed.point) continue;
      at = std::move(landed.point);
    }
    Found f(Found::Kind::requested, model_.refine(*at, true));
    f.lambda = target;
    found.push_back(std::move(f));
  }
}

void Engine::detect_amplitude(const PathFollower& follower, const PathPoint& from, const PathPoint& to,
                              std::vector<Found>& found) {
  if (!options_.max_amplitude) return;
  const double bound = *options_.max_amplitude;
  // On the refined states: near a stationary lambda (a strut near its Euler load) the amplitude
  // grows like 1 / (1 - P / P_E), and the corrector's state, within its tolerance, was 1e-3 off it.
  const auto excess = [&](const PathPoint& p) { return model_.amplitude(model_.refine(p, false)) - bound; };
  if (!(model_.amplitude(from) < bound) || model_.amplitude(to) < bound) return;
  // Located to round-off in the arclength: there a bracket of event_tolerance in lambda leaves
  // the amplitude off by 1e-3 of the bound.
  std::optional<PathPoint> located = follower.locate(from, to, excess, 0.0);
  if (!located) located = follower.locate(from, to, excess, options_.event_tolerance);
  Found f(Found::Kind::amplitude, model_.refine(located ? *located : to, false));
  f.lambda = f.point.lambda;
  found.push_back(std::move(f));
}

std::optional<std::string> Engine::detect(const PathFollower& follower, const PathPoint& from, const PathPoint& to,
                                          std::vector<Found>& found) {
  if (std::optional<std::string> why = detect_return(follower, from, to, found)) return why;
  std::optional<CrossingSearch> searched;
  if (found.empty()) {  // (at a branch's return the fold there is the crossing's own, by symmetry)
    // The model's crossings first: what lies past the step's first switch of configuration is the
    // next configuration's to find. A switch the model takes at once (a point it reached across
    // the switch without locating it, before anything watched here) leaves nothing to look for on
    // this step; a located one bounds the search for a fold or a change of stability (near the
    // shallow arch's limit point a lift-off limit moves on by a node at every step, and the fold
    // beyond each switch was located on each of those steps in vain). Where the configuration's
    // stability changes between the step's ends away from a fold (where the change is the fold's),
    // its switches are located, none taken at once: the change is then looked for on the part of
    // the step where the configuration holds.
    const bool changes = stability_.negative_eigenvalues != candidate_.negative_eigenvalues ||
                         (std::isfinite(stability_.margin) && std::isfinite(candidate_.margin) &&
                          (stability_.margin > 0.0) != (candidate_.margin > 0.0));
    const bool turns = from.tangent_lambda != 0.0 && (from.tangent_lambda > 0) != (to.tangent_lambda > 0);
    searched = model_.crossing(from, to, follower, !changes || turns);
    bool nothing_before = false;  // the step switches at its start, or at once across (point_after)
    std::optional<PathPoint> until;
    for (const Crossing& c : searched->crossings) {
      if (!c.switches) continue;
      nothing_before = c.at_start || c.point_after;
      if (!nothing_before)
        if (const auto tangent = follower.tangent(c.point.x, c.point.lambda, &from)) {
          until = c.point;
          until->tangent_x = tangent->first;
          until->tangent_lambda = tangent->second;
        }
      break;
    }
    if (!searched->fail && !searched->reject && !nothing_before) {
      const StabilityState at_end = candidate_;
      if (until) candidate_ = model_.stability(*until);
      detect_fold(follower, from, until ? *until : to, found);
      detect_bifurcation(follower, from, until ? *until : to, found);
      candidate_ = at_end;
      detect_requested(follower, from, to, found);
      detect_amplitude(follower, from, to, found);
    }
  } else {
    detect_requested(follower, from, to, found);
    detect_amplitude(follower, from, to, found);
  }
  CrossingSearch search = searched ? std::move(*searched) : model_.crossing(from, to, follower, false);
  if (search.fail) {
    finished_ = {TraceTermination::solver_failure, *search.fail};
    return std::nullopt;
  }
  if (search.reject) return search.reject;
  for (Crossing& c : search.crossings) {
    Found f(Found::Kind::crossing, c.point);
    f.lambda = f.point.lambda;
    f.crossing = std::move(c);
    found.push_back(std::move(f));
  }
  // In the order of arclength; at one point, in the order detected (a return or a crossing first).
  std::stable_sort(found.begin(), found.end(),
                   [](const Found& a, const Found& b) { return a.point.arclength < b.point.arclength; });
  // A fold located where the run ends anyway (within event_tolerance of lambda of a crossing that
  // switches, or of a switched branch's return) is that point's: the old configuration's tangent
  // turns there because it ends (a Ritz piece vanishing as the member lifts off entirely), and
  // whether the path folds is the new configuration's to say (PathModel::Entry::events); a branch
  // turns back where it meets the path it left (its mirror image beyond: the shallow arch's, by
  // symmetry), and that point is the bifurcation.
  std::vector<double> switches;
  for (const Found& c : found)
    if ((c.kind == Found::Kind::crossing && c.crossing->switches) || c.kind == Found::Kind::branch_return)
      switches.push_back(c.lambda);
  std::erase_if(found, [&](const Found& f) {
    return f.kind == Found::Kind::fold && std::any_of(switches.begin(), switches.end(), [&](double lambda) {
             // (Relative: at the return the fold is flat in lambda, and the two are located by
             // different means: 7e-9 apart at lambda = 88.6 on the shallow arch.)
             return std::abs(f.lambda - lambda) <= options_.event_tolerance * std::max(1.0, std::abs(lambda));
           });
  });
  return std::nullopt;
}

bool Engine::take(const PathFollower& follower, Found& f, double step) {
  // (Words and position of the state before anything switches: a switch changes the model.)
  const std::string state = model_.describe_state(f.point);
  const double position = model_.event_position(f.point);
  switch (f.kind) {
    case Found::Kind::branch_return:
      if (!keep(f.point, nullptr, false, std::nullopt, step)) return true;
      ++bifurcations_;
      event({f.lambda, EventKind::bifurcation, position,
             fmt::format(
                 "bifurcation: the bifurcated branch meets the path it left again at lambda = {:.10g} "
                 "({}){}; the switched branch ends here",
                 f.lambda, state,
                 f.refined ? "" : "; not located on the crossing: the point where the branch's amplitude vanished")});
      finished_ = {TraceTermination::completed,
                   fmt::format("the bifurcated branch met the path it left again at lambda = {:.10g}", f.lambda)};
      return true;
    case Found::Kind::crossing: {
      const Crossing& c = *f.crossing;
      if (!c.at_start && !c.point_after && !keep(f.point, &c, false, std::nullopt, step)) return true;
      if (!c.point_after)  // (else after its point, recorded once the model has entered: run())
        for (const TraceEvent& e : c.events) event(e);
      if (c.switches) pending_.enter = c;
      return c.switches;
    }
    case Found::Kind::fold: {
      if (!keep(f.point, nullptr, false, std::nullopt, step)) return true;
      ++limit_points_;
      event({f.lambda, EventKind::limit_point, position,
             fmt::format("limit point: lambda reaches a {} {:.10g} ({})", f.maximum ? "maximum" : "minimum", f.lambda,
                         state)});
      return false;
    }
    case Found::Kind::bifurcation: {
      ++bifurcations_;
      const bool loses = f.before.verdict() == Stability::stable && f.after.verdict() == Stability::unstable;
      const std::string counts = f.before.negative_eigenvalues >= 0
                                     ? fmt::format(", negative eigenvalues of the tangent {} -> {}",
                                                   f.before.negative_eigenvalues, f.after.negative_eigenvalues)
                                     : "";
      std::string then;
      if (loses && options_.switch_branch && !switched_) {
        BranchSwitch s = model_.switch_branch(f.point, follower);
        if (s.branch) {
          then = fmt::format("; the path switches to the bifurcated branch ({})", s.branch->description);
          pending_.branch = std::move(s.branch);
          switched_ = true;
        } else {
          then = "; the path stays on this branch: " + s.why_not;
        }
      }
      event({f.lambda, EventKind::bifurcation, position,
             fmt::format("bifurcation at lambda = {:.10g} ({}): the tangent stiffness on the contact set turns "
                         "singular ({} to {}{}): another branch crosses the path{}",
                         f.lambda, state, to_string(f.before.verdict()), to_string(f.after.verdict()), counts, then)});
      if (pending_.branch) return true;
      // Not switching: the bifurcation point is a step of its own (its event carries its state).
      return !keep(f.point, nullptr, false, std::nullopt, step);
    }
    case Found::Kind::requested:
      return !keep(f.point, nullptr, true, std::nullopt, step);
    case Found::Kind::amplitude:
      if (!keep(f.point, nullptr, false, std::nullopt, step)) return true;
      finished_ = {TraceTermination::completed,
                   fmt::format("amplitude {:.6g} reached (max_amplitude) at lambda = {:.10g}",
                               model_.amplitude(f.point), f.point.lambda)};
      return true;
  }
  return false;
}

ObserverVerdict Engine::observe(const PathFollower& follower, const PathPoint& from, PathPoint& to) {
  const double step = to.arclength - from.arclength;  // the follower's (before the model cuts the step short)
  const bool at_end = to.lambda == options_.arc_length.lambda_max || to.lambda == options_.arc_length.lambda_min;
  to = model_.refine(to, at_end || options_.arc_length.control == PathControl::load);
  Screening screening = model_.screen(from, to, follower);
  if (screening.verdict == Screening::Verdict::admit) {
    candidate_ = model_.stability(to);
    screening = screen_stability(from, to);
  }
  if (screening.verdict == Screening::Verdict::reject) {
    rejection_ = std::move(screening.reason);
    return ObserverVerdict::reject;
  }
  std::vector<Found> found;
  if (std::optional<std::string> why = detect(follower, from, to, found)) {
    rejection_ = std::move(*why);
    return ObserverVerdict::reject;
  }
  if (finished_) {
    to = from;
    return ObserverVerdict::stop;
  }
  for (Found& f : found) {
    if (!take(follower, f, step)) continue;
    to = f.point;  // the run ends here
    return ObserverVerdict::stop;
  }
  const double next = follower.next_step(step, to.iterations);
  const bool restart = model_.wants_new_problem(to);  // (before the record: it may re-express to's tangent)
  if (!keep(to, nullptr, false, candidate_, next)) return ObserverVerdict::stop;
  stability_ = candidate_;
  if (result_.summary.steps >= options_.arc_length.max_steps) {
    finished_ = {TraceTermination::step_limit, fmt::format("max_steps = {} reached", options_.arc_length.max_steps)};
    return ObserverVerdict::stop;
  }
  if (restart) {
    pending_.restart = true;
    pending_.restart_step = next;
    return ObserverVerdict::stop;
  }
  return ObserverVerdict::proceed;
}

std::string Engine::counts() const {
  return fmt::format("{} steps ({} rejected), {} event(s), {} limit point(s), {} bifurcation(s){}",
                     result_.summary.steps, result_.summary.rejected_steps, result_.events.size(), limit_points_,
                     bifurcations_, model_.summary_note().empty() ? "" : ", " + model_.summary_note());
}

TraceResult Engine::finish(TraceTermination termination, std::string message) {
  TraceSummary& s = result_.summary;
  s.termination = termination;
  s.message = message + ": " + counts();
  s.path = model_.kind();
  if (!result_.steps.empty()) s.final_load_factor = result_.steps.back().load_factor;
  model_.fill_summary(s);
  s.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
  return std::move(result_);
}

TraceResult Engine::run() {
  result_.summary.path = model_.kind();
  result_.summary.final_load_factor = options_.arc_length.lambda_min;
  PathModel::Start start = model_.start(follower_options());
  if (!start.point) return finish(start.failure, start.why);
  double step_length = start.first_step > 0.0 ? start.first_step : options_.arc_length.initial_step;
  if (start.record && !keep(*start.point, nullptr, false, std::nullopt, step_length))
    return finish(finished_->first, finished_->second);
  PathPoint point = *start.point;
  while (true) {
    if (result_.summary.steps >= options_.arc_length.max_steps)
      return finish(TraceTermination::step_limit, fmt::format("max_steps = {} reached", options_.arc_length.max_steps));
    const PathFollower follower(model_.problem(), follower_options());
    stability_ = model_.stability(point);
    pending_ = {};
    const ArcLengthResult run = follower.follow(
        point, [&](const PathPoint& from, PathPoint& to) { return observe(follower, from, to); }, step_length);
    result_.summary.rejected_steps += run.rejected_steps;
    result_.summary.corrector_iterations += run.corrector_iterations;
    step_length = run.step_length;
    if (finished_) return finish(finished_->first, finished_->second);
    if (pending_.enter) {
      PathModel::Entry entry = model_.enter(*pending_.enter, follower_options());
      for (const TraceEvent& e : entry.events) {
        if (e.kind == EventKind::limit_point) ++limit_points_;
        event(e);
      }
      if (!entry.point) return finish(entry.failure, entry.why);
      if (entry.record && !keep(*entry.point, nullptr, false, std::nullopt, step_length))
        return finish(finished_->first, finished_->second);
      point = std::move(*entry.point);
      if (pending_.enter->point_after) {
        // A whole step was taken: the next one grows as after any accepted step.
        step_length = follower.next_step(step_length, point.iterations);
        // (Its metric too, as after any accepted step: the next follower is built on it. The
        // upheaval buckle's descending branch, each step across a node pair's switch, kept the
        // metric of its rising branch and took 26 steps of a few centimetres at 512 elements.)
        model_.wants_new_problem(point);
        if (!keep(point, nullptr, false, std::nullopt, step_length)) return finish(finished_->first, finished_->second);
        for (const TraceEvent& e : pending_.enter->events) event(e);
      }
    }
    if (pending_.branch) {
      watch_ = std::move(pending_.branch);
      if (!keep(watch_->point, nullptr, false, std::nullopt, step_length))
        return finish(finished_->first, finished_->second);
      point = watch_->point;
    }
    if (pending_.restart) {
      point = run.points.back();
      step_length = pending_.restart_step;
    }
    if (pending_.enter || pending_.branch || pending_.restart) {
      // A run stopped at the range's end (a switch taken there) ends the trace there.
      const ArcLengthOptions& o = options_.arc_length;
      if ((point.lambda >= o.lambda_max && point.tangent_lambda > 0) ||
          (point.lambda <= o.lambda_min && point.tangent_lambda < 0))
        return finish(TraceTermination::completed, fmt::format("lambda = {:.10g} reached", point.lambda));
      continue;
    }
    switch (run.termination) {
      case ArcLengthTermination::completed:
        return finish(TraceTermination::completed,
                      fmt::format("lambda = {:.10g} reached", result_.summary.final_load_factor));
      case ArcLengthTermination::step_rejected:
        return finish(TraceTermination::solver_failure,
                      fmt::format("no admissible state beyond lambda = {:.10g} (the step was refined down to "
                                  "min_step = {:.3g}): {}",
                                  result_.summary.final_load_factor, options_.arc_length.min_step, rejection_));
      case ArcLengthTermination::step_too_small:
        return finish(TraceTermination::step_too_small, run.message);
      case ArcLengthTermination::step_limit:
        return finish(TraceTermination::step_limit,
                      fmt::format("max_steps = {} reached", options_.arc_length.max_steps));
      default:
        return finish(TraceTermination::solver_failure, run.message);
    }
  }
}

}  // namespace

TraceResult follow_path(PathModel& model, const TraceOptions& options, const TraceSink& sink) {
  Engine engine(model, options, sink);
  return engine.run();
}

}  // namespace liftoff::continuation
