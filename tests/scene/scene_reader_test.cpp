// Tests of src/scene/scene_reader.*: valid scenes read into the expected values, and every class
// of mistake is refused with a one-line message naming the file, the line and the key.

#include "scene/scene_reader.hpp"

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.hpp"
#include "support/scratch.hpp"

using namespace liftoff::scene;
using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;

namespace {

// A small valid beam scene; the error tests change one line of it (line numbers on the right).
const std::string beam_scene = R"([structure]
kind = "beam"
length = 2.0
EI = 1.0

[supports]
left = "pinned"
right = "clamped"

[foundation]
nondimensional_k = 1.0e4

[[loads]]
kind = "force"
at = 0.5
value = 1.0
)";
//  1 [structure]   2 kind   3 length   4 EI
//  6 [supports]    7 left   8 right
// 10 [foundation] 11 k
// 13 [[loads]]    14 kind  15 at       16 value

const std::string arch_scene = R"([structure]
kind = "arch"
radius = 100.0
half_angle_deg = 10.0
EI = 1.0
EA = 420.0

[supports]
left = "pinned"
right = "roller"

[foundation]
nondimensional_k = 1.0e4

[[loads]]
kind = "force"
at = 0.0
value = 1.0
)";
//  1 [structure]   2 kind   3 radius   4 half_angle_deg   5 EI   6 EA
//  8 [supports]    9 left  10 right
// 12 [foundation] 13 k
// 15 [[loads]]    16 kind  17 at      18 value

// `text` with the first occurrence of `from` replaced by `to` (which must be there).
std::string edited(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}

// The message of the InputError that reading `text` throws; checks it is one line.
std::string error_of(const std::string& text) {
  try {
    parse_scene(text, "scene.toml");
  } catch (const liftoff::InputError& e) {
    const std::string message = e.what();
    CHECK(message.find('\n') == std::string::npos);
    return message;
  }
  FAIL("the scene was accepted but should have been refused:\n" << text);
  return {};
}

}  // namespace

TEST_CASE("the enum names round-trip and the member ends follow the kind", "[scene]") {
  CHECK(to_string(Method::automatic) == "auto");
  CHECK(parse_method("auto") == Method::automatic);
  CHECK(parse_method("automatic") == std::nullopt);
  CHECK(parse_end_support("roller") == EndSupport::roller);
  CHECK(parse_load_kind(to_string(LoadKind::uniform)) == LoadKind::uniform);
  CHECK(parse_load_case(to_string(LoadCase::dead)) == LoadCase::dead);
  CHECK(parse_structure_kind("plate") == std::nullopt);

  Scene scene;
  scene.structure.kind = StructureKind::beam;
  scene.structure.length = 3.0;
  CHECK(scene.begin() == 0.0);
  CHECK(scene.end() == 3.0);
  scene.structure.kind = StructureKind::arch;
  scene.structure.half_angle_deg = 25.0;
  CHECK(scene.begin() == -25.0);
  CHECK(scene.end() == 25.0);
}

TEST_CASE("a full beam scene reads into the expected values", "[scene]") {
  const std::string text = R"(# every key of a beam scene
[structure]
kind = "beam"
length = 2
EI = 3.5
EA = 1e6

[supports]
left = "clamped"
right = "free"
interior = [1.5, 0.5]

[foundation]
modulus = 0.014
tensionless = false
from = 0.25
to = 2.0

[[loads]]
kind = "force"
at = 2.0
value = -1.5

[[loads]]
kind = "moment"
at = 0
value = 2
case = "dead"

[[loads]]
kind = "uniform"
value = 0.5
from = 0.5
to = 1.0
case = "live"

[solve]
method = "auto"
elements = 64
)";
  const Scene scene = parse_scene(text, "full_beam.toml");
  CHECK(scene.source_name == "full_beam.toml");
  CHECK(scene.text == text);

  CHECK(scene.structure.kind == StructureKind::beam);
  CHECK(scene.structure.length == 2.0);  // an integer is accepted for a float
  CHECK(scene.structure.bending_stiffness == 3.5);
  REQUIRE(scene.structure.axial_stiffness.has_value());
  CHECK(*scene.structure.axial_stiffness == 1e6);
  CHECK(scene.begin() == 0.0);
  CHECK(scene.end() == 2.0);

  CHECK(scene.supports.left == EndSupport::clamped);
  CHECK(scene.supports.right == EndSupport::free);
  CHECK(scene.supports.interior == std::vector<double>{0.5, 1.5});  // sorted

  CHECK_FALSE(scene.foundation.k.has_value());
  REQUIRE(scene.foundation.modulus.has_value());
  CHECK(*scene.foundation.modulus == 0.014);
  CHECK_FALSE(scene.foundation.tensionless);
  CHECK(scene.foundation.from == 0.25);
  CHECK(scene.foundation.to == 2.0);

  REQUIRE(scene.loads.size() == 3);
  CHECK(scene.loads[0].kind == LoadKind::force);
  CHECK(scene.loads[0].at == 2.0);
  CHECK(scene.loads[0].value == -1.5);
  CHECK(scene.loads[0].load_case == LoadCase::live);
  CHECK(scene.loads[1].kind == LoadKind::moment);
  CHECK(scene.loads[1].at == 0.0);
  CHECK(scene.loads[1].value == 2.0);
  CHECK(scene.loads[1].load_case == LoadCase::dead);
  CHECK(scene.loads[2].kind == LoadKind::uniform);
  CHECK(scene.loads[2].value == 0.5);
  CHECK(scene.loads[2].from == 0.5);
  CHECK(scene.loads[2].to == 1.0);
  CHECK(scene.loads[2].load_case == LoadCase::live);

  CHECK(scene.solve.method == Method::automatic);
  CHECK(scene.solve.elements == 64);
}

TEST_CASE("a minimal beam scene takes the defaults", "[scene]") {
  const Scene scene = parse_scene(edited(beam_scene, "[[loads]]", R"([[loads]]
kind = "uniform"
value = 2.0

[[loads]])"),
                                  "minimal.toml");
  CHECK_FALSE(scene.structure.axial_stiffness.has_value());
  CHECK(scene.supports.interior.empty());
  REQUIRE(scene.foundation.k.has_value());
  CHECK(*scene.foundation.k == 1.0e4);
  CHECK_FALSE(scene.foundation.modulus.has_value());
  CHECK(scene.foundation.tensionless);
  CHECK(scene.foundation.from == 0.0);  // the whole member
  CHECK(scene.foundation.to == 2.0);
  REQUIRE(scene.loads.size() == 2);
  CHECK(scene.loads[0].kind == LoadKind::uniform);
  CHECK(scene.loads[0].from == 0.0);
  CHECK(scene.loads[0].to == 2.0);
  CHECK(scene.loads[0].load_case == LoadCase::live);
  CHECK(scene.loads[1].load_case == LoadCase::live);
  CHECK(scene.solve.method == Method::automatic);
  CHECK(scene.solve.elements == 200);
}

TEST_CASE("a scene without loads is legal", "[scene]") {
  const Scene scene = parse_scene(beam_scene.substr(0, beam_scene.find("[[loads]]")), "x.toml");
  CHECK(scene.loads.empty());
}

TEST_CASE("a full arch scene reads into the expected values", "[scene]") {
  const std::string text = R"([structure]
kind = "arch"
radius = 100
half_angle_deg = 10.0
EI = 1.0
EA = 420

[supports]
left = "roller"
right = "clamped"
interior = [-5.0]

[foundation]
nondimensional_k = 1.0e4
tensionless = true
from = -8

[[loads]]
kind = "force"
at = -10.0
value = 1.0

[[loads]]
kind = "uniform"
value = -0.25
to = 5.0
case = "dead"

[solve]
method = "primal"
)";
  const Scene scene = parse_scene(text, "arch.toml");
  CHECK(scene.structure.kind == StructureKind::arch);
  CHECK(scene.structure.radius == 100.0);
  CHECK(scene.structure.half_angle_deg == 10.0);
  CHECK(scene.structure.bending_stiffness == 1.0);
  REQUIRE(scene.structure.axial_stiffness.has_value());
  CHECK(*scene.structure.axial_stiffness == 420.0);
  CHECK(scene.begin() == -10.0);
  CHECK(scene.end() == 10.0);

  CHECK(scene.supports.left == EndSupport::roller);
  CHECK(scene.supports.right == EndSupport::clamped);
  CHECK(scene.supports.interior == std::vector<double>{-5.0});

  CHECK(*scene.foundation.k == 1.0e4);
  CHECK(scene.foundation.tensionless);
  CHECK(scene.foundation.from == -8.0);
  CHECK(scene.foundation.to == 10.0);  // default: the right end

  REQUIRE(scene.loads.size() == 2);
  CHECK(scene.loads[0].at == -10.0);
  CHECK(scene.loads[1].kind == LoadKind::uniform);
  CHECK(scene.loads[1].from == -10.0);  // default: the left end
  CHECK(scene.loads[1].to == 5.0);
  CHECK(scene.loads[1].load_case == LoadCase::dead);

  CHECK(scene.solve.method == Method::primal);
  CHECK(scene.solve.elements == 200);
}

TEST_CASE("positions within a relative 1e-12 of an end snap onto it", "[scene]") {
  const Scene scene = parse_scene(edited(beam_scene, "at = 0.5", "at = 2.000000000001"), "x.toml");
  CHECK(scene.loads[0].at == 2.0);
  CHECK_THAT(error_of(edited(beam_scene, "at = 0.5", "at = 2.00000001")),
             Contains("key 'loads[0].at': expected a position in [0, 2], got 2.00000001"));
}

TEST_CASE("a missing key names the table and its line", "[scene][errors]") {
  CHECK(error_of(edited(beam_scene, "EI = 1.0\n", "\n")) ==
        "scene.toml:1: key 'structure.EI': missing (expected a number > 0)");
  CHECK(
      error_of(edited(beam_scene, "right = \"clamped\"\n", "\n")) ==
      R"(scene.toml:6: key 'supports.right': missing (expected "pinned", "clamped" or "free", or a table { kind = ... }))");
  CHECK(error_of(edited(beam_scene, "at = 0.5\n", "\n")) ==
        "scene.toml:13: key 'loads[0].at': missing (expected a position in [0, 2])");
  CHECK(error_of(edited(beam_scene, "length = 2.0\n", "\n")) ==
        "scene.toml:1: key 'structure.length': missing (expected a number > 0)");
  CHECK(error_of(edited(arch_scene, "EA = 420.0\n", "\n")) ==
        "scene.toml:1: key 'structure.EA': missing (expected a number > 0)");
  // A missing table has no line.
  CHECK(error_of(edited(beam_scene, "[supports]\nleft = \"pinned\"\nright = \"clamped\"\n", "")) ==
        "scene.toml: key 'supports': missing (expected a table [supports])");
}

TEST_CASE("a value of the wrong type is refused", "[scene][errors]") {
  CHECK(error_of(edited(beam_scene, "EI = 1.0", "EI = \"stiff\"")) ==
        R"(scene.toml:4: key 'structure.EI': expected a number > 0, got "stiff")");
  CHECK(error_of(edited(beam_scene, "nondimensional_k = 1.0e4", "nondimensional_k = 1.0e4\ntensionless = \"yes\"")) ==
        R"(scene.toml:12: key 'foundation.tensionless': expected true or false, got "yes")");
  CHECK(error_of(edited(beam_scene, "left = \"pinned\"", "left = 1")) ==
        R"(scene.toml:7: key 'supports.left': expected "pinned", "clamped" or "free", got 1)");
  CHECK(error_of(edited(beam_scene, "[[loads]]", "[loads]")) ==
        "scene.toml:13: key 'loads': expected an array of tables [[loads]], got a table");
  CHECK(error_of(edited(beam_scene, "[supports]", "[[supports]]")) ==
        "scene.toml:6: key 'supports': expected a table [supports], got an array");
}

TEST_CASE("an unknown key is refused, with a suggestion", "[scene][errors]") {
  CHECK(error_of(edited(beam_scene, "length = 2.0", "lenght = 2.0")) ==
        "scene.toml:3: key 'structure.lenght': unknown key (did you mean 'length'?); the keys of "
        "[structure] are kind, length, radius, half_angle_deg, EI, EA, theory");
  CHECK_THAT(error_of(edited(beam_scene, "value = 1.0", "value = 1.0\ncasee = \"dead\"")),
             StartsWith("scene.toml:17: key 'loads[0].casee': unknown key (did you mean 'case'?)"));
  CHECK_THAT(error_of(edited(beam_scene, "EI = 1.0", "EI = 1.0\n[structure.extra]\na = 1")),
             StartsWith("scene.toml:5: key 'structure.extra': unknown key;"));
}

TEST_CASE("an unknown table is refused", "[scene][errors]") {
  CHECK(error_of(beam_scene + "\n[solver]\nmethod = \"dual\"\n") ==
        "scene.toml:18: key 'solver': unknown table (did you mean 'solve'?); the tables of a scene "
        "are [structure], [supports], [foundation], [[loads]], [geometry], [solve], [ritz], [trace], [compare], "
        "[units], "
        "[[combinations]], [moving]");
  CHECK_THAT(error_of("title = \"x\"\n" + beam_scene), StartsWith("scene.toml:1: key 'title': unknown key;"));
}

TEST_CASE("an unknown value of a choice is refused", "[scene][errors]") {
  CHECK(error_of(edited(beam_scene, "kind = \"beam\"", "kind = \"plate\"")) ==
        R"(scene.toml:2: key 'structure.kind': expected "beam" or "arch", got "plate")");
  CHECK(
      error_of(beam_scene + "[solve]\nmethod = \"fastest\"\n") ==
      R"(scene.toml:18: key 'solve.method': expected "dual", "primal", "fast", "auto", "ritz" or "all", got "fastest")");
  CHECK(
      error_of(edited(beam_scene, "kind = \"force\"", "kind = \"torque\"")) ==
      R"(scene.toml:14: key 'loads[0].kind': expected "force", "moment", "uniform", "distributed", "curvature", "axial", "temperature" or "sine", got "torque")");
  // A free case name is a load case for [[combinations]]; a name that is no word is refused.
  CHECK(
      error_of(edited(beam_scene, "value = 1.0", "value = 1.0\ncase = \"perm anent\"")) ==
      R"(scene.toml:17: key 'loads[0].case': expected "dead", "live" or a load case name of letters, digits, '_' and '-' ("G", "Q"), got "perm anent")");
}

TEST_CASE("stiffnesses and lengths must be positive", "[scene][errors]") {
  CHECK(error_of(edited(beam_scene, "EI = 1.0", "EI = -1")) ==
        "scene.toml:4: key 'structure.EI': expected a number > 0, got -1");
  CHECK(error_of(edited(beam_scene, "EI = 1.0", "EI = 0.0")) ==
        "scene.toml:4: key 'structure.EI': expected a number > 0, got 0.0");
  CHECK(error_of(edited(beam_scene, "length = 2.0", "length = 0")) ==
        "scene.toml:3: key 'structure.length': expected a number > 0, got 0");
  CHECK(error_of(edited(beam_scene, "length = 2.0", "length = -2.5")) ==
        "scene.toml:3: key 'structure.length': expected a number > 0, got -2.5");
  CHECK(error_of(edited(arch_scene, "radius = 100.0", "radius = -100.0")) ==
        "scene.toml:3: key 'structure.radius': expected a number > 0, got -100.0");
  CHECK(error_of(edited(arch_scene, "EA = 420.0", "EA = 0")) ==
        "scene.toml:6: key 'structure.EA': expected a number > 0, got 0");
  CHECK(error_of(edited(arch_scene, "half_angle_deg = 10.0", "half_angle_deg = 180")) ==
        "scene.toml:4: key 'structure.half_angle_deg': expected an angle in degrees in (0, 180), "
        "got 180");
  CHECK(error_of(edited(beam_scene, "nondimensional_k = 1.0e4", "nondimensional_k = -3")) ==
        "scene.toml:11: key 'foundation.nondimensional_k': expected a number > 0, got -3");
}

TEST_CASE("keys of the other kind of structure are refused", "[scene][errors]") {
  CHECK(error_of(edited(beam_scene, "EI = 1.0", "EI = 1.0\nradius = 5.0")) ==
        "scene.toml:5: key 'structure.radius': not allowed for a beam (arches only)");
  CHECK_THAT(error_of(edited(arch_scene, "EI = 1.0", "EI = 1.0\nlength = 5.0")),
             StartsWith("scene.toml:6: key 'structure.length': not allowed for an arch"));
}

TEST_CASE("a load or support outside the member is refused", "[scene][errors]") {
  CHECK(error_of(edited(beam_scene, "at = 0.5", "at = 2.5")) ==
        "scene.toml:15: key 'loads[0].at': expected a position in [0, 2], got 2.5");
  CHECK(error_of(edited(beam_scene, "at = 0.5", "at = -0.1")) ==
        "scene.toml:15: key 'loads[0].at': expected a position in [0, 2], got -0.1");
  CHECK(error_of(edited(arch_scene, "at = 0.0", "at = 12")) ==
        "scene.toml:17: key 'loads[0].at': expected an angle in degrees in [-10, 10], got 12");
  CHECK(error_of(edited(arch_scene, "nondimensional_k = 1.0e4", "nondimensional_k = 1.0e4\nto = -10.5")) ==
        "scene.toml:14: key 'foundation.to': expected an angle in degrees in [-10, 10], got -10.5");
  // The second load is loads[1].
  CHECK_THAT(error_of(beam_scene + "\n[[loads]]\nkind = \"moment\"\nat = 3\nvalue = 1\n"),
             StartsWith("scene.toml:20: key 'loads[1].at': expected a position in [0, 2], got 3"));
  // Interior supports: strictly inside and distinct.
  CHECK(error_of(edited(beam_scene, "right = \"clamped\"", "right = \"clamped\"\ninterior = [0.5, 2.0]")) ==
        "scene.toml:9: key 'supports.interior[1]': expected a position strictly inside (0, 2), "
        "got 2.0");
  CHECK(error_of(edited(beam_scene, "right = \"clamped\"", "right = \"clamped\"\ninterior = [0.5, 1, 0.5]")) ==
        "scene.toml:9: key 'supports.interior[2]': expected distinct positions, got 0.5 twice");
  CHECK(error_of(edited(beam_scene, "right = \"clamped\"", "right = \"clamped\"\ninterior = 0.5")) ==
        "scene.toml:9: key 'supports.interior': expected an array of positions or tables { at = ..., kind = ... }, got "
        "0.5");
}

TEST_CASE("the foundation needs exactly one of k and modulus", "[scene][errors]") {
  CHECK(error_of(edited(beam_scene, "nondimensional_k = 1.0e4", "nondimensional_k = 1.0e4\nmodulus = 0.014")) ==
        "scene.toml:12: key 'foundation.modulus': expected exactly one of 'nondimensional_k' and 'modulus', got both");
  CHECK(error_of(edited(beam_scene, "nondimensional_k = 1.0e4", "")) ==
        "scene.toml:10: key 'foundation.nondimensional_k': missing (expected exactly one of 'nondimensional_k' (K "
        "l^4/EI) and "
        "'modulus' (K), a number > 0)");
}

TEST_CASE("an extent needs from < to", "[scene][errors]") {
  CHECK(error_of(edited(beam_scene, "nondimensional_k = 1.0e4", "nondimensional_k = 1.0e4\nfrom = 0.8\nto = 0.2")) ==
        "scene.toml:13: key 'foundation.to': expected from < to, got from = 0.8 and to = 0.2");
  CHECK(error_of(edited(beam_scene, "nondimensional_k = 1.0e4", "nondimensional_k = 1.0e4\nfrom = 2")) ==
        "scene.toml:12: key 'foundation.from': expected from < to, got from = 2 and to = 2");
  const std::string uniform = R"([[loads]]
kind = "uniform"
value = 1.0
from = 1.0
to = 1.0
)";
  CHECK(error_of(beam_scene + uniform) ==
        "scene.toml:21: key 'loads[1].to': expected from < to, got from = 1 and to = 1");
}

TEST_CASE("at and from/to belong to different kinds of load", "[scene][errors]") {
  CHECK(error_of(edited(beam_scene, "kind = \"force\"", "kind = \"uniform\"")) ==
        "scene.toml:15: key 'loads[0].at': not allowed for a uniform load (it acts on from..to)");
  CHECK(error_of(edited(beam_scene, "at = 0.5", "at = 0.5\nfrom = 0.0")) ==
        "scene.toml:16: key 'loads[0].from': not allowed for a force (it acts at one point, 'at')");
}

// kind = "sine": value sin(n pi (x - from) / (to - from)), n half-waves, from..to the member by default.
TEST_CASE("a sine load reads its value, half-waves and extent", "[scene][sine]") {
  const std::string whole = R"([[loads]]
kind = "sine"
value = 2.5
case = "dead"
)";
  const Scene scene = parse_scene(beam_scene + whole, "scene.toml");
  REQUIRE(scene.loads.size() == 2);
  CHECK(scene.loads[1].kind == LoadKind::sine);
  CHECK(scene.loads[1].value == 2.5);
  CHECK(scene.loads[1].half_waves == 1);
  CHECK(scene.loads[1].from == 0.0);
  CHECK(scene.loads[1].to == 2.0);
  CHECK(scene.loads[1].load_case == LoadCase::dead);
  const Scene part =
      parse_scene(beam_scene + "[[loads]]\nkind = \"sine\"\nvalue = -1\nn = 3\nfrom = 0.5\nto = 1.5\n", "scene.toml");
  CHECK(part.loads[1].half_waves == 3);
  CHECK(part.loads[1].from == 0.5);
  CHECK(part.loads[1].to == 1.5);
  CHECK(parse_load_kind("sine") == LoadKind::sine);
}

TEST_CASE("a sine load's mistakes are refused by key", "[scene][sine][errors]") {
  const std::string head = "[[loads]]\nkind = \"sine\"\nvalue = 1.0\n";  // lines 17-19
  CHECK(error_of(beam_scene + head + "n = 1.5\n") ==
        "scene.toml:20: key 'loads[1].n': expected an integer in [1, 1000000], got 1.5");
  CHECK(error_of(beam_scene + head + "n = 0\n") ==
        "scene.toml:20: key 'loads[1].n': expected an integer in [1, 1000000], got 0");
  CHECK(error_of(beam_scene + head + "from = 1.5\nto = 0.5\n") ==
        "scene.toml:21: key 'loads[1].to': expected from < to, got from = 1.5 and to = 0.5");
  CHECK(error_of(beam_scene + head + "at = 1.0\n") ==
        "scene.toml:20: key 'loads[1].at': not allowed for a sine load (it acts on from..to)");
  CHECK(error_of(beam_scene + "[[loads]]\nkind = \"uniform\"\nvalue = 1.0\nn = 2\n") ==
        "scene.toml:20: key 'loads[1].n': not allowed but with kind = \"sine\" (the number of half-waves)");
  CHECK_THAT(error_of(beam_scene + "[[loads]]\nkind = \"sine\"\nn = 2\n"),
             StartsWith("scene.toml:17: key 'loads[1].value': missing"));
  CHECK(
      error_of(edited(arch_scene, "kind = \"force\"", "kind = \"sine\"")) ==
      "scene.toml:16: key 'loads[0].kind': expected \"force\", \"moment\", \"uniform\" or \"distributed\" for an arch, "
      "got \"sine\" (a sinusoidal load is supported on beams only)");
}

TEST_CASE("elements must be an integer in range", "[scene][errors]") {
  CHECK(error_of(beam_scene + "[solve]\nelements = 0\n") ==
        "scene.toml:18: key 'solve.elements': expected an integer in [1, 10000000], got 0");
  CHECK(error_of(beam_scene + "[solve]\nelements = 2.5\n") ==
        "scene.toml:18: key 'solve.elements': expected an integer in [1, 10000000], got 2.5");
  CHECK(error_of(beam_scene + "[solve]\nelements = 200.0\n") ==
        "scene.toml:18: key 'solve.elements': expected an integer in [1, 10000000], got 200.0");
  CHECK(error_of(beam_scene + "[solve]\nelements = 10_000_001\n") ==
        "scene.toml:18: key 'solve.elements': expected an integer in [1, 10000000], got 10000001");
  CHECK(parse_scene(beam_scene + "[solve]\nelements = 10_000_000\n", "x").solve.elements == 10'000'000);
}

TEST_CASE("non-finite numbers are refused", "[scene][errors]") {
  CHECK(error_of(edited(beam_scene, "value = 1.0", "value = nan")) ==
        "scene.toml:16: key 'loads[0].value': expected a finite number, got nan");
  CHECK(error_of(edited(beam_scene, "EI = 1.0", "EI = inf")) ==
        "scene.toml:4: key 'structure.EI': expected a number > 0, got inf");
  CHECK(error_of(edited(beam_scene, "at = 0.5", "at = -inf")) ==
        "scene.toml:15: key 'loads[0].at': expected a position in [0, 2], got -inf");
}

TEST_CASE("integers read exactly where a double holds them, and are refused by key where it cannot",
          "[scene][errors]") {
  // 2^53 + 1 is the smallest positive integer a double cannot hold: toml++ gives no double for
  // it, which was once read through an empty optional as ~1e-323 (a wrong answer, exit 0).
  CHECK(error_of(edited(beam_scene, "value = 1.0", "value = -9007199254740993")) ==
        "scene.toml:16: key 'loads[0].value': expected a finite number, got -9007199254740993, an integer that a "
        "double cannot hold exactly (write it as a float, e.g. -9.0071992547409920e+15, to use the nearest double)");
  CHECK_THAT(
      error_of(edited(beam_scene, "nondimensional_k = 1.0e4", "nondimensional_k = 9007199254740993")),
      StartsWith(
          "scene.toml:11: key 'foundation.nondimensional_k': expected a number > 0, got 9007199254740993, an integer"));
  // The largest int64 rounds up to 2^63, which is no int64: refused too.
  CHECK_THAT(
      error_of(edited(beam_scene, "EI = 1.0", "EI = 9223372036854775807")),
      StartsWith("scene.toml:4: key 'structure.EI': expected a number > 0, got 9223372036854775807, an integer"));
  // In an array as well.
  CHECK_THAT(
      error_of(edited(beam_scene, "right = \"clamped\"", "right = \"clamped\"\ninterior = [1, 9007199254740993]")),
      StartsWith("scene.toml:9: key 'supports.interior[1]': expected a position strictly inside (0, 2), got "
                 "9007199254740993, an integer"));

  // Integers a double holds exactly read as that double: 2^53, and beyond it multiples of a
  // power of two, up to -2^63 (exact comparisons: no rounding is involved).
  CHECK(parse_scene(edited(beam_scene, "value = 1.0", "value = 9007199254740992"), "s").loads[0].value == 0x1p53);
  CHECK(parse_scene(edited(beam_scene, "value = 1.0", "value = -9007199254740994"), "s").loads[0].value == -0x1p53 - 2);
  CHECK(parse_scene(edited(beam_scene, "value = 1.0", "value = -9223372036854775808"), "s").loads[0].value == -0x1p63);
  CHECK(parse_scene(edited(beam_scene, "EI = 1.0", "EI = 3"), "s").structure.bending_stiffness == 3.0);
}

TEST_CASE("a roller is refused for a beam, with a hint", "[scene][errors]") {
  CHECK(error_of(edited(beam_scene, "left = \"pinned\"", "left = \"roller\"")) ==
        R"(scene.toml:7: key 'supports.left': expected "pinned", "clamped" or "free", got "roller" )"
        R"((for a beam, roller is the same as pinned))");
  CHECK(error_of(edited(arch_scene, "left = \"pinned\"", "left = \"hinged\"")) ==
        R"(scene.toml:9: key 'supports.left': expected "pinned", "roller", "clamped" or "free", )"
        R"(got "hinged")");
}

TEST_CASE("a TOML syntax error is one line with line and column", "[scene][errors]") {
  const std::string message = error_of(edited(beam_scene, "EI = 1.0", "EI = = 1.0"));
  CHECK_THAT(message, StartsWith("scene.toml:4:6: TOML syntax error: "));
  CHECK_THAT(error_of(edited(beam_scene, "EI = 1.0", "EI = 1.0\nEI = 2.0")), StartsWith("scene.toml:5:"));
  CHECK_THAT(error_of(edited(beam_scene, "kind = \"beam\"", "kind = \"beam")),
             StartsWith("scene.toml:2:") && Contains("TOML syntax error"));
}

TEST_CASE("user strings are escaped so the message stays on one line", "[scene][errors]") {
  CHECK(error_of(edited(beam_scene, "kind = \"beam\"", "kind = \"be\\nam\"")) ==
        R"(scene.toml:2: key 'structure.kind': expected "beam" or "arch", got "be\nam")");
}

TEST_CASE("read_scene_file reads a file and reports one it cannot read", "[scene][file]") {
  const liftoff::test::Scratch scratch("liftoff_scene_reader_test");
  const auto& directory = scratch.dir;
  const auto path = directory / "beam.toml";
  std::ofstream(path) << beam_scene;

  const Scene scene = read_scene_file(path);
  CHECK(scene.source_name == path.string());
  CHECK(scene.text == beam_scene);
  CHECK(scene.structure.length == 2.0);

  std::ofstream(path) << edited(beam_scene, "EI = 1.0", "EI = -1");
  REQUIRE_THROWS_WITH(read_scene_file(path), path.string() + ":4: key 'structure.EI': expected a number > 0, got -1");

  const auto absent = directory / "no_such_scene.toml";
  REQUIRE_THROWS_WITH(read_scene_file(absent),
                      absent.string() + ": cannot read the scene file (No such file or directory)");
  REQUIRE_THROWS_AS(read_scene_file(absent), liftoff::InputError);
  REQUIRE_THROWS_WITH(read_scene_file(directory), StartsWith(directory.string() + ": cannot read the scene file ("));
  // A file name with a newline: the message stays on one line.
  const auto odd = directory / "two\nlines.toml";
  std::ofstream(odd) << edited(beam_scene, "EI = 1.0", "EI = -1");
  REQUIRE_THROWS_WITH(read_scene_file(odd), (directory / "two\\nlines.toml").string() +
                                                ":4: key 'structure.EI': expected a number > 0, got -1");
}

TEST_CASE("the [ritz] table: modes, topology and initial limits", "[scene][ritz]") {
  const Scene defaults = parse_scene(beam_scene, "scene.toml");
  CHECK(defaults.ritz.modes == 0);  // "auto"
  CHECK(defaults.ritz.topology.empty());

  const Scene given = parse_scene(beam_scene +
                                      "[ritz]\nmodes = 24\ntopology = [\"lift_off\", \"contact\"]\n"
                                      "limits = [0.7]\n",
                                  "scene.toml");
  CHECK(given.ritz.modes == 24);
  CHECK(given.ritz.topology == std::vector<bool>{false, true});
  CHECK(given.ritz.limits == std::vector<double>{0.7});

  CHECK(
      error_of(beam_scene + "[ritz]\ntopology = [\"contact\", \"contact\"]\n") ==
      R"(scene.toml:18: key 'ritz.topology': expected "auto" or an array of alternating "contact" and "lift_off", got an array)");
  CHECK_THAT(error_of(beam_scene + "[ritz]\ntopology = [\"contact\", \"lift_off\"]\nlimits = [0.5, 0.7]\n"),
             StartsWith("scene.toml:19: key 'ritz.limits': expected 1 increasing positions"));
  CHECK_THAT(error_of(beam_scene + "[ritz]\nlimits = [0.5]\n"),
             Contains("key 'ritz.limits': not allowed without a topology"));
  CHECK_THAT(error_of(beam_scene + "[ritz]\nmodes = \"many\"\n"), Contains("key 'ritz.modes'"));
  CHECK_THAT(error_of(beam_scene + "[ritz]\ntopology = [\"contact\", \"lift_off\"]\nlimits = [2.5]\n"),
             Contains("strictly inside the foundation"));
}

// [trace]: the load history of `liftoff trace`. Lines: the table starts at line 17.
TEST_CASE("a [trace] table reads into the expected values, with defaults", "[scene][trace]") {
  CHECK_FALSE(parse_scene(beam_scene, "scene.toml").trace.has_value());

  const Scene minimal = parse_scene(beam_scene + "[trace]\nlambda_max = 8\n", "scene.toml");
  REQUIRE(minimal.trace.has_value());
  const TraceSettings defaults;
  CHECK(minimal.trace->lambda_max == 8.0);
  CHECK(minimal.trace->lambda_min == 0.0);
  CHECK_FALSE(minimal.trace->method.has_value());
  CHECK(minimal.trace->control == TraceControl::arc_length);
  // The steps' defaults are fractions of the load range (here 8).
  CHECK(minimal.trace->initial_step == 8.0 * defaults.initial_step);
  CHECK(minimal.trace->min_step == 8.0 * defaults.min_step);
  CHECK(minimal.trace->max_step == 8.0 * defaults.max_step);
  CHECK(minimal.trace->max_steps == defaults.max_steps);
  CHECK_FALSE(minimal.trace->monitor.has_value());
  CHECK(minimal.trace->samples == 101);
  CHECK_FALSE(minimal.trace->refine);
  CHECK(minimal.trace->line == 17);

  const Scene full = parse_scene(beam_scene + R"([trace]
lambda_min = -1.5
lambda_max = 2.5
method = "ritz"
control = "load"
initial_step = 0.01
min_step = 1e-6
max_step = 0.1
max_steps = 500
monitor = 1.25
samples = 51
refine = true
)",
                                 "scene.toml");
  const TraceSettings& t = *full.trace;
  CHECK(t.lambda_min == -1.5);
  CHECK(t.lambda_max == 2.5);
  CHECK(t.method == Method::ritz);
  CHECK(t.control == TraceControl::load);
  CHECK(t.initial_step == 0.01);
  CHECK(t.min_step == 1e-6);
  CHECK(t.max_step == 0.1);
  CHECK(t.max_steps == 500);
  CHECK(t.monitor == 1.25);
  CHECK(t.samples == 51);
  CHECK(t.refine);
  CHECK(parse_trace_control("arc_length") == TraceControl::arc_length);
  CHECK(to_string(TraceControl::load) == "load");

  // lambda_max may be absent: `solve` ignores the table and `trace` asks for it.
  CHECK_FALSE(parse_scene(beam_scene + "[trace]\nsamples = 11\n", "scene.toml").trace->lambda_max.has_value());

  // report_at: as written (app/trace_load.hpp converts and checks it), with its line for messages.
  CHECK(minimal.trace->report_at.empty());
  const Scene asked = parse_scene(beam_scene + "[trace]\nlambda_max = 8\nreport_at = [2.5e6, 1, -3]\n", "scene.toml");
  CHECK(asked.trace->report_at == std::vector<double>{2.5e6, 1.0, -3.0});
  CHECK(asked.trace->report_at_line == 19);
}

TEST_CASE("a bad [trace] value is refused with file, line and key", "[scene][trace][errors]") {
  const auto trace = [](const std::string& lines) { return beam_scene + "[trace]\n" + lines; };
  CHECK(error_of(trace("lambda_max = 0\n")) ==
        "scene.toml:18: key 'trace.lambda_max': expected a number > lambda_min = 0, got 0");
  CHECK(error_of(trace("lambda_min = 2\nlambda_max = 1.0\n")) ==
        "scene.toml:19: key 'trace.lambda_max': expected a number > lambda_min = 2, got 1.0");
  CHECK(error_of(trace("lambda_max = \"big\"\n")) ==
        R"(scene.toml:18: key 'trace.lambda_max': expected a number > lambda_min = 0, got "big")");
  CHECK(
      error_of(trace("lambda_max = 1\nmethod = \"fastest\"\n")) ==
      R"(scene.toml:19: key 'trace.method': expected "dual", "primal", "fast", "auto", "ritz" or "all", got "fastest")");
  CHECK(error_of(trace("lambda_max = 1\ncontrol = \"arclength\"\n")) ==
        R"(scene.toml:19: key 'trace.control': expected "arc_length" or "load", got "arclength")");
  CHECK(error_of(trace("lambda_max = 1\nmax_step = 0.1\ninitial_step = 0.2\n")) ==
        "scene.toml:20: key 'trace.initial_step': expected a number in (0, max_step = 0.1], got 0.2");
  CHECK(error_of(trace("lambda_max = 1\ninitial_step = 0.01\nmin_step = 0.02\n")) ==
        "scene.toml:20: key 'trace.min_step': expected a number in (0, initial_step = 0.01], got 0.02");
  CHECK(error_of(trace("lambda_max = 1\nmax_step = -1\n")) ==
        "scene.toml:19: key 'trace.max_step': expected a number > 0, got -1");
  CHECK(error_of(trace("lambda_max = 1\nmax_steps = 0\n")) ==
        "scene.toml:19: key 'trace.max_steps': expected an integer in [1, 100000000], got 0");
  CHECK(error_of(trace("lambda_max = 1\nsamples = 1\n")) ==
        "scene.toml:19: key 'trace.samples': expected an integer in [2, 1000000], got 1");
  CHECK(error_of(trace("lambda_max = 1\nmonitor = 3.0\n")) ==
        "scene.toml:19: key 'trace.monitor': expected a position in [0, 2], got 3.0");
  CHECK(error_of(trace("lambda_max = 1\nrefine = 1\n")) ==
        "scene.toml:19: key 'trace.refine': expected true or false, got 1");
  CHECK(error_of(trace("lambda_max = 1\nreport_at = 2.5\n")) ==
        "scene.toml:19: key 'trace.report_at': expected a non-empty array of numbers (loads in the live load's unit, "
        "or load factors where the live case mixes kinds), got 2.5");
  CHECK(error_of(trace("lambda_max = 1\nreport_at = []\n")) ==
        "scene.toml:19: key 'trace.report_at': expected a non-empty array of numbers (loads in the live load's unit, "
        "or load factors where the live case mixes kinds), got an array");
  CHECK(error_of(trace("lambda_max = 1\nreport_at = [1, \"x\"]\n")) ==
        R"(scene.toml:19: key 'trace.report_at[1]': expected a finite number, got "x")");
  CHECK_THAT(error_of(trace("lambda_max = 1\nlamda_min = 0\n")),
             StartsWith("scene.toml:19: key 'trace.lamda_min': unknown key (did you mean 'lambda_min'?)"));
}

TEST_CASE("a [compare] table: a published contact half-angle, arches only", "[scene][compare]") {
  CHECK_FALSE(parse_scene(arch_scene, "scene.toml").compare.has_value());
  const Scene s =
      parse_scene(arch_scene + "[compare]\nsource = \"the paper\"\ncontact_half_angle_deg = 3.73\n", "scene.toml");
  REQUIRE(s.compare.has_value());
  CHECK(s.compare->source == "the paper");
  CHECK(s.compare->contact_half_angle_deg == 3.73);

  const auto compare = [](const std::string& lines) { return arch_scene + "[compare]\n" + lines; };
  CHECK(error_of(compare("contact_half_angle_deg = 3.73\n")) ==
        "scene.toml:19: key 'compare.source': missing (expected a string naming where the value comes from)");
  CHECK(error_of(compare("source = 3\ncontact_half_angle_deg = 3.73\n")) ==
        "scene.toml:20: key 'compare.source': expected a non-empty string, got 3");
  CHECK(error_of(compare("source = \"p\"\ncontact_half_angle_deg = 12\n")) ==
        "scene.toml:21: key 'compare.contact_half_angle_deg': expected an angle in degrees in (0, half_angle_deg = "
        "10], got 12");
  CHECK_THAT(error_of(compare("source = \"p\"\n")),
             StartsWith("scene.toml:19: key 'compare.contact_half_angle_deg': missing"));
  CHECK_THAT(error_of(beam_scene + "[compare]\nsource = \"p\"\ncontact_half_angle_deg = 1\n"),
             StartsWith("scene.toml:17: key 'compare': not allowed for a beam"));
}

TEST_CASE("a distributed load reads its table; a curvature load its range", "[scene][issue12]") {
  const std::string loads = R"([[loads]]
kind = "distributed"
at = [0.0, 0.5, 0.5, 2.0]
value = [1.0, 2.0, -1.0, 0.0]
case = "dead"

[[loads]]
kind = "curvature"
value = 0.25
from = 0.5
)";
  const Scene scene = parse_scene(beam_scene + loads, "scene.toml");
  REQUIRE(scene.loads.size() == 3);
  CHECK(scene.loads[1].kind == LoadKind::distributed);
  CHECK(scene.loads[1].table_at == std::vector<double>{0.0, 0.5, 0.5, 2.0});
  CHECK(scene.loads[1].table_value == std::vector<double>{1.0, 2.0, -1.0, 0.0});
  CHECK(scene.loads[1].load_case == LoadCase::dead);
  CHECK(scene.loads[2].kind == LoadKind::curvature);
  CHECK(scene.loads[2].value == 0.25);
  CHECK(scene.loads[2].from == 0.5);
  CHECK(scene.loads[2].to == 2.0);  // the member's end by default
}

TEST_CASE("a malformed distributed or curvature load is refused by key", "[scene][issue12][errors]") {
  const std::string head = beam_scene + "\n[[loads]]\n";  // loads[1] starts on line 18
  CHECK(error_of(head + "kind = \"distributed\"\nat = [0.0, 1.0]\nvalue = [1.0]\n") ==
        "scene.toml:21: key 'loads[1].value': expected one value per position in 'at' (2), got 1");
  CHECK(error_of(head + "kind = \"distributed\"\nat = [1.0, 0.5]\nvalue = [1.0, 2.0]\n") ==
        "scene.toml:20: key 'loads[1].at': expected non-decreasing positions (a repeated one is a step), got at[1] "
        "= 0.5 after at[0] = 1");
  CHECK(error_of(head + "kind = \"distributed\"\nat = [0.0, 3.0]\nvalue = [1.0, 2.0]\n") ==
        "scene.toml:20: key 'loads[1].at[1]': expected a position in [0, 2], got 3.0");
  CHECK(error_of(head + "kind = \"distributed\"\nat = [0.5]\nvalue = [1.0]\n") ==
        "scene.toml:20: key 'loads[1].at': expected an array of at least two non-decreasing positions in [0, 2], "
        "got an array");
  CHECK(error_of(head + "kind = \"distributed\"\nat = [0.5, 0.5]\nvalue = [1.0, 1.0]\n") ==
        "scene.toml:20: key 'loads[1].at': expected a table spanning a positive length, got all its positions equal");
  CHECK(error_of(head + "kind = \"distributed\"\nvalue = [1.0, 1.0]\n") ==
        "scene.toml:18: key 'loads[1].at': missing (expected an array of at least two non-decreasing positions in "
        "[0, 2])");
  CHECK(error_of(head + "kind = \"distributed\"\nat = [0.0, 1.0]\nvalue = [1.0, 1.0]\nfrom = 0.0\n") ==
        "scene.toml:22: key 'loads[1].from': not allowed for a distributed load (its table 'at' gives where it acts; "
        "zero outside the table)");
  CHECK(error_of(head + "kind = \"curvature\"\nvalue = 0.1\nfrom = 1.0\nto = 2.5\n") ==
        "scene.toml:22: key 'loads[1].to': expected a position in [0, 2], got 2.5");
  CHECK(error_of(head + "kind = \"curvature\"\nvalue = 0.1\nat = 1.0\n") ==
        "scene.toml:21: key 'loads[1].at': not allowed for a curvature load (it acts on from..to)");
  CHECK(error_of(head + "kind = \"uniform\"\nvalue = 0.1\ndirection = \"vertical\"\n") ==
        "scene.toml:21: key 'loads[1].direction': not allowed for a beam (a beam's loads are transverse)");
  CHECK(error_of(head + "kind = \"uniform\"\nvalue = 0.1\nper = \"arc\"\n") ==
        "scene.toml:21: key 'loads[1].per': not allowed for a beam (a beam's loads are transverse)");
  const std::string arch_head = arch_scene + "\n[[loads]]\n";
  CHECK_THAT(error_of(arch_head + "kind = \"curvature\"\nvalue = 0.1\n"),
             StartsWith("scene.toml:21: key 'loads[1].kind': expected") && Contains("beams only"));
}

TEST_CASE("arch loads: direction and per, and where they are refused", "[scene][errors]") {
  const std::string vertical = edited(edited(arch_scene, "kind = \"force\"", "kind = \"uniform\""), "at = 0.0\n",
                                      "direction = \"vertical\"\nper = \"projection\"\n");
  const Scene s = parse_scene(vertical, "scene.toml");
  REQUIRE(s.loads.size() == 1);
  CHECK(s.loads[0].direction == LoadDirection::vertical);
  CHECK(s.loads[0].per == LoadBasis::projection);
  const Scene point = parse_scene(edited(arch_scene, "at = 0.0", "at = 0.0\ndirection = \"horizontal\""), "scene.toml");
  CHECK(point.loads[0].direction == LoadDirection::horizontal);
  CHECK(parse_scene(arch_scene, "scene.toml").loads[0].direction == LoadDirection::radial);  // the default

  CHECK(error_of(edited(beam_scene, "at = 0.5", "at = 0.5\ndirection = \"vertical\"")) ==
        "scene.toml:16: key 'loads[0].direction': not allowed for a beam (a beam's loads are transverse)");
  CHECK(error_of(edited(beam_scene, "at = 0.5", "at = 0.5\nper = \"arc\"")) ==
        "scene.toml:16: key 'loads[0].per': not allowed for a beam (a beam's loads are transverse)");
  CHECK(error_of(edited(arch_scene, "at = 0.0", "at = 0.0\ndirection = \"up\"")) ==
        "scene.toml:18: key 'loads[0].direction': expected \"radial\", \"tangential\", \"vertical\" or "
        "\"horizontal\", got \"up\"");
  CHECK(error_of(edited(vertical, "direction = \"vertical\"", "direction = \"tangential\"")) ==
        "scene.toml:17: key 'loads[0].direction': expected \"radial\" or \"vertical\", got \"tangential\" (a uniform "
        "or distributed load on an arch is radial or vertical)");
  CHECK(error_of(edited(vertical, "direction = \"vertical\"", "direction = \"radial\"")) ==
        "scene.toml:18: key 'loads[0].per': not allowed with direction = \"radial\" (per goes with direction = "
        "\"vertical\")");
  CHECK(error_of(edited(arch_scene, "at = 0.0", "at = 0.0\nper = \"arc\"")) ==
        "scene.toml:18: key 'loads[0].per': not allowed for a point force (per goes with vertical uniform and "
        "distributed loads)");
  CHECK(error_of(edited(vertical, "per = \"projection\"", "per = \"length\"")) ==
        "scene.toml:18: key 'loads[0].per': expected \"arc\" or \"projection\", got \"length\"");
  CHECK(error_of(edited(edited(arch_scene, "kind = \"force\"", "kind = \"moment\""), "at = 0.0",
                        "at = 0.0\ndirection = \"radial\"")) ==
        "scene.toml:18: key 'loads[0].direction': not allowed for a moment (it turns the arch in its plane)");
  // Per unit projection only where the arch is not steeper than vertical.
  const std::string wide = edited(vertical, "half_angle_deg = 10.0", "half_angle_deg = 120.0");
  CHECK(error_of(wide) ==
        "scene.toml:18: key 'loads[0].per': expected a load per unit horizontal projection within theta = -90..90 "
        "deg (where the arch is not steeper than vertical), got a load on -120 .. 120");
  CHECK(parse_scene(edited(wide, "per = \"projection\"", "per = \"projection\"\nfrom = -90\nto = 90"), "scene.toml")
            .loads[0]
            .per == LoadBasis::projection);
}

TEST_CASE("[foundation] side: inside or outside, arches only", "[scene][errors]") {
  CHECK(parse_scene(arch_scene, "scene.toml").foundation.side == FoundationSide::inside);
  CHECK(parse_scene(edited(arch_scene, "nondimensional_k = 1.0e4", "nondimensional_k = 1.0e4\nside = \"outside\""),
                    "scene.toml")
            .foundation.side == FoundationSide::outside);
  CHECK(error_of(edited(arch_scene, "nondimensional_k = 1.0e4", "nondimensional_k = 1.0e4\nside = \"above\"")) ==
        "scene.toml:14: key 'foundation.side': expected \"inside\" or \"outside\", got \"above\"");
  CHECK(error_of(edited(beam_scene, "nondimensional_k = 1.0e4", "nondimensional_k = 1.0e4\nside = \"outside\"")) ==
        "scene.toml:12: key 'foundation.side': not allowed for a beam (arches only: the foundation inside or outside "
        "the arch)");
}

TEST_CASE("[[foundation.segments]]: pieces sorted, voids allowed, each with its modulus", "[scene][segments]") {
  const std::string pieces = R"(tensionless = false

[[foundation.segments]]
from = 1.5
to = 2.0
modulus = 4.0

[[foundation.segments]]
from = 0.0
to = 0.5
nondimensional_k = 20.0

[[foundation.segments]]
from = 0.5
to = 1.0
modulus = 2.0
)";
  const Scene s = parse_scene(edited(beam_scene, "nondimensional_k = 1.0e4\n", pieces), "scene.toml");
  REQUIRE(s.foundation.segments.size() == 3);
  CHECK_FALSE(s.foundation.tensionless);
  CHECK(s.foundation.segments[0].from == 0.0);
  CHECK(*s.foundation.segments[0].k == 20.0);
  CHECK(s.foundation.segments[1].to == 1.0);
  CHECK(*s.foundation.segments[2].modulus == 4.0);
  CHECK(s.foundation.from == 0.0);  // the extent spans the pieces
  CHECK(s.foundation.to == 2.0);
  CHECK_FALSE(s.foundation.k.has_value());
  for (const auto& piece : s.foundation.segments) CHECK_FALSE(piece.at_to.has_value());
}

TEST_CASE("[[foundation.segments]]: a modulus linear within a piece, [at from, at to]", "[scene][segments]") {
  const std::string pieces = R"(
[[foundation.segments]]
from = 1.0
to = 2.0
nondimensional_k = [20.0, 5.0]

[[foundation.segments]]
from = 0.0
to = 1.0
modulus = [3.0, 3.0]
)";
  const Scene s = parse_scene(edited(beam_scene, "nondimensional_k = 1.0e4\n", pieces), "scene.toml");
  REQUIRE(s.foundation.segments.size() == 2);
  CHECK(*s.foundation.segments[0].modulus == 3.0);  // equal ends: constant
  CHECK_FALSE(s.foundation.segments[0].at_to.has_value());
  CHECK(*s.foundation.segments[1].k == 20.0);  // at from
  REQUIRE(s.foundation.segments[1].at_to.has_value());
  CHECK(*s.foundation.segments[1].at_to == 5.0);
}

TEST_CASE("[[foundation.segments]]: malformed pieces are refused by key", "[scene][segments][errors]") {
  auto with = [](const std::string& foundation) {
    return edited(beam_scene, "nondimensional_k = 1.0e4\n", foundation);
  };
  const std::string one = "\n[[foundation.segments]]\nfrom = 0.0\nto = 1.0\nmodulus = 3.0\n";
  CHECK_THAT(
      error_of(with("nondimensional_k = 1.0\n" + one)),
      StartsWith(
          "scene.toml:11: key 'foundation.nondimensional_k': not allowed together with [[foundation.segments]]"));
  CHECK_THAT(error_of(with("from = 0.5\n" + one)), Contains("key 'foundation.from': not allowed together"));
  CHECK_THAT(error_of(with("\n[[foundation.segments]]\nfrom = 0.0\nto = 2.5\nmodulus = 3.0\n")),
             Contains("key 'foundation.segments[0].to': expected a position in [0, 2]"));
  CHECK_THAT(error_of(with("\n[[foundation.segments]]\nfrom = 1.0\nto = 0.5\nmodulus = 3.0\n")),
             Contains("key 'foundation.segments[0].to': expected from < to, got from = 1 and to = 0.5"));
  CHECK_THAT(error_of(with("\n[[foundation.segments]]\nfrom = 0.0\nto = 1.0\nmodulus = -3.0\n")),
             Contains("key 'foundation.segments[0].modulus': expected a number > 0, got -3"));
  CHECK_THAT(
      error_of(with("\n[[foundation.segments]]\nfrom = 0.0\nto = 1.0\nmodulus = 3.0\nnondimensional_k = 1.0\n")),
      Contains("key 'foundation.segments[0].modulus': expected exactly one of 'nondimensional_k' and 'modulus'"));
  CHECK_THAT(error_of(with("\n[[foundation.segments]]\nfrom = 0.0\nto = 1.0\n")),
             Contains("key 'foundation.segments[0].nondimensional_k': missing"));
  const std::string linear = "a number > 0, or two numbers > 0 [at from, at to] for a linear variation";
  CHECK_THAT(error_of(with("\n[[foundation.segments]]\nfrom = 0.0\nto = 1.0\nmodulus = [3.0, 1.0, 2.0]\n")),
             Contains("key 'foundation.segments[0].modulus': expected " + linear));
  CHECK_THAT(error_of(with("\n[[foundation.segments]]\nfrom = 0.0\nto = 1.0\nnondimensional_k = []\n")),
             Contains("key 'foundation.segments[0].nondimensional_k': expected " + linear));
  CHECK_THAT(error_of(with("\n[[foundation.segments]]\nfrom = 0.0\nto = 1.0\nmodulus = [3.0, 0.0]\n")),
             Contains("key 'foundation.segments[0].modulus[1]': expected a number > 0, got 0"));
  CHECK_THAT(error_of(with("\n[[foundation.segments]]\nfrom = 0.0\nto = 1.0\nnondimensional_k = [3.0, \"soft\"]\n")),
             Contains("key 'foundation.segments[0].nondimensional_k[1]': expected a number > 0"));
  CHECK_THAT(
      error_of(with("\n[[foundation.segments]]\nfrom = 0.0\nto = 1.0\nnondimensional_k = [3.0, 1.0]\nmodulus = 2.0\n")),
      Contains("key 'foundation.segments[0].modulus': expected exactly one of 'nondimensional_k' and 'modulus'"));
  CHECK_THAT(error_of(with("\n[[foundation.segments]]\nfrom = 0.0\nto = 1.0\nmodulus = 3.0\nmodulos = 1.0\n")),
             Contains("key 'foundation.segments[0].modulos': unknown key (did you mean 'modulus'?)"));
  CHECK_THAT(error_of(with(one + "\n[[foundation.segments]]\nfrom = 0.8\nto = 1.5\nmodulus = 3.0\n")),
             Contains("key 'foundation.segments[1]': expected segments that do not overlap, got [0.8, 1.5] "
                      "overlapping segments[0] = [0, 1]"));
  CHECK_THAT(error_of(with("segments = 3\n")), Contains("key 'foundation.segments': expected a non-empty array"));
}

TEST_CASE("[foundation] gap and gap_file: the ground's distance below the axis", "[scene][issue12][gap]") {
  auto with = [](const std::string& keys) {
    return edited(beam_scene, "nondimensional_k = 1.0e4\n", "nondimensional_k = 1.0e4\n" + keys);
  };
  const Scene s =
      parse_scene(with("gap = { at = [0.0, 1.0, 1.0, 2.0], value = [0.0, 1e-3, -2e-3, 0.0] }\n"), "scene.toml");
  CHECK(s.foundation.gap_at == std::vector<double>{0.0, 1.0, 1.0, 2.0});
  CHECK(s.foundation.gap_value == std::vector<double>{0.0, 1e-3, -2e-3, 0.0});
  CHECK(s.foundation.gap_key() == "foundation.gap");
  // One point is a constant gap; positions beyond the member are allowed (g is constant there).
  CHECK(parse_scene(with("gap = { at = [-5.0], value = [1e-3] }\n"), "scene.toml").foundation.gap_at.size() == 1);

  // A survey file next to the scene: a header, semicolons, commas and whitespace, a blank line.
  const liftoff::test::Scratch scratch("liftoff_gap_file_test");
  const auto& dir = scratch.dir;
  scratch.write("bed.csv", "position; gap\n-1.0; 0.0\n\n0.5, -1e-3\n 1.5\t2e-3\n");
  const Scene f = parse_scene(with("gap_file = \"bed.csv\"\n"), (dir / "scene.toml").string());
  CHECK(f.foundation.gap_at == std::vector<double>{-1.0, 0.5, 1.5});
  CHECK(f.foundation.gap_value == std::vector<double>{0.0, -1e-3, 2e-3});
  CHECK(f.foundation.gap_key() == "foundation.gap_file");
  scratch.write("bad.csv", "x,g\n0.0, 0.0\n0.5, oops\n");
  CHECK_THAT(error_of(with("gap_file = \"bad.csv\"\n")),
             Contains("key 'foundation.gap_file': cannot read"));  // relative to the scene's directory: none here
  try {
    parse_scene(with("gap_file = \"bad.csv\"\n"), (dir / "scene.toml").string());
    FAIL("bad.csv was accepted");
  } catch (const liftoff::InputError& e) {
    CHECK_THAT(e.what(), Contains("key 'foundation.gap_file': "));
    CHECK_THAT(e.what(), Contains("bad.csv:3: expected two finite numbers (position, gap), got \"0.5, oops\""));
  }
  scratch.write("decreasing.csv", "1.0 0.0\n0.5 0.0\n");
  try {
    parse_scene(with("gap_file = \"decreasing.csv\"\n"), (dir / "scene.toml").string());
    FAIL("decreasing.csv was accepted");
  } catch (const liftoff::InputError& e) {
    CHECK_THAT(e.what(), Contains("expected non-decreasing positions"));
  }
}

TEST_CASE("[foundation] gap, gap_file, tension_modulus, tension_nondimensional_k: malformed ones are refused by key",
          "[scene][issue12][gap][errors]") {
  auto with = [](const std::string& keys) {
    return edited(beam_scene, "nondimensional_k = 1.0e4\n", "nondimensional_k = 1.0e4\n" + keys);
  };
  CHECK(error_of(with("gap = { at = [0.0, 1.0, 0.5], value = [0.0, 0.0, 0.0] }\n")) ==
        "scene.toml:12: key 'foundation.gap.at': expected non-decreasing positions (a repeated one is a step), got "
        "at[2] = 0.5 after at[1] = 1");
  CHECK_THAT(error_of(with("gap = { at = [0.0, 1.0, 1.0, 1.0], value = [0.0, 0.0, 0.0, 0.0] }\n")),
             Contains("key 'foundation.gap.at': expected each position at most twice (a step)"));
  CHECK_THAT(error_of(with("gap = { at = [0.0, 1.0], value = [0.0] }\n")),
             Contains("key 'foundation.gap.value': expected one value per position in 'at' (2), got 1"));
  CHECK_THAT(error_of(with("gap = { at = [], value = [] }\n")),
             Contains("key 'foundation.gap.at': expected a non-empty"));
  CHECK_THAT(error_of(with("gap = { value = [0.0] }\n")), Contains("key 'foundation.gap.at': missing"));
  CHECK_THAT(error_of(with("gap = { at = [0.0], value = [0.0], step = 1 }\n")),
             Contains("key 'foundation.gap.step': unknown key"));
  CHECK_THAT(error_of(with("gap = 0.1\n")), Contains("key 'foundation.gap': expected a table { at = [...]"));
  CHECK_THAT(error_of(with("gap = { at = [0.0], value = [0.0] }\ngap_file = \"x.csv\"\n")),
             Contains("key 'foundation.gap_file': expected one of 'gap' and 'gap_file', got both"));
  CHECK_THAT(error_of(with("gap_file = 3\n")),
             Contains("key 'foundation.gap_file': expected the name of a two-column"));

  CHECK(*parse_scene(with("tension_nondimensional_k = 1.0e3\n"), "scene.toml").foundation.tension_k == 1.0e3);
  CHECK_THAT(error_of(with("tension_nondimensional_k = -1.0\n")),
             Contains("key 'foundation.tension_nondimensional_k': expected a number >= 0, got -1"));
  CHECK_THAT(error_of(with("tension_nondimensional_k = 2.0e4\n")),
             Contains("key 'foundation.tension_nondimensional_k': expected at most the compression modulus 10000 "
                      "everywhere, got 20000"));
  CHECK_THAT(error_of(with("tension_modulus = 1.0\n")),
             Contains("key 'foundation.tension_modulus': expected 'tension_nondimensional_k' for a foundation given by "
                      "'nondimensional_k', got 'tension_modulus'"));
  CHECK_THAT(error_of(with("tension_nondimensional_k = 1.0\ntension_modulus = 1.0\n")),
             Contains("key 'foundation.tension_nondimensional_k': expected one of 'tension_modulus' and "
                      "'tension_nondimensional_k', got both"));
  CHECK_THAT(error_of(with("tensionless = false\ntension_nondimensional_k = 1.0\n")),
             Contains("key 'foundation.tension_nondimensional_k': not allowed with tensionless = false"));
  CHECK_THAT(
      error_of(edited(beam_scene, "nondimensional_k = 1.0e4\n", "modulus = 5.0\ntension_nondimensional_k = 1.0\n")),
      Contains(
          "key 'foundation.tension_nondimensional_k': expected 'tension_modulus' for a foundation given by 'modulus'"));
  CHECK(*parse_scene(edited(beam_scene, "nondimensional_k = 1.0e4\n", "modulus = 5.0\ntension_modulus = 5.0\n"),
                     "scene.toml")
             .foundation.tension_modulus == 5.0);
  // On a linear piece the tensionless part k(s) - K_t must stay positive: K_t below its least k.
  const std::string linear = edited(beam_scene, "nondimensional_k = 1.0e4\n",
                                    "tension_nondimensional_k = TK\n[[foundation.segments]]\nfrom = 0.0\nto = "
                                    "2.0\nnondimensional_k = [3.0e3, 1.0e3]\n");
  CHECK(*parse_scene(edited(linear, "TK", "999.0"), "scene.toml").foundation.tension_k == 999.0);
  CHECK_THAT(
      error_of(edited(linear, "TK", "1000.0")),
      Contains(
          "key 'foundation.tension_nondimensional_k': expected below the compression modulus on a linear segment (its "
          "least value 1000), got 1000"));
}

TEST_CASE("[supports] as tables: springs and settlements at the ends and inside", "[scene][issue12][supports]") {
  const std::string text = edited(edited(beam_scene, "left = \"pinned\"\n",
                                         "left = { kind = \"spring\", stiffness = 1e6, rotational_stiffness = 2.0, "
                                         "settlement = 0.005 }\n"
                                         "interior = [1.5, { at = 0.5, kind = \"spring\", stiffness = 3.0 }, "
                                         "{ at = 1.0, kind = \"pinned\", settlement = -0.002 }]\n"),
                                  "right = \"clamped\"\n", "right = { kind = \"clamped\", settlement = 0.01 }\n");
  const Scene s = parse_scene(text, "scene.toml");
  CHECK(s.supports.left == EndSupport::free);  // a spring end is otherwise free
  CHECK(s.supports.left_detail.spring);
  CHECK(s.supports.left_detail.stiffness == 1e6);
  CHECK(s.supports.left_detail.rotational_stiffness == 2.0);
  CHECK(s.supports.left_detail.settlement == 0.005);
  CHECK(s.supports.right == EndSupport::clamped);
  CHECK(s.supports.right_detail.settlement == 0.01);
  CHECK_FALSE(s.supports.right_detail.spring);
  CHECK(s.supports.interior == std::vector<double>{1.0, 1.5});  // rigid points, sorted
  CHECK(s.supports.interior_settlement == std::vector<double>{-0.002, 0.0});
  REQUIRE(s.supports.interior_springs.size() == 1);
  CHECK(s.supports.interior_springs[0].at == 0.5);
  CHECK(s.supports.interior_springs[0].detail.stiffness == 3.0);
  // The string form and plain numbers read as before: no springs, no settlements.
  const Scene plain = parse_scene(beam_scene, "scene.toml");
  CHECK_FALSE(plain.supports.left_detail.spring);
  CHECK(plain.supports.interior_settlement.empty());
}

TEST_CASE("[supports] tables: malformed springs and settlements are refused by key",
          "[scene][issue12][supports][errors]") {
  auto left = [](const std::string& value) {
    return edited(beam_scene, "left = \"pinned\"\n", "left = " + value + "\n");
  };
  CHECK_THAT(error_of(left("{ kind = \"spring\", stiffness = -1.0 }")),
             StartsWith("scene.toml:7: key 'supports.left.stiffness': expected a number >= 0, got -1"));
  CHECK_THAT(error_of(left("{ kind = \"spring\" }")),
             Contains("key 'supports.left.rotational_stiffness': expected a spring with stiffness > 0 or "
                      "rotational_stiffness > 0"));
  CHECK_THAT(error_of(left("{ kind = \"spring\", stiffness = 0.0, rotational_stiffness = 0.0 }")),
             Contains("key 'supports.left.stiffness': expected a spring with stiffness > 0"));
  CHECK_THAT(error_of(left("{ kind = \"free\", settlement = 0.1 }")),
             Contains("key 'supports.left.settlement': not allowed on a free end"));
  CHECK_THAT(error_of(left("{ kind = \"spring\", rotational_stiffness = 1.0, settlement = 0.1 }")),
             Contains("key 'supports.left.settlement': not allowed on a spring without translational stiffness"));
  CHECK_THAT(
      error_of(left("{ kind = \"hinge\" }")),
      Contains("key 'supports.left.kind': expected \"spring\", \"pinned\", \"clamped\" or \"free\", got \"hinge\""));
  CHECK_THAT(error_of(left("{ kind = \"roller\" }")), Contains("roller is the same as pinned"));
  CHECK_THAT(error_of(left("{ kind = \"pinned\", stiffness = 5.0 }")),
             Contains("key 'supports.left.stiffness': not allowed on a support of kind \"pinned\""));
  CHECK_THAT(error_of(left("{ stiffness = 5.0 }")), Contains("key 'supports.left.kind': missing"));
  CHECK_THAT(error_of(left("{ kind = \"spring\", stifness = 5.0 }")),
             Contains("key 'supports.left.stifness': unknown key (did you mean 'stiffness'?)"));
  CHECK_THAT(error_of(left("{ kind = \"pinned\", settlement = \"a lot\" }")),
             Contains("key 'supports.left.settlement': expected a finite number"));
  auto interior = [](const std::string& value) {
    return edited(beam_scene, "right = \"clamped\"\n", "right = \"clamped\"\ninterior = [" + value + "]\n");
  };
  CHECK_THAT(error_of(interior("{ at = 2.5, kind = \"spring\", stiffness = 1.0 }")),
             Contains("key 'supports.interior[0].at': expected a position strictly inside (0, 2)"));
  CHECK_THAT(error_of(interior("{ at = 1.0, kind = \"clamped\" }")),
             Contains("key 'supports.interior[0].kind': expected \"pinned\" or \"spring\""));
  CHECK_THAT(error_of(interior("{ kind = \"pinned\" }")), Contains("key 'supports.interior[0].at': missing"));
  CHECK_THAT(error_of(interior("1.0, { at = 1.0, kind = \"spring\", stiffness = 1.0 }")),
             Contains("key 'supports.interior[1]': expected distinct positions, got 1 twice"));
  CHECK_THAT(error_of(interior("\"middle\"")), Contains("key 'supports.interior[0]': expected a position"));
}

TEST_CASE("[units]: a system or the free labels length and force, labels only", "[scene][units]") {
  CHECK_FALSE(parse_scene(beam_scene, "scene.toml").units.stated());  // none: every label empty
  for (const auto& [name, label] : unit_labels(parse_scene(beam_scene, "scene.toml").units)) CHECK(label.empty());

  const Scene kn_m = parse_scene(beam_scene + "\n[units]\nsystem = \"kN-m\"\n", "scene.toml");
  CHECK(kn_m.units.system == "kN-m");
  CHECK(kn_m.units.force == "kN");
  CHECK(kn_m.units.length == "m");
  CHECK(kn_m.units.moment() == "kN m");
  CHECK(kn_m.units.distributed_force() == "kN/m");
  CHECK(kn_m.units.modulus() == "kN/m^2");
  CHECK(kn_m.units.bending_stiffness() == "kN m^2");
  CHECK(*kn_m.units.newtons() == 1e3);
  CHECK(*kn_m.units.metres() == 1.0);
  // Labels only: the scene's numbers are what they were.
  CHECK(*kn_m.foundation.k == *parse_scene(beam_scene, "scene.toml").foundation.k);

  const Scene kip_ft = parse_scene(beam_scene + "\n[units]\nsystem = \"kip-ft\"\n", "scene.toml");
  CHECK(*kip_ft.units.metres() == 0.3048);
  CHECK(*kip_ft.units.newtons() == 4448.2216152605);

  const Scene labels = parse_scene(beam_scene + "\n[units]\nlength = \"furlong\"\nforce = \"kN\"\n", "scene.toml");
  CHECK(labels.units.system.empty());
  CHECK(labels.units.modulus() == "kN/furlong^2");
  CHECK_FALSE(labels.units.metres());  // not a known unit: no SI size
}

TEST_CASE("[units]: anything but exactly one of the two ways is refused by key", "[scene][units][errors]") {
  // The [units] header is line 18 of beam_scene + "\n[units]\n...".
  const auto with = [](const std::string& keys) { return beam_scene + "\n[units]\n" + keys; };
  CHECK_THAT(error_of(with("system = \"N-furlong\"\n")),
             StartsWith("scene.toml:19: key 'units.system': expected one of \"N-m\", \"N-cm\", \"N-mm\"") &&
                 Contains("\"kip-ft\", got \"N-furlong\" (or give free labels: length = \"m\", force = \"kN\")"));
  CHECK(error_of(with("system = \"N-m\"\nlength = \"m\"\n")) ==
        "scene.toml:20: key 'units.length': expected either 'system' or the labels 'length' and 'force', got both "
        "ways");
  CHECK_THAT(error_of(with("length = \"m\"\n")),
             StartsWith("scene.toml:18: key 'units.force': missing (expected a label of 1 to 32 printable"));
  CHECK_THAT(error_of(with("")), StartsWith("scene.toml:18: key 'units.system': missing (expected one of \"N-m\""));
  CHECK_THAT(error_of(with("length = 3\nforce = \"N\"\n")),
             StartsWith("scene.toml:19: key 'units.length': expected a label of 1 to 32 printable characters"));
  CHECK_THAT(error_of(with("system = 1\n")), StartsWith("scene.toml:19: key 'units.system': expected one of"));
  CHECK_THAT(error_of(with("mass = \"kg\"\n")), StartsWith("scene.toml:19: key 'units.mass': unknown key"));
  CHECK_THAT(error_of("units = \"N-m\"\n" + beam_scene), Contains("key 'units': expected a table [units]"));
}

TEST_CASE("the old names k and tension_k read as nondimensional_k and tension_nondimensional_k, with a warning",
          "[scene][units]") {
  CHECK(parse_scene(beam_scene, "scene.toml").warnings.empty());  // the new name: no warning
  const std::string old = edited(beam_scene, "nondimensional_k = 1.0e4", "k = 1.0e4");
  const Scene s = parse_scene(old, "scene.toml");
  CHECK(*s.foundation.k == 1.0e4);
  REQUIRE(s.warnings.size() == 1);
  // Where, what the key means now, and the dimensional K's key.
  CHECK_THAT(s.warnings[0],
             StartsWith("scene.toml:11: key 'foundation.k': 'k' is the old name of 'nondimensional_k' (K l^4/EI, "
                        "nondimensional") &&
                 Contains("read as nondimensional_k = 10000.0") &&
                 Contains("the dimensional foundation modulus K (force per length per length) is 'modulus'"));
  CHECK(error_of(edited(old, "k = 1.0e4", "k = 1.0e4\nnondimensional_k = 1.0e4")) ==
        "scene.toml:11: key 'foundation.k': expected one of 'nondimensional_k' and 'k' (its old name), got both");
  CHECK(error_of(edited(old, "k = 1.0e4", "k = 1.0e4\nmodulus = 2.0")) ==
        "scene.toml:12: key 'foundation.modulus': expected exactly one of 'k' and 'modulus', got both");

  const Scene tension = parse_scene(edited(old, "k = 1.0e4", "k = 1.0e4\ntension_k = 10.0"), "scene.toml");
  CHECK(*tension.foundation.tension_k == 10.0);
  REQUIRE(tension.warnings.size() == 2);
  CHECK_THAT(tension.warnings[1], StartsWith("scene.toml:12: key 'foundation.tension_k': 'tension_k' is the old "
                                             "name of 'tension_nondimensional_k'"));

  const Scene segments = parse_scene(
      edited(beam_scene, "nondimensional_k = 1.0e4\n", "\n[[foundation.segments]]\nfrom = 0.0\nto = 2.0\nk = 5.0\n"),
      "scene.toml");
  CHECK(*segments.foundation.segments.at(0).k == 5.0);
  REQUIRE(segments.warnings.size() == 1);
  CHECK_THAT(segments.warnings[0], Contains("key 'foundation.segments[0].k': 'k' is the old name"));
}

TEST_CASE("load cases by name, [[combinations]] and [moving] are read", "[scene][envelope]") {
  const Scene s = parse_scene(beam_scene + R"(case = "G"
[moving]
case = "Q"
loads = [{ kind = "force", offset = 0.0, value = 2.0 }, { kind = "moment", offset = 0.5, value = -1.0 }]
from = 0.0
to = 1.4
step = 0.5
[[combinations]]
name = "ULS"
factors = { G = 1.35, Q = 1.5 }
)",
                              "scene.toml");
  CHECK(s.loads[0].case_name == "G");
  CHECK(s.loads[0].load_case == LoadCase::live);  // solve applies it once, as any load
  REQUIRE(s.moving);
  CHECK(s.moving->case_name == "Q");
  REQUIRE(s.moving->group.size() == 2);
  CHECK(s.moving->group[1].kind == LoadKind::moment);
  CHECK(s.moving->group[1].at == 0.5);
  // from..to by step, and `to` itself where the step does not divide the range (the group's end).
  CHECK(s.moving->positions == std::vector<double>{0.0, 0.5, 1.0, 1.4});
  REQUIRE(s.combinations.size() == 1);
  CHECK(s.combinations[0].factor_of("G") == 1.35);
  CHECK(s.combinations[0].factor_of("Q") == 1.5);
  CHECK(s.combinations[0].factor_of("W") == 0.0);  // a case not named is not in the combination
}

TEST_CASE("combinations and moving loads: mistakes are refused with their key", "[scene][envelope]") {
  const std::string with_case = beam_scene + "case = \"G\"\n";
  // A typo'd case in a combination: the key, and the cases the scene has.
  CHECK_THAT(error_of(with_case + "[[combinations]]\nname = \"ULS\"\nfactors = { G = 1.35, Qk = 1.5 }\n"),
             StartsWith("scene.toml:20: key 'combinations[0].factors.Qk': unknown load case") && Contains("G"));
  CHECK_THAT(error_of(with_case + "[[combinations]]\nname = \"ULS\"\nfactors = { G = -1.0 }\n"),
             Contains("key 'combinations[0].factors.G'") && Contains(">= 0"));
  CHECK_THAT(error_of(with_case + "[[combinations]]\nfactors = { G = 1.0 }\n"),
             Contains("key 'combinations[0].name': missing"));
  CHECK_THAT(error_of(with_case + "[[combinations]]\nname = \"A\"\nfactors = { G = 1.0 }\n[[combinations]]\nname = "
                                  "\"A\"\nfactors = { G = 2.0 }\n"),
             Contains("key 'combinations[1].name'") && Contains("not used by an earlier"));
  CHECK_THAT(error_of(beam_scene + "case = \"\"\n"), Contains("key 'loads[0].case'"));

  const std::string group = "[moving]\nloads = [{ kind = \"force\", offset = 0.0, value = 1.0 }]\n";
  CHECK_THAT(error_of(beam_scene + group + "from = 0.0\nto = 1.0\nstep = -0.5\n"),
             Contains("key 'moving.step': expected a number > 0, got -0.5"));
  CHECK_THAT(error_of(beam_scene + "[moving]\nloads = []\nfrom = 0.0\nto = 1.0\nstep = 0.5\n"),
             Contains("key 'moving.loads': expected a non-empty array"));
  CHECK_THAT(error_of(beam_scene + "[moving]\nfrom = 0.0\nto = 1.0\nstep = 0.5\n"),
             Contains("key 'moving.loads': missing"));
  CHECK_THAT(error_of(beam_scene + "[moving]\nloads = [{ kind = \"uniform\", offset = 0.0, value = 1.0 }]\npositions "
                                   "= [0.5]\n"),
             Contains("key 'moving.loads[0].kind'"));
  CHECK_THAT(error_of(beam_scene + "[moving]\nloads = [{ kind = \"force\", at = 0.0, value = 1.0 }]\npositions = "
                                   "[0.5]\n"),
             Contains("key 'moving.loads[0].at': unknown key"));
  // The group must stay on the member: a lead position that puts a load beyond the end.
  CHECK_THAT(error_of(beam_scene + "[moving]\nloads = [{ kind = \"force\", offset = 0.0, value = 1.0 }, { kind = "
                                   "\"force\", offset = 1.0, value = 1.0 }]\nfrom = 0.0\nto = 1.5\nstep = 0.5\n"),
             Contains("key 'moving.to'") && Contains("[from = 0, 1]"));
  CHECK_THAT(error_of(beam_scene + group + "positions = [1.0, 0.5]\n"),
             Contains("key 'moving.positions'") && Contains("ascending"));
  CHECK_THAT(error_of(beam_scene + group + "positions = [0.5]\nstep = 0.5\n"),
             Contains("key 'moving.step': not allowed with 'positions'"));
}

TEST_CASE("axial and temperature loads read into their compressive force", "[scene][axial]") {
  const Scene scene = parse_scene(edited(beam_scene, "EI = 1.0", "EI = 1.0\nEA = 2.0e6") +
                                      "\n[[loads]]\nkind = \"axial\"\nvalue = 3.5\ncase = \"dead\"\n"
                                      "\n[[loads]]\nkind = \"temperature\"\nvalue = 60.0\nalpha = 1.2e-5\n",
                                  "axial.toml");
  REQUIRE(scene.loads.size() == 3);
  CHECK(scene.loads[1].kind == LoadKind::axial);
  CHECK(scene.loads[1].load_case == LoadCase::dead);
  CHECK(scene.loads[1].axial_force(scene.structure) == 3.5);
  CHECK(scene.loads[2].kind == LoadKind::temperature);
  CHECK(scene.loads[2].load_case == LoadCase::live);
  // N = EA alpha dT: 2e6 * 1.2e-5 * 60 = 1440.
  CHECK(scene.loads[2].axial_force(scene.structure) == Approx(1440.0).epsilon(1e-15));
  CHECK(scene.loads[0].axial_force(scene.structure) == 0.0);  // a transverse force has none
}

TEST_CASE("axial loads are refused where they cannot apply", "[scene][axial][errors]") {
  const std::string axial = "\n[[loads]]\nkind = \"axial\"\nvalue = 1.0\n";
  CHECK(error_of(arch_scene + axial) ==
        "scene.toml:21: key 'loads[1].kind': expected \"force\", \"moment\", \"uniform\" or \"distributed\" for an "
        "arch, got \"axial\" (an axial force is supported on beams only)");
  CHECK(error_of(beam_scene + "\n[[loads]]\nkind = \"axial\"\nvalue = 1.0\nat = 0.5\n") ==
        "scene.toml:21: key 'loads[1].at': not allowed for a axial load (it acts along the whole member)");
  CHECK(error_of(beam_scene + "\n[[loads]]\nkind = \"axial\"\n") ==
        "scene.toml:18: key 'loads[1].value': missing (expected a finite number)");
  CHECK_THAT(error_of(beam_scene + "\n[[loads]]\nkind = \"temperature\"\nvalue = 60.0\nalpha = 1e-5\n"),
             StartsWith("scene.toml:19: key 'loads[1].kind': expected [structure] EA for a temperature load"));
  CHECK_THAT(error_of(edited(beam_scene, "EI = 1.0", "EI = 1.0\nEA = 1.0") +
                      "\n[[loads]]\nkind = \"temperature\"\nvalue = 60.0\n"),
             StartsWith("scene.toml:19: key 'loads[1].alpha': missing"));
  CHECK_THAT(error_of(beam_scene + "\n[[loads]]\nkind = \"axial\"\nvalue = 1.0\nalpha = 1e-5\n"),
             StartsWith("scene.toml:21: key 'loads[1].alpha': not allowed"));
  CHECK_THAT(error_of(beam_scene + "\n[[loads]]\nkind = \"axial\"\nvalue = 1e308\n"),
             StartsWith("scene.toml:20: key 'loads[1].value': expected an axial force whose P L^2/EI is finite"));
}

TEST_CASE("an initial shape reads as a table or a named shape", "[scene][axial]") {
  SECTION("a table") {
    const Scene scene = parse_scene(
        beam_scene + "\n[geometry]\ninitial_shape = { at = [0.0, 1.0, 2.0], value = [0.0, -0.01, 0.0] }\n", "x.toml");
    CHECK(scene.initial_shape.shape == "table");
    CHECK(scene.initial_shape.at == std::vector<double>{0.0, 1.0, 2.0});
    CHECK(scene.initial_shape.value == std::vector<double>{0.0, -0.01, 0.0});
  }
  SECTION("a half sine over the member") {
    const Scene scene =
        parse_scene(beam_scene + "\n[geometry]\ninitial_shape = { shape = \"half_sine\", amplitude = -0.02 }\n", "x");
    REQUIRE(scene.initial_shape.at.size() == initial_shape_samples + 1);
    CHECK(scene.initial_shape.at.front() == 0.0);
    CHECK(scene.initial_shape.at.back() == 2.0);
    CHECK(scene.initial_shape.value[initial_shape_samples / 2] == Approx(-0.02).epsilon(1e-15));
    CHECK(scene.initial_shape.value.front() == 0.0);
    CHECK(scene.initial_shape.value.back() == 0.0);
  }
  SECTION("a bump") {
    const Scene scene = parse_scene(
        beam_scene + "\n[geometry]\ninitial_shape = { shape = \"bump\", amplitude = 0.1, at = 1.0, length = 0.5 }\n",
        "x");
    CHECK(scene.initial_shape.at.front() == 0.75);
    CHECK(scene.initial_shape.at.back() == 1.25);
    CHECK(scene.initial_shape.value[initial_shape_samples / 2] == Approx(0.1).epsilon(1e-15));
  }
}

TEST_CASE("a malformed initial shape is refused naming the key", "[scene][axial][errors]") {
  const std::string geometry = beam_scene + "\n[geometry]\ninitial_shape = ";
  CHECK_THAT(error_of(geometry + "1.0\n"),
             StartsWith("scene.toml:19: key 'geometry.initial_shape': expected a table { at = [...], value = [...] }"));
  CHECK_THAT(error_of(geometry + "{ at = [0.0, 1.0], value = [0.0] }\n"),
             StartsWith("scene.toml:19: key 'geometry.initial_shape.value': expected one value per position"));
  CHECK_THAT(error_of(geometry + "{ at = [0.0, 0.0, 1.0], value = [0.0, 1.0, 0.0] }\n"),
             StartsWith("scene.toml:19: key 'geometry.initial_shape.at': expected increasing positions"));
  CHECK_THAT(error_of(geometry + "{ shape = \"wave\", amplitude = 1.0 }\n"),
             StartsWith("scene.toml:19: key 'geometry.initial_shape.shape': expected \"half_sine\" or \"bump\""));
  CHECK_THAT(error_of(geometry + "{ shape = \"half_sine\" }\n"),
             StartsWith("scene.toml:19: key 'geometry.initial_shape.amplitude': missing"));
  CHECK_THAT(error_of(geometry + "{ shape = \"bump\", amplitude = 1.0, at = 1.9, length = 0.5 }\n"),
             StartsWith("scene.toml:19: key 'geometry.initial_shape.length': expected a bump within the member"));
  CHECK_THAT(error_of(geometry + "{ shape = \"half_sine\", amplitude = 1.0, length = 0.5 }\n"),
             StartsWith("scene.toml:19: key 'geometry.initial_shape.length': unknown key"));
  CHECK_THAT(error_of(arch_scene + "\n[geometry]\ninitial_shape = { shape = \"half_sine\", amplitude = 1.0 }\n"),
             StartsWith("scene.toml:21: key 'geometry.initial_shape': not allowed for an arch"));
}

// Issue 16: [structure] theory and the ends' axial restraint (key `axial` of a support table).
TEST_CASE("a von Karman scene: theory and the ends' axial restraints read, with their defaults",
          "[scene][von_karman]") {
  SECTION("linear by default; the restraints' defaults by end kind, which linear theory does not read") {
    const Scene linear = parse_scene(beam_scene, "scene.toml");
    CHECK(linear.structure.theory == Theory::linear);
    CHECK(linear.supports.left_axially_restrained);   // pinned
    CHECK(linear.supports.right_axially_restrained);  // clamped
    const Scene free_end = parse_scene(edited(beam_scene, "right = \"clamped\"", "right = \"free\""), "scene.toml");
    CHECK_FALSE(free_end.supports.right_axially_restrained);
    const Scene spring = parse_scene(
        edited(beam_scene, "left = \"pinned\"", "left = { kind = \"spring\", stiffness = 1.0e3 }"), "scene.toml");
    CHECK_FALSE(spring.supports.left_axially_restrained);
    CHECK(parse_scene(edited(beam_scene, "kind = \"beam\"", "kind = \"beam\"\ntheory = \"linear\""), "x")
              .structure.theory == Theory::linear);
    CHECK(to_string(Theory::von_karman) == "von_karman");
    CHECK(parse_theory("von_karman") == Theory::von_karman);
    CHECK(parse_theory("nonlinear") == std::nullopt);
  }
  const std::string von_karman = edited(beam_scene, "EI = 1.0", "EI = 1.0\nEA = 4.0e4\ntheory = \"von_karman\"");
  SECTION("von Karman: the defaults, and axial as written") {
    const Scene s = parse_scene(von_karman, "scene.toml");
    CHECK(s.structure.theory == Theory::von_karman);
    CHECK(s.supports.left_axially_restrained);
    CHECK(s.supports.right_axially_restrained);
    const Scene both_free =
        parse_scene(edited(edited(von_karman, "left = \"pinned\"", "left = { kind = \"pinned\", axial = \"free\" }"),
                           "right = \"clamped\"", "right = { kind = \"clamped\", axial = \"free\" }"),
                    "scene.toml");  // N = 0: the linear beam, allowed
    CHECK_FALSE(both_free.supports.left_axially_restrained);
    CHECK_FALSE(both_free.supports.right_axially_restrained);
    const Scene written = parse_scene(
        edited(edited(von_karman, "left = \"pinned\"", "left = { kind = \"pinned\", axial = \"restrained\" }"),
               "right = \"clamped\"", "right = { kind = \"free\", axial = \"free\" }"),
        "scene.toml");
    CHECK(written.supports.left_axially_restrained);
    CHECK_FALSE(written.supports.right_axially_restrained);
    // A spring end: free by default, restrained when asked.
    const std::string spring =
        edited(von_karman, "left = \"pinned\"", "left = { kind = \"spring\", stiffness = 1.0e3 }");
    CHECK_FALSE(parse_scene(spring, "scene.toml").supports.left_axially_restrained);
    CHECK(parse_scene(edited(spring, "stiffness = 1.0e3", "stiffness = 1.0e3, axial = \"restrained\""), "scene.toml")
              .supports.left_axially_restrained);
    // A shallow arch of any shape: a von Karman beam with an initial shape.
    const Scene arch_like = parse_scene(
        von_karman + "\n[geometry]\ninitial_shape = { shape = \"half_sine\", amplitude = -0.06 }\n", "scene.toml");
    CHECK(arch_like.initial_shape.amplitude == -0.06);
  }
}

TEST_CASE("a von Karman scene: each mistake in theory and axial is one keyed line", "[scene][von_karman][errors]") {
  const std::string von_karman = edited(beam_scene, "EI = 1.0", "EI = 1.0\nEA = 4.0e4\ntheory = \"von_karman\"");
  //  1 [structure]  2 kind  3 length  4 EI  5 EA  6 theory   8 [supports]  9 left  10 right
  CHECK(error_of(edited(beam_scene, "kind = \"beam\"", "kind = \"beam\"\ntheory = \"nonlinear\"")) ==
        "scene.toml:3: key 'structure.theory': expected \"linear\" or \"von_karman\", got \"nonlinear\"");
  CHECK(error_of(edited(beam_scene, "kind = \"beam\"", "kind = \"beam\"\ntheory = \"von_karman\"")) ==
        "scene.toml:1: key 'structure.EA': missing (expected a number > 0 with theory = \"von_karman\": the membrane "
        "stiffness EA L^2/EI)");
  // Arches take von Karman theory (the circular arch's Marguerre/Donnell form); an end's u is its kind's,
  // so `axial` is refused on an arch under either theory.
  {
    const Scene arch =
        parse_scene(edited(arch_scene, "kind = \"arch\"", "kind = \"arch\"\ntheory = \"von_karman\""), "scene.toml");
    CHECK(arch.structure.theory == Theory::von_karman);
    CHECK(arch.structure.kind == StructureKind::arch);
  }
  CHECK(error_of(edited(edited(arch_scene, "kind = \"arch\"", "kind = \"arch\"\ntheory = \"von_karman\""),
                        "left = \"pinned\"", "left = { kind = \"pinned\", axial = \"free\" }")) ==
        "scene.toml:10: key 'supports.left.axial': not allowed for an arch (an arch end's kind sets its tangential "
        "displacement u under either theory: pinned and clamped hold u, roller and free release it; got kind "
        "\"pinned\")");
  CHECK(error_of(edited(von_karman, "EA = 4.0e4", "EA = 1.0e308")) ==
        "scene.toml:5: key 'structure.EA': expected EA L^2/EI to be a finite, nonzero double, got EA = 1e+308");
  // Under linear theory `axial` would do nothing: refused, so nobody believes it acts.
  CHECK(error_of(edited(beam_scene, "left = \"pinned\"", "left = { kind = \"pinned\", axial = \"restrained\" }")) ==
        "scene.toml:7: key 'supports.left.axial': not allowed with theory = \"linear\" (an axial restraint acts only "
        "with theory = \"von_karman\", [structure] theory: linear theory has no membrane strain)");
  CHECK(error_of(edited(von_karman, "right = \"clamped\"", "right = { kind = \"free\", axial = \"restrained\" }")) ==
        "scene.toml:10: key 'supports.right.axial': expected \"free\" on a free end, got \"restrained\" (nothing "
        "holds a free end axially; a spring end may be restrained)");
  CHECK(error_of(edited(von_karman, "left = \"pinned\"", "left = { kind = \"pinned\", axial = \"fixed\" }")) ==
        "scene.toml:9: key 'supports.left.axial': expected \"restrained\" or \"free\", got \"fixed\"");
  CHECK(error_of(edited(von_karman, "left = \"pinned\"", "left = { kind = \"pinned\", axial = true }")) ==
        "scene.toml:9: key 'supports.left.axial': expected \"restrained\" or \"free\", got true");
  CHECK_THAT(error_of(edited(von_karman, "right = \"clamped\"",
                             "right = \"clamped\"\ninterior = [{ at = 1.0, kind = \"pinned\", axial = \"free\" }]")),
             StartsWith("scene.toml:11: key 'supports.interior[0].axial': unknown key"));
  // A given axial force and the membrane force are not combined yet.
  CHECK(error_of(von_karman + "\n[[loads]]\nkind = \"axial\"\nvalue = 1.0\n") ==
        "scene.toml:21: key 'loads[1].kind': expected a transverse load with theory = \"von_karman\", got \"axial\" (a "
        "given axial force and the membrane force from the deflection are not combined yet)");
  CHECK_THAT(error_of(von_karman + "\n[[loads]]\nkind = \"temperature\"\nvalue = 60.0\nalpha = 1e-5\n"),
             StartsWith("scene.toml:21: key 'loads[1].kind': expected a transverse load with theory = \"von_karman\", "
                        "got \"temperature\""));
}
