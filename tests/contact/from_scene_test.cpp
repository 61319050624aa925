#include "contact/from_scene.hpp"

#include <catch2/catch.hpp>
#include <optional>
#include <stdexcept>

using namespace liftoff;

TEST_CASE("contact method: the scene's FE methods become the contact solver's, by name", "[contact]") {
  for (contact::Method m :
       {contact::Method::dual, contact::Method::primal, contact::Method::fast, contact::Method::automatic}) {
    const std::optional<scene::Method> in_scene = scene::parse_method(contact::to_string(m));
    REQUIRE(in_scene);
    CHECK(contact::to_contact(*in_scene) == m);
    CHECK(from_string<contact::Method>(contact::to_string(m)) == m);  // the table reads back
  }
  CHECK(contact::to_string(contact::Method::automatic) == "auto");
  // The Ritz model and "all" are no contact methods.
  CHECK_THROWS_AS(contact::to_contact(scene::Method::ritz), std::logic_error);
  CHECK_THROWS_AS(contact::to_contact(scene::Method::all), std::logic_error);
}
