#pragma once
// Reading and validating a scene from TOML (toml++).
//
// Every problem is reported as liftoff::InputError with a one-line message
//   "FILE:LINE: key 'section.key': expected WHAT, got WHAT"
// (LINE where the parser knows it). Unknown keys are errors too, so a typo is never ignored.
// After a successful read the scene is meaningful: stiffnesses and lengths positive, loads and
// supports inside the member, exactly one of foundation k and modulus, defaults filled in.
// Numbers written with their unit ("30 MN/m^2") are converted into the scene's [units] by the
// dimension schema.hpp gives their key (unit_library.hpp); the numbers of a Scene are plain.

#include <filesystem>
#include <string>
#include <string_view>

#include "scene/scene.hpp"

namespace liftoff::scene {

Scene read_scene_file(const std::filesystem::path& path);
Scene parse_scene(std::string_view toml_text, std::string source_name);

}  // namespace liftoff::scene
