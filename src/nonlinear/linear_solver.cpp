#include "nonlinear/linear_solver.hpp"

// Why:
//  - DenseLu stops at the first exactly zero pivot, as LAPACK's getrf and SUNDIALS' dense LU
//    do. Near-singular but nonzero pivots are left to Newton, whose line search and residual
//    test judge the step.
//  - SparseLu compares the compressed pattern (outer and inner indices) with the analysed one
//    before each factorisation: O(nnz) integers, negligible against the numerical LU, and it
//    makes "symbolic analysis once" safe against an owner who rebuilds the matrix.

#include <algorithm>
#include <cmath>

namespace liftoff::nonlinear {

DenseLu::DenseLu(int n) : matrix_(Eigen::MatrixXd::Zero(n, n)) {}

Factorisation DenseLu::factorise() {
  ++factorisations_;
  factorised_ = false;
  sign_ = 0;
  zero_pivot_ = 0;
  if (!matrix_.allFinite()) return Factorisation::not_finite;
  lu_ = matrix_;
  const Eigen::Index n = lu_.rows();
  pivots_.resize(static_cast<std::size_t>(n));
  int sign = 1;
  for (Eigen::Index k = 0; k < n; ++k) {
    double* col_k = lu_.col(k).data();
    Eigen::Index l = k;  // the pivot row: the first largest |a(i, k)|, i >= k
    for (Eigen::Index i = k + 1; i < n; ++i)
      if (std::abs(col_k[i]) > std::abs(col_k[l])) l = i;
    pivots_[static_cast<std::size_t>(k)] = l;
    if (col_k[l] == 0.0) {
      zero_pivot_ = k + 1;
      return Factorisation::singular;
    }
    if (l != k) {
      lu_.row(k).swap(lu_.row(l));
      sign = -sign;
    }
    if (col_k[k] < 0) sign = -sign;
    const double multiplier = 1.0 / col_k[k];
    for (Eigen::Index i = k + 1; i < n; ++i) col_k[i] *= multiplier;
    for (Eigen::Index j = k + 1; j < n; ++j) {
      double* col_j = lu_.col(j).data();
      const double a_kj = col_j[k];
      if (a_kj != 0.0)
        for (Eigen::Index i = k + 1; i < n; ++i) col_j[i] -= a_kj * col_k[i];
    }
  }
  sign_ = sign;
  factorised_ = true;
  return Factorisation::ok;
}

bool DenseLu::solve(Eigen::VectorXd& rhs) const {
  const Eigen::Index n = lu_.rows();
  if (!factorised_ || rhs.size() != n) return false;
  double* b = rhs.data();
  for (Eigen::Index k = 0; k < n; ++k) {
    const Eigen::Index p = pivots_[static_cast<std::size_t>(k)];
    if (p != k) std::swap(b[k], b[p]);
  }
  for (Eigen::Index k = 0; k + 1 < n; ++k) {  // L y = b (unit lower)
    const double* col_k = lu_.col(k).data();
    for (Eigen::Index i = k + 1; i < n; ++i) b[i] -= col_k[i] * b[k];
  }
  for (Eigen::Index k = n - 1; k > 0; --k) {  // U x = y
    const double* col_k = lu_.col(k).data();
    b[k] /= col_k[k];
    for (Eigen::Index i = 0; i < k; ++i) b[i] -= col_k[i] * b[k];
  }
  if (n > 0) b[0] /= lu_(0, 0);
  return true;
}

SparseLu::SparseLu(int n) : matrix_(n, n) {}

bool SparseLu::same_pattern() const {
  if (!analysed_ || outer_.size() != matrix_.outerSize() + 1 || inner_.size() != matrix_.nonZeros()) return false;
  return std::equal(outer_.data(), outer_.data() + outer_.size(), matrix_.outerIndexPtr()) &&
         std::equal(inner_.data(), inner_.data() + inner_.size(), matrix_.innerIndexPtr());
}

Factorisation SparseLu::factorise() {
  ++factorisations_;
  factorised_ = false;
  sign_ = 0;
  zero_pivot_ = 0;
  matrix_.makeCompressed();
  if (!matrix_.coeffs().allFinite()) return Factorisation::not_finite;
  if (!same_pattern()) {
    lu_.analyzePattern(matrix_);
    outer_ = Eigen::Map<const Eigen::VectorXi>(matrix_.outerIndexPtr(), matrix_.outerSize() + 1);
    inner_ = Eigen::Map<const Eigen::VectorXi>(matrix_.innerIndexPtr(), matrix_.nonZeros());
    analysed_ = true;
    ++analyses_;
  }
  lu_.factorize(matrix_);
  if (lu_.info() != Eigen::Success) return Factorisation::singular;
  factor_nonzeros_ = static_cast<long>(lu_.nnzL() + lu_.nnzU());
  sign_ = static_cast<int>(lu_.signDeterminant());
  if (sign_ == 0) return Factorisation::singular;
  factorised_ = true;
  return Factorisation::ok;
}

bool SparseLu::solve(Eigen::VectorXd& rhs) const {
  if (!factorised_ || rhs.size() != matrix_.rows()) return false;
  Eigen::VectorXd x = lu_.solve(rhs);
  rhs.swap(x);
  return true;
}

}  // namespace liftoff::nonlinear
