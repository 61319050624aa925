#pragma once
// The schema of a scene file: every table a scene may hold, the keys each accepts and the
// dimension of each key's number. The reader (scene_reader.cpp) refuses any other table or key,
// so a typo is never ignored, and converts a number written with its unit ("30 MN/m^2") into the
// scene's [units] by the key's dimension listed here; the reference (src/scene/README.md)
// documents every key listed here (tests/scene/schema_test.cpp compares the two). Adding a key is
// one line here, the code that reads it and its row in the reference.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "scene/scene.hpp"

namespace liftoff::scene {

// What a key's number measures. A plain number is always in the scene's [units]; a string
// "VALUE UNIT" is converted to them when the key has a dimension (not none, not not_a_number).
enum class Dimension {
  not_a_number,         // text, a flag or a table: never a number
  none,                 // nondimensional (K l^4/EI, a load factor, a tolerance, a count)
  length,               // settlement, gap, amplitude
  position,             // where on the member: a length on a beam, an angle (degrees) on an arch
  angle,                // degrees
  force,                // F
  force_length,         // F L: a moment, a rotational spring's stiffness (per radian)
  force_length2,        // F L^2: EI
  force_per_length,     // F/L: a distributed force, a spring's stiffness
  force_per_length2,    // F/L^2: the foundation modulus K
  inverse_length,       // 1/L: an imposed curvature
  temperature,          // a temperature rise dT, in kelvin (a rise in degC is the same number)
  inverse_temperature,  // 1/K: a coefficient of thermal expansion
  load_value,           // a load's value: its kind's dimension (load_value_dimension)
  live_load,            // trace.report_at: the live load's dimension where it has one, else none
};

struct KeySpec {
  std::string_view name;
  Dimension dimension = Dimension::not_a_number;
};

struct TableSpec {
  std::string_view name;  // its path in the scene: "structure", "foundation.segments"
  bool array_of_tables;   // [[loads]] rather than [structure]
  std::vector<KeySpec> keys;

  std::vector<std::string_view> key_names() const;
};

// The tables at the top of a scene, in the reference's order.
const std::vector<TableSpec>& top_level_tables();

// Tables inside a key of a top-level table. Where the keys depend on the form chosen (a named
// initial shape or a table of points), each form is a spec of its own under the same name.
namespace nested {
const TableSpec& end_support();              // supports.left / supports.right written as a table
const TableSpec& interior_support();         // an entry of supports.interior written as a table
const TableSpec& foundation_segment();       // [[foundation.segments]]
const TableSpec& foundation_gap();           // foundation.gap = { at, value }
const TableSpec& moving_load();              // an entry of moving.loads
const TableSpec& initial_shape_points();     // geometry.initial_shape = { at, value }
const TableSpec& initial_shape_half_sine();  // geometry.initial_shape = { shape = "half_sine", ... }
const TableSpec& initial_shape_bump();       // geometry.initial_shape = { shape = "bump", ... }
}  // namespace nested

// Every spec above, top-level tables first.
std::vector<const TableSpec*> every_table();

// The dimension of the number at a key's path as messages write it: "structure.EI",
// "loads[2].value", "supports.right.stiffness", "foundation.segments[0].modulus[1]" (indices of
// arrays and of arrays of tables are dropped; supports.right's table is supports.left's). Keys
// of combinations[i].factors are load factors (none). nullopt for a path the schema does not list.
std::optional<Dimension> key_dimension(std::string_view path);

// A load's value by its kind: force, moment, distributed force (uniform, distributed, sine),
// 1/length (curvature), compressive force (axial), temperature rise (temperature).
Dimension load_value_dimension(LoadKind kind);

// "force/length^2" (for messages; position and load_value as such: resolve them first).
std::string_view to_string(Dimension dimension);
// The dimension's unit in the scene's units ("kN/m^2"); temperatures in K, angles in degrees
// whatever [units] say; "" for none and for a length-based dimension when no units are stated.
std::string unit_in(Dimension dimension, const Units& units);
// The dimension's SI unit ("N/m^2"), to name the dimension of a unit the user wrote.
std::string_view si_unit(Dimension dimension);

}  // namespace liftoff::scene
