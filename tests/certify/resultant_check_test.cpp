// The resultant check: a member only the foundation holds is answered no_equilibrium before any
// solver runs when compressive reactions cannot balance its loads, and left to the solvers when
// they can.

#include "certify/resultant_check.hpp"

#include <catch2/catch.hpp>

#include "fe/discretisation.hpp"
#include "model/from_scene.hpp"
#include "support/scenes.hpp"

using namespace liftoff;
using scene::EndSupport;

namespace {
certify::ResultantCheck check_scene(const scene::Scene& s, int elements = 40) {
  const model::MemberModel model = model::make_member_model(s);
  return certify::check_resultant(model, fe::discretise(model, elements));
}
}  // namespace

TEST_CASE("free-free beam: the net load must press into the foundation", "[certify][resultant]") {
  scene::Scene s = test::beam_scene(2.0, 1e6, EndSupport::free, EndSupport::free, 100.0);
  s.loads = {test::point_force(1.0, -1000.0)};  // pulls the beam off the foundation
  const certify::ResultantCheck pulled = check_scene(s);
  CHECK(pulled.applies);
  CHECK(pulled.rigid_motions == 2);
  CHECK_FALSE(pulled.balanced);
  CHECK_THAT(pulled.message,
             Catch::Contains("no equilibrium") && Catch::Contains("1000") && Catch::Contains("away from"));
  s.loads = {test::point_force(1.0, 1000.0)};
  CHECK(check_scene(s).balanced);
}

TEST_CASE("free-free beam: the line of action must fall inside the foundation", "[certify][resultant]") {
  // A force P at the middle with a moment M moves the line of action by -M/P (counterclockwise
  // positive): outside the beam for |M| > P L/2, inside for less.
  scene::Scene s = test::beam_scene(2.0, 1e6, EndSupport::free, EndSupport::free, 100.0);
  s.loads = {test::point_force(1.0, 1000.0), test::point_moment(1.0, -1100.0)};  // line of action x = 2.1
  const certify::ResultantCheck outside = check_scene(s);
  CHECK_FALSE(outside.balanced);
  CHECK_THAT(outside.message, Catch::Contains("x = 2.1") && Catch::Contains("outside"));
  s.loads = {test::point_force(1.0, 1000.0), test::point_moment(1.0, -900.0)};  // x = 1.9: inside
  CHECK(check_scene(s).balanced);
  // A foundation on part of the beam only: x = 1.9 is outside [0, 1.5].
  s.foundation.to = 1.5;
  CHECK_FALSE(check_scene(s).balanced);
}

TEST_CASE("one pin: the loads' moment about it must press the member into the foundation", "[certify][resultant]") {
  scene::Scene s = test::beam_scene(1.0, 1.0, EndSupport::pinned, EndSupport::free, 100.0);
  s.loads = {test::point_force(0.5, -1.0)};  // turns the beam about x = 0, away from the foundation
  const certify::ResultantCheck away = check_scene(s);
  CHECK(away.applies);
  CHECK(away.rigid_motions == 1);
  CHECK_FALSE(away.balanced);
  s.loads = {test::point_force(0.5, 1.0)};
  CHECK(check_scene(s).balanced);
}

TEST_CASE("supported members and bilateral foundations: the check does not apply", "[certify][resultant]") {
  scene::Scene s = test::beam_scene(1.0, 1.0, EndSupport::pinned, EndSupport::pinned, 100.0);
  s.loads = {test::point_force(0.5, -1.0)};
  CHECK_FALSE(check_scene(s).applies);
  CHECK(check_scene(s).balanced);
  scene::Scene bilateral = test::beam_scene(1.0, 1.0, EndSupport::free, EndSupport::free, 100.0, false);
  bilateral.loads = {test::point_force(0.5, -1.0)};
  CHECK_FALSE(check_scene(bilateral).applies);
}
