#include "continuation/result.hpp"

namespace liftoff::continuation {

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

std::vector<bool> fe_contact_set(const TraceStep& step) {
  if (!std::holds_alternative<FeContactSet>(step.state_topology) || step.state.size() < fe_state_tail) return {};
  std::vector<bool> set;
  for (std::size_t i = 0; i + fe_state_tail < step.state.size(); ++i) set.push_back(step.state[i] > 0.5);
  return set;
}

}  // namespace liftoff::continuation

namespace liftoff {

template <>
std::optional<continuation::EventKind> from_string(std::string_view name) {
  return value_in<continuation::EventKind>(continuation::event_kind_names, name);
}
template <>
std::optional<continuation::TraceTermination> from_string(std::string_view name) {
  return value_in<continuation::TraceTermination>(continuation::trace_termination_names, name);
}
template <>
std::optional<continuation::PathKind> from_string(std::string_view name) {
  return value_in<continuation::PathKind>(continuation::path_kind_names, name);
}
template <>
std::optional<continuation::Stability> from_string(std::string_view name) {
  return value_in<continuation::Stability>(continuation::stability_names, name);
}

}  // namespace liftoff
