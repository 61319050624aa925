#include "lcp/lemke.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <tuple>

using Eigen::MatrixXd;
using Eigen::VectorXd;
using liftoff::lcp::LemkeOptions;
using liftoff::lcp::LemkeTermination;
using liftoff::lcp::solve_lemke;

namespace {

constexpr double eps = std::numeric_limits<double>::epsilon();

// Round-off budget of one backward-stable solve of size n: a few eps per row. Residuals that
// are normalised (see lemke.hpp) must come out below this.
double round_off(int n) { return 16.0 * (n + 1) * eps; }

MatrixXd random_matrix(int rows, int cols, std::mt19937& rng) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  MatrixXd A(rows, cols);
  for (int j = 0; j < cols; ++j)
    for (int i = 0; i < rows; ++i) A(i, j) = uniform(rng);
  return A;
}

VectorXd random_vector(int n, std::mt19937& rng) { return random_matrix(n, 1, rng).col(0); }

// The solution of min 1/2 z^T M z + q^T z, z >= 0 (M symmetric positive definite) by projected
// Gauss-Seidel, independent of any pivoting. Returns the iterate and an error estimate from
// its own last update size d_k and contraction rate r = d_k / d_{k-1}: |z - z*| <~ d_k r/(1-r).
std::pair<VectorXd, double> projected_gauss_seidel(const MatrixXd& M, const VectorXd& q) {
  const int n = static_cast<int>(q.size());
  VectorXd z = VectorXd::Zero(n);
  double update = 0.0, previous_update = 0.0;
  for (int sweep = 0; sweep < 1000000; ++sweep) {
    previous_update = update;
    update = 0.0;
    for (int i = 0; i < n; ++i) {
      const double zi = std::max(0.0, z(i) - (q(i) + M.row(i).dot(z)) / M(i, i));
      update = std::max(update, std::abs(zi - z(i)));
      z(i) = zi;
    }
    if (update <= 4.0 * eps * z.cwiseAbs().maxCoeff()) break;
  }
  const double rate = previous_update > 0.0 ? std::min(update / previous_update, 0.999) : 0.5;
  return {z, update * rate / (1.0 - rate) + 4.0 * eps * z.cwiseAbs().maxCoeff()};
}

// Every property of a solution of the LCP, checked on (z, w) as returned.
void require_solution(const MatrixXd& M, const VectorXd& q, const liftoff::lcp::LemkeResult& r, double tolerance) {
  INFO(r.summary.brief_report() << " / " << r.summary.message);
  REQUIRE(r.summary.termination == LemkeTermination::solution);
  REQUIRE(r.summary.is_usable());
  const double scale =
      std::max({1.0, q.cwiseAbs().maxCoeff(), M.cwiseAbs().rowwise().sum().maxCoeff() * r.z.cwiseAbs().maxCoeff()});
  const double z_scale = std::max(1.0, r.z.cwiseAbs().maxCoeff());
  CHECK(r.z.minCoeff() >= -tolerance * z_scale);
  CHECK(r.w.minCoeff() >= -tolerance * scale);
  CHECK((r.w - q - M * r.z).cwiseAbs().maxCoeff() <= tolerance * scale);
  CHECK(r.z.cwiseProduct(r.w).cwiseAbs().maxCoeff() <= tolerance * scale * z_scale);
  CHECK(r.summary.feasibility_residual <= tolerance);
  CHECK(r.summary.complementarity_residual <= tolerance);
  CHECK(r.summary.equation_residual <= tolerance);
  CHECK(r.summary.time_s >= 0.0);
}

}  // namespace

TEST_CASE("q >= 0 is solved by z = 0 without pivots", "[lemke]") {
  MatrixXd M(2, 2);
  M << 2, 1, 1, 2;
  const VectorXd q = (VectorXd(2) << 3.0, 0.0).finished();
  const auto r = solve_lemke(M, q);
  REQUIRE(r.summary.termination == LemkeTermination::solution);
  CHECK(r.summary.pivots == 0);
  CHECK(r.z == VectorXd::Zero(2));
  CHECK(r.w == q);
  CHECK(r.basic_z.empty());
}

TEST_CASE("small LCPs with hand solutions", "[lemke]") {
  const double tol = 1e-12;
  SECTION("2x2, both z positive: M z = -q") {
    MatrixXd M(2, 2);
    M << 2, 1, 1, 2;
    const VectorXd q = (VectorXd(2) << -5.0, -6.0).finished();
    const auto r = solve_lemke(M, q);
    require_solution(M, q, r, tol);
    CHECK(std::abs(r.z(0) - 4.0 / 3.0) <= tol);
    CHECK(std::abs(r.z(1) - 7.0 / 3.0) <= tol);
    CHECK(r.w.cwiseAbs().maxCoeff() <= tol);
    CHECK(r.basic_z == std::vector<int>{0, 1});
  }
  SECTION("2x2, one contact: z = (1/2, 0), w = (0, 7/2)") {
    MatrixXd M(2, 2);
    M << 2, 1, 1, 2;
    const VectorXd q = (VectorXd(2) << -1.0, 3.0).finished();
    const auto r = solve_lemke(M, q);
    require_solution(M, q, r, tol);
    CHECK(std::abs(r.z(0) - 0.5) <= tol);
    CHECK(r.z(1) == 0.0);
    CHECK(std::abs(r.w(0)) <= tol);
    CHECK(std::abs(r.w(1) - 3.5) <= tol);
    CHECK(r.basic_z == std::vector<int>{0});
  }
  SECTION("3x3 tridiagonal: z = (1, 0, 2), w = (0, 1, 0)") {
    // Built backwards: q = w* - M z* with complementary (z*, w*); M is positive definite,
    // so the solution is unique.
    MatrixXd M(3, 3);
    M << 2, 1, 0, 1, 2, 1, 0, 1, 2;
    const VectorXd q = (VectorXd(3) << -2.0, -2.0, -4.0).finished();
    const auto r = solve_lemke(M, q);
    require_solution(M, q, r, tol);
    CHECK((r.z - Eigen::Vector3d(1.0, 0.0, 2.0)).cwiseAbs().maxCoeff() <= tol);
    CHECK((r.w - Eigen::Vector3d(0.0, 1.0, 0.0)).cwiseAbs().maxCoeff() <= tol);
    CHECK(r.basic_z == std::vector<int>{0, 2});
  }
}

TEST_CASE("random positive definite LCP agrees with an independent QP solution", "[lemke]") {
  const int n = 30;
  std::mt19937 rng(20240611);
  const MatrixXd A = random_matrix(n, n, rng);
  const MatrixXd M = A.transpose() * A + MatrixXd::Identity(n, n);
  const VectorXd q = random_vector(n, rng) * 10.0;
  const auto r = solve_lemke(M, q);
  // M is symmetric positive definite: cond(M) bounds the error amplification of the polish.
  const Eigen::SelfAdjointEigenSolver<MatrixXd> eigen(M);
  const double condition = eigen.eigenvalues().maxCoeff() / eigen.eigenvalues().minCoeff();
  require_solution(M, q, r, round_off(n));

  // Brute force over the active set: z_i > 0 => w_i = 0, and the basic set alone reproduces z.
  int active = 0;
  for (int i = 0; i < n; ++i) {
    if (r.z(i) > 0.0) {
      ++active;
      CHECK(std::abs(r.w(i)) <= round_off(n) * q.cwiseAbs().maxCoeff());
    }
  }
  CHECK(active == static_cast<int>(r.basic_z.size()));
  CHECK(active > 0);
  CHECK(active < n);  // a genuine mix of contact and lift-off
  VectorXd z_active = VectorXd::Zero(n);
  const VectorXd z_alpha = MatrixXd(M(r.basic_z, r.basic_z)).lu().solve(VectorXd(-q(r.basic_z)));
  z_active(r.basic_z) = z_alpha;
  CHECK((z_active - r.z).cwiseAbs().maxCoeff() <= condition * round_off(n) * r.z.cwiseAbs().maxCoeff());

  const auto [z_reference, error_estimate] = projected_gauss_seidel(M, q);
  INFO("PGS error estimate " << error_estimate << ", condition " << condition);
  CHECK((r.z - z_reference).cwiseAbs().maxCoeff() <=
        10.0 * error_estimate + condition * round_off(n) * r.z.cwiseAbs().maxCoeff());
}

TEST_CASE("degenerate LCPs terminate with a solution and do not cycle", "[lemke]") {
  SECTION("all ratios tie: M = I + ones ones^T, q = -ones") {
    // The first pivot ties on all n rows (q_i equal). After it xB = 0 on the n - 1 slack rows
    // and the entering column of z_r has a_i = M_rr - M_ir = 1 there, so the plain minimum
    // ratio 0 ties on n - 1 rows at every following step: only the lexicographic rule decides.
    for (int n : {2, 5, 12, 40}) {
      const MatrixXd M = MatrixXd::Identity(n, n) + MatrixXd::Ones(n, n);
      const VectorXd q = -VectorXd::Ones(n);
      const auto r = solve_lemke(M, q);
      require_solution(M, q, r, round_off(n));
      CHECK((r.z.array() - 1.0 / (n + 1)).abs().maxCoeff() <= round_off(n));
      CHECK(r.summary.pivots <= n + 1);  // each z_i enters once, then z0 leaves
    }
  }
  SECTION("degenerate solution: z_i = w_i = 0 on half the rows, repeated block structure") {
    // Blocks of identical rows and columns, and q built from a solution with z*_i = w*_i = 0
    // on every other index: many ratios tie at zero and the solution itself is degenerate.
    const int blocks = 6, size = 4, n = blocks * size;
    MatrixXd block(size, size);
    block << 4, -1, 0, -1, -1, 4, -1, 0, 0, -1, 4, -1, -1, 0, -1, 4;
    MatrixXd M = MatrixXd::Zero(n, n);
    for (int b = 0; b < blocks; ++b) {
      const Eigen::Index at = Eigen::Index{b} * size, next = at + size;
      M.block(at, at, size, size) = block;
      if (b + 1 < blocks) {
        M.block(at, next, size, size) = -MatrixXd::Identity(size, size);
        M.block(next, at, size, size) = -MatrixXd::Identity(size, size);
      }
    }
    VectorXd z_star = VectorXd::Zero(n), w_star = VectorXd::Zero(n);
    for (int i = 0; i < n; ++i) {
      if (i % 4 == 0) z_star(i) = 1.0;
      if (i % 4 == 2) w_star(i) = 1.0;  // i % 4 == 1, 3: both zero
    }
    const VectorXd q = w_star - M * z_star;
    const auto r = solve_lemke(M, q);
    require_solution(M, q, r, round_off(n));
    // M is positive definite (diagonally dominant), so the solution is unique.
    CHECK((r.z - z_star).cwiseAbs().maxCoeff() <= 1e3 * round_off(n));
    CHECK(r.summary.pivots <= 2 * (n + 1));
  }
  SECTION("a problem on which naive tie-breaking cycles") {
    // Found by a search over small integer LCPs: with ties broken by the first row, the last
    // row or the largest pivot instead of lexicographically, Lemke cycles here (it hits any
    // pivot limit); the lexicographic rule reaches the solution in 5 pivots, through two
    // ratio tests with two rows tied at a zero step. The solution is degenerate (z_1 = w_1 = 0).
    MatrixXd M(5, 5);
    M << -1, -2, 2, 2, -1, -1, 0, 0, 1, 1, 2, 2, 1, -1, -2, 1, 0, 0, 1, 2, 2, 2, 1, 0, -1;
    const VectorXd q = (VectorXd(5) << 1, -1, -1, -1, -1).finished();
    const auto r = solve_lemke(M, q);
    require_solution(M, q, r, round_off(5));
    // z = (0, 0, 2, 1, 0): M z = 2 M(:,2) + M(:,3) = (6, 1, 1, 1, 2), w = q + M z.
    CHECK((r.z - (VectorXd(5) << 0, 0, 2, 1, 0).finished()).cwiseAbs().maxCoeff() <= round_off(5));
    CHECK((r.w - (VectorXd(5) << 7, 0, 0, 0, 1).finished()).cwiseAbs().maxCoeff() <= round_off(5));
    CHECK(r.summary.pivots <= 10);
  }
  SECTION("z0 tied with another row leaves at once") {
    // In the first complementary ratio test z0 ties with w_0 and w_2 (step 1). Letting z0 leave
    // gives the fully degenerate solution z = (0, 1, 0), w = 0; continuing the lexicographic
    // rule instead ends in a ray (M is not copositive-plus, so that ray would prove nothing).
    MatrixXd M(3, 3);
    M << 2, 0, -1, 1, 1, 2, 2, 1, -2;
    const VectorXd q = (VectorXd(3) << 0, -1, -1).finished();
    const auto r = solve_lemke(M, q);
    require_solution(M, q, r, round_off(3));
    CHECK((r.z - Eigen::Vector3d(0, 1, 0)).cwiseAbs().maxCoeff() <= round_off(3));
    CHECK(r.w.cwiseAbs().maxCoeff() <= round_off(3));
    CHECK(r.summary.pivots == 2);
  }
  SECTION("Beale's cycling LP as an LCP") {
    // min -3/4 x1 + 20 x2 - 1/2 x3 + 6 x4  s.t.  1/4 x1 - 8 x2 - x3 + 9 x4 <= 0,
    // 1/2 x1 - 12 x2 - 1/2 x3 + 3 x4 <= 0,  x3 <= 1,  x >= 0: the simplex method with the
    // textbook rule cycles. Its KKT conditions are the LCP M = [[0, A^T], [-A, 0]],
    // q = [c; b] with zero right-hand sides (degenerate) and a zero diagonal (no scaling).
    MatrixXd A(3, 4);
    A << 0.25, -8, -1, 9, 0.5, -12, -0.5, 3, 0, 0, 1, 0;
    const VectorXd c = (VectorXd(4) << -0.75, 20, -0.5, 6).finished();
    const VectorXd b = (VectorXd(3) << 0, 0, 1).finished();
    MatrixXd M = MatrixXd::Zero(7, 7);
    M.topRightCorner(4, 3) = A.transpose();
    M.bottomLeftCorner(3, 4) = -A;
    VectorXd q(7);
    q << c, b;
    const auto r = solve_lemke(M, q);
    require_solution(M, q, r, round_off(7));
    const VectorXd x = r.z.head(4), y = r.z.tail(3);
    CHECK(std::abs(c.dot(x) - (-1.25)) <= round_off(7));   // the optimum, x = (1, 0, 1, 0)
    CHECK(std::abs(b.dot(y) + c.dot(x)) <= round_off(7));  // strong duality: b^T y = -c^T x
    CHECK(r.summary.pivots <= 10 * 8);
  }
}

TEST_CASE("positive semidefinite (singular) M with a solution", "[lemke]") {
  // The primal structure [[K, -K], [-K, K]] (rank 3 of 6) plus one row and column of zeros
  // (a zero diagonal entry: no scaling there). Built from u* = z1 - z2 with mixed signs and
  // slacks s1, s2 zero exactly where z1, z2 are positive.
  MatrixXd K(3, 3);
  K << 3, -1, 0, -1, 3, -1, 0, -1, 2;
  MatrixXd M = MatrixXd::Zero(7, 7);
  M.block(0, 0, 3, 3) = K;
  M.block(0, 3, 3, 3) = -K;
  M.block(3, 0, 3, 3) = -K;
  M.block(3, 3, 3, 3) = K;
  const Eigen::Vector3d u_star(1.0, -2.0, 0.5);
  const Eigen::Vector3d s1(0.0, 1.5, 0.0), s2(0.7, 0.0, 0.0);
  VectorXd q(7);
  q << -K * u_star + s1, K * u_star + s2, 2.0;
  const auto r = solve_lemke(M, q);
  require_solution(M, q, r, round_off(7));
  // z is not unique (z1 and z2 may both grow) but w is for symmetric PSD M, and so is K u.
  VectorXd w_star(7);
  w_star << s1, s2, 2.0;
  CHECK((r.w - w_star).cwiseAbs().maxCoeff() <= 1e2 * round_off(7));
  const Eigen::Vector3d u = r.z.head(3) - r.z.segment(3, 3);
  CHECK((K * (u - u_star)).cwiseAbs().maxCoeff() <= 1e2 * round_off(7));
  CHECK(r.z(6) == 0.0);
}

TEST_CASE("ray termination on infeasible LCPs", "[lemke]") {
  auto require_certificate = [](const MatrixXd& M, const VectorXd& q, const liftoff::lcp::LemkeResult& r) {
    const int n = static_cast<int>(q.size());
    INFO(r.summary.message);
    REQUIRE(r.summary.termination == LemkeTermination::ray);
    CHECK_FALSE(r.summary.is_usable());
    CHECK(r.summary.message.find("no solution") != std::string::npos);
    REQUIRE(r.ray.size() == n + 1);
    const VectorXd dz = r.ray.head(n);
    CHECK(dz.minCoeff() >= 0.0);
    CHECK(dz.maxCoeff() > 0.5);  // normalised to |ray|_inf = 1, and the z part carries it
    // Round-off of products with M, for |dz|_inf = 1.
    const double tolerance = round_off(n) * std::max(1.0, M.cwiseAbs().rowwise().sum().maxCoeff());
    CHECK(std::abs(r.ray(n)) <= tolerance);  // dz0 = 0 for copositive-plus M
    // The Farkas-type certificate: M dz >= 0, dz^T M dz = 0, q^T dz < 0.
    CHECK((M * dz).minCoeff() >= -tolerance);
    CHECK(std::abs(dz.dot(M * dz)) <= tolerance);
    CHECK(q.dot(dz) < -tolerance * q.cwiseAbs().maxCoeff());
  };
  SECTION("M = [0], q = [-1]: w = -1 whatever z") {
    const MatrixXd M = MatrixXd::Zero(1, 1);
    const VectorXd q = -VectorXd::Ones(1);
    const auto r = solve_lemke(M, q);
    require_certificate(M, q, r);
    CHECK(r.ray(0) == 1.0);
  }
  SECTION("M = [[1, -1], [-1, 1]], q = (-1, -1): w_1 + w_2 = -2 whatever z") {
    MatrixXd M(2, 2);
    M << 1, -1, -1, 1;
    const VectorXd q = -VectorXd::Ones(2);
    const auto r = solve_lemke(M, q);
    require_certificate(M, q, r);
    CHECK((r.ray.head(2) - VectorXd::Ones(2)).cwiseAbs().maxCoeff() <= round_off(2));
  }
  SECTION("rank one M = v v^T, v = (2, -1), q = (-1, -1): the ray is in original units") {
    // w_1 = -1 + 2u, w_2 = -1 - u with u = 2 z_1 - z_2: u >= 1/2 and u <= -1 at once.
    // The certificate must have v^T dz = 0, i.e. dz ~ (1, 2); equilibration (D = (1/2, 1))
    // turns it into (1, 1) internally, so this fails if the ray is not scaled back.
    MatrixXd M(2, 2);
    M << 4, -2, -2, 1;
    const VectorXd q = -VectorXd::Ones(2);
    const auto r = solve_lemke(M, q);
    require_certificate(M, q, r);
    CHECK((r.ray.head(2) - Eigen::Vector2d(0.5, 1.0)).cwiseAbs().maxCoeff() <= round_off(2));
  }
  SECTION("the primal structure [[K, -K], [-K, K]] with q_1 + q_2 < 0: a mechanism") {
    // w_1 + w_2 = q_1 + q_2 < 0 whatever z. In exact arithmetic the entering column becomes
    // zero in several rows on the way; in floating point those entries are round-off of
    // either sign, and pivoting on them (no pivot tolerance) wrecks the basis.
    const int m = 20, n = 2 * m;
    std::mt19937 rng(11);
    const MatrixXd B = random_matrix(m, m, rng);
    const MatrixXd K = B.transpose() * B + 0.1 * MatrixXd::Identity(m, m);
    MatrixXd M(n, n);
    M << K, -K, -K, K;
    const VectorXd q = -VectorXd::Ones(n) + 0.5 * random_vector(n, rng);
    REQUIRE((q.head(m) + q.tail(m)).maxCoeff() < 0.0);
    const auto r = solve_lemke(M, q);
    require_certificate(M, q, r);
  }
  SECTION("an infeasible LP (x <= -1, x >= 0) as an LCP") {
    // min x s.t. x <= -1, x >= 0: M = [[0, 1], [-1, 0]], q = (1, -1).
    MatrixXd M(2, 2);
    M << 0, 1, -1, 0;
    const VectorXd q = (VectorXd(2) << 1.0, -1.0).finished();
    require_certificate(M, q, solve_lemke(M, q));
  }
}

TEST_CASE("equilibration: same answer on a badly scaled problem, residuals at round-off", "[lemke]") {
  // M = S C S, q = S p with C well conditioned (unit diagonal) and S = diag(10^k) over a range
  // of decades: the diagonal of M spans 10^-2k..10^2k (stiffness next to flexibility). With
  // y = S z the problem is the well-conditioned LCP(C, p), solved as the reference, so every
  // component of z is known to round-off.
  const int n = 9;
  std::mt19937 rng(7);
  const MatrixXd B = random_matrix(n, n, rng);
  MatrixXd C = B.transpose() * B + n * MatrixXd::Identity(n, n);
  const VectorXd unit = C.diagonal().cwiseSqrt().cwiseInverse();
  C = unit.asDiagonal() * C * unit.asDiagonal();
  const VectorXd p = random_vector(n, rng) * 10.0;
  const auto reference = solve_lemke(C, p);
  require_solution(C, p, reference, round_off(n));
  REQUIRE(reference.basic_z.size() > 1);
  REQUIRE(reference.basic_z.size() < n);

  auto problem = [&](double decades) {
    VectorXd s(n);
    for (int i = 0; i < n; ++i) s(i) = std::pow(10.0, decades * (2.0 * i / (n - 1) - 1.0));
    return std::tuple{VectorXd(s), MatrixXd(s.asDiagonal() * C * s.asDiagonal()), VectorXd(s.cwiseProduct(p))};
  };
  // Componentwise agreement with the reference in the balanced variables y = S z.
  auto matches_reference = [&](const VectorXd& s, const liftoff::lcp::LemkeResult& r) {
    return r.basic_z == reference.basic_z && (s.cwiseProduct(r.z) - reference.z).cwiseAbs().maxCoeff() <=
                                                 1e2 * round_off(n) * reference.z.cwiseAbs().maxCoeff();
  };
  LemkeOptions raw;
  raw.equilibrate = false;

  SECTION("diagonal over 1e-8..1e8: on and off agree") {
    const auto [s, M, q] = problem(4.0);
    REQUIRE(M.diagonal().minCoeff() <= 1.0001e-8);
    REQUIRE(M.diagonal().maxCoeff() >= 0.9999e8);
    const auto scaled = solve_lemke(M, q), unscaled = solve_lemke(M, q, raw);
    INFO(scaled.summary.brief_report() << "\n" << unscaled.summary.brief_report());
    require_solution(M, q, scaled, round_off(n));
    require_solution(M, q, unscaled, round_off(n));
    CHECK(matches_reference(s, scaled));
    CHECK(matches_reference(s, unscaled));
  }
  SECTION("diagonal over 1e-12..1e12: without scaling, a wrong answer is at least flagged") {
    // Without equilibration the pivot tolerance (relative to the column) drops the entries
    // of the flexible rows and the wrong active set comes out; the scaled residuals expose it.
    const auto [s, M, q] = problem(6.0);
    const auto scaled = solve_lemke(M, q), unscaled = solve_lemke(M, q, raw);
    INFO(scaled.summary.brief_report() << "\n" << unscaled.summary.brief_report() << "\n" << unscaled.summary.message);
    require_solution(M, q, scaled, round_off(n));
    CHECK(matches_reference(s, scaled));
    CHECK((!unscaled.summary.is_usable() || matches_reference(s, unscaled)));
  }
}

TEST_CASE("pivot limit", "[lemke]") {
  MatrixXd M(2, 2);
  M << 2, 1, 1, 2;
  const VectorXd q = (VectorXd(2) << -5.0, -6.0).finished();
  LemkeOptions options;
  options.max_pivots = 1;
  const auto r = solve_lemke(M, q, options);
  CHECK(r.summary.termination == LemkeTermination::pivot_limit);
  CHECK(r.summary.pivots == 1);
  CHECK_FALSE(r.summary.is_usable());
  CHECK(r.summary.equation_residual > 0.1);  // the artificial vertex is far from a solution
  CHECK(r.ray.size() == 0);
  // The default limit 10 (n + 1) is ample for the same problem.
  CHECK(solve_lemke(M, q).summary.termination == LemkeTermination::solution);
}

TEST_CASE("the last vertex is reported in original units", "[lemke]") {
  // Diagonal 4, 16, 1/4: the equilibration D = diag(1/2, 1/4, 2) is exact, and the vertex of
  // the scaled system w' = D q + D M D y + 1 z0 means w - q - M z = z0 D^-1 1 in original
  // units: its entries times D_ii must all equal z0 > 0.
  MatrixXd M(3, 3);
  M << 4, 1, 0, 1, 16, 1, 0, 1, 0.25;
  const VectorXd q = (VectorXd(3) << -1.0, -2.0, -0.5).finished();
  LemkeOptions options;
  options.max_pivots = 2;
  const auto r = solve_lemke(M, q, options);
  REQUIRE(r.summary.termination == LemkeTermination::pivot_limit);
  const VectorXd covering = (r.w - q - M * r.z).cwiseProduct(Eigen::Vector3d(0.5, 0.25, 2.0));
  INFO("z = " << r.z.transpose() << ", w = " << r.w.transpose());
  CHECK(covering.minCoeff() > 0.0);
  CHECK(covering.maxCoeff() - covering.minCoeff() <= round_off(3) * covering.maxCoeff());
  CHECK(r.z.minCoeff() >= 0.0);
  CHECK(r.w.minCoeff() >= 0.0);
  CHECK(r.z.maxCoeff() > 0.0);  // one z became basic in the second pivot
  // And the full run solves it.
  require_solution(M, q, solve_lemke(M, q), round_off(3));
}

TEST_CASE("invalid input throws, outcomes do not", "[lemke]") {
  MatrixXd M(2, 2);
  M << 2, 1, 1, 2;
  VectorXd q = (VectorXd(2) << -1.0, std::numeric_limits<double>::quiet_NaN()).finished();
  CHECK_THROWS_AS(solve_lemke(M, q), std::invalid_argument);
  q(1) = 1.0;
  M(0, 1) = std::numeric_limits<double>::infinity();
  CHECK_THROWS_AS(solve_lemke(M, q), std::invalid_argument);
  M(0, 1) = 1.0;
  CHECK_THROWS_AS(solve_lemke(M, VectorXd::Ones(3)), std::invalid_argument);
  CHECK_THROWS_AS(solve_lemke(MatrixXd::Ones(2, 3), q), std::invalid_argument);

  LemkeOptions options;
  options.pivot_tolerance = 0.0;
  CHECK_THROWS_WITH(options.validate(), Catch::Contains("pivot_tolerance"));
  CHECK_THROWS_AS(solve_lemke(M, q, options), std::invalid_argument);
  options.pivot_tolerance = -1e-9;
  CHECK_THROWS_AS(options.validate(), std::invalid_argument);
  options.pivot_tolerance = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_AS(options.validate(), std::invalid_argument);
  CHECK_NOTHROW(LemkeOptions{}.validate());
}

TEST_CASE("names and the one-line report", "[lemke]") {
  using liftoff::lcp::to_string;
  CHECK(to_string(LemkeTermination::solution) == "solution");
  CHECK(to_string(LemkeTermination::ray) == "ray");
  CHECK(to_string(LemkeTermination::pivot_limit) == "pivot_limit");
  CHECK(to_string(LemkeTermination::numerical_failure) == "numerical_failure");
  MatrixXd M(2, 2);
  M << 2, 1, 1, 2;
  const auto r = solve_lemke(M, (VectorXd(2) << -5.0, -6.0).finished());
  const std::string line = r.summary.brief_report();
  CHECK(line.find('\n') == std::string::npos);
  CHECK(line.find("solution") != std::string::npos);
  CHECK(line.find(std::to_string(r.summary.pivots) + " pivots") != std::string::npos);
  CHECK(line.find("complementarity") != std::string::npos);
}
