#include "lcp/lemke.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace liftoff::lcp {

namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

constexpr double eps = std::numeric_limits<double>::epsilon();
// Ratios (and lexicographic entries) closer than this, relative to their round-off scale, are
// treated as tied. The updated xB drifts slowly (measured |q - B xB| relative: 1e-15 after
// 1600 pivots for well-conditioned M, ~1e-12 for cond(M) = 1e12, ~1e-9 at 1e15, n = 300),
// while genuinely different ratios of a well-posed problem differ by far more. Refactorising
// the basis every ~50 pivots was tried: it cut that drift 100-fold but changed no outcome
// (the final polish removes the drift from the answer) and cost up to 5x time, so it is not done.
constexpr double tie_tolerance = 1e-11;
// A complementary basis whose best (z, w) has a residual above this is no solution: the
// pivoting lost accuracy. Generous, as a degenerate z_i of an ill-conditioned block may come
// out as -cond * eps; far above that, the active set itself is wrong.
constexpr double acceptable_residual = 1e-6;

// The basis of  w - M z - d z0 = q  (scaled data, d = ones). Variables are numbered
// w_i = i, z_j = n + j, z0 = 2n; basis[row] is the variable of that row of the basis inverse.
class Basis {
 public:
  Basis(const MatrixXd& M, const VectorXd& q)
      : M_(M),
        n_(static_cast<int>(q.size())),
        basis_(n_),
        row_of_(2 * n_ + 1, -1),
        basis_inverse_(MatrixXd::Identity(n_, n_)),
        xB_(q) {
    for (int i = 0; i < n_; ++i) {  // all-slack start: B = I
      basis_[i] = i;
      row_of_[i] = i;
    }
  }

  int n() const { return n_; }
  int z0() const { return 2 * n_; }
  int complement(int v) const { return v < n_ ? v + n_ : v - n_; }
  int variable(int row) const { return basis_[row]; }
  int row_of(int v) const { return row_of_[v]; }
  const VectorXd& xB() const { return xB_; }
  const MatrixXd& basis_inverse() const { return basis_inverse_; }

  // B^-1 times the column of v: how the basic variables fall as v rises (O(n^2)).
  VectorXd entering_column(int v) const {
    if (v < n_) return basis_inverse_.col(v);
    if (v < 2 * n_) return -(basis_inverse_ * M_.col(v - n_));
    return -basis_inverse_.rowwise().sum();
  }

  // Product-form update: `entering` replaces the variable of `row`; a = B^-1 column(entering).
  void pivot(int row, int entering, const VectorXd& a) {
    const double pivot_element = a(row);
    const Eigen::RowVectorXd pivot_row = basis_inverse_.row(row) / pivot_element;
    const double x_row = xB_(row) / pivot_element;
    VectorXd multipliers = a;
    multipliers(row) = 0.0;
    basis_inverse_.noalias() -= multipliers * pivot_row;  // rank one, O(n^2)
    xB_ -= multipliers * x_row;
    basis_inverse_.row(row) = pivot_row;
    xB_(row) = x_row;
    row_of_[basis_[row]] = -1;
    basis_[row] = entering;
    row_of_[entering] = row;
  }

 private:
  const MatrixXd& M_;
  int n_;
  std::vector<int> basis_;
  std::vector<int> row_of_;
  MatrixXd basis_inverse_;
  VectorXd xB_;
};

// Lexicographic minimum-ratio test. Candidates are rows with a_i > threshold; the plain
// minimum ratio xB_i / a_i is found first, then ties are broken by z0 (leave at once) and
// finally by the rows of B^-1 / a_i, which are linearly independent, so exactly one row
// remains in exact arithmetic and the basis stays lexicographically positive (no cycling).
// Returns -1 when no row blocks: ray termination.
int blocking_row(const Basis& basis, const VectorXd& a, double threshold) {
  const int n = basis.n();
  const VectorXd& xB = basis.xB();
  double theta = std::numeric_limits<double>::infinity();
  for (int i = 0; i < n; ++i)
    if (a(i) > threshold) theta = std::min(theta, xB(i) / a(i));
  if (!std::isfinite(theta)) return -1;

  const double x_scale = xB.cwiseAbs().maxCoeff();
  std::vector<int> tied;
  for (int i = 0; i < n; ++i)
    if (a(i) > threshold && xB(i) / a(i) - theta <= tie_tolerance * (std::abs(theta) + x_scale / a(i)))
      tied.push_back(i);
  if (tied.size() == 1) return tied.front();
  const int z0_row = basis.row_of(basis.z0());
  if (std::find(tied.begin(), tied.end(), z0_row) != tied.end()) return z0_row;

  const MatrixXd& basis_inverse = basis.basis_inverse();
  double lex_scale = 0.0;
  for (int i : tied) lex_scale = std::max(lex_scale, basis_inverse.row(i).cwiseAbs().maxCoeff() / a(i));
  for (int j = 0; j < n && tied.size() > 1; ++j) {
    double lowest = std::numeric_limits<double>::infinity();
    for (int i : tied) lowest = std::min(lowest, basis_inverse(i, j) / a(i));
    std::erase_if(tied, [&](int i) { return basis_inverse(i, j) / a(i) > lowest + tie_tolerance * lex_scale; });
  }
  // Still several only if round-off hides the difference: take the largest pivot.
  return *std::max_element(tied.begin(), tied.end(), [&](int i, int k) { return a(i) < a(k); });
}

struct Residuals {
  double feasibility = 0.0, complementarity = 0.0, equation = 0.0;
  double worst() const { return std::max({feasibility, complementarity, equation}); }
};

// D_ii = 1/sqrt|M_ii| rounded to a power of two (1 where M_ii = 0): D M D and D q are then
// exact, so the scaled problem is the original data, only better balanced.
VectorXd diagonal_scaling(const MatrixXd& M) {
  VectorXd D = VectorXd::Ones(M.rows());
  for (Eigen::Index i = 0; i < M.rows(); ++i)
    if (M(i, i) != 0.0) D(i) = std::ldexp(1.0, static_cast<int>(std::lround(-0.5 * std::log2(std::abs(M(i, i))))));
  return D;
}

// Residuals as documented in lemke.hpp: those of y = D^-1 z, v = D w in the diagonally scaled
// LCP (Ms = D M D, qs = D q), so that a stiff row cannot hide the error of a flexible one.
Residuals residuals(const MatrixXd& Ms, const VectorXd& qs, const VectorXd& D, const VectorXd& z, const VectorXd& w) {
  Residuals r;
  if (qs.size() == 0) return r;
  const VectorXd y = z.cwiseQuotient(D), v = w.cwiseProduct(D);
  const double y_norm = y.cwiseAbs().maxCoeff();
  double scale = std::max(qs.cwiseAbs().maxCoeff(), Ms.cwiseAbs().rowwise().sum().maxCoeff() * y_norm);
  if (!(scale > 0.0)) scale = 1.0;
  const double y_scale = y_norm > 0.0 ? y_norm : 1.0;
  r.feasibility = std::max({0.0, (-y).maxCoeff() / y_scale, (-v).maxCoeff() / scale});
  r.complementarity = y.cwiseProduct(v).cwiseAbs().maxCoeff() / (scale * y_scale);
  r.equation = (v - qs - Ms * y).cwiseAbs().maxCoeff() / scale;
  return r;
}

// Why a ray is not a proof of infeasibility, or "" if it is one. The proof (Farkas): dz >= 0 with
// M^T dz <= 0 and q^T dz < 0 leaves no z >= 0 with w = q + M z >= 0, since then
// 0 <= dz^T w = q^T dz + (M^T dz)^T z < 0. Lemke's secondary ray of a copositive-plus M has
// dz0 = 0 and M^T dz = -M dz <= 0 in exact arithmetic; in floating point each condition is
// checked against the round-off of its own terms, in the scaled units (y = D^-1 dz). Entering
// columns computed from an ill-conditioned basis can show "no blocking row" where exact
// arithmetic has one: such false rays (seen on the primal LCP of a floating footing, issue 10)
// violate M^T dz <= 0 by the full size of its terms, where a true ray is at ~1e-12.
std::string ray_defect(const MatrixXd& Ms, const VectorXd& qs, const VectorXd& D, const VectorXd& ray) {
  const Eigen::Index n = qs.size();
  const VectorXd y = ray.head(n).cwiseQuotient(D);
  const double y_norm = y.cwiseAbs().maxCoeff();
  if (!(y_norm > 0.0)) return "its z part is zero";
  if (std::abs(ray(n)) > acceptable_residual * ray.cwiseAbs().maxCoeff())
    return fmt::format("the artificial variable moves along it, dz0 = {:.1e}", ray(n));
  const VectorXd transposed = Ms.transpose() * y, magnitude = Ms.cwiseAbs().transpose() * y.cwiseAbs();
  const double floor = eps * magnitude.maxCoeff();
  double worst = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) worst = std::max(worst, transposed(i) / (magnitude(i) + floor));
  if (worst > acceptable_residual) return fmt::format("M^T dz <= 0 fails by {:.1e} of its terms", worst);
  const double q_dot = qs.dot(y), q_magnitude = qs.cwiseAbs().dot(y.cwiseAbs());
  if (!(q_dot < -acceptable_residual * q_magnitude))
    return fmt::format("q^T dz = {:.1e} is not clearly negative (terms {:.1e})", q_dot, q_magnitude);
  return "";
}

std::string variable_name(int v, int n) {
  if (v == 2 * n) return "z0";
  return fmt::format("{}_{}", v < n ? 'w' : 'z', v < n ? v : v - n);
}

}  // namespace

void LemkeOptions::validate() const {
  if (!(std::isfinite(pivot_tolerance) && pivot_tolerance > 0.0 && pivot_tolerance < 1.0))
    throw std::invalid_argument(
        fmt::format("LemkeOptions.pivot_tolerance: expected a finite number in (0, 1), got {}", pivot_tolerance));
}

namespace {
constexpr EnumName<LemkeTermination> lemke_termination_names[] = {
    {LemkeTermination::solution, "solution"},
    {LemkeTermination::ray, "ray"},
    {LemkeTermination::pivot_limit, "pivot_limit"},
    {LemkeTermination::numerical_failure, "numerical_failure"},
};
}  // namespace

std::string_view to_string(LemkeTermination t) { return name_in<LemkeTermination>(lemke_termination_names, t); }

std::string LemkeSummary::brief_report() const {
  return fmt::format(
      "lemke: {} after {} pivots; residuals: feasibility {:.2e}, complementarity {:.2e}, "
      "equation {:.2e}; {:.3f} ms",
      to_string(termination), pivots, feasibility_residual, complementarity_residual, equation_residual, time_s * 1e3);
}

LemkeResult solve_lemke(const MatrixXd& M, const VectorXd& q, const LemkeOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  options.validate();
  if (M.rows() != q.size() || M.cols() != q.size())
    throw std::invalid_argument(fmt::format(
        "solve_lemke: M is {}x{} but q has size {}; M must be square of the size of q", M.rows(), M.cols(), q.size()));
  if (!M.allFinite()) throw std::invalid_argument("solve_lemke: M contains NaN or Inf");
  if (!q.allFinite()) throw std::invalid_argument("solve_lemke: q contains NaN or Inf");

  const int n = static_cast<int>(q.size());
  const int max_pivots = options.max_pivots > 0 ? options.max_pivots : 10 * (n + 1);
  LemkeResult result;
  LemkeSummary& summary = result.summary;
  // The scaled problem serves the residuals and the polish always, the pivoting if asked.
  const VectorXd D_exact = diagonal_scaling(M);
  const MatrixXd M_scaled = D_exact.asDiagonal() * M * D_exact.asDiagonal();
  const VectorXd q_scaled = D_exact.cwiseProduct(q);
  auto finish = [&](LemkeTermination termination, std::string message, int pivots) {
    const Residuals r = residuals(M_scaled, q_scaled, D_exact, result.z, result.w);
    summary.termination = termination;
    summary.message = std::move(message);
    summary.pivots = pivots;
    summary.feasibility_residual = r.feasibility;
    summary.complementarity_residual = r.complementarity;
    summary.equation_residual = r.equation;
    summary.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
  };

  if (n == 0 || q.minCoeff() >= 0.0) {  // the slack basis is complementary: z = 0
    result.z = VectorXd::Zero(n);
    result.w = q;
    return finish(LemkeTermination::solution, "q >= 0: z = 0 solves the LCP without pivots", 0);
  }

  // Symmetric scaling y = D^-1 z: w' = D w = D q + (D M D) y keeps the LCP's structure.
  const VectorXd D = options.equilibrate ? D_exact : VectorXd::Ones(n);
  const MatrixXd& Ms = options.equilibrate ? M_scaled : M;
  const VectorXd& qs = options.equilibrate ? q_scaled : q;
  Basis basis(Ms, qs);
  // The z-part of the current vertex in original units, and its w-part (which includes z0's
  // contribution until z0 leaves).
  auto set_vertex = [&] {
    result.z = VectorXd::Zero(n);
    result.w = VectorXd::Zero(n);
    result.basic_z.clear();
    for (int row = 0; row < n; ++row) {
      const int v = basis.variable(row);
      if (v < n) {
        result.w(v) = basis.xB()(row) / D(v);
      } else if (v < 2 * n) {
        result.z(v - n) = basis.xB()(row) * D(v - n);
        result.basic_z.push_back(v - n);
      }
    }
    std::sort(result.basic_z.begin(), result.basic_z.end());
  };

  // First pivot: z0 enters with column -d (a = -1 as B = I) and z0 = -min q. The leaving row
  // is the lexicographic minimum of [q_i, e_i]: the most negative q_i, the last index on a tie.
  int first_row = 0;
  const double q_min = qs.minCoeff();
  for (int i = 0; i < n; ++i)
    if (qs(i) <= q_min + tie_tolerance * std::abs(q_min)) first_row = i;
  basis.pivot(first_row, basis.z0(), -VectorXd::Ones(n));
  int pivots = 1;
  int entering = basis.complement(first_row);

  while (true) {
    if (pivots >= max_pivots) {
      set_vertex();
      return finish(LemkeTermination::pivot_limit,
                    fmt::format("pivot limit of {} reached before z0 left the basis (z0 = {:.3e}); "
                                "the last vertex is not a solution",
                                max_pivots, basis.xB()(basis.row_of(basis.z0()))),
                    pivots);
    }
    const VectorXd a = basis.entering_column(entering);
    if (!a.allFinite()) {
      set_vertex();
      return finish(LemkeTermination::numerical_failure,
                    fmt::format("NaN or Inf in the column of {} after {} pivots", variable_name(entering, n), pivots),
                    pivots);
    }
    // Entries below the pivot tolerance, relative to the column, count as zero: they neither
    // block nor serve as a pivot. (A floor from |B^-1| |column| was tried and rejected: on
    // ill-conditioned positive definite M it discarded genuine pivots and reported false rays.)
    const double threshold = options.pivot_tolerance * a.cwiseAbs().maxCoeff();
    const int row = blocking_row(basis, a, threshold);

    if (row < 0) {
      // Secondary ray: the entering variable rises by t, basic variables change by -t a_i,
      // all >= 0 (entries below the threshold count as zero). Keep the (z, z0) part.
      set_vertex();
      result.ray = VectorXd::Zero(n + 1);
      auto add = [&](int v, double rate) {
        if (v >= n && v < 2 * n)
          result.ray(v - n) = rate * D(v - n);
        else if (v == basis.z0())
          result.ray(n) = rate;
      };
      add(entering, 1.0);
      for (int i = 0; i < n; ++i) add(basis.variable(i), std::max(0.0, -a(i)));
      if (const double largest = result.ray.cwiseAbs().maxCoeff(); largest > 0.0) result.ray /= largest;
      // A ray is a claim that no solution exists: it is returned only as a checked proof.
      if (const std::string defect = ray_defect(M_scaled, q_scaled, D_exact, result.ray); !defect.empty()) {
        result.ray.resize(0);
        return finish(LemkeTermination::numerical_failure,
                      fmt::format("the entering variable {} had no blocking row after {} pivots, but the ray is no "
                                  "proof that the LCP has no solution ({}): the pivoting lost accuracy",
                                  variable_name(entering, n), pivots, defect),
                      pivots);
      }
      return finish(LemkeTermination::ray,
                    fmt::format("ray termination after {} pivots: the LCP has no solution (for "
                                "copositive-plus M); entering variable {} has no blocking row",
                                pivots, variable_name(entering, n)),
                    pivots);
    }

    const int leaving = basis.variable(row);
    basis.pivot(row, entering, a);
    ++pivots;
    if (!basis.xB().allFinite()) {
      set_vertex();
      return finish(LemkeTermination::numerical_failure,
                    fmt::format("NaN or Inf in the basic solution after {} pivots", pivots), pivots);
    }
    if (leaving == basis.z0()) break;
    entering = basis.complement(leaving);
  }

  // z0 left: the basis is complementary (right or wrong: the caller may check its set).
  // Polish: solve M_aa z_a = -q_a afresh, so the answer does not carry the round-off of the
  // pivots. The LU is of the exactly scaled block
  // (D M D)_aa, i.e. of the original data, balanced so that rcond means something.
  set_vertex();
  result.complementary = true;
  const Residuals pivoted = residuals(M_scaled, q_scaled, D_exact, result.z, result.w);
  const std::vector<int>& alpha = result.basic_z;
  std::string polish_note = "polished by a fresh LU of M on the final basic set";
  VectorXd z_polished = VectorXd::Zero(n);
  bool singular = false;
  if (!alpha.empty()) {
    const Eigen::PartialPivLU<MatrixXd> lu(M_scaled(alpha, alpha));
    singular = !(lu.rcond() > eps);
    if (!singular) {
      const VectorXd z_alpha = D_exact(alpha).cwiseProduct(lu.solve(VectorXd(-q_scaled(alpha))));
      z_polished(alpha) = z_alpha;
    }
  }
  const VectorXd w_polished = q + M * z_polished;
  if (singular || !z_polished.allFinite()) {
    polish_note = "the final basic block of M is singular; kept the pivoted vertex";
  } else if (residuals(M_scaled, q_scaled, D_exact, z_polished, w_polished).worst() > pivoted.worst()) {
    polish_note = "polishing did not reduce the residuals; kept the pivoted vertex";
  } else {
    result.z = z_polished;
    result.w = w_polished;
  }
  if (const double worst = residuals(M_scaled, q_scaled, D_exact, result.z, result.w).worst();
      !(worst <= acceptable_residual))
    return finish(
        LemkeTermination::numerical_failure,
        fmt::format("z0 left the basis after {} pivots, but the complementary basis "
                    "leaves a residual of {:.1e} (> {:.0e}): the pivoting lost accuracy{}",
                    pivots, worst, acceptable_residual, options.equilibrate ? "" : "; try equilibrate = true"),
        pivots);
  return finish(LemkeTermination::solution,
                fmt::format("solution after {} pivots ({} of {} z basic); {}", pivots, alpha.size(), n, polish_note),
                pivots);
}

}  // namespace liftoff::lcp

namespace liftoff {
template <>
std::optional<lcp::LemkeTermination> from_string(std::string_view name) {
  return value_in<lcp::LemkeTermination>(lcp::lemke_termination_names, name);
}
}  // namespace liftoff
