// Arch loads in any direction: the consistent nodal forces of fe/arch_loads.hpp, worked on the
// arch's rigid motions, give the load's resultant and moment about the centre computed by hand in
// global components. The rigid motions are interpolated by the element (w Hermite cubic, u
// Lagrange quartic), so the work differs from the exact resultant by the interpolation error of
// cos and sin: at most h^4/384 (Hermite) per unit load and arc, plus the quartic's ~h^5/120; the
// tolerance is twice the Hermite bound times the load's total, and the error falls like h^4.
#include "fe/arch_loads.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "fe/shape_functions.hpp"
#include "support/solve.hpp"

using namespace liftoff;
using model::LoadBasis;
using model::LoadDirection;

namespace {

// Rigid motion j at theta as (u, w, w') with w > 0 inward: 0 x translation, 1 y translation (up),
// 2 rotation about the centre (u = 1, clockwise). Outside, w and w' change sign.
Eigen::Vector3d rigid(int j, double t, bool outside) {
  const double c = std::cos(t), s = std::sin(t), sign = outside ? -1.0 : 1.0;
  if (j == 0) return {c, sign * -s, sign * -c};
  if (j == 1) return {-s, sign * -c, sign * s};
  return {1.0, 0.0, 0.0};
}

// The work of a distributed load on [a, b] (n elements) on the three rigid motions.
Eigen::Vector3d work(double a, double b, int n, LoadDirection direction, LoadBasis per, bool outside, double q) {
  Eigen::Vector3d out = Eigen::Vector3d::Zero();
  const double h = (b - a) / n;
  for (int e = 0; e < n; ++e) {
    const double s0 = a + e * h;
    const auto f = fe::arch_element_load(s0, h, direction, per, outside, [&](double) { return q; });
    for (int j = 0; j < 3; ++j) {
      Eigen::Matrix<double, 9, 1> m;
      const Eigen::Vector3d m0 = rigid(j, s0, outside), m1 = rigid(j, s0 + h, outside);
      m.head<4>() << m0[1], m0[2], m1[1], m1[2];
      for (int i = 0; i < 5; ++i) m[4 + i] = rigid(j, s0 + fe::quartic_nodes[i] * h, outside)[0];
      out[j] += f.dot(m);
    }
  }
  return out;
}

}  // namespace

TEST_CASE("arch loads: resultants in global components, inside and outside", "[fe][arch]") {
  const double a = -1.1, b = 0.7, q = 2.5;  // an asymmetric range, radians
  // By hand, x right and y up, the point at (sin t, cos t): a vertical load q per arc has
  // Fy = -q (b - a) and moment about the centre (x Fy - y Fx) = -q int sin = q (cos b - cos a);
  // per projection (q cos t per arc) Fy = -q (sin b - sin a), moment -q int sin cos =
  // q (cos^2 b - cos^2 a) / 2. Work on the motions: x -> Fx, y -> Fy, u = 1 (clockwise) -> -moment.
  struct Case {
    LoadDirection direction;
    LoadBasis per;
    Eigen::Vector3d expected;
  };
  const Case cases[] = {
      {LoadDirection::vertical, LoadBasis::arc, {0.0, -q * (b - a), -q * (std::cos(b) - std::cos(a))}},
      {LoadDirection::vertical,
       LoadBasis::projection,
       {0.0, -q * (std::sin(b) - std::sin(a)), -0.5 * q * (std::pow(std::cos(b), 2) - std::pow(std::cos(a), 2))}},
      // Radial toward an inside foundation: -q (sin t, cos t), no moment about the centre.
      {LoadDirection::radial, LoadBasis::arc, {q * (std::cos(b) - std::cos(a)), -q * (std::sin(b) - std::sin(a)), 0.0}},
  };
  for (const bool outside : {false, true}) {
    for (const Case& c : cases) {
      CAPTURE(outside, static_cast<int>(c.direction), static_cast<int>(c.per));
      Eigen::Vector3d expected = c.expected;
      if (outside && c.direction == LoadDirection::radial) expected.head<2>() *= -1.0;  // toward the soil outside
      std::vector<double> sizes, errors;
      for (const int n : {8, 16, 32}) {
        const double h = (b - a) / n;
        const double err = (work(a, b, n, c.direction, c.per, outside, q) - expected).lpNorm<Eigen::Infinity>();
        CHECK(err <= 2.0 * q * (b - a) * std::pow(h, 4) / 384.0);
        sizes.push_back(h);
        errors.push_back(err);
      }
      if (errors.back() > 1e-13) CHECK(test::observed_order(sizes, errors) > 3.5);  // h^4, not a wrong direction
    }
  }
}

TEST_CASE("arch point forces: components of each direction", "[fe][arch]") {
  const double t = 0.4, c = std::cos(t), s = std::sin(t);
  using V = Eigen::Vector2d;
  // Inside: w along -(sin t, cos t), u along (cos t, -sin t).
  CHECK((fe::arch_load_components(LoadDirection::radial, LoadBasis::arc, t, false) - V(1, 0)).norm() == 0.0);
  CHECK((fe::arch_load_components(LoadDirection::tangential, LoadBasis::arc, t, false) - V(0, 1)).norm() == 0.0);
  CHECK((fe::arch_load_components(LoadDirection::vertical, LoadBasis::arc, t, false) - V(c, s)).norm() <= 1e-16);
  CHECK((fe::arch_load_components(LoadDirection::horizontal, LoadBasis::arc, t, false) - V(-s, c)).norm() <= 1e-16);
  // Outside, w > 0 is outward: the radial components of the global directions change sign, a
  // radial load still pushes toward the foundation.
  CHECK((fe::arch_load_components(LoadDirection::radial, LoadBasis::arc, t, true) - V(1, 0)).norm() == 0.0);
  CHECK((fe::arch_load_components(LoadDirection::vertical, LoadBasis::arc, t, true) - V(-c, s)).norm() <= 1e-16);
  CHECK((fe::arch_load_components(LoadDirection::horizontal, LoadBasis::arc, t, true) - V(s, c)).norm() <= 1e-16);
}
