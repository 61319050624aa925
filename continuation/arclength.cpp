#include "continuation/arclength.hpp"

// Why things are done the way they are:
//  - The tangent is solved from the bordered system with the previous tangent as the border row
//    (not with a fixed unit vector): the system stays nonsingular through a regular fold, and
//    r . t = 1 > 0 gives the new tangent the sense of the old one for free.
//  - Landing on the end of the lambda range uses a fixed-lambda correction (exactly lambda_max),
//    falling back to locating lambda - lambda_max = 0 along the step near a fold, then corrected
//    at fixed lambda from the located point.
//  - A step whose tangent turns by more than 60 degrees is rejected and retried shorter: a long
//    step near a sharp turn can let the corrector land on another part of the branch.
//  - Folds are located by Illinois on t_lambda(sigma). At a fold lambda is flat in sigma, so a
//    bracket of width tol in lambda means an error of about tol in the fold's lambda.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include "core/enum_names.hpp"
#include "nonlinear/bordered_solver.hpp"
#include "nonlinear/linear_solver.hpp"

namespace liftoff::continuation {

using Eigen::MatrixXd;
using Eigen::VectorXd;

// The follower's linear algebra and KINSOL adapters, made on first use (a follower that only
// answers tangent() never builds KINSOL) and shared by the follower's copies.
struct PathFollower::Workspace {
  std::unique_ptr<nonlinear::LinearSolver> g_x;           // G_x of the fixed-lambda solves
  std::unique_ptr<nonlinear::LinearSolver> bordered_g_x;  // G_x inside the bordered system
  std::unique_ptr<nonlinear::BorderedSolver> bordered;    // corrector and tangent
  std::unique_ptr<nonlinear::NewtonSolver> fixed_lambda;  // over g_x
  std::unique_ptr<nonlinear::NewtonSolver> corrector;     // over bordered
};

namespace {
constexpr EnumName<ArcLengthTermination> arc_length_termination_names[] = {
    {ArcLengthTermination::completed, "completed"},
    {ArcLengthTermination::stopped_by_observer, "stopped_by_observer"},
    {ArcLengthTermination::step_too_small, "step_too_small"},
    {ArcLengthTermination::step_limit, "step_limit"},
    {ArcLengthTermination::step_rejected, "step_rejected"},
    {ArcLengthTermination::start_failed, "start_failed"},
    {ArcLengthTermination::singular_tangent, "singular_tangent"},
};
}  // namespace

std::string_view to_string(ArcLengthTermination t) {
  return name_in<ArcLengthTermination>(arc_length_termination_names, t);
}

std::string ArcLengthResult::brief_report() const {
  return fmt::format(
      "arclength: {} after {} points ({} rejected steps, {} corrector iterations), {} folds; lambda "
      "{:.10g}",
      to_string(termination), points.size(), rejected_steps, corrector_iterations, folds.size(),
      points.empty() ? std::nan("") : points.back().lambda);
}

void PathProblem::validate() const {
  if (unknowns < 1) throw std::invalid_argument(fmt::format("PathProblem.unknowns: expected >= 1, got {}", unknowns));
  if (!residual) throw std::invalid_argument("PathProblem.residual: expected a function, got none");
  const auto check = [this](const char* field, const VectorXd& v) {
    if (v.size() != 0 && v.size() != unknowns)
      throw std::invalid_argument(
          fmt::format("PathProblem.{}: expected empty or size {} (unknowns), got size {}", field, unknowns, v.size()));
    for (Eigen::Index i = 0; i < v.size(); ++i)
      if (!(std::isfinite(v(i)) && v(i) > 0))
        throw std::invalid_argument(
            fmt::format("PathProblem.{}({}): expected a finite number > 0, got {}", field, i, v(i)));
  };
  check("unknown_scale", unknown_scale);
  check("residual_scale", residual_scale);
  if (constraints.size() != 0 && constraints.size() != unknowns)
    throw std::invalid_argument(fmt::format(
        "PathProblem.constraints: expected empty or size {} (unknowns), got size {}", unknowns, constraints.size()));
}

void ArcLengthOptions::validate() const {
  const auto positive = [](const char* field, double v) {
    if (!(std::isfinite(v) && v > 0))
      throw std::invalid_argument(fmt::format("ArcLengthOptions.{}: expected a finite number > 0, got {}", field, v));
  };
  if (!(std::isfinite(lambda_min) && std::isfinite(lambda_max) && lambda_min < lambda_max))
    throw std::invalid_argument(fmt::format(
        "ArcLengthOptions.lambda_min, lambda_max: expected finite with lambda_min < lambda_max, got {} and {}",
        lambda_min, lambda_max));
  if (direction != 1 && direction != -1)
    throw std::invalid_argument(fmt::format("ArcLengthOptions.direction: expected +1 or -1, got {}", direction));
  positive("initial_step", initial_step);
  positive("min_step", min_step);
  positive("max_step", max_step);
  positive("fold_tolerance", fold_tolerance);
  if (!(min_step <= initial_step && initial_step <= max_step))
    throw std::invalid_argument(
        fmt::format("ArcLengthOptions.initial_step: expected min_step <= initial_step <= max_step, got {} <= {} <= {}",
                    min_step, initial_step, max_step));
  if (target_iterations < 1)
    throw std::invalid_argument(
        fmt::format("ArcLengthOptions.target_iterations: expected >= 1, got {}", target_iterations));
  if (max_steps < 1)
    throw std::invalid_argument(fmt::format("ArcLengthOptions.max_steps: expected >= 1, got {}", max_steps));
}

PathFollower::PathFollower(PathProblem problem, ArcLengthOptions options)
    : problem_(std::move(problem)), options_(std::move(options)) {
  problem_.validate();
  options_.validate();
  options_.corrector.validate(problem_.unknowns + 1);
  scale_ = problem_.unknown_scale.size() ? problem_.unknown_scale : VectorXd(VectorXd::Ones(problem_.unknowns));
  workspace_ = std::make_shared<Workspace>();
}

PathFollower::Workspace& PathFollower::workspace() const {
  Workspace& w = *workspace_;
  if (!w.bordered) {
    const int n = problem_.unknowns;
    const auto g_x = [&]() -> std::unique_ptr<nonlinear::LinearSolver> {
      if (problem_.sparse_jacobian) return std::make_unique<nonlinear::SparseLu>(n);
      return std::make_unique<nonlinear::DenseLu>(n);
    };
    w.g_x = g_x();
    w.bordered_g_x = g_x();
    w.bordered = std::make_unique<nonlinear::BorderedSolver>(*w.bordered_g_x);
  }
  return w;
}

int PathFollower::newton_setups() const {
  const Workspace& w = *workspace_;
  return (w.fixed_lambda ? w.fixed_lambda->setups() : 0) + (w.corrector ? w.corrector->setups() : 0);
}

bool PathFollower::fill_jacobian(const VectorXd& x, double lambda, nonlinear::LinearSolver& g_x) const {
  const int n = problem_.unknowns;
  if (problem_.sparse_jacobian) {
    Eigen::SparseMatrix<double>& m = static_cast<nonlinear::SparseLu&>(g_x).matrix();
    const bool accepted = problem_.sparse_jacobian(x, lambda, m);
    if (m.rows() != n || m.cols() != n)
      throw std::invalid_argument(fmt::format(
          "PathProblem.sparse_jacobian: the callback resized G_x from {0}x{0} to {1}x{2}; it must keep the size", n,
          m.rows(), m.cols()));
    m.makeCompressed();
    return accepted && m.coeffs().allFinite();
  }
  return evaluate_jacobian(x, lambda, static_cast<nonlinear::DenseLu&>(g_x).matrix());
}

double PathFollower::scaled_dot(const VectorXd& a, const VectorXd& b) const {
  return (a.array() * scale_.array().square() * b.array()).sum();
}

bool PathFollower::evaluate_jacobian(const VectorXd& x, double lambda, MatrixXd& g_x) const {
  const int n = problem_.unknowns;
  g_x.setZero(n, n);
  if (problem_.jacobian) return problem_.jacobian(x, lambda, g_x) && g_x.allFinite();
  // Central differences, step relative to the unknown's typical size.
  VectorXd xp = x, gp(n), gm(n);
  for (int j = 0; j < n; ++j) {
    const double h = 1e-6 * (std::abs(x(j)) + 1.0 / scale_(j));
    xp(j) = x(j) + h;
    if (!problem_.residual(xp, lambda, gp)) return false;
    xp(j) = x(j) - h;
    if (!problem_.residual(xp, lambda, gm)) return false;
    xp(j) = x(j);
    g_x.col(j) = (gp - gm) / (2 * h);
  }
  return g_x.allFinite();
}

bool PathFollower::evaluate_lambda_derivative(const VectorXd& x, double lambda, VectorXd& g_lambda) const {
  const int n = problem_.unknowns;
  g_lambda.setZero(n);
  if (problem_.lambda_derivative) return problem_.lambda_derivative(x, lambda, g_lambda) && g_lambda.allFinite();
  const double h = 1e-6 * (std::abs(lambda) + 1.0);
  VectorXd gp(n), gm(n);
  if (!problem_.residual(x, lambda + h, gp) || !problem_.residual(x, lambda - h, gm)) return false;
  g_lambda = (gp - gm) / (2 * h);
  return g_lambda.allFinite();
}

std::optional<std::pair<VectorXd, double>> PathFollower::tangent(const VectorXd& x, double lambda,
                                                                 const PathPoint* reference) const {
  const int n = problem_.unknowns;
  if (reference && reference->tangent_x.size() != n)
    throw std::invalid_argument(fmt::format("PathFollower::tangent: the reference tangent has size {}, expected {}",
                                            reference->tangent_x.size(), n));
  nonlinear::BorderedSolver& bordered = *workspace().bordered;
  bordered.zero();
  VectorXd g_lambda;
  if ((!bordered.inner_held() && !fill_jacobian(x, lambda, bordered.inner())) ||
      !evaluate_lambda_derivative(x, lambda, g_lambda))
    return std::nullopt;
  bordered.column() = g_lambda;
  if (reference) {
    bordered.row() = scale_.array().square() * reference->tangent_x.array();
    bordered.corner() = reference->tangent_lambda;
  } else {
    bordered.corner() = options_.direction;
  }
  if (bordered.factorise() != nonlinear::Factorisation::ok) return std::nullopt;
  if (problem_.jacobian_constant && !bordered.used_fallback()) bordered.hold_inner(true);
  VectorXd t = VectorXd::Zero(n + 1);
  t(n) = 1.0;
  if (!bordered.solve(t) || !t.allFinite()) return std::nullopt;
  const VectorXd t_x = t.head(n);
  const double norm = std::sqrt(scaled_dot(t_x, t_x) + t(n) * t(n));
  if (!(norm > 0)) return std::nullopt;
  return std::make_pair(VectorXd(t_x / norm), t(n) / norm);
}

std::optional<PathPoint> PathFollower::start(VectorXd x, double lambda, nonlinear::NewtonSummary* summary,
                                             const std::optional<PathPoint>& orientation) const {
  const int n = problem_.unknowns;
  if (x.size() != n)
    throw std::invalid_argument(fmt::format("PathFollower::start: x has size {}, expected {}", x.size(), n));
  nonlinear::NewtonOptions newton = options_.corrector;
  newton.unknown_scale = scale_;
  newton.residual_scale = problem_.residual_scale;
  newton.constraints = problem_.constraints;
  Workspace& w = workspace();
  if (!w.fixed_lambda) w.fixed_lambda = std::make_unique<nonlinear::NewtonSolver>(*w.g_x);
  const nonlinear::NewtonSummary s = w.fixed_lambda->solve(
      [&](const VectorXd& z, VectorXd& g) { return problem_.residual(z, lambda, g); },
      [&](const VectorXd& z, const VectorXd&) { return fill_jacobian(z, lambda, *w.g_x); }, x, newton);
  if (summary) *summary = s;
  if (!s.is_usable()) return std::nullopt;
  const auto t = tangent(x, lambda, orientation ? &*orientation : nullptr);
  if (!t) return std::nullopt;
  PathPoint p;
  p.x = std::move(x);
  p.lambda = lambda;
  p.tangent_x = t->first;
  p.tangent_lambda = t->second;
  p.iterations = s.iterations;
  return p;
}

StepOutcome PathFollower::step(const PathPoint& from, double ds, bool with_tangent) const {
  const int n = problem_.unknowns;
  StepOutcome outcome;
  if (options_.control == PathControl::load) {
    // lambda fixed; x predicted along the tangent unless the tangent is (nearly) vertical.
    const double lambda = from.lambda + options_.direction * ds;
    PathPoint guess = from;
    if (std::abs(from.tangent_lambda) > 1e-3)
      guess.x = from.x + (lambda - from.lambda) / from.tangent_lambda * from.tangent_x;
    outcome = step_to_lambda(guess, lambda);
    if (outcome.point) outcome.point->arclength = from.arclength + ds;
    return outcome;
  }

  // Pseudo-arc-length: unknowns z = (x, lambda), bordered residual.
  VectorXd z(n + 1);
  z.head(n) = from.x + ds * from.tangent_x;
  z(n) = from.lambda + ds * from.tangent_lambda;
  const VectorXd weights = scale_.array().square() * from.tangent_x.array();
  const auto residual = [&](const VectorXd& y, VectorXd& f) {
    VectorXd g(n);
    if (!problem_.residual(y.head(n), y(n), g)) return false;
    f.head(n) = g;
    f(n) = weights.dot(y.head(n) - from.x) + from.tangent_lambda * (y(n) - from.lambda) - ds;
    return true;
  };
  Workspace& w = workspace();
  nonlinear::BorderedSolver& bordered = *w.bordered;
  VectorXd g_lambda;
  const auto jacobian = [&](const VectorXd& y, const VectorXd&) {  // zeroed by the adapter
    if ((!bordered.inner_held() && !fill_jacobian(y.head(n), y(n), bordered.inner())) ||
        !evaluate_lambda_derivative(y.head(n), y(n), g_lambda))
      return false;
    bordered.column() = g_lambda;
    bordered.row() = weights;
    bordered.corner() = from.tangent_lambda;
    return true;
  };
  nonlinear::NewtonOptions newton = options_.corrector;
  newton.unknown_scale.setOnes(n + 1);
  newton.unknown_scale.head(n) = scale_;
  newton.residual_scale.setOnes(n + 1);
  if (problem_.residual_scale.size()) newton.residual_scale.head(n) = problem_.residual_scale;
  if (problem_.constraints.size()) {
    newton.constraints.setZero(n + 1);
    newton.constraints.head(n) = problem_.constraints;
    for (int i = 0; i < n; ++i) {  // a predictor outside the constraints: shorten the step
      const int c = newton.constraints(i);
      const double v = z(i);
      if ((c == 1 && v < 0) || (c == 2 && v <= 0) || (c == -1 && v > 0) || (c == -2 && v >= 0)) {
        outcome.corrector.termination = nonlinear::NewtonTermination::residual_failed;
        outcome.corrector.message = "the predictor violates the unknowns' sign constraints";
        return outcome;
      }
    }
  }
  if (!w.corrector) w.corrector = std::make_unique<nonlinear::NewtonSolver>(bordered);
  outcome.corrector = w.corrector->solve(residual, jacobian, z, newton);
  if (!outcome.corrector.is_usable()) return outcome;
  if (problem_.jacobian_constant && outcome.corrector.jacobian_evaluations > 0 && !bordered.used_fallback())
    bordered.hold_inner(true);
  PathPoint p;
  p.tangent_x = from.tangent_x;
  p.tangent_lambda = from.tangent_lambda;
  if (with_tangent) {
    const auto t = tangent(z.head(n), z(n), &from);
    if (!t) return outcome;
    p.tangent_x = t->first;
    p.tangent_lambda = t->second;
  }
  p.x = z.head(n);
  p.lambda = z(n);
  p.arclength = from.arclength + ds;
  p.iterations = outcome.corrector.iterations;
  outcome.point = std::move(p);
  return outcome;
}

StepOutcome PathFollower::step_to_lambda(const PathPoint& from, double lambda, const VectorXd* guess) const {
  StepOutcome outcome;
  nonlinear::NewtonSummary summary;
  const PathPoint reference = from;
  std::optional<PathPoint> p = start(guess ? *guess : from.x, lambda, &summary, reference);
  outcome.corrector = summary;
  if (!p) return outcome;
  // The arclength coordinate of the point, measured as the bordered constraint measures it.
  p->arclength =
      from.arclength + scaled_dot(from.tangent_x, p->x - from.x) + from.tangent_lambda * (lambda - from.lambda);
  outcome.point = std::move(p);
  return outcome;
}

std::optional<PathPoint> PathFollower::locate(const PathPoint& from, const PathPoint& to,
                                              const std::function<double(const PathPoint&)>& event,
                                              double lambda_tolerance, bool event_reads_tangent) const {
  double sa = 0.0, sb = to.arclength - from.arclength;
  double fa = event(from), fb = event(to);
  if (!(fa * fb <= 0.0)) return std::nullopt;
  if (fb == 0.0) return to;
  if (fa == 0.0) return from;
  PathPoint a = from, b = to;
  std::optional<PathPoint> best;
  double previous_lambda = std::numeric_limits<double>::quiet_NaN();
  int stale_side = 0;
  for (int iteration = 0; iteration < 200; ++iteration) {
    double sc = sb - fb * (sb - sa) / (fb - fa);
    if (!(sc > std::min(sa, sb) && sc < std::max(sa, sb))) sc = 0.5 * (sa + sb);
    StepOutcome c = step(from, sc, event_reads_tangent);
    if (!c.point) return std::nullopt;
    const double fc = event(*c.point);
    const double lambda_c = c.point->lambda;
    best = c.point;
    if (fc == 0.0) break;
    const bool converged = std::abs(lambda_c - previous_lambda) <= lambda_tolerance ||
                           std::abs(a.lambda - b.lambda) <= lambda_tolerance ||
                           std::abs(sb - sa) <= 1e-14 * std::abs(to.arclength - from.arclength);
    previous_lambda = lambda_c;
    if ((fc > 0) == (fb > 0)) {  // c replaces b
      sb = sc, fb = fc, b = *c.point;
      if (stale_side == -1) fa *= 0.5;  // Illinois: a kept twice, halve its value
      stale_side = -1;
    } else {
      sa = sc, fa = fc, a = *c.point;
      if (stale_side == 1) fb *= 0.5;
      stale_side = 1;
    }
    if (converged) break;
  }
  if (best && !event_reads_tangent && options_.control == PathControl::arc_length) {
    const auto t = tangent(best->x, best->lambda, &from);
    if (!t) return std::nullopt;
    best->tangent_x = t->first;
    best->tangent_lambda = t->second;
  }
  return best;
}

double PathFollower::next_step(double ds, int iterations) const {
  const double ratio = iterations == 0 ? 2.0 : static_cast<double>(options_.target_iterations) / iterations;
  return std::clamp(ds * std::clamp(ratio, 0.5, 2.0), options_.min_step, options_.max_step);
}

ArcLengthResult PathFollower::follow(const PathPoint& start_point, const StepObserver& observer,
                                     std::optional<double> first_step) const {
  ArcLengthResult result;
  result.points.push_back(start_point);
  const ArcLengthOptions& o = options_;
  const bool arc = o.control == PathControl::arc_length;
  double ds = std::clamp(first_step.value_or(o.initial_step), o.min_step, o.max_step);
  result.step_length = ds;
  int accepted = 0;

  while (true) {
    if (accepted >= o.max_steps) {
      result.termination = ArcLengthTermination::step_limit;
      result.message = fmt::format("step limit: max_steps = {} accepted steps done at lambda = {:.10g}", o.max_steps,
                                   result.points.back().lambda);
      return result;
    }
    const PathPoint from = result.points.back();
    StepOutcome outcome = step(from, ds);
    const bool turned =
        outcome.point && arc &&
        scaled_dot(from.tangent_x, outcome.point->tangent_x) + from.tangent_lambda * outcome.point->tangent_lambda <
            0.5;
    if (!outcome.point || turned) {
      ++result.rejected_steps;
      if (!outcome.point) result.last_failure = outcome.corrector;
      if (ds <= o.min_step) {
        result.termination = ArcLengthTermination::step_too_small;
        result.message =
            arc ? fmt::format(
                      "step too small: the corrector failed at the minimum step {:.3g} from lambda = {:.10g} "
                      "({})",
                      o.min_step, from.lambda, outcome.corrector.message)
                : fmt::format(
                      "step too small: no equilibrium found beyond lambda = {:.10g} within the minimum step "
                      "{:.3g}; load control cannot pass a limit point (a fold in lambda): use arc-length "
                      "control ({})",
                      from.lambda, o.min_step, outcome.corrector.message);
        return result;
      }
      ds = std::max(0.5 * ds, o.min_step);
      continue;
    }
    PathPoint to = std::move(*outcome.point);
    result.corrector_iterations += to.iterations;

    // 1. The end of the lambda range, landed on exactly.
    bool at_end = false;
    for (double end : {o.lambda_max, o.lambda_min}) {
      const bool crossed =
          (end == o.lambda_max) ? (to.lambda >= end && from.lambda < end) : (to.lambda <= end && from.lambda > end);
      if (!crossed) continue;
      StepOutcome landed = step_to_lambda(from, end);
      const bool between = landed.point && landed.point->arclength > from.arclength &&
                           landed.point->arclength <= to.arclength * (1 + 1e-12) + 1e-300;
      if (between) {
        to = std::move(*landed.point);
      } else if (auto located = locate(
                     from, to, [end](const PathPoint& p) { return p.lambda - end; }, o.fold_tolerance)) {
        // Located to fold_tolerance; landed on the end exactly from there (the point is near it).
        StepOutcome exact = step_to_lambda(*located, end);
        to = exact.point ? std::move(*exact.point) : std::move(*located);
      }
      at_end = true;
      break;
    }

    // 2. The observer (events of the model); it may cut the step short, or reject it.
    bool stop = false;
    if (observer) {
      const double before = to.arclength;
      const ObserverVerdict verdict = observer(from, to);
      if (verdict == ObserverVerdict::reject) {
        ++result.rejected_steps;
        if (ds <= o.min_step) {
          result.termination = ArcLengthTermination::step_rejected;
          result.message =
              fmt::format("the observer rejected the step from lambda = {:.10g} at the minimum step {:.3g}",
                          from.lambda, o.min_step);
          return result;
        }
        ds = std::max(0.5 * ds, o.min_step);
        continue;
      }
      stop = verdict == ObserverVerdict::stop;
      if (to.arclength < before) at_end = false;
    }

    // 3. A fold between the two points.
    if (arc && o.locate_folds && from.tangent_lambda != 0.0 && (from.tangent_lambda > 0) != (to.tangent_lambda > 0)) {
      const auto t_lambda = [](const PathPoint& p) { return p.tangent_lambda; };
      if (auto fold = locate(from, to, t_lambda, o.fold_tolerance))
        result.folds.push_back({fold->lambda, fold->x, fold->arclength, from.tangent_lambda > 0});
    }

    result.points.push_back(std::move(to));
    ++accepted;
    result.step_length = ds;
    if (stop) {
      result.termination = ArcLengthTermination::stopped_by_observer;
      result.message = fmt::format("stopped by the observer at lambda = {:.10g}", result.points.back().lambda);
      return result;
    }
    if (at_end) {
      result.termination = ArcLengthTermination::completed;
      result.message =
          fmt::format("completed: lambda = {:.10g} reached after {} steps", result.points.back().lambda, accepted);
      return result;
    }
    // 4. The next step length from the corrector's effort.
    ds = next_step(ds, result.points.back().iterations);
  }
}

}  // namespace liftoff::continuation
