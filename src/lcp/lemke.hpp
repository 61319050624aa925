#pragma once
// Lemke's complementary pivoting algorithm for the linear complementarity problem
//
//   find z such that  w = q + M z,  w >= 0,  z >= 0,  w^T z = 0.
//
// Scheme 1 of Cottle, Pang & Stone (1992, sec. 4.4): an artificial variable z0 with a covering
// vector d > 0 makes the all-slack basis feasible; complementary pivots follow until z0 leaves
// the basis (a solution) or the entering column has no blocking row (ray termination). The
// minimum-ratio test breaks ties lexicographically on the rows of the basis inverse, so a
// degenerate problem cannot cycle. The basis inverse is kept dense and updated in place; the
// final complementary basis is refactorised once and solved afresh ("polishing"), so the answer
// is accurate to round-off whatever the number of pivots.
//
// Lemke processes every LCP whose M is copositive-plus (for instance positive semidefinite, as
// both of liftoff's contact formulations are): for those, ray termination proves that the LCP
// has no solution, and the ray is returned as the certificate, after it has been checked as
// one (dz >= 0, M^T dz <= 0, q^T dz < 0, each against the round-off of its terms); a ray that
// fails the check is a numerical_failure.
//
// Limits of double precision. Each pivot is decided on an entering column B^-1 m computed in
// floating point, whose entries carry errors of about cond(B) eps relative to its largest. When
// the bases are ill-conditioned (the primal contact LCP holds the stiffness K, cond ~ N^4: 1e10
// to 1e12 at 200 elements on a soft foundation), entries of 1e-7 .. 1e-10 relative are noise,
// yet the ratio test must use them: the path then ends at a wrong complementary basis or a false
// ray. Refactorising the basis does not help (measured on issue 10's footing: a fresh inverse
// every 100 pivots changed a wrong basis into a false ray), nor do larger pivot tolerances or
// largest-pivot tie-breaking: the noise is in the bases, not in the updates. Hence the check of
// rays, `complementary`, and the contact solver's check of the final contact set.

#include <Eigen/Dense>
#include <string>
#include <string_view>
#include <vector>

#include "core/enum_names.hpp"

namespace liftoff::lcp {

struct LemkeOptions {
  // Pivot limit; a value <= 0 means 10 * (n + 1).
  int max_pivots = 0;
  // An entry of the entering column counts as positive (a candidate blocking row) above this,
  // relative to the column's largest entry. Must lie in (0, 1).
  double pivot_tolerance = 1e-12;
  // Symmetric diagonal scaling D M D, D q (D_ii = 1/sqrt|M_ii| rounded to a power of two, so
  // the scaling is exact; 1 where M_ii = 0) before pivoting. It preserves the solution set and
  // makes badly scaled problems (stiffness next to flexibility) tractable. The residuals and
  // the final polish use this scaling whatever the option (see LemkeSummary).
  bool equilibrate = true;
  // Throws std::invalid_argument naming the field if a value is meaningless.
  void validate() const;
};

enum class LemkeTermination {
  solution,           // z0 left the basis: (z, w) solves the LCP; residuals below say how well
  ray,                // no blocking row for the entering column: the LCP has no solution (for
                      // copositive-plus M); `ray` holds the direction, z stays at the last vertex
  pivot_limit,        // max_pivots reached; z is the last (artificial) vertex, not a solution
  numerical_failure,  // NaN appeared, or z0 left but the complementary basis does not solve
                      // the LCP (a residual above 1e-6: accuracy lost; `complementary` is
                      // set), or a ray failed its check as a proof of infeasibility; z is not
                      // a solution
};
std::string_view to_string(LemkeTermination);

struct LemkeSummary {
  LemkeTermination termination = LemkeTermination::numerical_failure;
  std::string message;  // what happened, in words
  int pivots = -1;      // complementary pivots taken (the first z0 pivot counts)
  // Residuals of the returned (z, w), evaluated with the original M and q but in diagonally
  // scaled units, so that a stiff row cannot hide the error of a flexible one: with D as for
  // LemkeOptions::equilibrate (computed whether or not pivoting used it),
  //   Ms = D M D, qs = D q, y = D^-1 z, v = D w   (v = qs + Ms y for an exact solution),
  //   s  = max(|qs|_inf, |Ms|_inf |y|_inf)   (|.|_inf of a matrix: largest absolute row sum;
  //                                           s = 1 if that is 0),
  //   sy = |y|_inf                           (1 if y = 0),
  // they are dimensionless, invariant under q -> c q, M -> c M and any positive diagonal
  // rescaling of the problem, and of order eps for a solution accurate to round-off.
  // They are backward errors, relative to |M||z| rather than to q: where z is large in a
  // direction M (nearly) annihilates, they cannot see an error that is large against q. (The
  // primal contact LCP of a member only the foundation holds: z carries its rigid motion, and
  // |M||z| ~ 1e7 |q| for the footing of issue 10, so a violation of 3.5 % of the loads showed as
  // 2.7e-11.) A caller that knows what the rows mean must check the answer in those terms:
  // contact_solver.cpp re-solves the final contact set and checks its signs.
  double feasibility_residual = -1.0;      // max(0, max_i(-y_i) / sy, max_i(-v_i) / s)
  double complementarity_residual = -1.0;  // max_i |y_i v_i| / (s sy)   (y_i v_i = z_i w_i)
  double equation_residual = -1.0;         // |v - qs - Ms y|_inf / s
  double time_s = -1.0;
  bool is_usable() const { return termination == LemkeTermination::solution; }
  std::string brief_report() const;  // one line
};

struct LemkeResult {
  Eigen::VectorXd z;
  Eigen::VectorXd w;
  // On ray termination: the direction (dz_0..dz_{n-1}, dz0) of size n + 1, artificial z0 last,
  // along which the almost-complementary path leaves to infinity; dz >= 0, in original units,
  // scaled to |ray|_inf = 1. For copositive-plus M (exact arithmetic) dz0 = 0, dz != 0,
  // M dz >= 0, dz^T M dz = 0 (so M^T dz = -M dz <= 0) and q^T dz < 0: dz certifies that the
  // LCP is not even feasible, as dz^T (q + M z) <= q^T dz < 0 for every z >= 0. Empty otherwise.
  Eigen::VectorXd ray;
  // True when z0 left the basis, so the final basis is complementary, whatever the termination
  // (numerical_failure too, when its residual test failed): basic_z is then a candidate answer
  // that a caller with a better check of the application's conditions may verify.
  bool complementary = false;
  // Indices i for which z_i is basic at termination (the "active set": for the contact
  // problems, the nodes in contact). Useful as a warm start later.
  std::vector<int> basic_z;
  LemkeSummary summary;
};

// Solves the LCP. M must be square with the size of q; NaN or Inf input is misuse and throws
// std::invalid_argument. Never throws for an outcome: see summary.termination.
LemkeResult solve_lemke(const Eigen::MatrixXd& M, const Eigen::VectorXd& q, const LemkeOptions& options = {});

}  // namespace liftoff::lcp

namespace liftoff {
template <>  // the names' one table is in lemke.cpp
std::optional<lcp::LemkeTermination> from_string(std::string_view);
}  // namespace liftoff
