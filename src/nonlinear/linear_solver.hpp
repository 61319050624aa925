#pragma once
// The linear-solver seam of Newton's method and of the path follower: an object that holds the
// matrix of the current linear system (the Jacobian, or a bordered tangent), factorises it, and
// solves with the factors as often as asked. Newton (nonlinear::NewtonSolver) sees only this
// interface, so a model chooses dense or sparse storage without Newton knowing.
//
// The contract:
//  - The owner fills the matrix (DenseLu::matrix(), SparseLu::matrix(), ...) and calls
//    factorise(); zero() clears the values (the sparse pattern is kept).
//  - factorise() never throws for an outcome: a matrix with NaN or Inf is `not_finite`; one
//    whose LU meets an exactly zero pivot is `singular` (zero_pivot() names the column, 1-based).
//    A singular matrix is not an error of use: Newton reports it as linear_solver_failed.
//  - solve(b) overwrites b with A^{-1} b using the last successful factorisation; it returns
//    false if there is none (or the sizes differ).
//  - determinant_sign() is sign(det A) of the last factorisation (+1, -1; 0 when singular):
//    the parity of the negative eigenvalues of a symmetric A, which the stability checks need.
//  - factorisations() counts calls of factorise(); SparseLu::analyses() counts symbolic
//    analyses, which happen only when the sparsity pattern changes (set up once, solve many).

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <Eigen/SparseLU>
#include <string>
#include <vector>

namespace liftoff::nonlinear {

enum class Factorisation {
  ok,          // factors ready; solve() may be called
  singular,    // an exactly zero pivot (see zero_pivot())
  not_finite,  // the matrix holds NaN or Inf
};

class LinearSolver {
 public:
  virtual ~LinearSolver() = default;
  virtual int size() const = 0;
  virtual void zero() = 0;  // all values to zero, the pattern kept
  virtual Factorisation factorise() = 0;
  virtual bool solve(Eigen::VectorXd& rhs) const = 0;  // in place: b -> A^{-1} b
  virtual int determinant_sign() const = 0;
  // y = A x with the current matrix (for residual checks, e.g. the bordered solver's refinement).
  virtual void multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const = 0;
  virtual Eigen::MatrixXd to_dense() const = 0;    // the current matrix, densely (small n only)
  long zero_pivot() const { return zero_pivot_; }  // 1-based column of the zero pivot, else 0
  int factorisations() const { return factorisations_; }

 protected:
  long zero_pivot_ = 0;
  int factorisations_ = 0;
};

// Dense LU with partial pivoting, unblocked and column-oriented (the first largest |pivot| of
// each column): the small Ritz systems. The same operations in the same order as the dense LU
// KINSOL used before the seam (SUNDIALS' denseGETRF / denseGETRS), so the Ritz answers are
// unchanged bit for bit; Eigen's blocked PartialPivLU rounds differently, enough to leave a
// 256-mode Ritz solve stagnating at 1.1e-12 against a tolerance of 1e-12.
class DenseLu final : public LinearSolver {
 public:
  explicit DenseLu(int n);
  Eigen::MatrixXd& matrix() { return matrix_; }
  const Eigen::MatrixXd& matrix() const { return matrix_; }
  int size() const override { return static_cast<int>(matrix_.rows()); }
  void zero() override { matrix_.setZero(); }
  Factorisation factorise() override;
  bool solve(Eigen::VectorXd& rhs) const override;
  int determinant_sign() const override { return sign_; }
  void multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const override { y.noalias() = matrix_ * x; }
  Eigen::MatrixXd to_dense() const override { return matrix_; }

 private:
  Eigen::MatrixXd matrix_, lu_;
  std::vector<Eigen::Index> pivots_;
  bool factorised_ = false;
  int sign_ = 0;
};

// Sparse LU (Eigen::SparseLU, COLAMD ordering): the FE systems. The symbolic analysis (ordering
// and elimination tree) is done on the first factorise() and redone only when the pattern of
// matrix() changes; refilling values on the same pattern costs a numerical factorisation only.
// The matrix is kept compressed; build it once (setFromTriplets) and then update its values
// (coeffRef on existing entries, or valuePtr()).
class SparseLu final : public LinearSolver {
 public:
  explicit SparseLu(int n);
  Eigen::SparseMatrix<double>& matrix() { return matrix_; }
  const Eigen::SparseMatrix<double>& matrix() const { return matrix_; }
  int size() const override { return static_cast<int>(matrix_.rows()); }
  void zero() override { matrix_.coeffs().setZero(); }
  Factorisation factorise() override;
  bool solve(Eigen::VectorXd& rhs) const override;
  int determinant_sign() const override { return sign_; }
  void multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const override { y.noalias() = matrix_ * x; }
  Eigen::MatrixXd to_dense() const override { return Eigen::MatrixXd(matrix_); }
  int analyses() const { return analyses_; }
  // Nonzeros of the L and U factors of the last factorisation: the memory the solve takes
  // (linear in n for a banded FE stiffness under COLAMD).
  long factor_nonzeros() const { return factor_nonzeros_; }

 private:
  bool same_pattern() const;

  Eigen::SparseMatrix<double> matrix_;
  Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> lu_;
  Eigen::VectorXi outer_, inner_;  // the pattern the analysis was done for
  bool analysed_ = false, factorised_ = false;
  int sign_ = 0, analyses_ = 0;
  long factor_nonzeros_ = 0;
};

}  // namespace liftoff::nonlinear
