// Newton over the sparse seam on an FE model: the linear residual of a pinned beam of 1e5
// elements (from fe::discretise, in mixed form: see solve_beam) gives the direct sparse solve's answer, the
// symbolic analysis and the KINSOL setup happen once, and the factor's memory grows like n.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <vector>

#include "fe/discretisation.hpp"
#include "fe/mixed_form.hpp"
#include "model/from_scene.hpp"
#include "model/member_model.hpp"
#include "nonlinear/linear_solver.hpp"
#include "nonlinear/newton.hpp"
#include "support/scenes.hpp"

using namespace liftoff;
using Eigen::VectorXd;
using SparseMatrix = Eigen::SparseMatrix<double>;

namespace {
constexpr double eps = std::numeric_limits<double>::epsilon();

struct Run {
  VectorXd newton, direct;
  double residual_newton = 0, residual_direct = 0;  // |K u - f|_inf
  double inverse_norm = 0;                          // estimate of |J^-1|_inf
  double jacobian_norm = 0;                         // |J|_inf
  long factor_nonzeros = 0;
  int analyses = 0, factorisations = 0, setups = 0, iterations = 0;
  nonlinear::NewtonSummary summary;
};

// Hager's estimate of |B^-1|_1 from factorised B and B^T: a lower bound, in practice within a
// small factor of the truth.
double inverse_norm_estimate(const nonlinear::LinearSolver& b, const nonlinear::LinearSolver& b_transpose, int n) {
  VectorXd x = VectorXd::Constant(n, 1.0 / n);
  b.solve(x);
  double estimate = x.lpNorm<1>();
  for (int k = 0; k < 4; ++k) {
    VectorXd z = x.unaryExpr([](double v) { return v >= 0 ? 1.0 : -1.0; });
    b_transpose.solve(z);
    Eigen::Index j = 0;
    if (z.cwiseAbs().maxCoeff(&j) <= z.dot(x)) break;
    x = VectorXd::Unit(n, j);
    b.solve(x);
    estimate = std::max(estimate, x.lpNorm<1>());
  }
  return estimate;
}

// The FE model in the mixed form the fast contact solver uses (fe/mixed_form.hpp):
// unknowns z = (sigma, u), the element stress resultants and the displacements, and the
// linear residual
//     R(z) = [ H sigma - G u ]      so that G^T H^-1 G u = K u = f at the root.
//            [ G^T sigma - f ]
// Not K u - f itself: K of 1e5 Hermite elements has cond ~ N^4 ~ 1e20 > 1 / eps, so no double
// solve of it has digits to compare; the mixed system's cond grows like N^2.
Run solve_beam(int elements) {
  scene::Scene s = test::beam_scene(1.0, 1.0, scene::EndSupport::pinned, scene::EndSupport::pinned, 1e3);
  s.loads = {test::uniform_load(0.0, 1.0, 1.0), test::point_force(0.3, 0.5)};
  const fe::Discretisation d = fe::discretise(model::make_member_model(s), elements);
  REQUIRE(d.structure_is_stable());  // pinned-pinned: K alone is nonsingular
  const int m = d.stresses(), e = d.equations, n = m + e;
  const SparseMatrix jacobian_matrix = fe::mixed_matrix(d);
  VectorXd rhs = VectorXd::Zero(n);
  rhs.tail(e) = d.load(1.0);

  Run run;
  // The direct sparse solve.
  Eigen::SparseLU<SparseMatrix, Eigen::COLAMDOrdering<int>> direct(jacobian_matrix);
  REQUIRE(direct.info() == Eigen::Success);
  run.direct = direct.solve(rhs);

  // Newton through the seam, the Jacobian filled into the SparseLu's matrix (the pattern
  // built on the first call, the values refilled after).
  nonlinear::SparseLu lu(n);
  nonlinear::NewtonSolver newton(lu);
  const nonlinear::Residual residual = [&](const VectorXd& z, VectorXd& r) {
    r.noalias() = jacobian_matrix * z;
    r -= rhs;
    return true;
  };
  const nonlinear::JacobianFill jacobian = [&](const VectorXd&, const VectorXd&) {
    if (lu.matrix().nonZeros() == 0)
      lu.matrix() = jacobian_matrix;
    else
      std::copy(jacobian_matrix.valuePtr(), jacobian_matrix.valuePtr() + jacobian_matrix.nonZeros(),
                lu.matrix().valuePtr());
    return true;
  };
  // A componentwise backward-error test: row i's residual against |J_i| |z| + |rhs_i|, with
  // |z| the typical size of each block (the direct solve's, only as a unit).
  VectorXd typical(n);
  typical.head(m).setConstant(run.direct.head(m).lpNorm<Eigen::Infinity>());
  typical.tail(e).setConstant(run.direct.tail(e).lpNorm<Eigen::Infinity>());
  const VectorXd row_size = (SparseMatrix(jacobian_matrix.cwiseAbs()) * typical).array() + rhs.cwiseAbs().array();
  nonlinear::NewtonOptions options;
  options.residual_tolerance = 1e-12;
  options.residual_scale = row_size.cwiseInverse();
  options.unknown_scale = typical.cwiseInverse();
  // From z = 0 KINSOL's default step bound is 1 (1000 |D z0| is 0), but the root is |D z| ~
  // sqrt(n) away in the scaled metric: allow that.
  options.max_newton_step = 10.0 * std::sqrt(static_cast<double>(n));
  run.newton = VectorXd::Zero(n);
  run.summary = newton.solve(residual, jacobian, run.newton, options);

  VectorXd r(n);
  residual(run.newton, r);
  run.residual_newton = r.lpNorm<Eigen::Infinity>();
  residual(run.direct, r);
  run.residual_direct = r.lpNorm<Eigen::Infinity>();
  run.jacobian_norm = (SparseMatrix(jacobian_matrix.cwiseAbs()) * VectorXd::Ones(n)).maxCoeff();
  run.factor_nonzeros = lu.factor_nonzeros();
  run.analyses = lu.analyses();
  run.factorisations = lu.factorisations();
  run.setups = newton.setups();
  run.iterations = run.summary.iterations;
  nonlinear::SparseLu transpose(n);  // Hager needs J^-T as well as J^-1
  transpose.matrix() = jacobian_matrix.transpose();
  REQUIRE(transpose.factorise() == nonlinear::Factorisation::ok);
  run.inverse_norm = inverse_norm_estimate(transpose, lu, n);  // |J^-T|_1 = |J^-1|_inf
  return run;
}
}  // namespace

TEST_CASE("Newton over the sparse seam solves a 1e5-element FE beam as the direct solve does, in O(n)",
          "[newton][sparse][slow]") {
  const Run small = solve_beam(10000);
  const Run large = solve_beam(100000);
  for (const Run* run : {&small, &large}) {
    CAPTURE(run->summary.message, run->newton.size(), run->inverse_norm, run->residual_newton, run->residual_direct);
    REQUIRE(run->summary.is_usable());
    // A linear residual: one Newton step lands on the root; KINSOL may take one more to
    // confirm at round-off.
    CHECK(run->iterations <= 2);
    // Set up once: one KINSOL setup, one symbolic analysis, a numerical LU per iteration.
    CHECK(run->setups == 1);
    CHECK(run->analyses == 1);
    CHECK(run->factorisations == run->summary.jacobian_evaluations);
    // |z_newton - z_direct| <= |J^-1| (|R(z_newton)| + |R(z_direct)|), each residual known to
    // about eps |J| |z| (its own round-off); Hager's estimate is a lower bound of |J^-1| within
    // a small factor, hence the 10.
    const double bound = 10 * run->inverse_norm *
                         (run->residual_newton + run->residual_direct +
                          2 * eps * run->jacobian_norm * run->direct.lpNorm<Eigen::Infinity>());
    CHECK((run->newton - run->direct).lpNorm<Eigen::Infinity>() <= bound);
    // And the bound is no vacuous one: cond(J) ~ N^2 ~ 1e12 still leaves 3 digits.
    CHECK(bound <= 1e-3 * run->direct.lpNorm<Eigen::Infinity>());
  }
  // O(n) memory: ten times the elements, ten times the factor's nonzeros (COLAMD keeps a
  // banded K's LU banded), within 20 %.
  CAPTURE(small.factor_nonzeros, large.factor_nonzeros);
  const double ratio = static_cast<double>(large.factor_nonzeros) / static_cast<double>(small.factor_nonzeros);
  CHECK(ratio >= 8.0);
  CHECK(ratio <= 12.0);
  CHECK(large.factor_nonzeros <= 40L * large.newton.size());
}
