#pragma once
// The schema of a scene file: every table a scene may hold and the keys each accepts. The reader
// (scene_reader.cpp) refuses any other table or key, so a typo is never ignored; the reference
// (src/scene/README.md) documents every key listed here (tests/scene/schema_test.cpp compares
// the two). Adding a key is one line here, the code that reads it and its row in the reference.

#include <string_view>
#include <vector>

namespace liftoff::scene {

struct TableSpec {
  std::string_view name;  // its path in the scene: "structure", "foundation.segments"
  bool array_of_tables;   // [[loads]] rather than [structure]
  std::vector<std::string_view> keys;
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

}  // namespace liftoff::scene
