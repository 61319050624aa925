#include "ritz/from_scene.hpp"

namespace liftoff::ritz {

StartingPoint starting_point_from_scene(const scene::RitzSettings& settings, const model::MemberModel& model) {
  StartingPoint start;
  start.topology = {settings.topology.front(), static_cast<int>(settings.topology.size()) - 1};
  for (double limit : settings.limits) start.limits.push_back(model.s_from_user(limit));
  const double begin = model.foundation_begin, end = model.foundation_end;
  if (start.limits.empty())  // evenly spaced guesses
    for (int m = 0; m < start.topology.limits; ++m)
      start.limits.push_back(begin + (end - begin) * (m + 1) / (start.topology.limits + 1));
  if (static_cast<int>(start.limits.size()) != start.topology.limits) start.limits.clear();
  return start;
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
