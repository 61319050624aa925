#pragma once
// Newton's method for a square system F(x) = 0 with an analytic Jacobian, run by SUNDIALS
// KINSOL (line search or full steps) over a linear-solver seam (nonlinear/linear_solver.hpp:
// dense LU for Ritz, sparse LU for FE, a bordered solver for arc length). Model-independent: the Ritz model's
// equilibrium (modal amplitudes and contact-limit coordinates) and the corrector of a pseudo-arc-length continuation (a
// bordered system) both come here. This is the only place that calls SUNDIALS.
//
// The callbacks:
//  - Residual(x, f) writes F(x) into f (sized n on entry; keep the size). It returns false when
//    x is inadmissible (a contact length <= 0, say): KINSOL then halves the step and tries again,
//    up to five trial points per step, and fails with residual_failed if all are rejected. Only
//    these first trials may be rejected: a rejection during line-search backtracking ends the
//    solve (residual_failed), so keep iterates admissible with `constraints` where you can.
//    An f with NaN or Inf counts as a rejection.
//  - Jacobian(x, f, J) writes dF/dx at x into J (n x n, zeroed on entry); f = F(x) is given so
//    that shared work need not be redone. Returning false, or a non-finite J, ends the solve
//    with linear_solver_failed. With NewtonSolver the Jacobian is a JacobianFill(x, f) that
//    writes dF/dx into the matrix of the adapter's LinearSolver (zeroed on entry, its pattern
//    kept), under the same rules; the adapter then factorises it and solves with the factors.
//  - An exception thrown by either callback ends the solve and propagates out of solve_newton
//    unchanged (same type); x is then left as it was on entry.
//
// Convergence is measured as  r(x) = max_i |F_i(x)| * residual_scale_i  (KINSOL's stopping test).

#include <Eigen/Dense>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "nonlinear/linear_solver.hpp"

namespace liftoff::nonlinear {

using Residual = std::function<bool(const Eigen::VectorXd& x, Eigen::VectorXd& f)>;
using Jacobian = std::function<bool(const Eigen::VectorXd& x, const Eigen::VectorXd& f, Eigen::MatrixXd& jacobian)>;
using JacobianFill = std::function<bool(const Eigen::VectorXd& x, const Eigen::VectorXd& f)>;

enum class Globalisation {
  line_search,  // KIN_LINESEARCH: backtrack along the Newton direction until |F| decreases enough
  none,         // KIN_NONE: full Newton steps (cut only by max_newton_step and constraints)
};
std::string_view to_string(Globalisation);

struct NewtonOptions {
  double residual_tolerance = 1e-12;  // converged when r(x) <= this. Must be > 0 and finite.
  // Stop when the scaled step max_i |dx_i| / (|x_i| + 1 / unknown_scale_i) falls below this
  // (KINSetScaledStepTol). Must be > 0 and finite.
  double step_tolerance = 1e-15;
  int max_iterations = 50;  // Newton iterations (Jacobian evaluations); must be >= 1
  Globalisation globalisation = Globalisation::line_search;
  // Largest scaled step |unknown_scale .* dx|_2; 0 means KINSOL's default, 1000 |unknown_scale .* x0|_2
  // (at least 1). Five maximal steps in a row end the solve as diverging. Must be >= 0 and finite.
  double max_newton_step = 0;
  // Empty means ones; else size n, every entry > 0 and finite. unknown_scale_i ~ 1 / typical |x_i|,
  // residual_scale_i ~ 1 / typical |F_i| (KINSOL's u_scale and f_scale).
  Eigen::VectorXd unknown_scale, residual_scale;
  // Empty means none; else size n with KINSOL's code per unknown: 0 free, 1 x_i >= 0, 2 x_i > 0,
  // -1 x_i <= 0, -2 x_i < 0. Steps are shortened to keep them; x on entry must satisfy them.
  Eigen::VectorXi constraints;
  void validate(int n) const;  // throws std::invalid_argument naming the field and the rule
};

enum class NewtonTermination {
  converged,             // r(x) <= residual_tolerance at the returned x (possibly x on entry)
  step_below_tolerance,  // the scaled step fell below step_tolerance with r(x) still above the
                         // tolerance (KIN_STEP_LT_STPTOL): stagnation, not usable
  line_search_failed,    // no acceptable step along the Newton direction (KIN_LINESEARCH_NONCONV,
                         // KIN_LINESEARCH_BCFAIL): wrong Jacobian, or a local minimum of |F|
  iteration_limit,       // max_iterations done, r(x) still above the tolerance
  linear_solver_failed,  // the Jacobian is singular (LU zero pivot), was refused or not finite
  residual_failed,       // the residual rejected x0, a backtracking point, or five step halvings
  setup_failed,          // KINSOL or its vectors could not be created or configured
  other_failure,         // diverging (five maximal steps in a row) or another KINSOL failure
};
std::string_view to_string(NewtonTermination);

struct NewtonSummary {
  NewtonTermination termination = NewtonTermination::other_failure;
  std::string message;            // what happened and what to try, in words, ending with KINSOL's flag name
  int iterations = -1;            // Newton iterations started (KINGetNumNonlinSolvIters)
  int residual_evaluations = -1;  // calls of the Residual callback, including rejected points
  int jacobian_evaluations = -1;  // calls of the Jacobian callback
  int backtracks = -1;            // line-search backtracking steps (KINGetNumBacktrackOps: KINSOL counts
                                  // those of successful line searches only; rejected points not at all)
  // r at each distinct iterate, in order: r(x0) first, then one entry per Newton iteration that
  // moved x, the returned x last (so on convergence its size is iterations + 1 and the last entry
  // equals final_residual). Evidence of the rate: quadratic near a regular root, linear at a
  // singular one. Recorded from the f that KINSOL hands the Jacobian at every iterate.
  std::vector<double> residual_history;
  double final_residual = -1;  // r at the returned x; +Inf (and not in the history) if the
                               // residual rejects it, as when it rejects x0
  double time_s = -1;
  // Only `converged` is usable. A stop on step_tolerance counts as converged (and is reported
  // so) exactly when final_residual <= residual_tolerance; otherwise it is step_below_tolerance.
  bool is_usable() const { return termination == NewtonTermination::converged; }
  std::string brief_report() const;  // one line
};

// The KINSOL adapter, set up once and solved many times (as OSQP's osqp_setup / osqp_solve).
// The constructor creates the SUNDIALS context, the vectors, the KINSOL memory and a
// SUNLinearSolver that calls `linear_solver` (factorise at every iterate, then solve); every
// solve() rebinds the callbacks and options and allocates nothing in SUNDIALS. The linear
// solver is the caller's and must outlive the adapter; its size fixes n. A setup that fails
// (out of memory) is reported by every solve as setup_failed. Not thread-safe; not copyable.
class NewtonSolver {
 public:
  explicit NewtonSolver(LinearSolver& linear_solver);
  ~NewtonSolver();
  NewtonSolver(NewtonSolver&&) noexcept;
  NewtonSolver& operator=(NewtonSolver&&) noexcept;

  // As solve_newton below, with the Jacobian filled into linear_solver()'s matrix. x must have
  // size() entries (else std::invalid_argument).
  NewtonSummary solve(const Residual& residual, const JacobianFill& jacobian, Eigen::VectorXd& x,
                      const NewtonOptions& options = {});

  LinearSolver& linear_solver() const;
  int size() const;
  int setups() const;  // KINSOL setups of this adapter: 1 (0 if the setup failed)
  int solves() const;  // calls of solve() that passed the checks of use
  // KINSOL setups by every adapter of the process so far: lets a test prove that a loop of
  // solves (event location, say) reuses its adapter instead of rebuilding KINSOL.
  static long total_setups();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Solves F(x) = 0 from the initial guess x, which receives the last accepted iterate (the root
// when converged) whatever the outcome, except when a callback throws. If x already satisfies
// residual_tolerance, returns converged with 0 iterations. Misuse throws std::invalid_argument:
// invalid options (see validate), an empty x, NaN or Inf in x, x violating the constraints.
// Never throws for an outcome: see summary.termination.
// A one-shot convenience: a DenseLu and a NewtonSolver made for this solve only.
NewtonSummary solve_newton(const Residual& residual, const Jacobian& jacobian, Eigen::VectorXd& x,
                           const NewtonOptions& options = {});

}  // namespace liftoff::nonlinear
