#include "scene/schema.hpp"

namespace liftoff::scene {

const std::vector<TableSpec>& top_level_tables() {
  static const std::vector<TableSpec> tables = {
      {"structure", false, {"kind", "length", "radius", "half_angle_deg", "EI", "EA", "theory"}},
      {"supports", false, {"left", "right", "interior"}},
      {"foundation",
       false,
       {"nondimensional_k", "modulus", "tensionless", "from", "to", "segments", "side", "gap", "gap_file",
        "tension_modulus", "tension_nondimensional_k", "k", "tension_k"}},
      {"loads", true, {"kind", "at", "value", "from", "to", "case", "direction", "per", "alpha", "n"}},
      {"geometry", false, {"initial_shape"}},
      {"solve", false, {"method", "elements", "tolerance"}},
      {"ritz", false, {"modes", "max_modes", "mode_tolerance", "topology", "limits"}},
      {"trace",
       false,
       {"lambda_max", "lambda_min", "method", "control", "initial_step", "min_step", "max_step", "max_steps", "monitor",
        "samples", "refine", "max_amplitude", "switch_branch", "report_at"}},
      {"compare", false, {"source", "contact_half_angle_deg"}},
      {"units", false, {"system", "length", "force"}},
      {"combinations", true, {"name", "factors"}},
      {"moving", false, {"loads", "from", "to", "step", "positions", "case"}},
  };
  return tables;
}

namespace nested {
const TableSpec& end_support() {
  static const TableSpec spec{
      "supports.left", false, {"kind", "stiffness", "rotational_stiffness", "settlement", "axial"}};
  return spec;
}
const TableSpec& interior_support() {
  static const TableSpec spec{
      "supports.interior", true, {"at", "kind", "stiffness", "rotational_stiffness", "settlement"}};
  return spec;
}
const TableSpec& foundation_segment() {
  static const TableSpec spec{"foundation.segments", true, {"from", "to", "nondimensional_k", "modulus", "k"}};
  return spec;
}
const TableSpec& foundation_gap() {
  static const TableSpec spec{"foundation.gap", false, {"at", "value"}};
  return spec;
}
const TableSpec& moving_load() {
  static const TableSpec spec{"moving.loads", true, {"kind", "offset", "value"}};
  return spec;
}
const TableSpec& initial_shape_points() {
  static const TableSpec spec{"geometry.initial_shape", false, {"at", "value"}};
  return spec;
}
const TableSpec& initial_shape_half_sine() {
  static const TableSpec spec{"geometry.initial_shape", false, {"shape", "amplitude"}};
  return spec;
}
const TableSpec& initial_shape_bump() {
  static const TableSpec spec{"geometry.initial_shape", false, {"shape", "amplitude", "at", "length"}};
  return spec;
}
}  // namespace nested

std::vector<const TableSpec*> every_table() {
  std::vector<const TableSpec*> tables;
  for (const TableSpec& spec : top_level_tables()) tables.push_back(&spec);
  for (const TableSpec* spec : {&nested::end_support(), &nested::interior_support(), &nested::foundation_segment(),
                                &nested::foundation_gap(), &nested::moving_load(), &nested::initial_shape_points(),
                                &nested::initial_shape_half_sine(), &nested::initial_shape_bump()})
    tables.push_back(spec);
  return tables;
}

}  // namespace liftoff::scene
