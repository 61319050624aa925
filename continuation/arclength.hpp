#pragma once
// A model-independent path follower for G(x, lambda) = 0, G: R^n x R -> R^n (Keller's
// pseudo-arc-length continuation, or plain load control for comparison).
//
// A point of the path carries its unit tangent (dx/ds, dlambda/ds) in the scaled metric
//     |(dx, dlambda)|^2 = |D dx|^2 + dlambda^2,   D = diag(PathProblem::unknown_scale),
// so that a step length ds is comparable to a change of lambda. One step from a point P:
//  - predictor: (x, lambda) = P + ds (t_x, t_lambda);
//  - corrector: Newton (nonlinear::NewtonSolver, KINSOL) on the bordered system
//        G(x, lambda) = 0,   t_x . D^2 (x - x_P) + t_lambda (lambda - lambda_P) - ds = 0
//    (arc length), or on G(x, lambda_P + ds) = 0 (load control: lambda fixed, x unknown);
//  - the new tangent solves [G_x G_lambda; t_P^T] t = [0; 1], normalised, so it keeps the
//    sense of t_P: the branch is followed consistently through folds.
// Linear algebra: the bordered corrector and tangent systems are never factorised as such;
// nonlinear::BorderedSolver solves them by block elimination with the factors of G_x (two
// solves and a scalar, plus one refinement step), falling back to a dense bordered LU only
// where G_x is singular (at a fold) and n + 1 <= BorderedSolver::dense_fallback_limit; above
// that limit such a system counts as singular (see bordered_solver.hpp). G_x is dense
// (nonlinear::DenseLu, the Ritz models) unless the problem gives sparse_jacobian (then
// nonlinear::SparseLu, symbolic analysis once per follower: the FE models).
// Set up once: a follower owns its KINSOL adapters (one for the fixed-lambda solves, one for
// the bordered corrector) and its linear solvers, made on first use and shared by its copies,
// so that locate's many corrector solves rebuild nothing (newton_setups() counts them).
// Step length: halved when the corrector fails; after a success scaled by
// target_iterations / iterations (at most doubled, at least halved), clamped to
// [min_step, max_step]. A failure at min_step ends the run (step_too_small), which is where
// load control stops at a limit point: beyond it no equilibrium is near.
// Limit points (folds in lambda): a sign change of t_lambda between two accepted points; the
// fold is located by secant (Illinois) on t_lambda along the step from the earlier point, and
// reported with its lambda and x.
//
// PathFollower exposes the primitives (start, step, locate) and the loop (follow). A model
// whose unknowns change at events (the Ritz path's topology switches) runs `follow` once per
// topology, with an observer that locates its events between steps and stops at them.

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "continuation/path_control.hpp"
#include "nonlinear/newton.hpp"

namespace liftoff::continuation {

// The branch's equations. residual is required; jacobian (dG/dx, n x n) and lambda_derivative
// (dG/dlambda, n) are taken by central finite differences when empty. A callback returns false
// when (x, lambda) is inadmissible (the corrector then shortens its step).
struct PathProblem {
  int unknowns = 0;  // n
  std::function<bool(const Eigen::VectorXd& x, double lambda, Eigen::VectorXd& g)> residual;
  std::function<bool(const Eigen::VectorXd& x, double lambda, Eigen::MatrixXd& g_x)> jacobian;
  // Alternative to jacobian for large models: dG/dx written into a sparse matrix whose pattern
  // the callback keeps from call to call (values zeroed on entry; on the first call it is
  // empty, n x n, and the callback builds the pattern). When set, jacobian is not used.
  std::function<bool(const Eigen::VectorXd& x, double lambda, Eigen::SparseMatrix<double>& g_x)> sparse_jacobian;
  std::function<bool(const Eigen::VectorXd& x, double lambda, Eigen::VectorXd& g_lambda)> lambda_derivative;
  Eigen::VectorXd unknown_scale;   // D: 1 / typical |x_i| (empty: ones)
  Eigen::VectorXd residual_scale;  // 1 / typical |G_i| for the corrector's test (empty: ones)
  Eigen::VectorXi constraints;     // KINSOL's sign codes per unknown (empty: none), see NewtonOptions
  // dG/dx is one matrix for every (x, lambda) (a model linear in x whose stiffness does not depend on
  // lambda): the follower's bordered solves factorise it once and keep its factors.
  bool jacobian_constant = false;
  void validate() const;  // throws std::invalid_argument naming the field
};

struct ArcLengthOptions {
  PathControl control = PathControl::arc_length;
  double lambda_min = 0.0;     // the run ends (completed) on reaching either end of the range;
  double lambda_max = 1.0;     // the end point is landed on exactly (a fixed-lambda correction)
  int direction = +1;          // initial sense of lambda: +1 increasing, -1 decreasing
  double initial_step = 0.05;  // ds
  double min_step = 1e-8;
  double max_step = 0.25;
  int target_iterations = 4;      // corrector iterations the step length aims at
  int max_steps = 10000;          // accepted steps
  double fold_tolerance = 1e-10;  // folds located until the bracket in lambda is below this
  bool locate_folds = true;
  nonlinear::NewtonOptions corrector = default_corrector();
  void validate() const;  // throws std::invalid_argument naming the field and the rule

  static nonlinear::NewtonOptions default_corrector() {
    nonlinear::NewtonOptions o;
    o.residual_tolerance = 1e-11;
    o.max_iterations = 12;
    return o;
  }
};

// One point of the path with its unit tangent in the scaled metric (see the top).
struct PathPoint {
  Eigen::VectorXd x;
  double lambda = 0.0;
  Eigen::VectorXd tangent_x;
  double tangent_lambda = 0.0;
  double arclength = 0.0;  // from the start of the run
  int iterations = 0;      // corrector iterations that produced it
};

struct Fold {
  double lambda = 0.0;
  Eigen::VectorXd x;
  double arclength = 0.0;
  bool is_maximum = true;  // lambda reaches a maximum (t_lambda goes + to -) or a minimum
};

enum class ArcLengthTermination {
  completed,            // lambda_min or lambda_max reached (landed on exactly)
  stopped_by_observer,  // the observer asked to stop after the last accepted point
  step_too_small,       // the corrector failed at min_step (load control: a limit point)
  step_limit,           // max_steps accepted steps done
  step_rejected,        // the observer rejected the step even at min_step (see ObserverVerdict)
  start_failed,         // no equilibrium could be found at the starting lambda
  singular_tangent,     // the bordered tangent system is singular (a bifurcation point)
};
std::string_view to_string(ArcLengthTermination);

struct ArcLengthResult {
  std::vector<PathPoint> points;  // accepted points, the start first
  std::vector<Fold> folds;
  ArcLengthTermination termination = ArcLengthTermination::start_failed;
  std::string message;
  int rejected_steps = 0;
  int corrector_iterations = 0;
  // The step length the run would have taken next (where it stopped: the length of its last step),
  // so that a run continued from its last point (a new configuration) goes on at it.
  double step_length = 0.0;
  nonlinear::NewtonSummary last_failure;  // the corrector's summary of the last rejected step
  bool is_usable() const { return termination == ArcLengthTermination::completed; }
  std::string brief_report() const;
};

// What the observer answers for an accepted point.
enum class ObserverVerdict {
  proceed,  // keep the point, go on
  stop,     // keep the point (which the observer may have replaced, e.g. by a located event) and stop
  reject,   // discard the point: the step is retried at half the length, like a corrector failure;
            // at min_step the run ends (step_rejected). The observer must not have kept anything.
};
// Called for every accepted point after the start, with the point before it. It may replace
// `accepted` by a point between the two (one from PathFollower::step from `previous`).
using StepObserver = std::function<ObserverVerdict(const PathPoint& previous, PathPoint& accepted)>;

struct StepOutcome {
  std::optional<PathPoint> point;  // empty when the corrector failed
  nonlinear::NewtonSummary corrector;
};

class PathFollower {
 public:
  PathFollower(PathProblem problem, ArcLengthOptions options);  // validates both

  // Equilibrium at lambda from the guess x (Newton at fixed lambda) with its tangent oriented
  // so that lambda moves in options.direction (or along `orientation` if given).
  std::optional<PathPoint> start(Eigen::VectorXd x, double lambda, nonlinear::NewtonSummary* summary = nullptr,
                                 const std::optional<PathPoint>& orientation = std::nullopt) const;
  // One predictor-corrector step of length ds from `from` (arc length or load control as the
  // options say; ds may be negative only for load control). with_tangent false (arc length): the
  // point's tangent is not solved for (a factorisation less) and holds from's, a stand-in.
  StepOutcome step(const PathPoint& from, double ds, bool with_tangent = true) const;
  // The point on the path at lambda (x guessed from `from`, or `guess` if given; a fixed-lambda
  // correction), its arclength measured from `from`.
  StepOutcome step_to_lambda(const PathPoint& from, double lambda, const Eigen::VectorXd* guess = nullptr) const;
  // The point between `from` and `to` (to = step(from, ds)) where event(point) changes sign,
  // by secant (Illinois) on sigma in (0, ds), until the bracket is below lambda_tolerance in
  // lambda (or 1e-14 relative in sigma). nullopt if event does not change sign or a corrector
  // solve fails.
  // event_reads_tangent false: `event` does not read the points' tangents, which are then solved
  // for at the located point only.
  std::optional<PathPoint> locate(const PathPoint& from, const PathPoint& to,
                                  const std::function<double(const PathPoint&)>& event, double lambda_tolerance,
                                  bool event_reads_tangent = true) const;
  // Adaptive steps from `start` until lambda leaves [lambda_min, lambda_max] (landed on its
  // end), the observer stops, or a limit ends the run. `first_step` overrides initial_step.
  ArcLengthResult follow(const PathPoint& start, const StepObserver& observer = {},
                         std::optional<double> first_step = std::nullopt) const;

  // The step length after an accepted step of length ds that took `iterations` corrector
  // iterations (what follow uses; exposed so that a resumed run can continue identically).
  double next_step(double ds, int iterations) const;

  const PathProblem& problem() const { return problem_; }
  const ArcLengthOptions& options() const { return options_; }
  // The unit tangent at (x, lambda) with the sense of `reference` (if null: lambda grows in
  // options.direction). nullopt if the bordered system is singular.
  std::optional<std::pair<Eigen::VectorXd, double>> tangent(const Eigen::VectorXd& x, double lambda,
                                                            const PathPoint* reference) const;
  // KINSOL setups made by this follower and its copies so far (at most 2: one adapter for
  // the fixed-lambda solves, one for the bordered corrector).
  int newton_setups() const;

 private:
  struct Workspace;  // the linear solvers and KINSOL adapters, made on first use
  Workspace& workspace() const;
  // dG/dx at (x, lambda) into the G_x solver's matrix (dense or sparse).
  bool fill_jacobian(const Eigen::VectorXd& x, double lambda, nonlinear::LinearSolver& g_x) const;
  bool evaluate_jacobian(const Eigen::VectorXd& x, double lambda, Eigen::MatrixXd& g_x) const;
  bool evaluate_lambda_derivative(const Eigen::VectorXd& x, double lambda, Eigen::VectorXd& g_lambda) const;
  double scaled_dot(const Eigen::VectorXd& a, const Eigen::VectorXd& b) const;

  PathProblem problem_;
  ArcLengthOptions options_;
  Eigen::VectorXd scale_;  // D
  std::shared_ptr<Workspace> workspace_;
};

}  // namespace liftoff::continuation
