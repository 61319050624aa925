#pragma once
// The Ritz load history: the Ritz model with moving contact limits followed by the
// pseudo-arc-length driver (arclength.hpp); topology events located on their event functions
// and the topology switched.

#include "continuation/trace.hpp"
#include "scene/scene.hpp"

namespace liftoff::continuation {

TraceResult trace_ritz(const scene::Scene& scene, const TraceOptions& options, const TraceSink& sink = {});

}  // namespace liftoff::continuation
