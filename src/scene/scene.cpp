#include "scene/scene.hpp"

#include <array>
#include <utility>

namespace liftoff::scene {
namespace {

// The spelling of every enumerator in the scene file: one table per enum serves both directions.
template <class Enum, std::size_t N>
using Names = std::array<std::pair<Enum, std::string_view>, N>;

constexpr Names<StructureKind, 2> structure_kinds{{
    {StructureKind::beam, "beam"},
    {StructureKind::arch, "arch"},
}};
constexpr Names<EndSupport, 4> end_supports{{
    {EndSupport::pinned, "pinned"},
    {EndSupport::clamped, "clamped"},
    {EndSupport::free, "free"},
    {EndSupport::roller, "roller"},
}};
constexpr Names<LoadKind, 5> load_kinds{{
    {LoadKind::force, "force"},
    {LoadKind::moment, "moment"},
    {LoadKind::uniform, "uniform"},
    {LoadKind::distributed, "distributed"},
    {LoadKind::curvature, "curvature"},
}};
constexpr Names<LoadCase, 2> load_cases{{
    {LoadCase::live, "live"},
    {LoadCase::dead, "dead"},
}};
constexpr Names<LoadDirection, 4> load_directions{{
    {LoadDirection::radial, "radial"},
    {LoadDirection::tangential, "tangential"},
    {LoadDirection::vertical, "vertical"},
    {LoadDirection::horizontal, "horizontal"},
}};
constexpr Names<LoadBasis, 2> load_bases{{
    {LoadBasis::arc, "arc"},
    {LoadBasis::projection, "projection"},
}};
constexpr Names<FoundationSide, 2> foundation_sides{{
    {FoundationSide::inside, "inside"},
    {FoundationSide::outside, "outside"},
}};
constexpr Names<Method, 6> methods{{
    {Method::dual, "dual"},
    {Method::primal, "primal"},
    {Method::fast, "fast"},
    {Method::automatic, "auto"},
    {Method::ritz, "ritz"},
    {Method::all, "all"},
}};
constexpr Names<TraceControl, 2> trace_controls{{
    {TraceControl::arc_length, "arc_length"},
    {TraceControl::load, "load"},
}};

template <class Enum, std::size_t N>
std::string_view name_of(const Names<Enum, N>& names, Enum value) {
  for (const auto& [v, name] : names) {
    if (v == value) return name;
  }
  return "?";  // unreachable for a valid enumerator
}

template <class Enum, std::size_t N>
std::optional<Enum> value_of(const Names<Enum, N>& names, std::string_view text) {
  for (const auto& [v, name] : names) {
    if (name == text) return v;
  }
  return std::nullopt;
}

}  // namespace

std::string_view to_string(StructureKind v) { return name_of(structure_kinds, v); }
std::string_view to_string(EndSupport v) { return name_of(end_supports, v); }
std::string_view to_string(LoadKind v) { return name_of(load_kinds, v); }
std::string_view to_string(LoadCase v) { return name_of(load_cases, v); }
std::string_view to_string(LoadDirection v) { return name_of(load_directions, v); }
std::string_view to_string(LoadBasis v) { return name_of(load_bases, v); }
std::string_view to_string(FoundationSide v) { return name_of(foundation_sides, v); }
std::string_view to_string(Method v) { return name_of(methods, v); }
std::string_view to_string(TraceControl v) { return name_of(trace_controls, v); }

std::optional<StructureKind> parse_structure_kind(std::string_view s) { return value_of(structure_kinds, s); }
std::optional<EndSupport> parse_end_support(std::string_view s) { return value_of(end_supports, s); }
std::optional<LoadKind> parse_load_kind(std::string_view s) { return value_of(load_kinds, s); }
std::optional<LoadCase> parse_load_case(std::string_view s) { return value_of(load_cases, s); }
std::optional<Method> parse_method(std::string_view s) { return value_of(methods, s); }
std::optional<TraceControl> parse_trace_control(std::string_view s) { return value_of(trace_controls, s); }

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
