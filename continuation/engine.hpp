#pragma once
// The path engine: one loop that follows any model's equilibrium path in the load factor lambda,
// F = F_dead + lambda F_live, through contact events, limit points and bifurcations. Every path
// `liftoff trace` runs (linear FE, FE beam-columns, von Karman FE beams and arches, the Ritz model)
// is a PathModel driven by follow_path(); the engine does not know which model it drives.
//
// The split (BifurcationKit's problem / algorithm / events / branch, STYLE.md):
//  - the model owns the physics: the equations G(y, lambda) = 0 of its current *configuration* (a
//    contact set, a Ritz topology), the constraints under which that configuration holds and what
//    happens where one fails (PathModel::crossing, enter), its stability, its certificate and the
//    record of a state in the user's terms (PathModel::record);
//  - the engine owns the path: a PathFollower (arclength.hpp: tangent predictor, bordered corrector,
//    adaptive step) on the configuration's equations, the order in which things are looked at along
//    a step, the location of folds, bifurcations, a switched branch's return and the loads asked for,
//    the switches, the one sink every step and event goes to, max_steps and max_amplitude, and the
//    summary with its termination.
//
// Along each corrected step, from `from` to `to`, in this order (EngineObserver in engine.cpp):
//  1. refine:   the model's point (PathModel::refine: polished to round-off, where it needs it).
//  2. screen:   the model may reject the step (retried shorter, PathFollower's halving) or cut it
//               short (a nearer point on it).
//  3. detect:   what happens inside the step, each located on its own function along the step
//               (PathFollower::locate: secant on the arclength to event_tolerance in lambda) and
//               taken in the order of arclength:
//               - the model's constraint crossings (PathModel::crossing: contact events, a node
//                 leaving the set, a Ritz piece vanishing; located by the model, which knows its
//                 functions), which may change the configuration;
//               - a fold: the tangent's d lambda / ds changes sign (`limit_point`); one located
//                 where the run ends anyway (within event_tolerance of a crossing that switches,
//                 or of a branch's return) is that point's, not reported;
//               - a bifurcation: the tangent's count of negative eigenvalues changes without a
//                 fold (bisection on the count), or its stability margin changes sign (secant);
//                 where the path loses its stability, with TraceOptions::switch_branch, the model
//                 leaves along the critical mode (PathModel::switch_branch), once per trace;
//               - on a switched branch, its return to the path it left (the branch's amplitude
//                 along the critical mode back to zero): a second `bifurcation`, where the trace
//                 ends (the branch beyond is its own mirror image); a step on which it cannot be
//                 located is retried shorter;
//               - a load asked for (TraceOptions::report_at): lambda crossing it.
//               A step that holds a fold and a change of stability, or two changes of stability,
//               is retried shorter (down to 100 min_step) so that each is located on its own.
//  4. record:   every point the engine keeps (the step's end, each located point) is certified by
//               the model (PathModel::certify) and recorded (PathModel::record) to the sink; one
//               that fails ends the path there (solver_failure), the steps before it valid.
//               max_amplitude reached is located on the step and ends the path (completed).
// A configuration change (a crossing that switches) ends the follower's run at the crossing; the
// model enters the new configuration there (PathModel::enter: its first point, oriented), and a new
// follower continues with the step length the old one had reached.
//
// Ends: lambda_max (or lambda_min on a falling branch) landed on exactly (completed), the switched
// branch back on the path (completed), max_amplitude (completed), max_steps (step_limit), the corrector
// failing at min_step (step_too_small), a model that finds no equilibrium beyond some lambda
// (no_equilibrium, PathModel::enter or crossing says so), a state failing its certificate or a switch
// that does not hold (solver_failure). Every outcome's message gives the figures of the run.

#include <any>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "continuation/arclength.hpp"
#include "continuation/result.hpp"
#include "continuation/trace.hpp"

namespace liftoff::continuation {

// What a model says of a corrected step before anything is located on it.
struct Screening {
  enum class Verdict {
    admit,   // go on with `to` (which the model may have replaced by a nearer point of the step)
    reject,  // retried shorter; at min_step the path stops (solver_failure) with `reason`
  };
  Verdict verdict = Verdict::admit;
  std::string reason;
};

// A constraint crossing located by the model on a step.
struct Crossing {
  PathPoint point;                 // where, on the step (its arclength from the step's follower)
  std::vector<TraceEvent> events;  // recorded right after the step at `point` (possibly none: a node
                                   // leaving the set with no change of the contact topology)
  bool at_start = false;           // `point` is the step's start, recorded already: events only
  bool switches = true;            // the configuration changes at `point` (PathModel::enter next)
  // `point` is a state of the configuration after the change already (a crossing taken at the
  // step's end, not located: see PathModel::crossing): the engine records it once the model has
  // entered that configuration, as its first point.
  bool point_after = false;
  std::any transition;  // the model's own description of the change, for enter() and
                        // for the record of the step at `point` (its resumable state)
};

// What the model found inside a step: its crossings in the order of the path (events only, then
// at most one that switches, the last), or a reason to retry the step shorter.
struct CrossingSearch {
  std::vector<Crossing> crossings;
  std::optional<std::string> reject;  // the step cannot be trusted (retried shorter)
  std::optional<std::string> fail;    // the path cannot go on from the step's start (solver_failure)
};

// The stability of a state on its configuration, as far as the model knows it.
struct StabilityState {
  int negative_eigenvalues = -1;  // of the tangent on the configuration; -1: not known
  double margin = 0.0;            // > 0 stable; NaN: not known (count-based models)
  Stability verdict() const;
};

// How a model tells stability changes along a step: by the count of negative eigenvalues
// (bisection on it) or by a continuous margin (secant on it).
enum class StabilityMeasure { none, count, margin };

// The first point on a bifurcated branch, and how to see the branch come back.
struct BranchStart {
  PathPoint point;  // on the branch (in the configuration the model switched to), oriented away from
                    // the bifurcation point
  // The branch's amplitude along the critical mode, > 0 on it; its fall back to zero is the
  // branch's return to the path it left (located on it). Empty: not watched.
  std::function<double(const PathPoint&)> amplitude;
  // Zero means within this fraction of the largest amplitude the branch reached (the states'
  // accuracy: a step can land on the path itself, where the amplitude is round-off of either sign).
  double return_accuracy = 0.0;
  // The lambda tolerance of that location (0: to round-off in the arclength).
  double return_tolerance = 0.0;
  std::string description;  // appended to the bifurcation event's description
};
struct BranchSwitch {
  std::optional<BranchStart> branch;
  std::string why_not;  // when there is none: appended to the event ("the path stays ...")
};

// What a model is to the engine. The model holds its current configuration; the engine asks for
// the equations of it, follows them, and tells the model when to change it.
class PathModel {
 public:
  virtual ~PathModel() = default;

  // The path's kind (the summary's and the file's "fe" or "ritz").
  virtual PathKind kind() const = 0;

  // The equations of the current configuration. Called once per configuration (and again after
  // wants_new_problem()): the engine builds a follower on it.
  virtual PathProblem problem() const = 0;

  // The first point of the path: at options.arc_length.lambda_min, or from options.resume_from
  // (refused with a reason where the model does not resume), on the configuration it chooses, its
  // tangent oriented along options.arc_length.direction. The follower is one on problem() after the
  // configuration is chosen, with `options` (the engine's: its metric). nullopt: no start; `why`
  // says why (solver_failure, or no_equilibrium).
  struct Start {
    std::optional<PathPoint> point;
    bool record = true;       // false: a resumed step, in the file already
    double first_step = 0.0;  // 0: options.arc_length.initial_step
    TraceTermination failure = TraceTermination::solver_failure;
    std::string why;
  };
  virtual Start start(const ArcLengthOptions& options) = 0;

  // The point the engine decides on and records: the corrector's point taken to the model's own
  // accuracy (default: as it is). fixed_lambda: at its lambda (an end of the range, load control,
  // a requested load), else on the corrector's hyperplane.
  virtual PathPoint refine(const PathPoint& point, bool /*fixed_lambda*/) const { return point; }

  // The model's own admissibility of a corrected step (default: admitted).
  virtual Screening screen(const PathPoint& /*from*/, PathPoint& /*to*/, const PathFollower& /*follower*/) {
    return {};
  }

  // The constraint crossings of the current configuration inside the step, located: every event
  // along it up to the first change of configuration. `may_take` (false on a step where a
  // switched branch's return was found, or whose ends differ in stability on the configuration
  // away from a fold): a
  // change of configuration that changes no event (a
  // contact limit moving on by a node) may be taken without being located, at the step's end or
  // at the furthest point of the step where the state across it holds (Crossing::point_after),
  // so that the number of steps does not grow with the mesh; the model must then guarantee that
  // nothing the engine watches lies between the step's start and that point (a fold: the sign of
  // d lambda / ds; a change of stability; a load of TraceOptions::report_at; the amplitude bound),
  // which the engine does not look for on such a step, and fall back to locating the switch where
  // it cannot.
  virtual CrossingSearch crossing(const PathPoint& from, const PathPoint& to, const PathFollower& follower,
                                  bool may_take) = 0;

  // Enters the configuration after `crossing` (located at crossing.point) and returns its first
  // point there, its tangent oriented along the path (the side where the new configuration holds).
  // nullopt with `why` (and its termination) when there is none.
  struct Entry {
    std::optional<PathPoint> point;
    TraceTermination failure = TraceTermination::solver_failure;
    std::string why;
    std::vector<TraceEvent> events;  // found on entering (a fold at a set change), recorded at once
    bool record = false;             // the point is no longer the crossing's (a new zone opened a little
                                     // past it): recorded as a step of its own
  };
  // `options`: the engine's follower options (its metric), for the follower the model starts on.
  // A crossing with point_after: the model enters and returns crossing.point itself.
  virtual Entry enter(const Crossing& crossing, const ArcLengthOptions& options) = 0;

  // Stability.
  virtual StabilityMeasure stability_measure() const { return StabilityMeasure::none; }
  virtual StabilityState stability(const PathPoint& /*point*/) const { return {}; }
  // The stability a state recorded at a crossing reports (default: stability(point), of the
  // configuration before it); a model whose record carries on with the configuration after it may
  // give that one's.
  virtual StabilityState stability_at_crossing(const PathPoint& point, const Crossing& /*crossing*/) const {
    return stability(point);
  }
  // A located bifurcation's point and lambda refined where the model can (default: as located).
  virtual PathPoint refine_bifurcation(const PathPoint& point) const { return point; }
  // Leaves the path along the critical mode at the bifurcation point `at` (default: none).
  virtual BranchSwitch switch_branch(const PathPoint& /*at*/, const PathFollower& /*follower*/) {
    return {{}, "not offered"};
  }
  // The crossing of a switched branch with the path it left, refined from `located` (where the
  // branch's amplitude vanished; `peak`: the largest amplitude the branch reached); nullopt: keep
  // `located` (refined), its event's description saying so.
  virtual std::optional<PathPoint> refine_return(const PathPoint& /*located*/, double /*peak*/,
                                                 const PathFollower& /*follower*/) {
    return std::nullopt;
  }

  // Where a state's events are placed when they have no position of their own (a limit point, a
  // bifurcation), user coordinate; and the words of those events.
  virtual double event_position(const PathPoint& point) const = 0;
  virtual std::string describe_state(const PathPoint& point) const = 0;  // e.g. "axial force 5.1e6, amplitude 0.02"

  // The largest lift of the member off the foundation surface (TraceStep::amplitude, user length):
  // what TraceOptions::max_amplitude bounds, located on it.
  virtual double amplitude(const PathPoint& point) const = 0;

  // A state's certificate in the user's terms: empty if it passes, else the message.
  virtual std::optional<std::string> certify(const PathPoint& point) const = 0;
  // The step of a state: the whole state in the user's units (its stability is the engine's, set
  // after). `crossing` when recorded at one (its resumable state is the configuration after it);
  // next_step: the step length the engine goes on with from it (a resumed run takes the same).
  struct RecordContext {
    const Crossing* crossing = nullptr;
    double next_step = 0.0;
  };
  virtual TraceStep record(const PathPoint& point, const RecordContext& context) const = 0;
  // Before a step's end is recorded: true if the follower must be rebuilt on problem() from it (a
  // change of the metric; the model then re-expresses the point's tangent in the new one, and the
  // point is recorded so). The new follower goes on with the step length the old one would have taken.
  virtual bool wants_new_problem(PathPoint& /*point*/) { return false; }

  // Figures of the model's own for the summary (pivots, factorisations, modes); a note appended
  // to the message of a completed run.
  virtual void fill_summary(TraceSummary& /*summary*/) const {}
  virtual std::string summary_note() const { return {}; }
};

// Follows `model` over options.arc_length's range. Every step and event goes to `sink` as soon as it
// is known, and to the result. Misuse (invalid options) throws std::invalid_argument.
TraceResult follow_path(PathModel& model, const TraceOptions& options, const TraceSink& sink = {});

}  // namespace liftoff::continuation
