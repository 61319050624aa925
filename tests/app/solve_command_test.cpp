// `liftoff solve` as a library call: what method = auto picks and says, and fields computed
// only when asked for.

#include <catch2/catch.hpp>

#include "app/solve_command.hpp"
#include "support/scenes.hpp"

using namespace liftoff;
using scene::Method;

TEST_CASE("auto: Ritz when the scene gives the contact topology, an FE method otherwise", "[app][auto]") {
  auto scene = test::shipped_scene("seed_beam_end_moments_central_load");
  app::SolveRequest request;
  request.method = Method::automatic;
  const io::SolveReport small = app::solve_scene(scene, request);
  CHECK(small.method == "dual");
  CHECK_THAT(small.method_reason, Catch::StartsWith("dual:"));
  request.elements = 4000;
  const io::SolveReport big = app::solve_scene(scene, request);
  CHECK(big.method == "fast");
  CHECK_THAT(big.method_reason, Catch::StartsWith("fast:") && Catch::Contains("O(n)"));
  CHECK(big.active_set_iterations > 0);

  scene.ritz.topology = {true, false, true};  // contact, lift-off, contact
  request.elements.reset();
  const io::SolveReport ritz = app::solve_scene(scene, request);
  CHECK(ritz.method == "ritz");
  CHECK_THAT(ritz.method_reason, Catch::StartsWith("ritz:") && Catch::Contains("[ritz]"));
  CHECK(ritz.usable);
}

TEST_CASE("fields are sampled only when asked for; the extremes are the same either way", "[app][fields]") {
  const auto scene = test::shipped_scene("seed_beam_end_moments_central_load");
  app::SolveRequest request;
  request.method = Method::fast;
  const io::SolveReport with_fields = app::solve_scene(scene, request);
  request.fields = false;
  const io::SolveReport without = app::solve_scene(scene, request);
  CHECK(without.fields.w.empty());
  CHECK_FALSE(with_fields.fields.w.empty());
  // The same sample points, the same arithmetic: equal, not merely close.
  CHECK(without.w_max == with_fields.w_max);
  CHECK(without.at_w_max == with_fields.at_w_max);
  CHECK(without.w_min == with_fields.w_min);
  CHECK(without.at_w_min == with_fields.at_w_min);
  CHECK(without.max_reaction == with_fields.max_reaction);
}
