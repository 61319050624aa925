#include "continuation/trace.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace liftoff::continuation {

namespace {

constexpr EnumName<EventKind> event_kind_names[] = {
    {EventKind::lift_off_opens, "lift_off_opens"},     {EventKind::contact_opens, "contact_opens"},
    {EventKind::region_vanishes, "region_vanishes"},   {EventKind::lift_off_vanishes, "lift_off_vanishes"},
    {EventKind::limit_at_support, "limit_at_support"}, {EventKind::limit_at_load, "limit_at_load"},
    {EventKind::limit_at_end, "limit_at_end"},         {EventKind::limit_point, "limit_point"},
};

constexpr EnumName<TraceTermination> trace_termination_names[] = {
    {TraceTermination::completed, "completed"},           {TraceTermination::no_equilibrium, "no_equilibrium"},
    {TraceTermination::step_too_small, "step_too_small"}, {TraceTermination::step_limit, "step_limit"},
    {TraceTermination::solver_failure, "solver_failure"},
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

void TraceOptions::validate(double member_begin, double member_end) const {
  const auto fail = [](const std::string& what) { throw std::invalid_argument("TraceOptions." + what); };
  try {
    arc_length.validate();
  } catch (const std::invalid_argument& e) {  // named as a field of the trace's options
    const std::string what = e.what(), prefix = "ArcLengthOptions.";
    fail("arc_length." + (what.rfind(prefix, 0) == 0 ? what.substr(prefix.size()) : what));
  }
  if (!(event_tolerance > 0)) fail(fmt::format("event_tolerance: expected > 0, got {}", event_tolerance));
  if (elements < 1) fail(fmt::format("elements: expected >= 1, got {}", elements));
  if (contact_method == scene::Method::ritz || contact_method == scene::Method::all)
    fail(fmt::format("contact_method: expected dual, primal, fast or automatic, got {}",
                     scene::to_string(contact_method)));
  if (modes < 0) fail(fmt::format("modes: expected >= 0 (0: automatic), got {}", modes));
  const double lo = std::min(member_begin, member_end), hi = std::max(member_begin, member_end);
  for (double p : sample_points)
    if (!(p >= lo && p <= hi)) fail(fmt::format("sample_points: expected positions in [{}, {}], got {}", lo, hi, p));
  if (!(monitor >= lo && monitor <= hi))
    fail(fmt::format("monitor: expected a position in [{}, {}], got {}", lo, hi, monitor));
  if (resume_from && !std::isfinite(resume_from->load_factor))
    fail("resume_from: the step's load factor must be finite");
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

}  // namespace liftoff
