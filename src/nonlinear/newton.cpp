#include "nonlinear/newton.hpp"

// The KINSOL adapter: the only file in liftoff that calls SUNDIALS.
//
// Why the adapter does some things itself rather than leave them to KINSOL (6.4.1):
//  - The initial guess is tested here, against residual_tolerance itself: KINSOL accepts x0 only
//    when r(x0) <= 0.01 * fnormtol and would otherwise take a needless Newton step. The residual
//    at x0 is then handed to KINSOL's first call from a one-shot cache, so it is computed once.
//  - KINSetMaxSetupCalls(1) makes KINSOL evaluate the Jacobian at every iterate (a true Newton
//    method, quadratic near a regular root; for the small dense systems here the Jacobian costs
//    about as much as the residual). The Jacobian callback receives F at the current iterate,
//    which is where residual_history comes from without extra residual evaluations.
//  - The residual at the returned x is taken from the last evaluation if that was at the same
//    point (the usual case) and recomputed otherwise: after a failed line search, KINSOL's last
//    F belongs to a rejected trial point, not to the x it returns.
//  - KINGetReturnFlagName returns a malloc'ed string (freed here) and, in 6.4.1, "NONE" for the
//    KIN_*SYSFUNC* codes, which are therefore named from a table of our own.
//  - C++ exceptions must not unwind through KINSOL's C frames: the C callbacks catch everything,
//    park the exception, return -1 (unrecoverable; KINSOL stops at once), and solve_newton
//    rethrows it after KINSol has returned. The adapter owns every handle through unique_ptr
//    members declared in creation order, so they are freed in reverse order on every path.
//  - KINSOL's error messages go to a handler that collects them for the summary, not to stderr.

#include <fmt/format.h>
#include <fmt/ranges.h>  // fmt::join
#include <kinsol/kinsol.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <limits>
#include <memory>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include "core/enum_names.hpp"

namespace liftoff::nonlinear {

namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;
using ConstVectorMap = Eigen::Map<const VectorXd>;

constexpr double infinity = std::numeric_limits<double>::infinity();
constexpr std::size_t max_kinsol_messages = 4;  // KINSOL reports each failure once or twice

// The name of a KIN_* return value. KINGetReturnFlagName mallocs the string and, in 6.4.1,
// knows neither the system-function codes nor the vector-op and context errors.
std::string flag_name(int flag) {
  switch (flag) {
    case KIN_SYSFUNC_FAIL:
      return "KIN_SYSFUNC_FAIL";
    case KIN_FIRST_SYSFUNC_ERR:
      return "KIN_FIRST_SYSFUNC_ERR";
    case KIN_REPTD_SYSFUNC_ERR:
      return "KIN_REPTD_SYSFUNC_ERR";
    case KIN_VECTOROP_ERR:
      return "KIN_VECTOROP_ERR";
    case KIN_CONTEXT_ERR:
      return "KIN_CONTEXT_ERR";
    default:
      break;
  }
  const std::unique_ptr<char, decltype(&std::free)> name(KINGetReturnFlagName(flag), &std::free);
  if (!name || std::string_view(name.get()) == "NONE") return fmt::format("KINSOL flag {}", flag);
  return name.get();
}

bool same_point(const VectorXd& a, const double* b) { return (a.array() == ConstVectorMap(b, a.size()).array()).all(); }

// What the C callbacks reach through KINSOL's user_data: the user's functions, work space (so
// the iteration allocates nothing), the residual history and everything a summary needs.
class Problem {
 public:
  Problem(const Residual& residual, const JacobianFill& jacobian, LinearSolver& solver, VectorXd residual_scale)
      : residual_(residual),
        jacobian_(jacobian),
        solver_(solver),
        n_(solver.size()),
        residual_scale_(std::move(residual_scale)),
        x_(n_),
        f_(n_),
        f_given_(n_),
        last_x_(n_),
        last_f_(n_),
        recorded_x_(n_) {}

  int n() const { return n_; }

  // r(f) = max_i |f_i| * residual_scale_i, KINSOL's stopping quantity.
  double scaled_norm(const double* f) const {
    return (ConstVectorMap(f, n_).array().abs() * residual_scale_.array()).maxCoeff();
  }

  // F(x) into f (both n values). Returns 0 if admissible, 1 if the user rejected x or returned
  // a non-finite f. Throws what the user's callback throws.
  int residual(const double* x, double* f) {
    if (initial_cached_) {  // KINSOL's first call, at x0: served from the adapter's own test
      initial_cached_ = false;
      if (same_point(initial_x_, x)) {
        Eigen::Map<VectorXd>(f, n_) = initial_f_;
        return 0;
      }
    }
    x_ = ConstVectorMap(x, n_);
    ++residual_calls_;
    const bool accepted = residual_(x_, f_);
    if (f_.size() != n_)
      throw std::invalid_argument(fmt::format(
          "solve_newton: the residual callback resized f from {} to {}; it must keep the size", n_, f_.size()));
    last_x_ = x_;
    last_evaluation_valid_ = false;
    if (!accepted || !f_.allFinite()) {
      ++rejections_;
      return 1;
    }
    last_f_ = f_;
    last_evaluation_valid_ = true;
    Eigen::Map<VectorXd>(f, n_) = f_;
    return 0;
  }

  // dF/dx at x into the linear solver's matrix (zeroed by KINSOL just before, through the
  // SUNMatrix's zero op); f = F(x). Records r(x) in the history. Returns 0 on success, 1 if the
  // user refused (see jacobian_problem()). Throws what the user's callback throws.
  int jacobian(const double* x, const double* f) {
    record(x, scaled_norm(f));
    x_ = ConstVectorMap(x, n_);
    f_given_ = ConstVectorMap(f, n_);
    ++jacobian_calls_;
    if (!jacobian_(x_, f_given_)) {
      jacobian_problem_ = "the Jacobian callback refused the current iterate";
      return 1;
    }
    return 0;
  }

  // Factorises the filled matrix (KINSOL's linear-solver setup). Returns 0, or a positive
  // number (KINSOL then fails with KIN_LSETUP_FAIL) with the reason kept for the summary.
  int factorise() {
    switch (solver_.factorise()) {
      case Factorisation::ok:
        return 0;
      case Factorisation::not_finite:
        jacobian_problem_ = "the Jacobian callback returned NaN or Inf";
        return 1;
      case Factorisation::singular:
        break;
    }
    return solver_.zero_pivot() > 0 ? static_cast<int>(solver_.zero_pivot()) : 1;
  }
  LinearSolver& solver() { return solver_; }
  VectorXd& solve_work() { return solve_work_; }

  // The one-shot cache for KINSOL's first residual call (see the top of this file).
  void cache_initial(const VectorXd& x, const VectorXd& f) {
    initial_x_ = x;
    initial_f_ = f;
    initial_cached_ = true;
  }

  // Appends r if x is not the iterate recorded last, so that no iterate appears twice.
  void record(const double* x, double r) {
    if (!history_.empty() && same_point(recorded_x_, x)) return;
    recorded_x_ = ConstVectorMap(x, n_);
    history_.push_back(r);
  }

  // The residual at x as the last evaluation left it, if that was at x and admissible.
  const VectorXd* last_residual_at(const double* x) const {
    return last_evaluation_valid_ && same_point(last_x_, x) ? &last_f_ : nullptr;
  }

  int residual_calls() const { return residual_calls_; }
  int jacobian_calls() const { return jacobian_calls_; }
  int rejections() const { return rejections_; }
  const std::string& jacobian_problem() const { return jacobian_problem_; }
  std::vector<double>& history() { return history_; }

  // Filled by the C callbacks, read after KINSol returns.
  std::exception_ptr pending_exception;
  std::vector<std::string> kinsol_messages;

 private:
  const Residual& residual_;
  const JacobianFill& jacobian_;
  LinearSolver& solver_;
  int n_;
  VectorXd residual_scale_;
  VectorXd x_, f_, f_given_, solve_work_;
  VectorXd last_x_, last_f_;
  bool last_evaluation_valid_ = false;
  VectorXd initial_x_, initial_f_;
  bool initial_cached_ = false;
  VectorXd recorded_x_;
  std::vector<double> history_;
  int residual_calls_ = 0, jacobian_calls_ = 0, rejections_ = 0;
  std::string jacobian_problem_;
};

// The C side. No exception may leave these functions.
extern "C" {

static int kinsol_residual(N_Vector u, N_Vector f, void* user_data) {
  auto& problem = *static_cast<Problem*>(user_data);
  if (problem.pending_exception) return -1;
  try {
    return problem.residual(N_VGetArrayPointer(u), N_VGetArrayPointer(f));
  } catch (...) {
    problem.pending_exception = std::current_exception();
    return -1;
  }
}

static int kinsol_jacobian(N_Vector u, N_Vector fu, SUNMatrix /*jacobian*/, void* user_data, N_Vector /*tmp1*/,
                           N_Vector /*tmp2*/) {
  auto& problem = *static_cast<Problem*>(user_data);
  if (problem.pending_exception) return -1;
  try {
    return problem.jacobian(N_VGetArrayPointer(u), N_VGetArrayPointer(fu));
  } catch (...) {
    problem.pending_exception = std::current_exception();
    return -1;
  }
}

// The SUNMatrix KINSOL hands around is a stand-in for the seam's matrix: its content is the
// LinearSolver, its only working operation zero() (KINSOL zeroes a direct solver's matrix
// before each Jacobian evaluation). The Jacobian callback fills the seam's matrix itself.
static SUNMatrix_ID seam_matrix_id(SUNMatrix) { return SUNMATRIX_CUSTOM; }
static int seam_matrix_zero(SUNMatrix matrix) {
  static_cast<LinearSolver*>(matrix->content)->zero();
  return 0;
}
static void seam_matrix_destroy(SUNMatrix matrix) {
  matrix->content = nullptr;
  SUNMatFreeEmpty(matrix);
}

// The SUNLinearSolver that calls the seam: a direct solver (so KINSOL takes J p = -F as exact
// for its line search), set up by factorising, solving with the factors. Its content is the
// Problem of the current solve, rebound by every NewtonSolver::solve.
struct SeamContent {
  Problem* problem = nullptr;
  long last_flag = 0;
};
static SUNLinearSolver_Type seam_solver_type(SUNLinearSolver) { return SUNLINEARSOLVER_DIRECT; }
static SUNLinearSolver_ID seam_solver_id(SUNLinearSolver) { return SUNLINEARSOLVER_CUSTOM; }
static int seam_solver_initialize(SUNLinearSolver) { return SUNLS_SUCCESS; }
static int seam_solver_setup(SUNLinearSolver solver, SUNMatrix) {
  auto& content = *static_cast<SeamContent*>(solver->content);
  try {
    content.last_flag = content.problem->factorise();
  } catch (...) {
    content.problem->pending_exception = std::current_exception();
    content.last_flag = -1;
  }
  return static_cast<int>(content.last_flag);
}
static int seam_solver_solve(SUNLinearSolver solver, SUNMatrix, N_Vector x, N_Vector b, realtype) {
  auto& content = *static_cast<SeamContent*>(solver->content);
  LinearSolver& seam = content.problem->solver();
  try {
    Eigen::VectorXd& work = content.problem->solve_work();
    work = ConstVectorMap(N_VGetArrayPointer(b), seam.size());
    if (!seam.solve(work) || !work.allFinite()) {
      content.last_flag = SUNLS_PACKAGE_FAIL_UNREC;
      return SUNLS_PACKAGE_FAIL_UNREC;
    }
    Eigen::Map<VectorXd>(N_VGetArrayPointer(x), seam.size()) = work;
  } catch (...) {
    content.problem->pending_exception = std::current_exception();
    content.last_flag = SUNLS_PACKAGE_FAIL_UNREC;
    return SUNLS_PACKAGE_FAIL_UNREC;
  }
  content.last_flag = SUNLS_SUCCESS;
  return SUNLS_SUCCESS;
}
static sunindextype seam_solver_last_flag(SUNLinearSolver solver) {
  return static_cast<sunindextype>(static_cast<SeamContent*>(solver->content)->last_flag);
}
static int seam_solver_free(SUNLinearSolver solver) {
  if (solver == nullptr) return SUNLS_SUCCESS;
  solver->content = nullptr;  // owned by the adapter
  SUNLinSolFreeEmpty(solver);
  return SUNLS_SUCCESS;
}

static void kinsol_error_handler(int error_code, const char* module, const char* function, char* message,
                                 void* user_data) {
  if (user_data == nullptr) return;  // between solves, or during setup: the flag tells
  auto& problem = *static_cast<Problem*>(user_data);
  try {
    if (problem.kinsol_messages.size() < max_kinsol_messages)
      problem.kinsol_messages.push_back(fmt::format("{} in {}: {} [{}]", module ? module : "KINSOL",
                                                    function ? function : "?", message ? message : "",
                                                    flag_name(error_code)));
  } catch (...) {  // out of memory while reporting: drop the message
  }
}

}  // extern "C"

// Thrown by the adapter's constructor; becomes termination setup_failed.
struct SetupFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Owns every SUNDIALS handle of one NewtonSolver: created once, reused by every solve. Members
// are declared in creation order, so they are destroyed in reverse (KINSOL memory first, the
// context last), also when construction throws half-way.
class Kinsol {
 public:
  explicit Kinsol(LinearSolver& seam) {
    const int n = seam.size();
    SUNContext context = nullptr;
    if (SUNContext_Create(nullptr, &context) != 0 || context == nullptr) throw SetupFailure("SUNContext_Create failed");
    context_.reset(context);

    u_.reset(new_vector(n, "the unknowns"));
    u_scale_.reset(new_vector(n, "unknown_scale"));
    f_scale_.reset(new_vector(n, "residual_scale"));
    constraints_.reset(new_vector(n, "constraints"));

    SUNMatrix matrix = SUNMatNewEmpty(context_.get());
    if (!matrix) throw SetupFailure("SUNMatNewEmpty failed to allocate the Jacobian's stand-in");
    matrix_.reset(matrix);
    matrix->content = &seam;
    matrix->ops->getid = seam_matrix_id;
    matrix->ops->zero = seam_matrix_zero;
    matrix->ops->destroy = seam_matrix_destroy;

    SUNLinearSolver solver = SUNLinSolNewEmpty(context_.get());
    if (!solver) throw SetupFailure("SUNLinSolNewEmpty failed to allocate the linear solver");
    linear_solver_.reset(solver);
    solver->content = &content_;
    solver->ops->gettype = seam_solver_type;
    solver->ops->getid = seam_solver_id;
    solver->ops->initialize = seam_solver_initialize;
    solver->ops->setup = seam_solver_setup;
    solver->ops->solve = seam_solver_solve;
    solver->ops->lastflag = seam_solver_last_flag;
    solver->ops->free = seam_solver_free;

    kinsol_.reset(KINCreate(context_.get()));
    if (!kinsol_) throw SetupFailure("KINCreate failed");
    void* kin = kinsol_.get();
    check(KINSetErrHandlerFn(kin, kinsol_error_handler, nullptr), "KINSetErrHandlerFn");
    check(KINInit(kin, kinsol_residual, u_.get()), "KINInit");
    check(KINSetLinearSolver(kin, linear_solver_.get(), matrix_.get()), "KINSetLinearSolver");
    check(KINSetJacFn(kin, kinsol_jacobian), "KINSetJacFn");
    check(KINSetMaxSetupCalls(kin, 1), "KINSetMaxSetupCalls");  // a fresh Jacobian at every iterate
  }

  // Binds the solve's problem and options (cheap: no allocation).
  void configure(Problem& problem, const NewtonOptions& options) {
    void* kin = kinsol_.get();
    content_.problem = &problem;
    content_.last_flag = 0;
    fill(u_scale_.get(), options.unknown_scale);
    fill(f_scale_.get(), options.residual_scale);
    check(KINSetErrHandlerFn(kin, kinsol_error_handler, &problem), "KINSetErrHandlerFn");
    check(KINSetUserData(kin, &problem), "KINSetUserData");
    check(KINSetFuncNormTol(kin, options.residual_tolerance), "KINSetFuncNormTol");
    check(KINSetScaledStepTol(kin, options.step_tolerance), "KINSetScaledStepTol");
    check(KINSetNumMaxIters(kin, options.max_iterations), "KINSetNumMaxIters");
    check(KINSetMaxNewtonStep(kin, options.max_newton_step), "KINSetMaxNewtonStep");  // 0: KINSOL's default
    if (options.constraints.size() > 0) {
      fill(constraints_.get(), options.constraints.cast<double>());
      check(KINSetConstraints(kin, constraints_.get()), "KINSetConstraints");
    } else {
      check(KINSetConstraints(kin, nullptr), "KINSetConstraints");
    }
    strategy_ = options.globalisation == Globalisation::line_search ? KIN_LINESEARCH : KIN_NONE;
  }

  // Runs KINSol from x; x receives KINSOL's last iterate. Returns KINSOL's flag.
  int solve(VectorXd& x) {
    Eigen::Map<VectorXd>(N_VGetArrayPointer(u_.get()), x.size()) = x;
    const int flag = KINSol(kinsol_.get(), u_.get(), strategy_, u_scale_.get(), f_scale_.get());
    x = Eigen::Map<const VectorXd>(N_VGetArrayPointer(u_.get()), x.size());
    return flag;
  }

  // Unbinds the problem (it dies with the solve).
  void release() {
    content_.problem = nullptr;
    KINSetUserData(kinsol_.get(), nullptr);
    KINSetErrHandlerFn(kinsol_.get(), kinsol_error_handler, nullptr);
  }

  int iterations() const { return counter(KINGetNumNonlinSolvIters); }
  int backtracks() const { return counter(KINGetNumBacktrackOps); }
  // Column (1-based) of the zero pivot if the last factorisation failed, else 0.
  long zero_pivot_column() const { return content_.last_flag > 0 ? content_.last_flag : 0; }

 private:
  struct ContextDeleter {
    void operator()(SUNContext context) const { SUNContext_Free(&context); }
  };
  struct VectorDeleter {
    void operator()(N_Vector v) const { N_VDestroy(v); }
  };
  struct MatrixDeleter {
    void operator()(SUNMatrix m) const { SUNMatDestroy(m); }
  };
  struct SolverDeleter {
    void operator()(SUNLinearSolver s) const { SUNLinSolFree(s); }
  };
  struct KinsolDeleter {
    void operator()(void* kin) const { KINFree(&kin); }
  };
  using VectorHandle = std::unique_ptr<std::remove_pointer_t<N_Vector>, VectorDeleter>;

  N_Vector new_vector(int n, const char* what) const {
    N_Vector v = N_VNew_Serial(n, context_.get());
    if (v == nullptr) throw SetupFailure(fmt::format("N_VNew_Serial failed to allocate {}", what));
    return v;
  }
  static void fill(N_Vector v, const VectorXd& values) {
    auto data = Eigen::Map<VectorXd>(N_VGetArrayPointer(v), N_VGetLength(v));
    if (values.size() == 0)
      data.setOnes();
    else
      data = values;
  }
  static void check(int flag, const char* call) {
    if (flag != KIN_SUCCESS) throw SetupFailure(fmt::format("{} returned {}", call, flag_name(flag)));
  }
  int counter(int (*get)(void*, long*)) const {
    long value = -1;
    return get(kinsol_.get(), &value) == KIN_SUCCESS ? static_cast<int>(value) : -1;
  }

  SeamContent content_;
  // Creation order; destruction runs backwards.
  std::unique_ptr<std::remove_pointer_t<SUNContext>, ContextDeleter> context_;
  VectorHandle u_, u_scale_, f_scale_, constraints_;
  std::unique_ptr<std::remove_pointer_t<SUNMatrix>, MatrixDeleter> matrix_;
  std::unique_ptr<std::remove_pointer_t<SUNLinearSolver>, SolverDeleter> linear_solver_;
  std::unique_ptr<void, KinsolDeleter> kinsol_;
  int strategy_ = KIN_LINESEARCH;
};

std::atomic<long> kinsol_setups{0};

// What a KINSOL flag means for the user: the termination and a message in words.
struct Outcome {
  NewtonTermination termination;
  std::string message;
};

Outcome interpret(int flag, const NewtonSummary& s, const NewtonOptions& o, const Problem& problem,
                  long zero_pivot_column) {
  using T = NewtonTermination;
  const double r = s.final_residual, tol = o.residual_tolerance;
  switch (flag) {
    case KIN_SUCCESS:
    case KIN_INITIAL_GUESS_OK:
      return {T::converged, fmt::format("converged: residual {:.3e} <= residual_tolerance {:.3e} after {} iterations",
                                        r, tol, s.iterations)};
    case KIN_STEP_LT_STPTOL:
      if (r <= tol)
        return {T::converged, fmt::format("converged: residual {:.3e} <= residual_tolerance {:.3e} after {} "
                                          "iterations, when the scaled step fell below step_tolerance {:.3e}",
                                          r, tol, s.iterations, o.step_tolerance)};
      return {T::step_below_tolerance,
              fmt::format("stagnated: the scaled Newton step fell below step_tolerance {:.3e} with the residual {:.3e} "
                          "still above residual_tolerance {:.3e}; either the tolerance is below what round-off allows "
                          "for this F (loosen it, or scale F with residual_scale), or x sits near a singular point or "
                          "a minimum of |F| that is no root (check the Jacobian, start elsewhere)",
                          o.step_tolerance, r, tol)};
    case KIN_LINESEARCH_NONCONV:
      return {T::line_search_failed,
              fmt::format("line search failed: no point along the Newton direction reduces |F| enough (residual "
                          "{:.3e}); the Jacobian may not match the residual (check it against finite differences), "
                          "or the iterate is near a minimum of |F| that is no root: start closer to the solution",
                          r)};
    case KIN_LINESEARCH_BCFAIL:
      return {T::line_search_failed,
              fmt::format("line search failed: the steps repeatedly made too little progress (beta condition; "
                          "residual {:.3e}); the problem is badly scaled or the start far from a root: set "
                          "unknown_scale / residual_scale, or start closer",
                          r)};
    case KIN_MAXITER_REACHED:
      return {T::iteration_limit,
              fmt::format("iteration limit: max_iterations = {} reached with residual {:.3e} > residual_tolerance "
                          "{:.3e}; residual_history shows whether the iteration was still converging (raise "
                          "max_iterations) or stalling (start closer, check the Jacobian)",
                          o.max_iterations, r, tol)};
    case KIN_MXNEWT_5X_EXCEEDED:
      return {T::other_failure,
              fmt::format("diverging: five consecutive steps had the maximum length max_newton_step; the iterates run "
                          "away (no root in reach, or F is asymptotically flat); start closer, or raise "
                          "max_newton_step if such large steps are legitimate (residual {:.3e})",
                          r)};
    case KIN_LSETUP_FAIL:
      if (!problem.jacobian_problem().empty())
        return {T::linear_solver_failed,
                fmt::format("linear solver failed: {} (residual {:.3e})", problem.jacobian_problem(), r)};
      return {T::linear_solver_failed,
              fmt::format("linear solver failed: the Jacobian is singular (LU zero pivot in column {}) at an iterate "
                          "with residual {:.3e}; the equations are dependent there, an unknown does not enter F, "
                          "or x is at a limit point (continue past it with a bordered arc-length system)",
                          zero_pivot_column, r)};
    case KIN_LSOLVE_FAIL:
    case KIN_LINSOLV_NO_RECOVERY:
      return {T::linear_solver_failed,
              fmt::format("linear solver failed: the Newton system could not be solved with a current Jacobian "
                          "(residual {:.3e}); the Jacobian is singular or not finite",
                          r)};
    case KIN_SYSFUNC_FAIL:
      return {T::residual_failed,
              fmt::format("residual failed: the residual callback rejected a point tried while backtracking in the "
                          "line search ({} rejections in all); KINSOL tolerates an inadmissible point only as the "
                          "first trial of a step: keep iterates admissible with constraints, or bound the step with "
                          "max_newton_step",
                          problem.rejections())};
    case KIN_FIRST_SYSFUNC_ERR:
      return {T::residual_failed,
              "residual failed: the residual callback rejected the initial guess; start from an "
              "admissible point"};
    case KIN_REPTD_SYSFUNC_ERR:
      return {T::residual_failed,
              fmt::format("residual failed: the residual callback rejected five successive trial points of a Newton "
                          "step, the step halved each time ({} rejections in all); the iterate is at the edge of the "
                          "admissible set: keep iterates admissible with constraints, or start farther from it",
                          problem.rejections())};
    case KIN_MEM_NULL:
    case KIN_ILL_INPUT:
    case KIN_NO_MALLOC:
    case KIN_MEM_FAIL:
    case KIN_LINIT_FAIL:
    case KIN_CONTEXT_ERR:
      return {T::setup_failed, "setup failed: KINSOL refused its input or ran out of memory"};
    default:
      return {T::other_failure, fmt::format("KINSOL failed with an unexpected flag (residual {:.3e})", r)};
  }
}

std::string with_flag(std::string message, int flag, const std::vector<std::string>& kinsol_messages) {
  message += fmt::format(" ({})", flag_name(flag));
  if (!kinsol_messages.empty()) message += fmt::format("; KINSOL said: {}", fmt::join(kinsol_messages, " | "));
  return message;
}

void check_initial_guess(const VectorXd& x, const NewtonOptions& options) {
  if (!x.allFinite()) throw std::invalid_argument("solve_newton: the initial guess x contains NaN or Inf");
  for (Eigen::Index i = 0; i < options.constraints.size(); ++i) {
    const int c = options.constraints(i);
    const double xi = x(i);
    const bool ok =
        c == 0 || (c == 1 && xi >= 0.0) || (c == 2 && xi > 0.0) || (c == -1 && xi <= 0.0) || (c == -2 && xi < 0.0);
    if (!ok) {
      static constexpr std::string_view meaning[] = {"x < 0", "x <= 0", "free", "x >= 0", "x > 0"};
      throw std::invalid_argument(
          fmt::format("solve_newton: the initial guess violates the constraints: x({}) = {} but constraints({}) = {} "
                      "({}); start from a point that satisfies them",
                      i, xi, i, c, meaning[c + 2]));
    }
  }
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

void NewtonOptions::validate(int n) const {
  const auto positive = [](const char* field, double value) {
    if (!(std::isfinite(value) && value > 0.0))
      throw std::invalid_argument(fmt::format("NewtonOptions.{}: expected a finite number > 0, got {}", field, value));
  };
  positive("residual_tolerance", residual_tolerance);
  positive("step_tolerance", step_tolerance);
  if (max_iterations < 1)
    throw std::invalid_argument(fmt::format("NewtonOptions.max_iterations: expected >= 1, got {}", max_iterations));
  if (!(std::isfinite(max_newton_step) && max_newton_step >= 0.0))
    throw std::invalid_argument(fmt::format(
        "NewtonOptions.max_newton_step: expected a finite number >= 0 (0: KINSOL's default), got {}", max_newton_step));
  if (globalisation != Globalisation::line_search && globalisation != Globalisation::none)
    throw std::invalid_argument(fmt::format("NewtonOptions.globalisation: expected line_search or none, got {}",
                                            static_cast<int>(globalisation)));
  const auto scale = [n](const char* field, const VectorXd& s) {
    if (s.size() == 0) return;
    if (s.size() != n)
      throw std::invalid_argument(fmt::format(
          "NewtonOptions.{}: expected empty or size {} (the number of unknowns), got size {}", field, n, s.size()));
    for (Eigen::Index i = 0; i < n; ++i)
      if (!(std::isfinite(s(i)) && s(i) > 0.0))
        throw std::invalid_argument(
            fmt::format("NewtonOptions.{}({}): expected a finite number > 0, got {}", field, i, s(i)));
  };
  scale("unknown_scale", unknown_scale);
  scale("residual_scale", residual_scale);
  if (constraints.size() == 0) return;
  if (constraints.size() != n)
    throw std::invalid_argument(
        fmt::format("NewtonOptions.constraints: expected empty or size {} (the number of unknowns), got size {}", n,
                    constraints.size()));
  for (Eigen::Index i = 0; i < n; ++i)
    if (constraints(i) < -2 || constraints(i) > 2)
      throw std::invalid_argument(
          fmt::format("NewtonOptions.constraints({}): expected one of -2, -1, 0, 1, 2 (KINSOL's codes), got {}", i,
                      constraints(i)));
}

namespace {
constexpr EnumName<Globalisation> globalisation_names[] = {
    {Globalisation::line_search, "line_search"},
    {Globalisation::none, "none"},
};
}  // namespace

std::string_view to_string(Globalisation g) { return name_in<Globalisation>(globalisation_names, g); }

namespace {
constexpr EnumName<NewtonTermination> newton_termination_names[] = {
    {NewtonTermination::converged, "converged"},
    {NewtonTermination::step_below_tolerance, "step_below_tolerance"},
    {NewtonTermination::line_search_failed, "line_search_failed"},
    {NewtonTermination::iteration_limit, "iteration_limit"},
    {NewtonTermination::linear_solver_failed, "linear_solver_failed"},
    {NewtonTermination::residual_failed, "residual_failed"},
    {NewtonTermination::setup_failed, "setup_failed"},
    {NewtonTermination::other_failure, "other_failure"},
};
}  // namespace

std::string_view to_string(NewtonTermination t) { return name_in<NewtonTermination>(newton_termination_names, t); }

std::string NewtonSummary::brief_report() const {
  return fmt::format(
      "newton: {} after {} iterations ({} residual, {} Jacobian evaluations, {} backtracks); residual {:.2e}; "
      "{:.3f} ms",
      to_string(termination), iterations, residual_evaluations, jacobian_evaluations, backtracks, final_residual,
      time_s * 1e3);
}

struct NewtonSolver::Impl {
  explicit Impl(LinearSolver& seam) : solver(seam) {
    try {
      kinsol = std::make_unique<Kinsol>(seam);
      ++kinsol_setups;
      ++setups;
    } catch (const SetupFailure& failure) {
      setup_failure = failure.what();
    }
  }
  LinearSolver& solver;
  std::unique_ptr<Kinsol> kinsol;
  std::string setup_failure;
  int setups = 0, solves = 0;
};

NewtonSolver::NewtonSolver(LinearSolver& linear_solver) : impl_(std::make_unique<Impl>(linear_solver)) {}
NewtonSolver::~NewtonSolver() = default;
NewtonSolver::NewtonSolver(NewtonSolver&&) noexcept = default;
NewtonSolver& NewtonSolver::operator=(NewtonSolver&&) noexcept = default;

LinearSolver& NewtonSolver::linear_solver() const { return impl_->solver; }
int NewtonSolver::size() const { return impl_->solver.size(); }
int NewtonSolver::setups() const { return impl_->setups; }
int NewtonSolver::solves() const { return impl_->solves; }
long NewtonSolver::total_setups() { return kinsol_setups.load(); }

NewtonSummary NewtonSolver::solve(const Residual& residual, const JacobianFill& jacobian, VectorXd& x,
                                  const NewtonOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  if (!residual || !jacobian) throw std::invalid_argument("solve_newton: the residual or Jacobian callback is empty");
  if (x.size() == 0) throw std::invalid_argument("solve_newton: the initial guess x is empty");
  const int n = static_cast<int>(x.size());
  if (n != size())
    throw std::invalid_argument(
        fmt::format("NewtonSolver::solve: x has size {}, but the linear solver was set up for {} unknowns", n, size()));
  options.validate(n);
  check_initial_guess(x, options);
  ++impl_->solves;

  NewtonSummary summary;
  Problem problem(residual, jacobian, impl_->solver,
                  options.residual_scale.size() ? options.residual_scale : VectorXd(VectorXd::Ones(n)));
  const auto finish = [&](NewtonTermination termination, std::string message, int flag) {
    summary.termination = termination;
    summary.message = with_flag(std::move(message), flag, problem.kinsol_messages);
    summary.residual_evaluations = problem.residual_calls();
    summary.jacobian_evaluations = problem.jacobian_calls();
    summary.residual_history = std::move(problem.history());
    summary.time_s = seconds_since(start);
    return summary;
  };

  // 1. The initial guess, tested against residual_tolerance itself.
  VectorXd f0(n);
  if (problem.residual(x.data(), f0.data()) != 0) {
    summary.iterations = summary.backtracks = 0;
    summary.final_residual = infinity;
    return finish(NewtonTermination::residual_failed,
                  "residual failed: the residual callback rejected the initial guess (or returned NaN or Inf); "
                  "start from an admissible point",
                  KIN_FIRST_SYSFUNC_ERR);
  }
  const double r0 = problem.scaled_norm(f0.data());
  problem.record(x.data(), r0);
  if (r0 <= options.residual_tolerance) {
    summary.iterations = summary.backtracks = 0;
    summary.final_residual = r0;
    return finish(NewtonTermination::converged,
                  fmt::format("converged: the initial guess already satisfies residual_tolerance {:.3e} (residual "
                              "{:.3e}); no iteration taken",
                              options.residual_tolerance, r0),
                  KIN_INITIAL_GUESS_OK);
  }
  problem.cache_initial(x, f0);

  // 2. KINSOL, set up once by the constructor and bound to this solve's problem and options. A
  //    callback's exception is rethrown only here, after the C frames are gone; x is assigned
  //    only once everything that may throw has run.
  const auto setup_failed = [&](const std::string& why) {
    summary.iterations = summary.backtracks = 0;
    summary.final_residual = r0;
    return finish(NewtonTermination::setup_failed, fmt::format("setup failed: {}; KINSOL could not be configured", why),
                  KIN_MEM_FAIL);
  };
  if (!impl_->kinsol) return setup_failed(impl_->setup_failure);
  Kinsol& kinsol = *impl_->kinsol;
  struct Release {  // the problem dies with this solve: unbind it on every path
    Kinsol& kinsol;
    ~Release() { kinsol.release(); }
  } release{kinsol};
  try {
    kinsol.configure(problem, options);
  } catch (const SetupFailure& failure) {
    return setup_failed(failure.what());
  }
  VectorXd x_final = x;
  const int flag = kinsol.solve(x_final);
  if (problem.pending_exception) std::rethrow_exception(problem.pending_exception);
  summary.iterations = kinsol.iterations();
  summary.backtracks = kinsol.backtracks();

  // 3. The residual at the returned x, and the last history entry.
  if (const VectorXd* last_f = problem.last_residual_at(x_final.data())) {
    summary.final_residual = problem.scaled_norm(last_f->data());
  } else {
    VectorXd f(n);
    summary.final_residual = problem.residual(x_final.data(), f.data()) == 0 ? problem.scaled_norm(f.data()) : infinity;
  }
  if (std::isfinite(summary.final_residual)) problem.record(x_final.data(), summary.final_residual);
  x = x_final;

  Outcome outcome = interpret(flag, summary, options, problem, kinsol.zero_pivot_column());
  return finish(outcome.termination, std::move(outcome.message), flag);
}

NewtonSummary solve_newton(const Residual& residual, const Jacobian& jacobian, VectorXd& x,
                           const NewtonOptions& options) {
  if (!residual || !jacobian) throw std::invalid_argument("solve_newton: the residual or Jacobian callback is empty");
  if (x.size() == 0) throw std::invalid_argument("solve_newton: the initial guess x is empty");
  const int n = static_cast<int>(x.size());
  DenseLu lu(n);
  NewtonSolver newton(lu);
  const JacobianFill fill = [&](const VectorXd& z, const VectorXd& f) {
    MatrixXd& matrix = lu.matrix();
    const bool accepted = jacobian(z, f, matrix);
    if (matrix.rows() != n || matrix.cols() != n)
      throw std::invalid_argument(fmt::format(
          "solve_newton: the Jacobian callback resized the matrix from {0}x{0} to {1}x{2}; it must keep the size", n,
          matrix.rows(), matrix.cols()));
    return accepted;
  };
  return newton.solve(residual, fill, x, options);
}

}  // namespace liftoff::nonlinear
