// Tests of src/model/from_scene.*: the scene's theory and the ends' axial restraints reach the
// member model, with the von Karman beam's membrane stiffness EA L^2/EI (issue 16).

#include "model/from_scene.hpp"

#include <catch2/catch.hpp>
#include <string>

#include "scene/scene_reader.hpp"

using namespace liftoff;

namespace {

const std::string beam = R"([structure]
kind = "beam"
length = 2.0
EI = 3.0
EA = 6.0e4

[supports]
left = "pinned"
right = "clamped"

[foundation]
nondimensional_k = 1.0e2

[[loads]]
kind = "uniform"
value = 1.0
)";

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}

model::MemberModel model_of(const std::string& text) {
  return model::make_member_model(scene::parse_scene(text, "scene.toml"));
}

}  // namespace

TEST_CASE("the model of a linear scene: no membrane stiffness for a beam, whatever its EA", "[model][von_karman]") {
  const model::MemberModel m = model_of(beam);
  CHECK(m.theory == model::Theory::linear);
  CHECK(m.membrane_stiffness == 0.0);
  CHECK(model::to_model(scene::Theory::von_karman) == model::Theory::von_karman);
  CHECK(model::to_model(scene::Theory::linear) == model::Theory::linear);
}

TEST_CASE("von Karman: the theory, EA L^2/EI and the ends' axial restraints reach the model", "[model][von_karman]") {
  const std::string von_karman = replaced(beam, "kind = \"beam\"", "kind = \"beam\"\ntheory = \"von_karman\"");
  SECTION("the defaults: pinned and clamped ends restrained") {
    const model::MemberModel m = model_of(von_karman);
    CHECK(m.theory == model::Theory::von_karman);
    CHECK(m.membrane_stiffness == 6.0e4 * 2.0 * 2.0 / 3.0);  // 8e4, exact in binary
    CHECK(m.left_axially_restrained);
    CHECK(m.right_axially_restrained);
  }
  SECTION("as written, and a free end free") {
    const model::MemberModel m =
        model_of(replaced(replaced(von_karman, "left = \"pinned\"", "left = { kind = \"pinned\", axial = \"free\" }"),
                          "right = \"clamped\"", "right = \"free\""));
    CHECK_FALSE(m.left_axially_restrained);
    CHECK_FALSE(m.right_axially_restrained);
    CHECK(m.left == model::EndSupport::pinned);
    CHECK(m.right == model::EndSupport::free);
  }
  SECTION("a spring end restrained when asked") {
    const model::MemberModel m = model_of(replaced(
        von_karman, "right = \"clamped\"", "right = { kind = \"spring\", stiffness = 5.0, axial = \"restrained\" }"));
    CHECK(m.left_axially_restrained);
    CHECK(m.right_axially_restrained);
    CHECK(m.right == model::EndSupport::free);  // a spring end is otherwise free
  }
  SECTION("an initial half sine is kept exact beside its table: the shallow arch") {
    const model::MemberModel m =
        model_of(von_karman + "\n[geometry]\ninitial_shape = { shape = \"half_sine\", amplitude = -0.12 }\n");
    REQUIRE(m.initial_sine.has_value());
    CHECK(m.initial_sine->amplitude == -0.06);  // over L = 2
    CHECK(m.initial_sine->from == 0.0);
    CHECK(m.initial_sine->length == 1.0);
  }
}

TEST_CASE("the model of an arch scene keeps its membrane stiffness EA R^2/EI under linear theory",
          "[model][von_karman]") {
  const model::MemberModel m = model_of(R"([structure]
kind = "arch"
radius = 10.0
half_angle_deg = 20.0
EI = 2.0
EA = 4.0e3
[supports]
left = "pinned"
right = "pinned"
[foundation]
nondimensional_k = 1.0e3
)");
  CHECK(m.theory == model::Theory::linear);
  CHECK(m.membrane_stiffness == 4.0e3 * 10.0 * 10.0 / 2.0);
}

TEST_CASE("von Karman arch: the theory and EA R^2/EI reach the model; the ends' u is the support kind's",
          "[model][von_karman][arch]") {
  const std::string arch = R"([structure]
kind = "arch"
radius = 100.0
half_angle_deg = 10.0
EI = 1.4
EA = 420.0
theory = "von_karman"

[supports]
left = "pinned"
right = "roller"

[foundation]
nondimensional_k = 1.0e6

[[loads]]
kind = "force"
at = 0.0
value = 0.1
)";
  const model::MemberModel m = model_of(arch);
  CHECK(m.kind == model::StructureKind::arch);
  CHECK(m.theory == model::Theory::von_karman);
  CHECK(m.membrane_stiffness == Approx(420.0 * 100.0 * 100.0 / 1.4).epsilon(1e-15));
  CHECK(m.left == model::EndSupport::pinned);
  CHECK(m.right == model::EndSupport::roller);
}
