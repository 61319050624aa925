// The linear-solver seam: dense and sparse LU, and the bordered solver's block elimination.
#include "nonlinear/linear_solver.hpp"

#include <catch2/catch.hpp>
#include <limits>
#include <vector>

#include "nonlinear/bordered_solver.hpp"

using namespace liftoff::nonlinear;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {
constexpr double eps = std::numeric_limits<double>::epsilon();

// A nonsymmetric, diagonally dominant tridiagonal matrix with a chosen sign of each diagonal
// entry (dominance makes the LU pivots carry those signs, so det's sign is known).
MatrixXd tridiagonal(int n, const std::vector<int>& negative = {}) {
  MatrixXd a = MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    a(i, i) = 4.0 + 0.1 * i;
    if (i > 0) a(i, i - 1) = -1.0;
    if (i + 1 < n) a(i, i + 1) = -1.5;
  }
  for (int i : negative) a(i, i) = -a(i, i);
  return a;
}

Eigen::SparseMatrix<double> sparse(const MatrixXd& a) { return a.sparseView(); }
}  // namespace

TEST_CASE("dense and sparse LU solve the same system, give det's sign and report singularity", "[linear_solver]") {
  const int n = 12;
  const MatrixXd a = tridiagonal(n, {3, 7, 8});  // three negative pivots: det < 0
  const VectorXd x = VectorXd::LinSpaced(n, -1.0, 2.0);
  const VectorXd b = a * x;
  DenseLu dense(n);
  SparseLu sparse_lu(n);
  dense.matrix() = a;
  sparse_lu.matrix() = sparse(a);
  for (LinearSolver* s : std::vector<LinearSolver*>{&dense, &sparse_lu}) {
    REQUIRE(s->factorise() == Factorisation::ok);
    VectorXd y = b;
    REQUIRE(s->solve(y));
    // Forward error <= cond(A) * eps * a small multiple; cond(A) < 10 for this dominant A.
    CHECK((y - x).lpNorm<Eigen::Infinity>() <= 100 * eps * x.lpNorm<Eigen::Infinity>());
    CHECK(s->determinant_sign() == -1);
    VectorXd ax;
    s->multiply(x, ax);
    CHECK((ax - b).lpNorm<Eigen::Infinity>() <= 10 * eps * b.lpNorm<Eigen::Infinity>());
  }
  SECTION("a zero column is singular, NaN is not_finite; solve refuses without factors") {
    MatrixXd z = a;
    z.col(4).setZero();
    dense.matrix() = z;
    CHECK(dense.factorise() == Factorisation::singular);
    CHECK(dense.zero_pivot() == 5);
    CHECK(dense.determinant_sign() == 0);
    VectorXd y = b;
    CHECK(!dense.solve(y));
    sparse_lu.matrix().coeffRef(2, 2) = std::numeric_limits<double>::quiet_NaN();
    CHECK(sparse_lu.factorise() == Factorisation::not_finite);
  }
}

TEST_CASE("SparseLu analyses the pattern once and again only when it changes", "[linear_solver]") {
  const int n = 30;
  SparseLu lu(n);
  lu.matrix() = sparse(tridiagonal(n));
  for (int k = 0; k < 4; ++k) {  // new values on the same pattern
    lu.zero();
    const MatrixXd a = tridiagonal(n) * (1.0 + k);
    for (int j = 0; j < n; ++j)
      for (Eigen::SparseMatrix<double>::InnerIterator it(lu.matrix(), j); it; ++it) it.valueRef() = a(it.row(), j);
    REQUIRE(lu.factorise() == Factorisation::ok);
  }
  CHECK(lu.factorisations() == 4);
  CHECK(lu.analyses() == 1);
  MatrixXd wider = tridiagonal(n);
  wider(0, n - 1) = 0.5;  // a new entry: a new pattern
  lu.matrix() = sparse(wider);
  REQUIRE(lu.factorise() == Factorisation::ok);
  CHECK(lu.analyses() == 2);
}

TEST_CASE("the bordered solver's block elimination matches a dense LU of the bordered matrix", "[linear_solver]") {
  const int n = 40;
  const bool use_sparse = GENERATE(false, true);
  CAPTURE(use_sparse);
  DenseLu dense_inner(n);
  SparseLu sparse_inner(n);
  LinearSolver& inner = use_sparse ? static_cast<LinearSolver&>(sparse_inner) : dense_inner;
  BorderedSolver bordered(inner);
  REQUIRE(bordered.size() == n + 1);

  const auto fill = [&](const MatrixXd& a, const VectorXd& b, const VectorXd& c, double d) {
    bordered.zero();
    if (use_sparse)
      sparse_inner.matrix() = sparse(a);
    else
      dense_inner.matrix() = a;
    bordered.column() = b;
    bordered.row() = c;
    bordered.corner() = d;
  };
  const VectorXd b = VectorXd::LinSpaced(n, 1.0, 2.0), c = VectorXd::LinSpaced(n, -0.5, 0.5);
  const VectorXd rhs = VectorXd::LinSpaced(n + 1, 3.0, -1.0);

  SECTION("regular A: block elimination, the same answer and det's sign") {
    const MatrixXd a = tridiagonal(n, {5});
    fill(a, b, c, 0.7);
    REQUIRE(bordered.factorise() == Factorisation::ok);
    CHECK(!bordered.used_fallback());
    const MatrixXd m = bordered.to_dense();
    const Eigen::PartialPivLU<MatrixXd> reference(m);
    const VectorXd expected = reference.solve(rhs);
    VectorXd x = rhs;
    REQUIRE(bordered.solve(x));
    // Both within cond(M) eps of the truth; cond(M) is estimated by the dense LU.
    const double cond = 1.0 / reference.rcond();
    CHECK((x - expected).lpNorm<Eigen::Infinity>() <= 10 * cond * eps * expected.lpNorm<Eigen::Infinity>());
    CHECK(bordered.determinant_sign() == (reference.determinant() > 0 ? 1 : -1));
  }
  SECTION("singular A (a fold) with a regular M: the dense fallback solves it") {
    // A = diag with one zero: singular; b has a component along the null vector, c too.
    MatrixXd a = MatrixXd::Identity(n, n) * 2.0;
    a(n / 2, n / 2) = 0.0;
    fill(a, b, c + VectorXd::Unit(n, n / 2), 0.0);
    REQUIRE(bordered.factorise() == Factorisation::ok);
    CHECK(bordered.used_fallback());
    VectorXd x = rhs;
    REQUIRE(bordered.solve(x));
    VectorXd mx;
    bordered.multiply(x, mx);
    CHECK((mx - rhs).lpNorm<Eigen::Infinity>() <=
          100 * eps * rhs.lpNorm<Eigen::Infinity>() * x.lpNorm<Eigen::Infinity>());
  }
  SECTION("nearly singular A: block elimination with refinement keeps M's accuracy") {
    MatrixXd a = tridiagonal(n);
    const Eigen::JacobiSVD<MatrixXd> svd(a, Eigen::ComputeFullU | Eigen::ComputeFullV);
    // Shift the smallest singular value down to 1e-9 of the largest: cond(A) ~ 1e9, M regular.
    VectorXd sigma = svd.singularValues();
    sigma(n - 1) = 1e-9 * sigma(0);
    a = svd.matrixU() * sigma.asDiagonal() * svd.matrixV().transpose();
    fill(a, svd.matrixU().col(n - 1) + b * 1e-3, svd.matrixV().col(n - 1) + c * 1e-3, 0.0);
    REQUIRE(bordered.factorise() == Factorisation::ok);
    CHECK(!bordered.used_fallback());
    VectorXd x = rhs;
    REQUIRE(bordered.solve(x));
    VectorXd mx;
    bordered.multiply(x, mx);
    // M is well conditioned (the border spans A's near-null space), so the backward error
    // must be round-off, which block elimination without refinement would miss by ~cond(A) eps.
    CHECK((mx - rhs).lpNorm<Eigen::Infinity>() <=
          1e3 * eps * (rhs.lpNorm<Eigen::Infinity>() + x.lpNorm<Eigen::Infinity>() * 10));
  }
}
