#include "app/theory_gate.hpp"

#include <fmt/format.h>

#include "core/error.hpp"

namespace liftoff::app {

namespace {

std::string_view name(Command command) {
  switch (command) {
    case Command::solve:
      return "solve";
    case Command::sweep:
      return "sweep";
    case Command::trace:
      return "trace";
    case Command::envelope:
      return "envelope";
  }
  return "?";
}

}  // namespace

void require_honoured_theory(const scene::Scene& scene, Command command) {
  if (scene.structure.theory == scene::Theory::linear) return;
  // `trace` of a von Karman beam: the FE path follows it (continuation/fe_von_karman_path.hpp), and
  // the Ritz path has the membrane term (continuation/ritz_path.hpp).
  if (command == Command::trace && scene.structure.kind == scene::StructureKind::beam) return;
  throw InputError(fmt::format(
      "{}: key 'structure.theory': theory = \"{}\" is read but no solver honours it yet (liftoff {}); expected "
      "\"linear\" until one does",
      scene.source_name, scene::to_string(scene.structure.theory), name(command)));
}

}  // namespace liftoff::app
