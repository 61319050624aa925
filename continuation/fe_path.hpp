#pragma once
// The FE + LCP load history, traced exactly: for the linear model the discrete solution is
// piecewise linear in lambda, so the path is followed by parametric pivoting from breakpoint
// to breakpoint (a node changing contact status), with no step length and no Newton.

#include "continuation/trace.hpp"
#include "scene/scene.hpp"

namespace liftoff::continuation {

TraceResult trace_fe(const scene::Scene& scene, const TraceOptions& options, const TraceSink& sink = {});

}  // namespace liftoff::continuation
