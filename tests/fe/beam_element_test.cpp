// The beam and foundation element matrices against closed forms.
#include "fe/beam_element.hpp"

#include <Eigen/Dense>
#include <catch2/catch.hpp>

#include "fe/foundation_element.hpp"
#include "fe/shape_functions.hpp"

using namespace liftoff::fe;

namespace {
// Round-off bound for matrices of entries up to `scale` built from a few dozen operations.
double roundoff(double scale) { return 64 * std::numeric_limits<double>::epsilon() * scale; }
}  // namespace

TEST_CASE("beam stiffness is the exact bending energy of a cubic", "[fe][beam]") {
  // For w(s) = a + b s + c s^2 + d s^3 on [0, h], the energy integral of w''^2 is exact:
  // int (2c + 6 d s)^2 ds = 4c^2 h + 12 c d h^2 + 12 d^2 h^3.
  const double h = GENERATE(1.0, 0.37, 1e-3);
  const double a = 0.3, b = -1.1, c = 2.5, d = -0.7;
  auto w = [&](double s) { return a + s * (b + s * (c + s * d)); };
  auto dw = [&](double s) { return b + s * (2 * c + s * 3 * d); };
  const Eigen::Vector4d dofs(w(0), dw(0), w(h), dw(h));
  const double exact = 4 * c * c * h + 12 * c * d * h * h + 12 * d * d * h * h * h;
  const Eigen::Matrix4d k = beam_element::stiffness(h);
  CAPTURE(h);
  // u^T K u cancels terms of size |K| |u|^2 down to the energy: allow that round-off.
  CHECK(std::abs(dofs.dot(k * dofs) - exact) <= roundoff(k.norm() * dofs.squaredNorm()));
  // Rigid motions (translation, rotation) store no energy.
  CHECK((k * Eigen::Vector4d(1, 0, 1, 0)).norm() <= roundoff(k.norm()));
  CHECK((k * Eigen::Vector4d(0, 1, h, 1)).norm() <= roundoff(k.norm()));
  CHECK((k - k.transpose()).norm() == 0.0);
}

TEST_CASE("foundation coupling and flexibility match their closed forms", "[fe][foundation]") {
  const double h = GENERATE(1.0, 0.05);
  const double k = 1e4;
  Eigen::Matrix<double, 2, 4> coupling;
  coupling << 7.0 / 20, h / 20, 3.0 / 20, -h / 30,  //
      3.0 / 20, h / 30, 7.0 / 20, -h / 20;
  coupling *= h;
  CHECK((foundation_element::coupling(h) - coupling).norm() <= roundoff(coupling.norm()));
  Eigen::Matrix2d flexibility;
  flexibility << h / 3, h / 6, h / 6, h / 3;
  flexibility /= k;
  CHECK((foundation_element::flexibility(h, k) - flexibility).norm() <= roundoff(flexibility.norm()));
}

TEST_CASE("Hermite shape functions interpolate and differentiate a cubic exactly", "[fe][shape]") {
  const double h = 0.4;
  auto w = [](double s) { return 1 - 2 * s + 3 * s * s - 5 * s * s * s; };
  const Eigen::Vector4d dofs(w(0), -2, w(h), -2 + 6 * h - 15 * h * h);
  for (double xi : {0.0, 0.2, 0.5, 0.9, 1.0}) {
    const double s = xi * h;
    const HermiteCubic n = hermite_cubic(xi, h);
    CHECK(n.value.dot(dofs) == Approx(w(s)).margin(1e-14));
    CHECK(n.d1.dot(dofs) == Approx(-2 + 6 * s - 15 * s * s).margin(1e-13));
    CHECK(n.d2.dot(dofs) == Approx(6 - 30 * s).margin(1e-12));
    CHECK(n.d3.dot(dofs) == Approx(-30).margin(1e-11));
  }
}

TEST_CASE("the mixed form of the beam element gives its stiffness exactly", "[fe][beam][mixed]") {
  const double h = GENERATE(1.0, 0.37, 1e-3, 1e-6);
  CAPTURE(h);
  const Eigen::Matrix<double, 2, 4> g = beam_element::stress_coupling(h);
  const Eigen::Vector2d c = beam_element::compliance(h);
  const Eigen::Matrix4d from_mixed = g.transpose() * c.cwiseInverse().asDiagonal() * g;
  const Eigen::Matrix4d k = beam_element::stiffness(h);
  // Both sides are a few products of entries up to |K|: round-off only.
  CHECK((from_mixed - k).norm() <= roundoff(k.norm()));
  // The rounded G keeps the rigid motions in its kernel exactly: its entries are integers and
  // +-2/h, and rotation (h, 1) gives -2/h * h + ... with 2/h * h = 2 to the last bit or so.
  CHECK((g * Eigen::Vector4d(1, 0, 1, 0)).norm() == 0.0);
  CHECK((g * Eigen::Vector4d(0, 1, h, 1)).norm() <= 4 * std::numeric_limits<double>::epsilon());
}
