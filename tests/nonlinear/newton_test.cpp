#include "nonlinear/newton.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

using Catch::Matchers::Contains;
using Eigen::MatrixXd;
using Eigen::VectorXd;
using liftoff::nonlinear::Globalisation;
using liftoff::nonlinear::Jacobian;
using liftoff::nonlinear::NewtonOptions;
using liftoff::nonlinear::NewtonSummary;
using liftoff::nonlinear::NewtonTermination;
using liftoff::nonlinear::Residual;
using liftoff::nonlinear::solve_newton;

namespace {

constexpr double eps = std::numeric_limits<double>::epsilon();

// Two circles' worth of polynomial: x^2 + y^2 = 4, x y = 1. Roots with x > y > 0:
// x = (sqrt 6 + sqrt 2) / 2, y = (sqrt 6 - sqrt 2) / 2.
const Residual circle_residual = [](const VectorXd& u, VectorXd& f) {
  f(0) = u(0) * u(0) + u(1) * u(1) - 4.0;
  f(1) = u(0) * u(1) - 1.0;
  return true;
};
const Jacobian circle_jacobian = [](const VectorXd& u, const VectorXd&, MatrixXd& J) {
  J << 2.0 * u(0), 2.0 * u(1), u(1), u(0);
  return true;
};
const VectorXd circle_root =
    (VectorXd(2) << (std::sqrt(6.0) + std::sqrt(2.0)) / 2.0, (std::sqrt(6.0) - std::sqrt(2.0)) / 2.0).finished();

VectorXd vec(std::initializer_list<double> values) {
  VectorXd v(static_cast<Eigen::Index>(values.size()));
  Eigen::Index i = 0;
  for (double value : values) v(i++) = value;
  return v;
}

// Scalar problems f(x) = 0 as 1x1 systems.
template <class F, class DF>
std::pair<Residual, Jacobian> scalar(F f, DF df) {
  return {[f](const VectorXd& x, VectorXd& r) {
            r(0) = f(x(0));
            return true;
          },
          [df](const VectorXd& x, const VectorXd&, MatrixXd& J) {
            J(0, 0) = df(x(0));
            return true;
          }};
}

// The history invariants every run must satisfy (see NewtonSummary::residual_history).
void check_history(const NewtonSummary& s) {
  CAPTURE(s.brief_report());
  REQUIRE(!s.residual_history.empty());
  CHECK(s.residual_history.back() == s.final_residual);
  if (s.termination == NewtonTermination::converged)
    CHECK(s.residual_history.size() == static_cast<std::size_t>(s.iterations) + 1);
  else
    CHECK(s.residual_history.size() <= static_cast<std::size_t>(s.iterations) + 1);
}

// Observed order of convergence from three consecutive residuals.
double observed_order(double r0, double r1, double r2) { return std::log(r2 / r1) / std::log(r1 / r0); }

}  // namespace

TEST_CASE("a polynomial system converges to 1e-12 quadratically", "[newton]") {
  const Globalisation globalisation = GENERATE(Globalisation::line_search, Globalisation::none);
  CAPTURE(to_string(globalisation));
  NewtonOptions options;
  options.globalisation = globalisation;
  VectorXd x = vec({3.0, 1.5});
  const NewtonSummary s = solve_newton(circle_residual, circle_jacobian, x, options);
  CAPTURE(s.brief_report(), s.message);

  REQUIRE(s.termination == NewtonTermination::converged);
  CHECK(s.is_usable());
  CHECK((x - circle_root).cwiseAbs().maxCoeff() < 1e-12);
  CHECK(s.final_residual <= 1e-12);
  CHECK(s.jacobian_evaluations == s.iterations);  // a fresh Jacobian at every iterate
  CHECK(s.residual_evaluations >= s.iterations);
  CHECK(s.backtracks >= 0);
  CHECK(s.time_s >= 0.0);
  CHECK_THAT(s.message, Contains("KIN_SUCCESS"));
  check_history(s);

  // The last three residuals above round-off (100 eps, the scale of F being ~4) must show order 2.
  const std::vector<double>& r = s.residual_history;
  std::size_t last = r.size() - 1;
  while (last > 0 && r[last] < 100.0 * eps) --last;
  REQUIRE(last >= 2);
  const double order = observed_order(r[last - 2], r[last - 1], r[last]);
  CAPTURE(r, order, std::log(r[last]) / std::log(r[last - 1]));
  CHECK(order >= 1.8);
  CHECK(order <= 2.5);
}

TEST_CASE("the initial guess is accepted against residual_tolerance itself", "[newton]") {
  // A linear F: x0 exact, or off by half the tolerance (KINSOL alone would take a step, as it
  // tests the initial guess against 0.01 * residual_tolerance).
  const double offset = GENERATE(0.0, 0.5e-12);
  const Residual residual = [](const VectorXd& x, VectorXd& f) {
    f = x - vec({1.0, -2.0});
    return true;
  };
  const Jacobian jacobian = [](const VectorXd&, const VectorXd&, MatrixXd& J) {
    J.setIdentity();
    return true;
  };
  VectorXd x = vec({1.0 + offset, -2.0});
  const VectorXd x0 = x;
  const NewtonSummary s = solve_newton(residual, jacobian, x, {});
  CAPTURE(s.message);
  CHECK(s.termination == NewtonTermination::converged);
  CHECK(s.iterations == 0);
  CHECK(s.residual_evaluations == 1);
  CHECK(s.jacobian_evaluations == 0);
  CHECK(s.residual_history.size() == 1);
  CHECK(s.final_residual == (1.0 + offset) - 1.0);  // the offset as represented in x
  CHECK(x == x0);
  CHECK_THAT(s.message, Contains("KIN_INITIAL_GUESS_OK"));
}

TEST_CASE("a positivity constraint keeps the unknown positive and reaches the positive root", "[newton]") {
  // f = (x^2 - 4) / (x^2 + 1): roots -2 and +2. From x0 = 5 the full Newton step lands at -5.9;
  // with x > 0 imposed KINSOL shortens it to stay positive and the iteration reaches +2.
  double smallest_x = std::numeric_limits<double>::infinity();
  const Residual residual = [&](const VectorXd& x, VectorXd& f) {
    smallest_x = std::min(smallest_x, x(0));
    f(0) = (x(0) * x(0) - 4.0) / (x(0) * x(0) + 1.0);
    return true;
  };
  const Jacobian jacobian = [](const VectorXd& x, const VectorXd&, MatrixXd& J) {
    const double d = x(0) * x(0) + 1.0;
    J(0, 0) = 10.0 * x(0) / (d * d);
    return true;
  };
  NewtonOptions options;
  options.globalisation = Globalisation::none;

  SECTION("without the constraint, full Newton steps leave x > 0") {
    VectorXd x = vec({5.0});
    solve_newton(residual, jacobian, x, options);
    CHECK(smallest_x < 0.0);
  }
  SECTION("with it, every iterate stays positive") {
    options.globalisation = GENERATE(Globalisation::none, Globalisation::line_search);
    options.constraints = Eigen::VectorXi::Constant(1, 2);
    VectorXd x = vec({5.0});
    const NewtonSummary s = solve_newton(residual, jacobian, x, options);
    CAPTURE(s.message, to_string(options.globalisation));
    CHECK(s.termination == NewtonTermination::converged);
    CHECK(x(0) == Approx(2.0).epsilon(1e-12));
    CHECK(smallest_x > 0.0);
    check_history(s);
  }
  SECTION("x^2 - 4 from 0.5 under x > 0 goes to +2") {
    const auto [f, df] = scalar([](double t) { return t * t - 4.0; }, [](double t) { return 2.0 * t; });
    options.constraints = Eigen::VectorXi::Constant(1, 2);
    VectorXd x = vec({0.5});
    const NewtonSummary s = solve_newton(f, df, x, options);
    CHECK(s.termination == NewtonTermination::converged);
    CHECK(x(0) == Approx(2.0).epsilon(1e-12));
  }
}

TEST_CASE("an inadmissible trial point makes KINSOL cut the step rather than fail", "[newton]") {
  // f = log x - 1 (root e) is defined for x > 0 only. From x0 = 10 the Newton step goes to
  // x = 10 (2 - log 10) = -3.03; the residual refuses it and the halved step is taken instead.
  int rejected = 0;
  const Residual residual = [&](const VectorXd& x, VectorXd& f) {
    if (x(0) <= 0.0) {
      ++rejected;
      return false;
    }
    f(0) = std::log(x(0)) - 1.0;
    return true;
  };
  const Jacobian jacobian = [](const VectorXd& x, const VectorXd&, MatrixXd& J) {
    J(0, 0) = 1.0 / x(0);
    return true;
  };
  NewtonOptions options;
  options.globalisation = GENERATE(Globalisation::line_search, Globalisation::none);
  VectorXd x = vec({10.0});
  const NewtonSummary s = solve_newton(residual, jacobian, x, options);
  CAPTURE(s.message, to_string(options.globalisation));
  CHECK(s.termination == NewtonTermination::converged);
  CHECK(x(0) == Approx(std::exp(1.0)).epsilon(1e-12));
  CHECK(rejected >= 1);
  CHECK(s.residual_evaluations >= s.iterations + rejected);
  check_history(s);
}

TEST_CASE("a residual that rejects the initial guess is a residual failure", "[newton]") {
  const Residual residual = [](const VectorXd&, VectorXd&) { return false; };
  VectorXd x = vec({1.0});
  const NewtonSummary s = solve_newton(residual, circle_jacobian, x, {});
  CHECK(s.termination == NewtonTermination::residual_failed);
  CHECK(!s.is_usable());
  CHECK(s.iterations == 0);
  CHECK(s.residual_history.empty());
  CHECK(std::isinf(s.final_residual));
  CHECK_THAT(s.message, Contains("KIN_FIRST_SYSFUNC_ERR"));
}

TEST_CASE("the iteration limit is an outcome and not an error", "[newton]") {
  NewtonOptions options;
  options.max_iterations = 2;
  VectorXd x = vec({30.0, 0.1});
  const NewtonSummary s = solve_newton(circle_residual, circle_jacobian, x, options);
  CAPTURE(s.message);
  CHECK(s.termination == NewtonTermination::iteration_limit);
  CHECK(!s.is_usable());
  CHECK(s.iterations == 2);
  CHECK(!s.message.empty());
  CHECK_THAT(s.message, Contains("KIN_MAXITER_REACHED") && Contains("max_iterations"));
  CHECK(s.final_residual > options.residual_tolerance);
  CHECK(x.allFinite());
  check_history(s);
}

TEST_CASE("singular Jacobians are reported and not crashed on", "[newton]") {
  SECTION("a constant singular Jacobian: linear_solver_failed") {
    // F = A x - b with A of rank 1 and b outside its range: no root, no Newton step.
    const Residual residual = [](const VectorXd& x, VectorXd& f) {
      f << x(0) + 2.0 * x(1) - 1.0, 2.0 * x(0) + 4.0 * x(1) - 1.0;
      return true;
    };
    const Jacobian jacobian = [](const VectorXd&, const VectorXd&, MatrixXd& J) {
      J << 1.0, 2.0, 2.0, 4.0;
      return true;
    };
    VectorXd x = vec({0.0, 0.0});
    const NewtonSummary s = solve_newton(residual, jacobian, x, {});
    CAPTURE(s.message);
    CHECK(s.termination == NewtonTermination::linear_solver_failed);
    CHECK(!s.is_usable());
    CHECK_THAT(s.message, Contains("singular") && Contains("KIN_LSETUP_FAIL"));
    CHECK(x == vec({0.0, 0.0}));
    check_history(s);
  }
  SECTION("f = x^2 (singular at the root): converges only linearly, the history shows it") {
    const auto [f, df] = scalar([](double t) { return t * t; }, [](double t) { return 2.0 * t; });
    NewtonOptions options;
    VectorXd x = vec({1.0});
    const NewtonSummary s = solve_newton(f, df, x, options);
    CAPTURE(s.message, s.residual_history);
    REQUIRE(s.termination == NewtonTermination::converged);  // x halves per step: r falls 4x
    CHECK(s.iterations >= 19);
    const std::vector<double>& r = s.residual_history;
    const std::size_t k = r.size() - 1;
    CHECK(r[k] / r[k - 1] == Approx(0.25).epsilon(1e-6));
    CHECK(observed_order(r[k - 2], r[k - 1], r[k]) == Approx(1.0).epsilon(1e-6));

    options.max_iterations = 10;  // and with a budget it would need for quadratic convergence:
    x = vec({1.0});
    const NewtonSummary limited = solve_newton(f, df, x, options);
    CHECK(limited.termination == NewtonTermination::iteration_limit);
    CHECK(!limited.is_usable());
  }
  SECTION("a Jacobian callback that refuses, or returns NaN: linear_solver_failed") {
    const bool refuse = GENERATE(true, false);
    const Jacobian jacobian = [refuse](const VectorXd&, const VectorXd&, MatrixXd& J) {
      J.setConstant(std::numeric_limits<double>::quiet_NaN());
      return !refuse;
    };
    VectorXd x = vec({3.0, 1.5});
    const NewtonSummary s = solve_newton(circle_residual, jacobian, x, {});
    CAPTURE(s.message);
    CHECK(s.termination == NewtonTermination::linear_solver_failed);
    CHECK_THAT(s.message, Contains(refuse ? "refused" : "NaN"));
  }
}

TEST_CASE("a step below step_tolerance with a residual above tolerance is not usable", "[newton]") {
  // x^2 - 2 cannot vanish in floating point: at round-off the steps are ~1 ulp of x.
  const auto [f, df] = scalar([](double t) { return t * t - 2.0; }, [](double t) { return 2.0 * t; });
  NewtonOptions options;
  options.residual_tolerance = 1e-300;
  options.globalisation = Globalisation::none;
  VectorXd x = vec({1.5});
  const NewtonSummary s = solve_newton(f, df, x, options);
  CAPTURE(s.message, s.residual_history);
  CHECK(s.termination == NewtonTermination::step_below_tolerance);
  CHECK(!s.is_usable());
  CHECK(s.final_residual > options.residual_tolerance);
  CHECK(x(0) == Approx(std::sqrt(2.0)).epsilon(4 * eps));
  CHECK_THAT(s.message, Contains("KIN_STEP_LT_STPTOL"));
}

TEST_CASE("residual_scale weighs the stopping test", "[newton]") {
  // The first equation is in large units; scaled by 1e-6 it counts like the second.
  const Residual residual = [](const VectorXd& x, VectorXd& f) {
    f << 1e6 * (x(0) * x(0) - 4.0), x(1) - 3.0;
    return true;
  };
  const Jacobian jacobian = [](const VectorXd& x, const VectorXd&, MatrixXd& J) {
    J << 2e6 * x(0), 0.0, 0.0, 1.0;
    return true;
  };
  NewtonOptions options;
  options.residual_scale = vec({1e-6, 1.0});
  VectorXd x = vec({3.0, 0.0});
  const NewtonSummary s = solve_newton(residual, jacobian, x, options);
  CAPTURE(s.message);
  CHECK(s.termination == NewtonTermination::converged);
  CHECK(s.final_residual <= 1e-12);
  CHECK(s.residual_history.front() == Approx(5.0));  // max(1e-6 * 1e6 * 5, 3)
  CHECK(x(0) == Approx(2.0).epsilon(1e-12));
}

namespace {
struct CallbackError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
}  // namespace

TEST_CASE("an exception thrown by a callback reaches the caller unchanged", "[newton]") {
  VectorXd x = vec({3.0, 1.5});
  const VectorXd x0 = x;
  SECTION("from the residual, inside KINSOL") {
    int calls = 0;
    const Residual residual = [&](const VectorXd& u, VectorXd& f) {
      if (++calls == 3) throw CallbackError("residual exploded");
      return circle_residual(u, f);
    };
    CHECK_THROWS_AS(solve_newton(residual, circle_jacobian, x, {}), CallbackError);
    CHECK(calls == 3);
  }
  SECTION("from the residual, at the initial guess") {
    const Residual residual = [](const VectorXd&, VectorXd&) -> bool { throw CallbackError("at x0"); };
    CHECK_THROWS_AS(solve_newton(residual, circle_jacobian, x, {}), CallbackError);
  }
  SECTION("from the Jacobian") {
    const Jacobian jacobian = [](const VectorXd&, const VectorXd&, MatrixXd&) -> bool {
      throw CallbackError("jacobian exploded");
    };
    CHECK_THROWS_WITH(solve_newton(circle_residual, jacobian, x, {}), "jacobian exploded");
    CHECK_THROWS_AS(solve_newton(circle_residual, jacobian, x, {}), CallbackError);
  }
  SECTION("a residual that resizes f is misuse") {
    const Residual residual = [](const VectorXd&, VectorXd& f) {
      f.resize(5);
      f.setZero();
      return true;
    };
    CHECK_THROWS_AS(solve_newton(residual, circle_jacobian, x, {}), std::invalid_argument);
  }
  CHECK(x == x0);  // x untouched when a callback throws
}

TEST_CASE("options and inputs are validated", "[newton]") {
  NewtonOptions options;
  CHECK_NOTHROW(options.validate(2));
  SECTION("a negative tolerance") {
    options.residual_tolerance = -1e-12;
    CHECK_THROWS_AS(options.validate(2), std::invalid_argument);
    CHECK_THROWS_WITH(options.validate(2), Contains("residual_tolerance"));
    options.residual_tolerance = 1e-12;
    options.step_tolerance = std::numeric_limits<double>::quiet_NaN();
    CHECK_THROWS_WITH(options.validate(2), Contains("step_tolerance"));
  }
  SECTION("a constraint vector of the wrong size, or an unknown code") {
    options.constraints = Eigen::VectorXi::Zero(3);
    CHECK_THROWS_WITH(options.validate(2), Contains("constraints") && Contains("size 3"));
    options.constraints = (Eigen::VectorXi(2) << 0, 3).finished();
    CHECK_THROWS_WITH(options.validate(2), Contains("constraints(1)"));
  }
  SECTION("scales, iterations, step bound") {
    options.unknown_scale = vec({1.0, 0.0});
    CHECK_THROWS_WITH(options.validate(2), Contains("unknown_scale(1)"));
    options.unknown_scale.resize(0);
    options.residual_scale = vec({1.0});
    CHECK_THROWS_WITH(options.validate(2), Contains("residual_scale"));
    options.residual_scale.resize(0);
    options.max_iterations = 0;
    CHECK_THROWS_WITH(options.validate(2), Contains("max_iterations"));
    options.max_iterations = 50;
    options.max_newton_step = -1.0;
    CHECK_THROWS_WITH(options.validate(2), Contains("max_newton_step"));
  }
  SECTION("solve_newton checks before it calls anything") {
    int calls = 0;
    const Residual residual = [&](const VectorXd& u, VectorXd& f) {
      ++calls;
      return circle_residual(u, f);
    };
    VectorXd x = vec({std::numeric_limits<double>::quiet_NaN(), 1.0});
    CHECK_THROWS_AS(solve_newton(residual, circle_jacobian, x, {}), std::invalid_argument);
    x = vec({1.0, 1.0});
    options.residual_tolerance = -1.0;
    CHECK_THROWS_AS(solve_newton(residual, circle_jacobian, x, options), std::invalid_argument);
    options.residual_tolerance = 1e-12;
    options.constraints = (Eigen::VectorXi(2) << 2, 0).finished();
    x = vec({-1.0, 1.0});
    CHECK_THROWS_WITH(solve_newton(residual, circle_jacobian, x, options), Contains("x(0) = -1"));
    VectorXd empty;
    CHECK_THROWS_AS(solve_newton(residual, circle_jacobian, empty, {}), std::invalid_argument);
    CHECK(calls == 0);
  }
}

TEST_CASE("names and the one-line report", "[newton]") {
  CHECK(to_string(NewtonTermination::step_below_tolerance) == "step_below_tolerance");
  CHECK(to_string(Globalisation::line_search) == "line_search");
  VectorXd x = vec({3.0, 1.5});
  const NewtonSummary s = solve_newton(circle_residual, circle_jacobian, x, {});
  CHECK_THAT(s.brief_report(), Contains("newton: converged after"));
  const NewtonSummary unfilled;
  CHECK(unfilled.iterations == -1);
  CHECK(!unfilled.is_usable());
}
