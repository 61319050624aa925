#pragma once
// `liftoff solve`: scene -> member model -> mesh and assembly -> contact LCP -> fields,
// contact regions -> report. One verb per stage, as in the source.

#include <optional>

#include "io/report.hpp"
#include "scene/scene.hpp"

namespace liftoff::app {

struct SolveRequest {
  std::optional<scene::Method> method;  // overrides [solve] method
  std::optional<int> elements;          // overrides [solve] elements
  int samples_per_element = 16;         // field samples inside each element
};

// Throws InputError (a mechanism the loads drive: the message names the scene) and
// SolverFailure (a formulation refused). Lemke's outcomes are in report.summary.
io::SolveReport solve_scene(const scene::Scene& scene, const SolveRequest& request);

}  // namespace liftoff::app
