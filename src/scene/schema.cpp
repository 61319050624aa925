#include "scene/schema.hpp"

#include <algorithm>

namespace liftoff::scene {
namespace {
using D = Dimension;
constexpr D text = D::not_a_number;
}  // namespace

std::vector<std::string_view> TableSpec::key_names() const {
  std::vector<std::string_view> names;
  for (const KeySpec& key : keys) names.push_back(key.name);
  return names;
}

const std::vector<TableSpec>& top_level_tables() {
  static const std::vector<TableSpec> tables = {
      {"structure",
       false,
       {{"kind", text},
        {"length", D::length},
        {"radius", D::length},
        {"half_angle_deg", D::angle},
        {"EI", D::force_length2},
        {"EA", D::force},
        {"theory", text}}},
      {"supports", false, {{"left", text}, {"right", text}, {"interior", D::position}}},
      {"foundation",
       false,
       {{"nondimensional_k", D::none},
        {"modulus", D::force_per_length2},
        {"tensionless", text},
        {"from", D::position},
        {"to", D::position},
        {"segments", text},
        {"side", text},
        {"gap", text},
        {"gap_file", text},
        {"tension_modulus", D::force_per_length2},
        {"tension_nondimensional_k", D::none},
        {"k", D::none},
        {"tension_k", D::none}}},
      {"loads",
       true,
       {{"kind", text},
        {"at", D::position},
        {"value", D::load_value},
        {"from", D::position},
        {"to", D::position},
        {"case", text},
        {"direction", text},
        {"per", text},
        {"alpha", D::inverse_temperature},
        {"n", D::none}}},
      {"geometry", false, {{"initial_shape", text}}},
      {"solve", false, {{"method", text}, {"elements", D::none}, {"tolerance", D::none}}},
      {"ritz",
       false,
       {{"modes", D::none},
        {"max_modes", D::none},
        {"mode_tolerance", D::none},
        {"topology", text},
        {"limits", D::position}}},
      {"trace",
       false,
       {{"lambda_max", D::none},
        {"lambda_min", D::none},
        {"method", text},
        {"control", text},
        {"initial_step", D::none},
        {"min_step", D::none},
        {"max_step", D::none},
        {"max_steps", D::none},
        {"monitor", D::position},
        {"samples", D::none},
        {"refine", text},
        {"max_amplitude", D::length},
        {"switch_branch", text},
        {"report_at", D::live_load}}},
      {"compare", false, {{"source", text}, {"contact_half_angle_deg", D::angle}}},
      {"units", false, {{"system", text}, {"length", text}, {"force", text}}},
      {"combinations", true, {{"name", text}, {"factors", D::none}}},
      {"moving",
       false,
       {{"loads", text},
        {"from", D::position},
        {"to", D::position},
        {"step", D::position},
        {"positions", D::position},
        {"case", text}}},
  };
  return tables;
}

namespace nested {
const TableSpec& end_support() {
  static const TableSpec spec{"supports.left",
                              false,
                              {{"kind", text},
                               {"stiffness", D::force_per_length},
                               {"rotational_stiffness", D::force_length},
                               {"settlement", D::length},
                               {"axial", text}}};
  return spec;
}
const TableSpec& interior_support() {
  static const TableSpec spec{"supports.interior",
                              true,
                              {{"at", D::position},
                               {"kind", text},
                               {"stiffness", D::force_per_length},
                               {"rotational_stiffness", D::force_length},
                               {"settlement", D::length}}};
  return spec;
}
const TableSpec& foundation_segment() {
  static const TableSpec spec{"foundation.segments",
                              true,
                              {{"from", D::position},
                               {"to", D::position},
                               {"nondimensional_k", D::none},
                               {"modulus", D::force_per_length2},
                               {"k", D::none}}};
  return spec;
}
const TableSpec& foundation_gap() {
  static const TableSpec spec{"foundation.gap", false, {{"at", D::position}, {"value", D::length}}};
  return spec;
}
const TableSpec& moving_load() {
  static const TableSpec spec{
      "moving.loads", true, {{"kind", text}, {"offset", D::position}, {"value", D::load_value}}};
  return spec;
}
const TableSpec& initial_shape_points() {
  static const TableSpec spec{"geometry.initial_shape", false, {{"at", D::position}, {"value", D::length}}};
  return spec;
}
const TableSpec& initial_shape_half_sine() {
  static const TableSpec spec{"geometry.initial_shape", false, {{"shape", text}, {"amplitude", D::length}}};
  return spec;
}
const TableSpec& initial_shape_bump() {
  static const TableSpec spec{"geometry.initial_shape",
                              false,
                              {{"shape", text}, {"amplitude", D::length}, {"at", D::position}, {"length", D::length}}};
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

std::optional<Dimension> key_dimension(std::string_view path) {
  std::string plain;  // the path without its indices
  for (std::size_t i = 0; i < path.size(); ++i) {
    if (path[i] == '[') {
      i = path.find(']', i);
      if (i == std::string_view::npos) break;
      continue;
    }
    plain += path[i];
  }
  if (plain.rfind("combinations.factors.", 0) == 0) return Dimension::none;  // a case's partial factor
  if (plain.rfind("supports.right.", 0) == 0) plain.replace(0, 14, "supports.left");
  // The longest table name that prefixes the path, then the key after it.
  const TableSpec* table = nullptr;
  for (const TableSpec* spec : every_table()) {
    const std::string_view name = spec->name;
    const bool prefixes = plain.size() > name.size() && plain.compare(0, name.size(), name) == 0;
    if (prefixes && plain[name.size()] == '.' && (table == nullptr || name.size() > table->name.size())) table = spec;
  }
  if (table != nullptr) {
    const std::string_view key = std::string_view(plain).substr(table->name.size() + 1);
    for (const TableSpec* spec : every_table())  // forms that share a name (initial shapes)
      if (spec->name == table->name)
        for (const KeySpec& k : spec->keys)
          if (k.name == key) return k.dimension;
  }
  return std::nullopt;
}

Dimension load_value_dimension(LoadKind kind) {
  switch (kind) {
    case LoadKind::force:
    case LoadKind::axial:
      return Dimension::force;
    case LoadKind::moment:
      return Dimension::force_length;
    case LoadKind::uniform:
    case LoadKind::distributed:
    case LoadKind::sine:
      return Dimension::force_per_length;
    case LoadKind::curvature:
      return Dimension::inverse_length;
    case LoadKind::temperature:
      return Dimension::temperature;
  }
  return Dimension::none;
}

std::string_view to_string(Dimension d) {
  switch (d) {
    case D::not_a_number:
      return "not a number";
    case D::none:
      return "nondimensional";
    case D::length:
      return "length";
    case D::position:
      return "position";
    case D::angle:
      return "angle";
    case D::force:
      return "force";
    case D::force_length:
      return "force*length";
    case D::force_length2:
      return "force*length^2";
    case D::force_per_length:
      return "force/length";
    case D::force_per_length2:
      return "force/length^2";
    case D::inverse_length:
      return "1/length";
    case D::temperature:
      return "temperature";
    case D::inverse_temperature:
      return "1/temperature";
    case D::load_value:
      return "load value";
    case D::live_load:
      return "live load";
  }
  return "";
}

std::string unit_in(Dimension d, const Units& u) {
  switch (d) {
    case D::length:
      return u.length;
    case D::force:
      return u.force;
    case D::force_length:
      return u.moment();
    case D::force_length2:
      return u.bending_stiffness();
    case D::force_per_length:
      return u.distributed_force();
    case D::force_per_length2:
      return u.modulus();
    case D::inverse_length:
      return u.inverse_length();
    case D::angle:
      return "degree";
    case D::temperature:
      return "K";
    case D::inverse_temperature:
      return "1/K";
    default:
      return "";
  }
}

std::string_view si_unit(Dimension d) {
  switch (d) {
    case D::length:
      return "m";
    case D::force:
      return "N";
    case D::force_length:
      return "N m";
    case D::force_length2:
      return "N m^2";
    case D::force_per_length:
      return "N/m";
    case D::force_per_length2:
      return "N/m^2";
    case D::inverse_length:
      return "1/m";
    case D::angle:
      return "degree";
    case D::temperature:
      return "K";
    case D::inverse_temperature:
      return "1/K";
    default:
      return "";
  }
}

}  // namespace liftoff::scene
