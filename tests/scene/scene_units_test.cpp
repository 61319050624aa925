// Values with their units in a scene (src/scene/README.md, "Values with their units"): a number
// written as "VALUE UNIT" is checked for its key's dimension (scene/schema.hpp) and converted to
// the scene's [units]; every way it cannot be is a keyed one-line error (InputError, exit 2).
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "scene/scene_reader.hpp"

using namespace liftoff::scene;
using Catch::Matchers::Contains;

namespace {

// The eccentric footing of verification/scenes/engineering/footing_eccentric_column.toml in kN
// and m: B = 3.0 m, EI = 5.4e5 kN m^2, K = 3.0e4 kN/m^2, 800 kN and -400 kN m at x = 1.8 m.
// `EI` and `modulus` as written (TOML values); `extra` follows the loads.
std::string footing(const std::string& EI = "5.4e5", const std::string& modulus = "3.0e4",
                    const std::string& units = "system = \"kN-m\"", const std::string& extra = "") {
  return "[structure]\nkind = \"beam\"\nlength = 3.0\nEI = " + EI +
         "\n[supports]\nleft = \"free\"\nright = \"free\"\n[foundation]\nmodulus = " + modulus +
         "\n[[loads]]\nkind = \"force\"\nat = 1.8\nvalue = 800.0\n[[loads]]\nkind = \"moment\"\nat = 1.8\n"
         "value = -400.0\n" +
         extra + (units.empty() ? "" : "[units]\n" + units + "\n");
}

Scene read(const std::string& text) { return parse_scene(text, "scene.toml"); }

std::string error_of(const std::string& text) {
  try {
    read(text);
  } catch (const liftoff::InputError& e) {
    return e.what();
  }
  return "no error";
}

// A load (its table's lines) added to the footing.
std::string with_load(const std::string& lines, const std::string& units = "system = \"kN-m\"") {
  return footing("5.4e5", "3.0e4", units, "[[loads]]\n" + lines + "\n");
}

}  // namespace

TEST_CASE("units: a value with its unit reads as the same value in the scene's units, bit for bit", "[scene][units]") {
  // The issue's check: the kN-m footing with EI in N m^2 is the same scene as with kN m^2.
  const Scene plain = read(footing());
  const Scene in_newtons = read(footing("\"5.4e8 N m^2\""));
  CHECK(in_newtons.structure.bending_stiffness == plain.structure.bending_stiffness);
  CHECK(in_newtons.structure.bending_stiffness == 5.4e5);
  CHECK(read(footing("\"3.12e7 N m^2\"")).structure.bending_stiffness == 3.12e4);
  CHECK(*read(footing("5.4e5", "\"30 MN/m^2\"")).foundation.modulus == 3.0e4);
  CHECK(*read(footing("5.4e5", "\"30 N/mm^2\"")).foundation.modulus == 3.0e4);
  const Scene loads = read(with_load("kind = \"force\"\nat = \"1800 mm\"\nvalue = \"100000 N\""));
  CHECK(loads.loads.back().at == 1.8);
  CHECK(loads.loads.back().value == 100.0);
  CHECK(read(with_load("kind = \"moment\"\nat = 0.5\nvalue = \"25000 N m\"")).loads.back().value == 25.0);
  CHECK(read(with_load("kind = \"uniform\"\nvalue = \"5 N/mm\"")).loads.back().value == 5.0);
  CHECK(read(with_load("kind = \"uniform\"\nfrom = \"500 mm\"\nto = \"2.5 m\"\nvalue = 1.0")).loads.back().from == 0.5);
  // Nothing written with a unit is the same scene as before, and each converted key is recorded.
  CHECK(plain.given_with_unit.empty());
  CHECK(in_newtons.given_with_unit == std::vector<std::string>{"structure.EI"});
  CHECK(loads.given_with_unit == std::vector<std::string>{"loads[2].at", "loads[2].value"});
}

TEST_CASE("units: kip-ft scenes, springs, settlements, gaps and arrays convert", "[scene][units]") {
  const double lbf = 4.4482216152605, ft = 0.3048, round_off = 1e-15;
  const Scene us = read(footing("\"1.0e6 kip in^2\"", "\"1 kN/m^2\"", "system = \"kip-ft\""));
  CHECK(us.structure.bending_stiffness == Approx(1.0e6 / 144).epsilon(round_off));
  CHECK(*us.foundation.modulus == Approx(ft * ft / lbf).epsilon(4 * round_off));  // 1 kN = 1/lbf kip
  const Scene spring = read(footing("5.4e5", "3.0e4", "system = \"kN-m\"")
                                .replace(footing().find("left = \"free\""), 13,
                                         "left = { kind = \"spring\", stiffness = \"2 MN/m\", rotational_stiffness = "
                                         "\"3e6 N m\", settlement = \"5 mm\" "
                                         "}"));
  CHECK(spring.supports.left_detail.stiffness == 2000.0);
  CHECK(spring.supports.left_detail.rotational_stiffness == 3000.0);
  CHECK(spring.supports.left_detail.settlement == 0.005);
  const Scene gap = read(footing("5.4e5", "3.0e4\ngap = { at = [0.0, \"3000 mm\"], value = [\"10 mm\", 0.02] }"));
  CHECK(gap.foundation.gap_at == std::vector<double>{0.0, 3.0});
  CHECK(gap.foundation.gap_value == std::vector<double>{0.01, 0.02});
}

TEST_CASE("units: temperatures in kelvin, angles in degrees, and trace.report_at in the live load's unit",
          "[scene][units]") {
  const Scene thermal =
      read(footing("5.4e5\nEA = 1.8e7", "3.0e4", "system = \"kN-m\"",
                   "[[loads]]\nkind = \"temperature\"\nvalue = \"36 degF\"\nalpha = \"1e-5 1/degF\"\n"));
  CHECK(thermal.loads.back().value == Approx(20.0).epsilon(1e-14));    // a rise: the slope, no offset
  CHECK(thermal.loads.back().alpha == Approx(1.8e-5).epsilon(1e-14));  // per kelvin
  const std::string arch =
      "[structure]\nkind = \"arch\"\nradius = 10.0\nhalf_angle_deg = \"0.5 rad\"\nEI = 1.0e4\nEA = 1.0e6\n"
      "[supports]\nleft = \"pinned\"\nright = \"pinned\"\n[foundation]\nmodulus = 100.0\n"
      "[[loads]]\nkind = \"force\"\nat = \"0.1 rad\"\nvalue = 1.0\n[units]\nsystem = \"kN-m\"\n";
  const Scene a = read(arch);
  CHECK(a.structure.half_angle_deg == Approx(0.5 * 180 / M_PI).epsilon(1e-15));
  CHECK(a.loads[0].at == Approx(0.1 * 180 / M_PI).epsilon(1e-15));
  std::string in_metres = arch;
  in_metres.replace(in_metres.find("at = \"0.1 rad\""), 14, "at = \"3 m\"");
  CHECK(error_of(in_metres) ==
        R"(scene.toml:14: key 'loads[0].at': expected an angle (an angle in degrees in [-28.64788975654116, )"
        R"(28.64788975654116]) in degree or a unit convertible to it, got "3 m" ("m" is a length))");
  // The live load is the 800 kN force alone (the moment dead): report_at is in force units.
  std::string forces = footing("5.4e5", "3.0e4", "system = \"kN-m\"",
                               "[trace]\nlambda_max = 2.0\nreport_at = [\"900 kN\", \"1.2 MN\"]\n");
  forces.replace(forces.find("value = -400.0\n"), 15, "value = -400.0\ncase = \"dead\"\n");
  CHECK(read(forces).trace->report_at == std::vector<double>{900.0, 1200.0});
  // Both live: no single physical load, report_at is load factors and takes no unit.
  const std::string mixed =
      footing("5.4e5", "3.0e4", "system = \"kN-m\"", "[trace]\nlambda_max = 2.0\nreport_at = [\"900 kN\"]\n");
  CHECK_THAT(error_of(mixed), Contains("key 'trace.report_at[0]': expected a finite number, a plain number, got "
                                       "\"900 kN\" (this key is nondimensional: it takes no unit)"));
}

TEST_CASE("units: a wrong dimension is a keyed error naming the dimension expected and the one given",
          "[scene][units][errors]") {
  // One per dimension a key may need: the message names the key, the dimension, the scene's unit
  // and what the unit written is.
  CHECK(error_of(footing("5.4e5\nEA = \"5 m\"")) ==
        R"(scene.toml:5: key 'structure.EA': expected a force (a number > 0) in kN or a unit convertible to it, )"
        R"(got "5 m" ("m" is a length))");
  CHECK(error_of(footing("\"30 MN/m^2\"")) ==
        R"(scene.toml:4: key 'structure.EI': expected a force*length^2 (a number > 0) in kN m^2 or a unit )"
        R"(convertible to it, got "30 MN/m^2" ("MN/m^2" is a force/length^2))");
  CHECK(error_of(footing("5.4e5", "\"3 kN/m^3\"")) ==
        R"(scene.toml:9: key 'foundation.modulus': expected a force/length^2 (a number > 0) in kN/m^2 or a unit )"
        R"(convertible to it, got "3 kN/m^3" ("kN/m^3" is of another dimension))");
  CHECK_THAT(error_of(footing().replace(footing().find("length = 3.0"), 12, "length = \"3 kN\"")),
             Contains("key 'structure.length': expected a length (a number > 0) in m or a unit convertible to it, "
                      "got \"3 kN\" (\"kN\" is a force)"));
  CHECK_THAT(error_of(with_load("kind = \"force\"\nat = \"2 kN\"\nvalue = 1.0")),
             Contains("key 'loads[2].at': expected a length (a position in [0, 3]) in m"));
  CHECK_THAT(error_of(with_load("kind = \"force\"\nat = 1.0\nvalue = \"5 kN m\"")),
             Contains("key 'loads[2].value': expected a force (a finite number) in kN or a unit convertible to it, "
                      "got \"5 kN m\" (\"kN m\" is a force*length)"));
  CHECK_THAT(error_of(with_load("kind = \"moment\"\nat = 1.0\nvalue = \"5 kN/m\"")),
             Contains("key 'loads[2].value': expected a force*length (a finite number) in kN m"));
  CHECK_THAT(error_of(with_load("kind = \"uniform\"\nvalue = \"5 kN\"")),
             Contains("key 'loads[2].value': expected a force/length (a finite number) in kN/m"));
  CHECK_THAT(error_of(with_load("kind = \"curvature\"\nvalue = \"5 m\"")),
             Contains("key 'loads[2].value': expected a 1/length (a finite number) in 1/m"));
  CHECK_THAT(error_of(footing("5.4e5\nEA = 1.8e7", "3.0e4", "system = \"kN-m\"",
                              "[[loads]]\nkind = \"temperature\"\nvalue = \"20 m\"\nalpha = 1e-5\n")),
             Contains("key 'loads[2].value': expected a temperature (a finite number) in K"));
  CHECK_THAT(error_of(footing("5.4e5\nEA = 1.8e7", "3.0e4", "system = \"kN-m\"",
                              "[[loads]]\nkind = \"temperature\"\nvalue = 20\nalpha = \"1e-5 K\"\n")),
             Contains("key 'loads[2].alpha': expected a 1/temperature (a number > 0) in 1/K or a unit convertible to "
                      "it, got \"1e-5 K\" (\"K\" is a temperature)"));
  CHECK_THAT(error_of(footing().replace(footing().find("left = \"free\""), 13,
                                        "left = { kind = \"spring\", stiffness = \"2 kN\" }")),
             Contains("key 'supports.left.stiffness': expected a force/length (a number >= 0) in kN/m"));
  CHECK_THAT(error_of(footing().replace(footing().find("right = \"free\""), 14,
                                        "right = { kind = \"spring\", rotational_stiffness = \"2 kN\" }")),
             Contains("key 'supports.right.rotational_stiffness': expected a force*length (a number >= 0) in kN m"));
}

TEST_CASE("units: a unit where none can be converted is a keyed error", "[scene][units][errors]") {
  // A nondimensional key.
  CHECK(error_of(footing().replace(footing().find("modulus = 3.0e4"), 15, "nondimensional_k = \"4.5 kN/m^2\"")) ==
        R"(scene.toml:9: key 'foundation.nondimensional_k': expected a number > 0, a plain number, got )"
        R"("4.5 kN/m^2" (this key is nondimensional: it takes no unit))");
  // An unknown unit.
  CHECK(error_of(footing("\"5.4e8 Nm^2\"")) ==
        R"(scene.toml:4: key 'structure.EI': expected a force*length^2 (a number > 0) with a unit UDUNITS-2 knows )"
        R"((e.g. "N m^2"), got "5.4e8 Nm^2" (unknown unit "Nm^2"))");
  // No [units]: nothing to convert to.
  CHECK_THAT(error_of(footing("\"5.4e8 N m^2\"", "3.0e4", "")),
             Contains("key 'structure.EI': expected a force*length^2 (a number > 0) as a plain number, got \"5.4e8 N "
                      "m^2\" (a unit needs the scene's [units] to convert to"));
  // Free labels UDUNITS does not know; labels it knows convert like a system.
  CHECK_THAT(error_of(footing("\"5.4e8 N m^2\"", "3.0e4", "length = \"span\"\nforce = \"kN\"")),
             Contains("key 'structure.EI': expected a force*length^2 (a number > 0) as a plain number, got \"5.4e8 N "
                      "m^2\" (the scene's [units] labels make its unit \"kN span^2\", which UDUNITS-2 does not "
                      "know"));
  CHECK(read(footing("\"5.4e8 N m^2\"", "3.0e4", "length = \"m\"\nforce = \"kN\"")).structure.bending_stiffness ==
        5.4e5);
  // A string without a unit, and a value outside the key's range once converted.
  CHECK_THAT(error_of(footing("\"5.4e5\"")), Contains("a plain number, or a number and its unit, got \"5.4e5\""));
  CHECK(error_of(footing("\"-5 kN m^2\"")) ==
        R"(scene.toml:4: key 'structure.EI': expected a number > 0, got "-5 kN m^2" (-5.0 in the scene's units))");
}
