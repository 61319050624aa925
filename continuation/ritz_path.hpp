#pragma once
// The Ritz load history: the Ritz model with moving contact limits followed by the
// pseudo-arc-length driver (arclength.hpp); topology events located on their event functions
// and the topology switched.
//
// - Start: the topology and limits at lambda_min from the scene's [ritz] topology, or from an
//   FE + LCP solution there (options.elements), as `liftoff solve --method ritz` takes them;
//   solved by ritz::solve_ritz. Modes: options.modes, else [ritz] modes, else what automatic
//   modes settle on at lambda_min but at least 32 (limits that do not exist yet at lambda_min
//   say nothing about the N they will need). Beams use the load-point enrichment
//   (ritz::Enrichment::load_points), so w at point forces is accurate to ~N^-8.
// - Between accepted steps the event functions of the current topology (ritz_path.cpp lists
//   them) are checked; the first that changed sign is located to options.event_tolerance in
//   lambda, recorded (with the step at it) and the topology switched: a vanishing piece is
//   removed at the event, a new zone is opened slightly past it with the width the old
//   topology's local expansion gives. Folds of the path are recorded as limit_point events.
// - Steps carry a resumable state: state_topology "first_in_contact limits modes" (plus
//   " event direction delta" at a switching event, whose switch a resumed trace redoes) and
//   state = (x, tangent_x, tangent_lambda, next step length), so a resumed trace takes exactly
//   the steps the original took.
// Outcomes are in summary.termination: no_equilibrium when the member has lifted off entirely
// and nothing else holds it, solver_failure when no equilibrium is found at lambda_min or after
// a switch. Misuse throws std::invalid_argument naming the TraceOptions field (a bad range,
// sample points off the member, a resume_from that is no Ritz state); a scene the Ritz model
// cannot take throws as ritz::RitzModel does (std::invalid_argument, liftoff::MechanismError).

#include "continuation/trace.hpp"
#include "scene/scene.hpp"

namespace liftoff::continuation {

TraceResult trace_ritz(const scene::Scene& scene, const TraceOptions& options, const TraceSink& sink = {});

}  // namespace liftoff::continuation
