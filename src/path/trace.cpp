#include "path/trace.hpp"

namespace liftoff::path {

namespace {

constexpr EnumName<EventKind> event_kind_names[] = {
    {EventKind::lift_off_opens, "lift_off_opens"},     {EventKind::contact_opens, "contact_opens"},
    {EventKind::region_vanishes, "region_vanishes"},   {EventKind::lift_off_vanishes, "lift_off_vanishes"},
    {EventKind::limit_at_support, "limit_at_support"}, {EventKind::limit_at_load, "limit_at_load"},
    {EventKind::limit_at_end, "limit_at_end"},         {EventKind::limit_point, "limit_point"},
    {EventKind::bifurcation, "bifurcation"},
};

constexpr EnumName<TraceTermination> trace_termination_names[] = {
    {TraceTermination::completed, "completed"},           {TraceTermination::no_equilibrium, "no_equilibrium"},
    {TraceTermination::step_too_small, "step_too_small"}, {TraceTermination::step_limit, "step_limit"},
    {TraceTermination::solver_failure, "solver_failure"},
};

constexpr EnumName<Stability> stability_names[] = {
    {Stability::unknown, "unknown"},
    {Stability::stable, "stable"},
    {Stability::unstable, "unstable"},
};

constexpr EnumName<PathKind> path_kind_names[] = {
    {PathKind::fe, "fe"},
    {PathKind::ritz, "ritz"},
};

}  // namespace

std::string_view to_string(EventKind kind) { return name_in<EventKind>(event_kind_names, kind); }
std::string_view to_string(TraceTermination termination) {
  return name_in<TraceTermination>(trace_termination_names, termination);
}
std::string_view to_string(PathKind path) { return name_in<PathKind>(path_kind_names, path); }
std::string_view to_string(Stability stability) { return name_in<Stability>(stability_names, stability); }

}  // namespace liftoff::path

namespace liftoff {

template <>
std::optional<path::EventKind> from_string(std::string_view name) {
  return value_in<path::EventKind>(path::event_kind_names, name);
}
template <>
std::optional<path::TraceTermination> from_string(std::string_view name) {
  return value_in<path::TraceTermination>(path::trace_termination_names, name);
}
template <>
std::optional<path::PathKind> from_string(std::string_view name) {
  return value_in<path::PathKind>(path::path_kind_names, name);
}
template <>
std::optional<path::Stability> from_string(std::string_view name) {
  return value_in<path::Stability>(path::stability_names, name);
}

}  // namespace liftoff
