#include "continuation/trace.hpp"

namespace liftoff::continuation {

std::string_view to_string(EventKind kind) {
  switch (kind) {
    case EventKind::lift_off_opens:
      return "lift_off_opens";
    case EventKind::contact_opens:
      return "contact_opens";
    case EventKind::region_vanishes:
      return "region_vanishes";
    case EventKind::lift_off_vanishes:
      return "lift_off_vanishes";
    case EventKind::limit_at_support:
      return "limit_at_support";
    case EventKind::limit_at_load:
      return "limit_at_load";
    case EventKind::limit_at_end:
      return "limit_at_end";
    case EventKind::limit_point:
      return "limit_point";
  }
  return "unknown";
}

std::string_view to_string(TraceTermination termination) {
  switch (termination) {
    case TraceTermination::completed:
      return "completed";
    case TraceTermination::no_equilibrium:
      return "no_equilibrium";
    case TraceTermination::step_too_small:
      return "step_too_small";
    case TraceTermination::step_limit:
      return "step_limit";
    case TraceTermination::solver_failure:
      return "solver_failure";
  }
  return "unknown";
}

}  // namespace liftoff::continuation
