// Hobbs' vertical upheaval mode (verification/closed_form/upheaval.hpp) against the constants the
// literature quotes, each to half a unit of its last quoted digit.
#include "closed_form/upheaval.hpp"

#include <catch2/catch.hpp>
#include <cmath>

using namespace liftoff::closed_form;

TEST_CASE("Hobbs' vertical mode: P L^2/EI = 80.76, uplift 2.407e-3 q L^4/EI, crown moment 0.06938 q L^2",
          "[verification][beam_column]") {
  const UpheavalMode mode = hobbs_vertical_mode();
  CHECK(mode.z > M_PI);
  CHECK(mode.z < 1.5 * M_PI);
  CHECK(std::abs(std::tan(mode.z) - mode.z) <= 1e-12 * mode.z);
  CHECK(std::abs(mode.load_parameter - 80.76) <= 0.005);
  CHECK(std::abs(mode.uplift - 2.407e-3) <= 0.0005e-3);
  CHECK(std::abs(mode.crown_moment + 0.06938) <= 0.000005);
}

TEST_CASE("Hobbs' vertical mode: the deflection meets the touch-down conditions and lifts the crown",
          "[verification][beam_column]") {
  const UpheavalMode mode = hobbs_vertical_mode();
  CHECK(hobbs_vertical_deflection(0.0) == Approx(-mode.uplift).epsilon(1e-13));
  CHECK(hobbs_vertical_deflection(0.3) == hobbs_vertical_deflection(-0.3));
  CHECK(hobbs_vertical_deflection(0.7) == 0.0);
  // w, w' and w'' vanish at the touch-down points: central differences on the zone's side of
  // x = 1/2 extended by the formula (smooth across), truncation h^2 / 6 |w'''| with |w'''| <= 1.
  const double a = 0.5, h = 1e-4;
  auto w = [](double x) {
    const UpheavalMode m = hobbs_vertical_mode();
    const double n = 2 * m.z, p = m.load_parameter, b = 1.0 / (p * n * n * std::cos(m.z));
    return -b * std::cos(m.z) - 1.0 / (8 * p) + b * std::cos(n * x) + x * x / (2 * p);
  };
  CHECK(std::abs(w(a)) <= 1e-15);
  CHECK(std::abs((w(a + h) - w(a - h)) / (2 * h)) <= h * h);
  CHECK(std::abs((w(a + h) - 2 * w(a) + w(a - h)) / (h * h)) <= 1e-6);
  CHECK(hobbs_vertical_deflection(a - h) == Approx(w(a - h)).epsilon(1e-14));
}
