#include "continuation/ritz_path.hpp"

namespace liftoff::continuation {

// Placeholder until the ritz path lands.
TraceResult trace_ritz(const scene::Scene&, const TraceOptions&, const TraceSink&) {
  TraceResult result;
  result.summary.termination = TraceTermination::solver_failure;
  result.summary.path = "ritz";
  result.summary.message = "the ritz path is not implemented yet";
  return result;
}

}  // namespace liftoff::continuation
