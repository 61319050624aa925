// libFuzzer target on the scene reader (scene::parse_scene), an optional extra to the scene fuzzer:
// coverage-guided, in-process, millions of inputs. Every input must either read as a scene or be
// refused with InputError; anything else escaping, a crash or a sanitizer report is a finding.
// Built with clang only: `bash .ci/libfuzzer.sh [SECONDS]` (configures build-libfuzzer/ with
// -DLIFTOFF_LIBFUZZER=ON, seeds from the shipped scenes and tests/fuzz/corpus/, keys from
// tests/fuzz/scene.dict).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/error.hpp"
#include "scene/scene_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    liftoff::scene::parse_scene(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.toml");
  } catch (const liftoff::InputError&) {
  }
  return 0;
}
