// The curved (arch) element: exact strains for polynomial fields, zero energy for the rigid
// rotation about the centre, and no membrane locking: an inextensional deflection stores no
// membrane energy however stiff the membrane is.
#include "fe/arch_element.hpp"

#include <Eigen/Dense>
#include <catch2/catch.hpp>

#include "fe/shape_functions.hpp"

using namespace liftoff::fe;

namespace {

// Local dofs (w0, w0', w1, w1', u at xi = 0, 1/4, 1/2, 3/4, 1) of the fields w(t), u(t).
template <typename W, typename DW, typename U>
Eigen::Matrix<double, 9, 1> local_dofs(double h, W w, DW dw, U u) {
  Eigen::Matrix<double, 9, 1> dofs;
  dofs << w(0.0), dw(0.0), w(h), dw(h), u(0.0), u(0.25 * h), u(0.5 * h), u(0.75 * h), u(h);
  return dofs;
}

}  // namespace

TEST_CASE("arch element: rigid rotation about the centre stores no energy", "[fe][arch]") {
  const double h = 0.0175, membrane = 3e6;
  const auto k = arch_element::stiffness(h, membrane);
  Eigen::Matrix<double, 9, 1> rotation;
  rotation << 0, 0, 0, 0, 1, 1, 1, 1, 1;  // u = 1, w = 0
  CHECK(rotation.dot(k * rotation) <= 1e-14 * k.norm());
}

TEST_CASE("arch element: inextensional deflections are free of membrane locking", "[fe][arch]") {
  // w cubic and u = integral of w (quartic): the membrane strain u' - w vanishes identically.
  // A locking element cannot represent this and charges it EA R^2/EI times too much energy.
  const double h = GENERATE(0.0175, 0.2);
  auto w = [](double t) { return 0.3 - 2.0 * t + 5.0 * t * t - 40.0 * t * t * t; };
  auto dw = [](double t) { return -2.0 + 10.0 * t - 120.0 * t * t; };
  auto u = [](double t) { return 0.3 * t - t * t + 5.0 / 3.0 * t * t * t - 10.0 * t * t * t * t; };
  const auto dofs = local_dofs(h, w, dw, u);

  double membrane_integral = 0.0;  // integral of eps^2, the element's own quadrature
  for (const GaussPoint& g : gauss5) {
    const double eps = arch_element::membrane_strain_row(g.xi, h).dot(dofs);
    CHECK(std::abs(eps) <= 1e-13);
    membrane_integral += g.weight * h * eps * eps;
  }
  const double bending_only = dofs.dot(arch_element::stiffness(h, 0.0) * dofs);
  // Even at EA R^2/EI = 1e9 (R/h of about 1e4) the membrane adds nothing measurable.
  CHECK(1e9 * membrane_integral <= 1e-12 * bending_only);
  // And the assembled stiffness agrees, up to the round-off of u^T K u, which cancels terms of
  // size |K| |u|^2 down to the bending energy.
  const auto k = arch_element::stiffness(h, 3e6);
  const double roundoff = 64 * std::numeric_limits<double>::epsilon() * k.norm() * dofs.squaredNorm();
  CHECK(std::abs(dofs.dot(k * dofs) - bending_only) <= roundoff);
}

TEST_CASE("arch element: energies of polynomial fields are integrated exactly", "[fe][arch]") {
  // w = t^3, u = t^2 on [0, h]: eps = 2t - t^3, chi = 2t + 6t = 8t.
  const double h = 0.3, membrane = 7.0;
  auto w = [](double t) { return t * t * t; };
  auto dw = [](double t) { return 3 * t * t; };
  auto u = [](double t) { return t * t; };
  const auto dofs = local_dofs(h, w, dw, u);
  // int (2t - t^3)^2 = 4h^3/3 - 4h^5/5 + h^7/7 ; int (8t)^2 = 64h^3/3
  const double membrane_energy = 4 * std::pow(h, 3) / 3 - 4 * std::pow(h, 5) / 5 + std::pow(h, 7) / 7;
  const double bending_energy = 64 * std::pow(h, 3) / 3;
  CHECK(dofs.dot(arch_element::stiffness(h, membrane) * dofs) ==
        Approx(membrane * membrane_energy + bending_energy).epsilon(1e-13));
}

TEST_CASE("arch element: the mixed form gives the stiffness exactly, membrane stiffness up to 1e7",
          "[fe][arch][mixed]") {
  const double h = GENERATE(0.0175, 1e-4);
  const double membrane = GENERATE(3e2, 3e6, 1e7);
  CAPTURE(h, membrane);
  const auto g = arch_element::stress_coupling(h);
  const auto c = arch_element::compliance(h, membrane);
  const Eigen::Matrix<double, 9, 9> from_mixed = g.transpose() * c.cwiseInverse().asDiagonal() * g;
  const auto k = arch_element::stiffness(h, membrane);
  // Both are Gauss sums of products of the same strain rows (a few dozen operations each).
  CHECK((from_mixed - k).norm() <= 64 * std::numeric_limits<double>::epsilon() * k.norm());
}
