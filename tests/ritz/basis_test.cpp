// Ritz bases: the kinematic end conditions hold for every support combination, the functions
// are independent, free ends carry the rigid motions the supports allow, and the arch bases
// contain an inextensional partner (w = u') for every u, so they cannot lock.
#include "ritz/basis.hpp"

#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

using namespace liftoff;
using namespace liftoff::ritz;
using model::EndSupport;

namespace {

constexpr double pi = std::numbers::pi;

double largest_on(const TrigPolynomial& f, double a, double b) {
  double m = 0.0;
  for (int i = 0; i <= 1000; ++i) m = std::max(m, std::abs(f(a + (b - a) * i / 1000.0)));
  return m;
}

bool w_fixed(EndSupport e) { return e != EndSupport::free; }
bool slope_fixed(EndSupport e) { return e == EndSupport::clamped; }
bool u_fixed(EndSupport e) { return e == EndSupport::pinned || e == EndSupport::clamped; }

// Checks f (and f' if `slope`) vanish at s relative to their size on the member.
void check_end(const TrigPolynomial& f, double s, bool value, bool slope, double a, double b) {
  if (value) CHECK(std::abs(f(s)) <= 1e-13 * largest_on(f, a, b));
  if (slope) {
    const TrigPolynomial df = f.derivative();
    CHECK(std::abs(df(s)) <= 1e-12 * largest_on(df, a, b));
  }
}

// Smallest over largest eigenvalue of the H^2 Gram matrix int (f g + f' g' + f'' g'').
double h2_gram_conditioning(const std::vector<TrigPolynomial>& f, double a, double b) {
  const int n = static_cast<int>(f.size());
  Eigen::MatrixXd g(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      g(i, j) = (f[i] * f[j] + f[i].derivative() * f[j].derivative() + f[i].derivative(2) * f[j].derivative(2))
                    .integral(a, b);
  const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(g).eigenvalues();
  return ev.minCoeff() / ev.maxCoeff();
}

}  // namespace

TEST_CASE("ritz basis: beams satisfy their kinematic end conditions", "[ritz][basis]") {
  const EndSupport left = GENERATE(EndSupport::pinned, EndSupport::clamped, EndSupport::free, EndSupport::roller);
  const EndSupport right = GENERATE(EndSupport::pinned, EndSupport::clamped, EndSupport::free);
  const int modes = GENERATE(1, 2, 4, 12);
  const double a = 0.0, b = 1.0;
  const Basis basis = beam_basis(left, right, a, b, modes);
  CAPTURE(basis.description, modes);
  REQUIRE(static_cast<int>(basis.w.size()) == modes);
  CHECK(basis.u.empty());
  for (const TrigPolynomial& phi : basis.w) {
    CAPTURE(phi.to_string());
    CHECK(largest_on(phi, a, b) == Approx(1.0).epsilon(1e-3));  // normalised
    check_end(phi, a, w_fixed(left), slope_fixed(left), a, b);
    check_end(phi, b, w_fixed(right), slope_fixed(right), a, b);
  }
  if (modes >= 2 && !(left == EndSupport::free && right == EndSupport::free && modes < 3))
    CHECK(h2_gram_conditioning(basis.w, a, b) > 1e-10);  // independent
}

TEST_CASE("ritz basis: free ends carry the rigid motions the supports allow", "[ritz][basis]") {
  // Rigid motions have w'' = 0; count the independent ones in the span through the bending
  // Gram matrix int phi_i'' phi_j'' (its null space).
  auto rigid_count = [](EndSupport left, EndSupport right) {
    const Basis basis = beam_basis(left, right, 0.0, 1.0, 8);
    const int n = static_cast<int>(basis.w.size());
    Eigen::MatrixXd g(n, n);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) g(i, j) = (basis.w[i].derivative(2) * basis.w[j].derivative(2)).integral(0.0, 1.0);
    const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(g).eigenvalues();
    return static_cast<int>((ev.array() < 1e-10 * ev.maxCoeff()).count());
  };
  CHECK(rigid_count(EndSupport::free, EndSupport::free) == 2);    // translation and rotation
  CHECK(rigid_count(EndSupport::pinned, EndSupport::free) == 1);  // rotation about the pin
  CHECK(rigid_count(EndSupport::free, EndSupport::pinned) == 1);
  CHECK(rigid_count(EndSupport::clamped, EndSupport::free) == 0);  // a cantilever has none
  CHECK(rigid_count(EndSupport::pinned, EndSupport::pinned) == 0);
}

TEST_CASE("ritz basis: the seed's pinned-pinned family, on any interval", "[ritz][basis]") {
  // sin(j pi (s - a)/L), normalised to 1, for the first N - 2 functions; then one cubic per
  // pinned end carrying that end's curvature (w = 0 at both ends, w'' != 0 at its own end only).
  const Basis basis = beam_basis(EndSupport::pinned, EndSupport::pinned, 0.5, 2.5, 7);
  REQUIRE(basis.w.size() == 7);
  for (int j = 1; j <= 5; ++j)
    for (double s : {0.5, 0.9, 1.7, 2.5})
      CHECK(basis.w[j - 1](s) == Approx(std::sin(j * pi * (s - 0.5) / 2.0)).margin(1e-13));
  const TrigPolynomial& left = basis.w[5];
  const TrigPolynomial& right = basis.w[6];
  for (double s : {0.5, 2.5}) {
    CHECK(left(s) == Approx(0).margin(1e-13));
    CHECK(right(s) == Approx(0).margin(1e-13));
  }
  CHECK(std::abs(left.derivative(2)(0.5)) > 0.1);
  CHECK(left.derivative(2)(2.5) == Approx(0).margin(1e-12));
  CHECK(right.derivative(2)(0.5) == Approx(0).margin(1e-12));
  CHECK(std::abs(right.derivative(2)(2.5)) > 0.1);
  CHECK_THROWS_AS(beam_basis(EndSupport::pinned, EndSupport::pinned, 0.0, 1.0, 0), std::invalid_argument);
  CHECK_THROWS_AS(beam_basis(EndSupport::pinned, EndSupport::pinned, 1.0, 1.0, 3), std::invalid_argument);
}

TEST_CASE("ritz basis: arches satisfy their kinematic end conditions", "[ritz][basis]") {
  const EndSupport left = GENERATE(EndSupport::pinned, EndSupport::roller, EndSupport::clamped, EndSupport::free);
  const EndSupport right = GENERATE(EndSupport::pinned, EndSupport::roller, EndSupport::clamped, EndSupport::free);
  const int modes = GENERATE(1, 3, 10);
  const double gamma = 10.0 * pi / 180.0, a = -gamma, b = gamma;
  const Basis basis = arch_basis(left, right, a, b, modes);
  CAPTURE(basis.description, modes);
  REQUIRE(static_cast<int>(basis.w.size()) == modes);
  REQUIRE(static_cast<int>(basis.u.size()) == modes);
  for (const TrigPolynomial& phi : basis.w) {
    check_end(phi, a, w_fixed(left), slope_fixed(left), a, b);
    check_end(phi, b, w_fixed(right), slope_fixed(right), a, b);
  }
  for (const TrigPolynomial& psi : basis.u) {
    CAPTURE(psi.to_string());
    check_end(psi, a, u_fixed(left), false, a, b);
    check_end(psi, b, u_fixed(right), false, a, b);
    // u free at both ends: zero mean, the gauge that excludes the rigid rotation u = const.
    if (!u_fixed(left) && !u_fixed(right)) CHECK(std::abs(psi.integral(a, b)) <= 1e-13 * (b - a));
  }
}

TEST_CASE("ritz basis: arch u functions have their inextensional partner w = u' in the basis", "[ritz][basis]") {
  // For each u_i, the L2 distance of u_i' from the span of the w functions, relative to |u_i'|.
  // Zero (round-off) means the pair (u_i, w = u_i') has no membrane strain: no locking.
  const EndSupport ends = GENERATE(EndSupport::roller, EndSupport::pinned, EndSupport::clamped);
  const double gamma = 10.0 * pi / 180.0, a = -gamma, b = gamma;
  const int modes = 8;
  const Basis basis = arch_basis(ends, ends, a, b, modes);
  CAPTURE(basis.description);
  Eigen::MatrixXd ww(modes, modes);
  for (int i = 0; i < modes; ++i)
    for (int j = 0; j < modes; ++j) ww(i, j) = (basis.w[i] * basis.w[j]).integral(a, b);
  int inextensional = 0;
  for (int i = 0; i < modes; ++i) {
    const TrigPolynomial du = basis.u[i].derivative();
    Eigen::VectorXd wu(modes);
    for (int j = 0; j < modes; ++j) wu[j] = (basis.w[j] * du).integral(a, b);
    const Eigen::VectorXd c = ww.ldlt().solve(wu);
    TrigPolynomial mismatch = du;  // u_i' minus its L2 projection on the w span
    for (int j = 0; j < modes; ++j) mismatch -= c[j] * basis.w[j];
    const double distance2 = (mismatch * mismatch).integral(a, b), norm2 = (du * du).integral(a, b);
    CAPTURE(i, distance2 / norm2);
    if (distance2 <= 1e-20 * norm2)
      ++inextensional;
    else
      CHECK(distance2 >= 1e-4 * norm2);  // a missing partner is missing by a lot
  }
  // Where u is fixed at both ends, the last two u are the end-strain functions (no partner).
  CHECK(inextensional == (ends == EndSupport::roller ? modes : modes - 2));
}

TEST_CASE("ritz basis: roller arches hold the seed's symmetric family and its antisymmetric half", "[ritz][basis]") {
  // w_j = sin(j pi psi): odd j is +-cos(j pi theta/(2 gamma)) (the seed's eq. 5.2), even j is
  // +-sin((j/2) pi theta/gamma); u_j = +-cos(j pi psi) correspondingly.
  const double gamma = 10.0 * pi / 180.0;
  const Basis basis = arch_basis(EndSupport::roller, EndSupport::roller, -gamma, gamma, 4);
  for (double theta : {-0.1, 0.03, 0.15}) {
    CHECK(std::abs(basis.w[0](theta)) == Approx(std::cos(pi * theta / (2 * gamma))).epsilon(1e-12));
    CHECK(std::abs(basis.w[2](theta)) == Approx(std::abs(std::cos(3 * pi * theta / (2 * gamma)))).epsilon(1e-12));
    CHECK(std::abs(basis.w[1](theta)) == Approx(std::abs(std::sin(pi * theta / gamma))).epsilon(1e-12));
    CHECK(std::abs(basis.u[0](theta)) == Approx(std::abs(std::sin(pi * theta / (2 * gamma)))).epsilon(1e-12));
    CHECK(std::abs(basis.u[1](theta)) == Approx(std::abs(std::cos(pi * theta / gamma))).epsilon(1e-12));
  }
}
