// The seed's arch beyond linear theory (verification/seed_arch/departure.hpp): the claims of
// verification/report/report.md's section 5, on 200 and 100 elements (the report's table uses 400
// and 200; the figures agree to ~3e-5 across those meshes, so the tolerances below, 1e-3 on the
// departures and 2e-4 on the 1 % load factors, are 30 times the mesh's effect and far below the
// effects claimed: a broken von Karman arch solve moves these by their own size).
#include <catch2/catch.hpp>
#include <cmath>

#include "seed_arch/departure.hpp"
#include "support/scenes.hpp"

using namespace liftoff;

namespace {

struct Claim {
  const char* ends;
  double deflection, half_angle;                    // (von Karman - linear) / linear at the seed's load
  double deflection_crossing, half_angle_crossing;  // lambda where each first reaches 1 %
};

}  // namespace

TEST_CASE("seed arch beyond linear theory: the departures at the seed's load and the 1 % load factors",
          "[verification][von_karman][arch]") {
  const Claim claim =
      GENERATE(Claim{"pinned", 0.13626, 0.5585, 0.0150, 0.0218}, Claim{"clamped", 0.27751, 0.6405, 0.0110, 0.0287});
  for (int elements : {200, 100}) {
    const study::SeedArchStudy arch(test::shipped_scene(std::string("seed_arch_") + claim.ends), elements);
    contact::VonKarmanResult state;
    study::DepartureRow row;
    for (double lambda : {0.25, 0.5, 0.75, 1.0}) {
      row = arch.row(lambda, &state);
      REQUIRE(row.linear.usable);
      REQUIRE(row.von_karman.usable);
      CHECK(row.von_karman.stable);
    }
    CAPTURE(claim.ends, elements, row.deflection(), row.half_angle(), row.thrust());
    CHECK(std::abs(row.deflection() - claim.deflection) < 1e-3);
    CHECK(std::abs(row.half_angle() - claim.half_angle) < 2e-3);
    // The thrust is all but gone (|N_vK| below 5 % of the linear thrust: 4.0 % pinned, in tension;
    // 2.7 % clamped): the arch action is lost.
    CHECK(std::abs(row.von_karman.crown_thrust) < 0.05 * row.linear.crown_thrust);
    // The seed's linear figures (report section 4 and the issue: w(0)/R = 0.007, N(0) = 0.129).
    if (std::string(claim.ends) == "pinned") {
      CHECK(row.linear.crown_deflection == Approx(7.011e-3).epsilon(1e-3));
      CHECK(row.linear.crown_thrust * 1.4 / 1e4 == Approx(0.1287).epsilon(2e-3));
    }
    contact::VonKarmanResult start;
    const double d = study::crossing(arch, &study::DepartureRow::deflection, 0.01, 0.0, 0.05, 1e-4, start);
    const double a = study::crossing(arch, &study::DepartureRow::half_angle, 0.01, 0.0, 0.05, 1e-4, start);
    CAPTURE(d, a);
    CHECK(std::abs(d - claim.deflection_crossing) < 2e-4);
    CHECK(std::abs(a - claim.half_angle_crossing) < 2e-4);
  }
}

TEST_CASE("seed arch beyond linear theory: roller ends carry no thrust, and von Karman is linear to 1e-4",
          "[verification][von_karman][arch]") {
  const study::SeedArchStudy arch(test::shipped_scene("seed_arch_roller"), 200);
  contact::VonKarmanResult state;
  for (double lambda : {0.5, 1.0, 2.0}) {
    const study::DepartureRow row = arch.row(lambda, &state);
    REQUIRE(row.von_karman.usable);
    CAPTURE(lambda, row.deflection(), row.half_angle());
    CHECK(std::abs(row.deflection()) < 1e-4);
    CHECK(std::abs(row.half_angle()) < 1e-4);
  }
}
