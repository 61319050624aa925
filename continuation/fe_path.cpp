#include "continuation/fe_path.hpp"

namespace liftoff::continuation {

// Placeholder until the fe path lands.
TraceResult trace_fe(const scene::Scene&, const TraceOptions&, const TraceSink&) {
  TraceResult result;
  result.summary.termination = TraceTermination::solver_failure;
  result.summary.path = "fe";
  result.summary.message = "the fe path is not implemented yet";
  return result;
}

}  // namespace liftoff::continuation
