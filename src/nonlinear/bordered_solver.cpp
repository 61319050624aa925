#include "nonlinear/bordered_solver.hpp"

// Why:
//  - The refinement step is always taken (one solve and one product with A, O(n) for a banded
//    FE matrix): near a fold y = A^{-1} b is large and the cancellation in s = d - c.y costs
//    digits that plain block elimination never recovers.
//  - The Schur complement is judged against the size of the terms it is computed from, not
//    against 1: M's scale is the model's (the Ritz rows span (N pi)^4).

#include <cmath>
#include <limits>

namespace liftoff::nonlinear {

namespace {
constexpr double eps = std::numeric_limits<double>::epsilon();
}

BorderedSolver::BorderedSolver(LinearSolver& inner)
    : inner_(inner),
      column_(Eigen::VectorXd::Zero(inner.size())),
      row_(Eigen::VectorXd::Zero(inner.size())),
      y_(inner.size()),
      residual_(inner.size() + 1),
      correction_(inner.size() + 1) {}

void BorderedSolver::zero() {
  if (!hold_inner_) inner_.zero();
  column_.setZero();
  row_.setZero();
  corner_ = 0.0;
}

Eigen::MatrixXd BorderedSolver::to_dense() const {
  const int n = inner_.size();
  Eigen::MatrixXd m(n + 1, n + 1);
  m.topLeftCorner(n, n) = inner_.to_dense();
  m.topRightCorner(n, 1) = column_;
  m.bottomLeftCorner(1, n) = row_.transpose();
  m(n, n) = corner_;
  return m;
}

void BorderedSolver::multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
  const int n = inner_.size();
  Eigen::VectorXd top(n);
  inner_.multiply(x.head(n), top);
  y.resize(n + 1);
  y.head(n) = top + column_ * x(n);
  y(n) = row_.dot(x.head(n)) + corner_ * x(n);
}

Factorisation BorderedSolver::factorise() {
  ++factorisations_;
  factorised_ = false;
  fallback_.reset();
  sign_ = 0;
  zero_pivot_ = 0;
  if (!column_.allFinite() || !row_.allFinite() || !std::isfinite(corner_)) return Factorisation::not_finite;
  const Factorisation inner = hold_inner_ ? inner_state_ : inner_.factorise();
  inner_state_ = inner;
  if (inner == Factorisation::not_finite) return inner;
  if (inner == Factorisation::ok) {
    y_ = column_;
    if (inner_.solve(y_) && y_.allFinite()) {
      schur_ = corner_ - row_.dot(y_);
      const double size = std::abs(corner_) + row_.cwiseAbs().dot(y_.cwiseAbs());
      if (std::abs(schur_) > 1e3 * eps * size) {
        sign_ = inner_.determinant_sign() * (schur_ > 0 ? 1 : -1);
        factorised_ = true;
        return Factorisation::ok;
      }
    }
  }
  // A singular, or s all cancellation: the dense bordered LU, if M is small enough.
  if (size() > dense_fallback_limit) {
    zero_pivot_ = inner_.zero_pivot();
    return Factorisation::singular;
  }
  Dense dense;
  Eigen::MatrixXd m = to_dense();
  dense.rows = m.rowwise().lpNorm<Eigen::Infinity>().cwiseMax(1e-300).cwiseInverse();
  m = dense.rows.asDiagonal() * m;
  dense.cols = m.colwise().lpNorm<Eigen::Infinity>().transpose().cwiseMax(1e-300).cwiseInverse();
  m = m * dense.cols.asDiagonal();
  dense.lu.compute(m);
  if (!(dense.lu.rcond() > 1e3 * eps)) return Factorisation::singular;
  const double det = dense.lu.determinant();
  sign_ = det > 0 ? 1 : det < 0 ? -1 : 0;
  if (sign_ == 0) return Factorisation::singular;
  fallback_ = std::move(dense);
  factorised_ = true;
  return Factorisation::ok;
}

bool BorderedSolver::eliminate(const Eigen::VectorXd& rhs, Eigen::VectorXd& x) const {
  const int n = inner_.size();
  Eigen::VectorXd z = rhs.head(n);
  if (!inner_.solve(z)) return false;
  const double last = (rhs(n) - row_.dot(z)) / schur_;
  x.resize(n + 1);
  x.head(n) = z - y_ * last;
  x(n) = last;
  return x.allFinite();
}

bool BorderedSolver::solve(Eigen::VectorXd& rhs) const {
  if (!factorised_ || rhs.size() != size()) return false;
  if (fallback_) {
    Eigen::VectorXd x = fallback_->cols.asDiagonal() * fallback_->lu.solve(fallback_->rows.asDiagonal() * rhs);
    rhs.swap(x);
    return rhs.allFinite();
  }
  Eigen::VectorXd x;
  if (!eliminate(rhs, x)) return false;
  multiply(x, residual_);  // one step of refinement with M's own residual
  residual_ = rhs - residual_;
  if (!eliminate(residual_, correction_)) return false;
  x += correction_;
  rhs.swap(x);
  return true;
}

}  // namespace liftoff::nonlinear
