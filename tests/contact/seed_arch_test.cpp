// The seed paper's arch (R/h = 500, gamma = 10 deg, k = 1e6, crown load) for pinned, roller and
// clamped ends: one central contact region, and its half-angle converges with the mesh at the
// order of the reaction interpolation (h^2), which also shows the element does not lock.
#include <catch2/catch.hpp>
#include <cstdio>

#include "support/scenes.hpp"
#include "support/solve.hpp"

using namespace liftoff;

namespace {
constexpr double degrees = 180.0 / 3.14159265358979323846;
}

TEST_CASE("seed arch: contact half-angle converges with the mesh for every end condition", "[contact][arch][seed]") {
  const std::string ends = GENERATE("pinned", "roller", "clamped");
  const scene::Scene scene = test::shipped_scene("seed_arch_" + ends);
  const int reference_elements = 640;
  const std::vector<int> meshes{10, 20, 40, 80, 160};

  auto half_angle = [&](int elements) {
    const test::Solved s = test::solve(scene, contact::Method::dual, elements);
    REQUIRE(s.solution.summary.is_usable());
    REQUIRE(s.regions.size() == 1);  // one central contact region
    const double begin = s.regions[0].begin * degrees, end = s.regions[0].end * degrees;
    CHECK(std::abs(begin + end) <= 1e-6 * end);  // symmetric about the crown
    return 0.5 * (end - begin);
  };

  const double reference = half_angle(reference_elements);
  std::vector<double> h, error;
  std::printf("seed arch, %s ends: contact half-angle (deg) against elements\n", ends.c_str());
  for (int n : meshes) {
    const double angle = half_angle(n);
    h.push_back(1.0 / n);
    error.push_back(std::abs(angle - reference));
    std::printf("  %5d  %.9f  error %.2e\n", n, angle, error.back());
  }
  std::printf("  %5d  %.9f  (reference)\n", reference_elements, reference);

  // Observed order over the sequence: the P1 reaction interpolation gives h^2 at best, and a
  // locking element would converge far slower than h^1 on this R/h = 500 arch.
  const double order = test::observed_order(h, error);
  std::printf("  observed order %.2f\n", order);
  CAPTURE(ends, reference, order);
  CHECK(order >= 2.0);
  // With that order, the error of the scene's 200-element mesh extrapolated from the 160-element
  // one is below the 1e-3 degree that the Ritz comparison needs.
  const double error_at_200 = error.back() * std::pow(160.0 / 200.0, order);
  CHECK(error_at_200 < 1e-3);
}
