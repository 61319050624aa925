#include "ritz/from_scene.hpp"

namespace liftoff::ritz {

StartingPoint starting_point_from_scene(const scene::RitzSettings& settings, const model::MemberModel& model) {
  return starting_point_from_pieces(settings.topology, settings.limits, model);
}

RitzOptions ritz_options_from_scene(const scene::RitzSettings& settings, const model::MemberModel& model,
                                    std::optional<int> modes) {
  RitzOptions options;
  options.modes = modes.value_or(settings.modes);
  options.max_modes = settings.max_modes;
  options.mode_tolerance = settings.mode_tolerance * model.length();
  return options;
}

}  // namespace liftoff::ritz
