#pragma once
// The bordered system of pseudo-arc-length continuation,
//     M = [ A    b ]      A = G_x (n x n, held by an inner LinearSolver, dense or sparse),
//         [ c^T  d ],     b = G_lambda, c = the tangent row, d = its lambda entry,
// solved by block elimination with A's factors instead of factorising M:
//     factorise: A = LU, y = A^{-1} b (one solve), s = d - c.y (the Schur complement);
//     solve [r; rho]: z = A^{-1} r (the second solve), x_n = (rho - c.z) / s, x = z - y x_n,
// followed by one step of iterative refinement with M's own residual (one more solve), which
// makes block elimination as accurate as a direct LU of M near a fold, where A is nearly
// singular but M is not (Govaerts, Numerical Methods for Bifurcations of Dynamical Equilibria,
// ch. 3: block elimination plus one refinement step). det M = det A * s gives the sign.
//
// The near-singular guard: at an exact fold A is singular (an exactly zero pivot), and with
// s negligible (|s| <= 1e3 eps (|d| + |c||y|): it is all cancellation) block elimination cannot
// be trusted either. Then, for n + 1 <= dense_fallback_limit, M is assembled densely, rows and
// columns equilibrated (a Ritz Jacobian's diagonal spans (N pi)^4) and factorised by partial
// pivoting, and called singular when its reciprocal condition estimate is below 1e3 eps (the
// test the path follower always used). Above the limit (a large FE model) M is reported
// singular: an exact fold of a 1e5-unknown model is a measure-zero event, which the follower
// treats as a failed step (shorter steps then avoid landing on it).

#include <Eigen/Dense>
#include <optional>

#include "nonlinear/linear_solver.hpp"

namespace liftoff::nonlinear {

class BorderedSolver final : public LinearSolver {
 public:
  static constexpr int dense_fallback_limit = 2000;

  // `inner` holds A and must outlive this; size() = inner.size() + 1.
  explicit BorderedSolver(LinearSolver& inner);

  LinearSolver& inner() { return inner_; }
  Eigen::VectorXd& column() { return column_; }  // b
  Eigen::VectorXd& row() { return row_; }        // c
  double& corner() { return corner_; }           // d

  int size() const override { return inner_.size() + 1; }
  void zero() override;
  Factorisation factorise() override;
  bool solve(Eigen::VectorXd& rhs) const override;
  int determinant_sign() const override { return sign_; }
  void multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const override;
  Eigen::MatrixXd to_dense() const override;

  bool used_fallback() const { return fallback_.has_value(); }  // the last factorisation's route
  // A held fixed: zero() leaves it and factorise() keeps its factors (the caller factorised it once
  // with this solver, successfully), so only the border is eliminated again (one solve). For a
  // G_x that does not change (a linear model on a fixed configuration).
  void hold_inner(bool hold) { hold_inner_ = hold; }
  bool inner_held() const { return hold_inner_; }

 private:
  bool eliminate(const Eigen::VectorXd& rhs, Eigen::VectorXd& x) const;

  LinearSolver& inner_;
  Eigen::VectorXd column_, row_;
  double corner_ = 0.0;
  Eigen::VectorXd y_;  // A^{-1} b
  double schur_ = 0.0;
  struct Dense {
    Eigen::PartialPivLU<Eigen::MatrixXd> lu;
    Eigen::VectorXd rows, cols;  // equilibration
  };
  std::optional<Dense> fallback_;
  bool factorised_ = false;
  bool hold_inner_ = false;
  Factorisation inner_state_ = Factorisation::singular;  // the held A's
  int sign_ = 0;
  mutable Eigen::VectorXd residual_, correction_;
};

}  // namespace liftoff::nonlinear
