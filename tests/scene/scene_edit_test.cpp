// Editing one value of a scene's TOML text (for sweeps): the edited scene reads back with the
// new value, integers stay integers, and a path that does not exist is refused by name.
#include "scene/scene_edit.hpp"

#include <catch2/catch.hpp>

#include "core/error.hpp"
#include "scene/scene_reader.hpp"
#include "support/scene_text.hpp"

using namespace liftoff;

namespace {
const std::string text = std::string("\n") + test::beam_text("1.0", "1.0") + R"(k = 1.0e4
[[loads]]
kind = "force"
at = 0.5
value = 1.0
[[loads]]
kind = "moment"
at = 0.0
value = 2.0
[solve]
elements = 40
)";
}  // namespace

TEST_CASE("scene edit: values at table keys, array-of-table keys, integers", "[scene][edit]") {
  std::string edited = scene::with_value(text, "foundation.k", 250.0, "s.toml");
  edited = scene::with_value(edited, "loads[1].value", -3.5, "s.toml");
  edited = scene::with_value(edited, "solve.elements", 80, "s.toml");
  const scene::Scene s = scene::parse_scene(edited, "s.toml");
  CHECK(*s.foundation.k == 250.0);
  CHECK(s.loads[1].value == -3.5);
  CHECK(s.loads[0].value == 1.0);
  CHECK(s.solve.elements == 80);  // still an integer, so the reader accepts it
}

TEST_CASE("scene edit: a path that does not exist is refused by name", "[scene][edit]") {
  CHECK_THROWS_WITH(
      scene::with_value(text, "loads[2].value", 1.0, "s.toml"),
      Catch::Matchers::Contains("key 'loads[2].value'") && Catch::Matchers::Contains("no [[loads]] number 2"));
  CHECK_THROWS_WITH(scene::with_value(text, "ritz.modes", 8, "s.toml"), Catch::Matchers::Contains("no [ritz] table"));
  CHECK_THROWS_AS(scene::with_value(text, "foundation", 1.0, "s.toml"), InputError);
  // An index too large for any integer type is a missing table like any other (was std::stoi's
  // out_of_range: exit 1).
  CHECK_THROWS_WITH(scene::with_value(text, "loads[99999999999].value", 1.0, "s.toml"),
                    Catch::Matchers::Contains("no [[loads]] number 99999999999"));
  CHECK_THROWS_WITH(scene::with_value(text, "loads[99999999999999999999999999].value", 1.0, "s.toml"),
                    Catch::Matchers::Contains("no [[loads]] number 99999999999999999999999999"));
  CHECK_THROWS_AS(scene::with_value(text, "loads[-1].value", 1.0, "s.toml"), InputError);
  CHECK_THROWS_AS(scene::with_value(text, "loads[].value", 1.0, "s.toml"), InputError);
}
