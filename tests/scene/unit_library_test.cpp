// Tests of src/scene/unit_library.*: a quantity's number and unit, conversions between units of
// one dimension (exact where one way is an integer factor), and the refusals.
#include "scene/unit_library.hpp"

#include <catch2/catch.hpp>
#include <cmath>

using namespace liftoff::scene::unit_library;

namespace {

double converted(double number, const char* from, const char* to, bool difference = false) {
  const Conversion c = convert(number, from, to, difference);
  REQUIRE(c.outcome == Outcome::converted);
  return c.value;
}

}  // namespace

TEST_CASE("unit library: a quantity splits into its number and its unit", "[scene][units]") {
  const auto q = split("3.12e7 N m^2");
  REQUIRE(q);
  CHECK(q->number == 3.12e7);
  CHECK(q->unit == "N m^2");
  CHECK(split("1800mm")->unit == "mm");
  CHECK(split("  +5 kN ")->number == 5.0);
  CHECK(split("-2.5 kN")->number == -2.5);
  CHECK(split("7")->unit.empty());
  CHECK_FALSE(split("stiff"));
  CHECK_FALSE(split(""));
  CHECK_FALSE(split("kN 5"));
}

TEST_CASE("unit library: decimal prefixes convert exactly, as the number written in the target unit",
          "[scene][units]") {
  // One division by an exact integer is correctly rounded: the double of the decimal the user
  // would have written in the target unit, bit for bit.
  CHECK(converted(5.4e8, "N m^2", "kN m^2") == 5.4e5);
  CHECK(converted(3.12e7, "N m^2", "kN m^2") == 3.12e4);
  CHECK(converted(1800, "mm", "m") == 1.8);
  CHECK(converted(30, "MN/m^2", "kN/m^2") == 3.0e4);
  CHECK(converted(100, "kN", "N") == 1.0e5);
  CHECK(converted(30, "N/mm^2", "kN/m^2") == 3.0e4);
  CHECK(converted(2.5, "kN m", "N m") == 2500.0);
  CHECK(converted(5, "N.m2", "kN*m^2") == 5.0e-3);
}

TEST_CASE("unit library: US customary units convert by their definitions", "[scene][units]") {
  // 1 lbf = 4.4482216152605 N and 1 ft = 0.3048 m exactly (their definitions); a few roundings.
  const double lbf = 4.4482216152605, ft = 0.3048, round_off = 1e-15;
  CHECK(converted(1, "kip", "kN") == Approx(lbf).epsilon(round_off));
  CHECK(converted(1, "kN", "kip") == Approx(1 / lbf).epsilon(4 * round_off));
  CHECK(converted(1, "kip ft^2", "kN m^2") == Approx(lbf * ft * ft).epsilon(4 * round_off));
  CHECK(converted(120, "in", "ft") == Approx(10.0).epsilon(round_off));
  CHECK(converted(3, "m", "ft") == Approx(3 / ft).epsilon(round_off));
  CHECK(converted(1, "psi", "kN/m^2") == Approx(lbf / (0.0254 * 0.0254) / 1000).epsilon(4 * round_off));
}

TEST_CASE("unit library: a temperature difference converts by the slope, a temperature with its offset",
          "[scene][units]") {
  CHECK(converted(36, "degF", "K", true) == Approx(20.0).epsilon(1e-14));
  CHECK(converted(20, "degC", "K", true) == Approx(20.0).epsilon(1e-14));
  CHECK(converted(20, "degC", "K") == Approx(293.15).epsilon(1e-14));
  CHECK(converted(1e-5, "1/degF", "1/K") == Approx(1.8e-5).epsilon(1e-14));
}

TEST_CASE("unit library: unknown units and other dimensions are refused", "[scene][units]") {
  CHECK(convert(1, "furlongz", "m").outcome == Outcome::unknown_unit);
  CHECK(convert(1, "m", "spans").outcome == Outcome::unknown_target);
  CHECK(convert(1, "kN/m^3", "kN/m^2").outcome == Outcome::wrong_dimension);
  CHECK(convert(1, "kN", "kN m").outcome == Outcome::wrong_dimension);
  CHECK(known("kN m^2"));
  CHECK_FALSE(known("kNN"));
  CHECK(convertible("kip/ft", "N/m"));
  CHECK_FALSE(convertible("N", "m"));
  CHECK(dimensionless("percent"));
  CHECK_FALSE(dimensionless("m"));
}
