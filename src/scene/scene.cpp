#include "scene/scene.hpp"

#include "core/enum_names.hpp"

namespace liftoff::scene {
namespace {

// The spelling of every enumerator in the scene file: one table per enum serves both directions
// (core/enum_names.hpp).

constexpr EnumName<StructureKind> structure_kinds[] = {
    {StructureKind::beam, "beam"},
    {StructureKind::arch, "arch"},
};
constexpr EnumName<EndSupport> end_supports[] = {
    {EndSupport::pinned, "pinned"},
    {EndSupport::clamped, "clamped"},
    {EndSupport::free, "free"},
    {EndSupport::roller, "roller"},
};
constexpr EnumName<LoadKind> load_kinds[] = {
    {LoadKind::force, "force"},
    {LoadKind::moment, "moment"},
    {LoadKind::uniform, "uniform"},
    {LoadKind::distributed, "distributed"},
    {LoadKind::curvature, "curvature"},
    {LoadKind::axial, "axial"},
    {LoadKind::temperature, "temperature"},
    {LoadKind::sine, "sine"},
};
constexpr EnumName<LoadCase> load_cases[] = {
    {LoadCase::live, "live"},
    {LoadCase::dead, "dead"},
};
constexpr EnumName<LoadDirection> load_directions[] = {
    {LoadDirection::radial, "radial"},
    {LoadDirection::tangential, "tangential"},
    {LoadDirection::vertical, "vertical"},
    {LoadDirection::horizontal, "horizontal"},
};
constexpr EnumName<LoadBasis> load_bases[] = {
    {LoadBasis::arc, "arc"},
    {LoadBasis::projection, "projection"},
};
constexpr EnumName<FoundationSide> foundation_sides[] = {
    {FoundationSide::inside, "inside"},
    {FoundationSide::outside, "outside"},
};
constexpr EnumName<Method> methods[] = {
    {Method::dual, "dual"},      {Method::primal, "primal"}, {Method::fast, "fast"},
    {Method::automatic, "auto"}, {Method::ritz, "ritz"},     {Method::all, "all"},
};
constexpr EnumName<TraceControl> trace_controls[] = {
    {TraceControl::arc_length, "arc_length"},
    {TraceControl::load, "load"},
};
constexpr EnumName<Theory> theories[] = {
    {Theory::linear, "linear"},
    {Theory::von_karman, "von_karman"},
};

}  // namespace

std::string_view to_string(StructureKind v) { return name_in<StructureKind>(structure_kinds, v); }
std::string_view to_string(EndSupport v) { return name_in<EndSupport>(end_supports, v); }
std::string_view to_string(LoadKind v) { return name_in<LoadKind>(load_kinds, v); }
std::string_view to_string(LoadCase v) { return name_in<LoadCase>(load_cases, v); }
std::string_view to_string(LoadDirection v) { return name_in<LoadDirection>(load_directions, v); }
std::string_view to_string(LoadBasis v) { return name_in<LoadBasis>(load_bases, v); }
std::string_view to_string(FoundationSide v) { return name_in<FoundationSide>(foundation_sides, v); }
std::string_view to_string(Method v) { return name_in<Method>(methods, v); }
std::string_view to_string(TraceControl v) { return name_in<TraceControl>(trace_controls, v); }
std::string_view to_string(Theory v) { return name_in<Theory>(theories, v); }

std::optional<StructureKind> parse_structure_kind(std::string_view s) {
  return value_in<StructureKind>(structure_kinds, s);
}
std::optional<EndSupport> parse_end_support(std::string_view s) { return value_in<EndSupport>(end_supports, s); }
std::optional<LoadKind> parse_load_kind(std::string_view s) { return value_in<LoadKind>(load_kinds, s); }
std::optional<LoadCase> parse_load_case(std::string_view s) { return value_in<LoadCase>(load_cases, s); }
std::optional<Method> parse_method(std::string_view s) { return value_in<Method>(methods, s); }
std::optional<TraceControl> parse_trace_control(std::string_view s) {
  return value_in<TraceControl>(trace_controls, s);
}
std::optional<Theory> parse_theory(std::string_view s) { return value_in<Theory>(theories, s); }

double Load::axial_force(const Structure& structure) const {
  if (kind == LoadKind::axial) return value;
  if (kind == LoadKind::temperature) return structure.axial_stiffness.value_or(0.0) * alpha * value;
  return 0.0;
}

double Scene::begin() const { return structure.kind == StructureKind::beam ? 0.0 : -structure.half_angle_deg; }

double Scene::end() const {
  return structure.kind == StructureKind::beam ? structure.length : structure.half_angle_deg;
}

}  // namespace liftoff::scene

namespace liftoff::scene {

double Combination::factor_of(std::string_view case_name) const {
  for (const auto& [name, factor] : factors)
    if (name == case_name) return factor;
  return 0.0;
}

}  // namespace liftoff::scene
