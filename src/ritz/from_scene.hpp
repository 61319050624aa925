#pragma once
// The scene's [ritz] table as the Ritz solver's start and options: the one conversion, at the
// boundary between the scene and the numerics (model/from_scene.hpp says which), shared by
// `liftoff solve --method ritz` and the Ritz load history. Nothing in ritz/ but this file includes
// the scene.

#include <optional>

#include "model/member_model.hpp"
#include "ritz/ritz_solver.hpp"
#include "ritz/starting_point.hpp"
#include "scene/scene.hpp"

namespace liftoff::ritz {

// The scene's topology, with its limits or evenly spaced guesses. Requires a non-empty
// settings.topology.
StartingPoint starting_point_from_scene(const scene::RitzSettings& settings, const model::MemberModel& model);

// The solver options: modes (`modes` when given, else the table's), max_modes, and
// mode_tolerance made a length in s (times the member's length). The rest keeps RitzOptions'
// defaults.
RitzOptions ritz_options_from_scene(const scene::RitzSettings& settings, const model::MemberModel& model,
                                    std::optional<int> modes = std::nullopt);

}  // namespace liftoff::ritz
