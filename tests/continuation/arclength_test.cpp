// The pseudo-arc-length driver on a problem with genuine folds: Crisfield's shallow two-bar truss
// loaded through a linear spring in series (two degrees of freedom), against its closed form.
//
// Apex deflection w (down, in units of the rise), spring end v, spring stiffness c. The shallow
// truss' force is f(w) = w (w - 1) (w - 2) / 2; equilibrium of the apex and of the spring end:
//     G_1 = f(w) - c (v - w) = 0,      G_2 = c (v - w) - lambda = 0.
// So lambda = f(w) along the branch: a maximum (snap-through) at w = 1 - 1/sqrt(3), lambda =
// 1/(3 sqrt(3)), a minimum at w = 1 + 1/sqrt(3), lambda = -1/(3 sqrt(3)), then lambda grows
// again. Load control cannot pass the maximum.

#include "continuation/arclength.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

using namespace liftoff::continuation;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

constexpr double spring = 0.5;

double truss_force(double w) { return 0.5 * w * (w - 1) * (w - 2); }
double truss_stiffness(double w) { return 1.5 * w * w - 3 * w + 1; }

PathProblem shallow_truss(bool analytic_derivatives) {
  PathProblem p;
  p.unknowns = 2;
  p.residual = [](const VectorXd& x, double lambda, VectorXd& g) {
    g.resize(2);
    g(0) = truss_force(x(0)) - spring * (x(1) - x(0));
    g(1) = spring * (x(1) - x(0)) - lambda;
    return true;
  };
  if (analytic_derivatives) {
    p.jacobian = [](const VectorXd& x, double, MatrixXd& j) {
      j << truss_stiffness(x(0)) + spring, -spring, -spring, spring;
      return true;
    };
    p.lambda_derivative = [](const VectorXd&, double, VectorXd& g) {
      g << 0.0, -1.0;
      return true;
    };
  }
  return p;
}

const double fold_lambda = 1.0 / (3.0 * std::sqrt(3.0));
const double fold_w = 1.0 - 1.0 / std::sqrt(3.0);

}  // namespace

TEST_CASE("arc-length follows the shallow truss through both folds", "[arclength]") {
  const bool analytic = GENERATE(true, false);
  CAPTURE(analytic);
  ArcLengthOptions options;
  options.lambda_min = -1.0;
  options.lambda_max = 0.5;
  options.initial_step = 0.02;
  options.max_step = 0.1;
  const PathFollower follower(shallow_truss(analytic), options);
  const long setups_before = liftoff::nonlinear::NewtonSolver::total_setups();
  const auto start = follower.start(VectorXd::Zero(2), 0.0);
  REQUIRE(start);
  const ArcLengthResult result = follower.follow(*start);
  INFO(result.brief_report() << "; " << result.message);
  // Set up once: the whole run (every corrector, landing and fold location solve) used the
  // follower's two KINSOL adapters, built once each.
  CHECK(follower.newton_setups() == 2);
  CHECK(liftoff::nonlinear::NewtonSolver::total_setups() - setups_before == 2);
  REQUIRE(result.termination == ArcLengthTermination::completed);
  CHECK(result.points.back().lambda == options.lambda_max);  // landed on exactly

  // Every accepted point is an equilibrium: lambda = f(w) to the corrector's tolerance.
  for (const PathPoint& p : result.points) CHECK(std::abs(p.lambda - truss_force(p.x(0))) < 1e-10);

  // lambda rises to the fold, falls to the second one, then rises again to lambda_max.
  REQUIRE(result.folds.size() == 2);
  CHECK(result.folds[0].is_maximum);
  CHECK_FALSE(result.folds[1].is_maximum);
  // The fold's lambda: located until the bracket is below fold_tolerance (1e-10) in lambda; at a
  // fold lambda is flat in s, so that bracket bounds the error; the corrector adds its 1e-11.
  // With finite-difference derivatives the tangent (and so the fold's position in s) carries
  // their error, ~1e-6 relative in t_lambda, which enters lambda quadratically (< 1e-10).
  const double tolerance = options.fold_tolerance + 1e-10;
  CHECK(std::abs(result.folds[0].lambda - fold_lambda) < tolerance);
  CHECK(std::abs(result.folds[1].lambda + fold_lambda) < tolerance);
  // w at the fold: lambda - lambda* ~ f''/2 (w - w*)^2, so w is located to ~sqrt(tolerance / |f''|).
  const double w_tolerance = 10 * std::sqrt(tolerance / std::abs(3 * fold_w - 3));
  CHECK(std::abs(result.folds[0].x(0) - fold_w) < w_tolerance);
  CHECK(std::abs(result.folds[1].x(0) - (2 - fold_w)) < w_tolerance);

  // The path's own lambda history: up to the first fold, down to the second, up again.
  int direction_changes = 0;
  for (std::size_t i = 2; i < result.points.size(); ++i) {
    const double d1 = result.points[i - 1].lambda - result.points[i - 2].lambda;
    const double d2 = result.points[i].lambda - result.points[i - 1].lambda;
    if ((d1 > 0) != (d2 > 0)) ++direction_changes;
  }
  CHECK(direction_changes == 2);
  double highest_before_snap = -1;
  for (const PathPoint& p : result.points)
    if (p.x(0) < 1.0) highest_before_snap = std::max(highest_before_snap, p.lambda);
  CHECK(highest_before_snap <= fold_lambda + 1e-10);
  CHECK(result.points.back().x(0) > 2.0);  // past the snap-through: on the far, rising part

  // The steps adapt: not all of one length.
  double shortest = 1e300, longest = 0;
  for (std::size_t i = 1; i < result.points.size(); ++i) {
    const double ds = result.points[i].arclength - result.points[i - 1].arclength;
    shortest = std::min(shortest, ds);
    longest = std::max(longest, ds);
  }
  CHECK(longest > 1.5 * shortest);
}

TEST_CASE("load control stops at the fold and says so", "[arclength]") {
  ArcLengthOptions options;
  options.control = PathControl::load;
  options.lambda_min = -1.0;
  options.lambda_max = 0.5;
  options.initial_step = 0.02;
  options.max_step = 0.1;
  options.min_step = 1e-8;
  const PathFollower follower(shallow_truss(true), options);
  const auto start = follower.start(VectorXd::Zero(2), 0.0);
  REQUIRE(start);
  const ArcLengthResult result = follower.follow(*start);
  INFO(result.brief_report() << "; " << result.message);
  CHECK(result.termination == ArcLengthTermination::step_too_small);
  CHECK(result.message.find("limit point") != std::string::npos);
  CHECK(result.folds.empty());
  const double last = result.points.back().lambda;
  // Just below the fold: above it there is no equilibrium near the branch, and the step was
  // halved until a step of min_step from `last` failed. So the fold lies within a few min_step
  // of `last` (one if the corrector fails only where no solution exists; the Jacobian is nearly
  // singular there, so allow ten).
  CHECK(last < fold_lambda);
  CHECK(fold_lambda - last < 10 * options.min_step);
  for (const PathPoint& p : result.points) CHECK(p.x(0) < fold_w);  // never passed the snap
}

TEST_CASE("locate finds where an event function changes sign along a step", "[arclength]") {
  ArcLengthOptions options;
  options.lambda_min = -1.0;
  const PathFollower follower(shallow_truss(true), options);
  const auto start = follower.start(VectorXd::Zero(2), 0.0);
  REQUIRE(start);
  const StepOutcome step = follower.step(*start, 0.15);
  REQUIRE(step.point);
  // w = 0.02 somewhere on this step (w runs from 0 to about 0.047 along it).
  const auto event = [](const PathPoint& p) { return p.x(0) - 0.02; };
  REQUIRE(event(*step.point) > 0);
  const long setups_before = liftoff::nonlinear::NewtonSolver::total_setups();
  const auto located = follower.locate(*start, *step.point, event, 1e-12);
  REQUIRE(located);
  CHECK(std::abs(located->lambda - truss_force(0.02)) < 1e-11);
  // Event location reuses the follower's corrector: its many solves built no KINSOL.
  CHECK(liftoff::nonlinear::NewtonSolver::total_setups() == setups_before);
  CHECK(follower.newton_setups() == 2);
}

TEST_CASE("a sparse G_x (PathProblem::sparse_jacobian) follows the same path as the dense one", "[arclength]") {
  ArcLengthOptions options;
  options.lambda_min = -1.0;
  options.lambda_max = 0.5;
  options.initial_step = 0.02;
  options.max_step = 0.1;
  PathProblem sparse = shallow_truss(true);
  sparse.jacobian = nullptr;
  sparse.sparse_jacobian = [](const VectorXd& x, double, Eigen::SparseMatrix<double>& j) {
    if (j.nonZeros() == 0) {  // the pattern, once
      const std::vector<Eigen::Triplet<double>> all = {{0, 0, 1.0}, {0, 1, 1.0}, {1, 0, 1.0}, {1, 1, 1.0}};
      j.setFromTriplets(all.begin(), all.end());
    }
    j.coeffRef(0, 0) = truss_stiffness(x(0)) + spring;
    j.coeffRef(0, 1) = -spring;
    j.coeffRef(1, 0) = -spring;
    j.coeffRef(1, 1) = spring;
    return true;
  };
  const PathFollower dense_follower(shallow_truss(true), options), sparse_follower(sparse, options);
  const ArcLengthResult a = dense_follower.follow(*dense_follower.start(VectorXd::Zero(2), 0.0));
  const ArcLengthResult b = sparse_follower.follow(*sparse_follower.start(VectorXd::Zero(2), 0.0));
  REQUIRE(a.termination == ArcLengthTermination::completed);
  REQUIRE(b.termination == ArcLengthTermination::completed);
  REQUIRE(a.points.size() == b.points.size());
  REQUIRE(b.folds.size() == 2);
  // The same steps, to the corrector's tolerance (1e-11) times the steps' sensitivity.
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    CHECK(std::abs(a.points[i].lambda - b.points[i].lambda) < 1e-9);
    CHECK((a.points[i].x - b.points[i].x).lpNorm<Eigen::Infinity>() < 1e-9);
  }
  for (std::size_t i = 0; i < 2; ++i) CHECK(std::abs(a.folds[i].lambda - b.folds[i].lambda) < 1e-9);
  CHECK(sparse_follower.newton_setups() == 2);
}

TEST_CASE("arc-length options are validated", "[arclength]") {
  ArcLengthOptions options;
  options.min_step = 1.0;
  CHECK_THROWS_WITH(PathFollower(shallow_truss(true), options), Catch::Contains("initial_step"));
  options = {};
  options.direction = 0;
  CHECK_THROWS_WITH(PathFollower(shallow_truss(true), options), Catch::Contains("direction"));
  PathProblem bad = shallow_truss(true);
  bad.residual = nullptr;
  CHECK_THROWS_WITH(PathFollower(bad, ArcLengthOptions{}), Catch::Contains("residual"));
}

TEST_CASE("a step the observer rejects is retried shorter, and the run ends at min_step keeping the points before",
          "[arclength]") {
  // The observer rejects any step that reaches past lambda = 0.1 (as the Ritz path rejects a
  // state that is no contact solution): the steps shrink by halves toward it, every accepted
  // point stays below it, and once min_step is rejected too the run ends (step_rejected).
  ArcLengthOptions options;
  options.lambda_min = 0.0;
  options.lambda_max = 0.3;
  options.initial_step = 0.05;
  options.min_step = 1e-6;
  const PathFollower follower(shallow_truss(true), options);
  const auto start = follower.start(VectorXd::Zero(2), 0.0);
  REQUIRE(start);
  constexpr double barrier = 0.1;
  int rejections = 0;
  const ArcLengthResult r = follower.follow(*start, [&](const PathPoint&, PathPoint& to) {
    if (to.lambda <= barrier) return ObserverVerdict::proceed;
    ++rejections;
    return ObserverVerdict::reject;
  });
  INFO(r.message);
  CHECK(r.termination == ArcLengthTermination::step_rejected);
  CHECK(r.rejected_steps == rejections);
  REQUIRE(r.points.size() >= 2);
  for (const PathPoint& p : r.points) CHECK(p.lambda <= barrier);
  // Each rejection halves the step, so the last accepted point is within a few min_step (in the
  // scaled arc length, here about lambda) of the barrier.
  CHECK(r.points.back().lambda > barrier - 4 * options.min_step / std::abs(r.points.back().tangent_lambda));
}
