#pragma once
// The Ritz path of a scene as `liftoff trace` runs it: the member from the scene, the options'
// Ritz settings from its [ritz] table where the test left them as they were (modes 0: the table's).
// app::trace_options does the same for the command; the tests build their options by hand.

#include "continuation/models/ritz.hpp"
#include "model/from_scene.hpp"
#include "scene/scene.hpp"

namespace liftoff::test {

inline continuation::TraceOptions with_ritz_settings(const scene::Scene& scene, continuation::TraceOptions options) {
  if (options.ritz.modes == 0) options.ritz.modes = scene.ritz.modes;
  options.ritz.max_modes = scene.ritz.max_modes;
  options.ritz.mode_tolerance = scene.ritz.mode_tolerance;
  options.ritz.topology = scene.ritz.topology;
  options.ritz.limits = scene.ritz.limits;
  return options;
}

inline continuation::TraceResult trace_ritz_scene(const scene::Scene& scene, const continuation::TraceOptions& options,
                                                  const continuation::TraceSink& sink = {}) {
  return continuation::trace_ritz(model::make_member_model(scene), with_ritz_settings(scene, options), sink);
}

// The same with the member given (one the scene cannot describe yet, built field by field).
inline continuation::TraceResult trace_ritz_scene(const scene::Scene& scene, const model::MemberModel& member,
                                                  const continuation::TraceOptions& options,
                                                  const continuation::TraceSink& sink = {}) {
  return continuation::trace_ritz(member, with_ritz_settings(scene, options), sink);
}

}  // namespace liftoff::test
