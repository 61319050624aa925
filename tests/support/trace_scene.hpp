#pragma once
// The FE path of a scene, as `liftoff trace` runs it: the member model built from the scene, then
// continuation::trace_fe (the paths take members; scenes stay above app/).

#include "continuation/models/fe_member.hpp"
#include "model/from_scene.hpp"
#include "scene/scene.hpp"

namespace liftoff::test {

inline continuation::TraceResult trace_fe(const scene::Scene& scene, const continuation::TraceOptions& options,
                                          const continuation::TraceSink& sink = {}) {
  return continuation::trace_fe(model::make_member_model(scene), options, sink);
}

inline continuation::EventErrors estimate_event_errors(const scene::Scene& scene,
                                                       const continuation::TraceOptions& options,
                                                       const continuation::TraceResult& base) {
  return continuation::estimate_event_errors(model::make_member_model(scene), options, base);
}

}  // namespace liftoff::test
