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

// The table: which solvers honour von Karman kinematics, and why the others do not.
struct Entry {
  Solver solver;
  bool von_karman;
  const char* key;     // the key that chose this solver
  const char* reason;  // why it does not honour von Karman (empty when it does)
};
constexpr Entry table[] = {
    {Solver::fe_fast, true, "solve.method", ""},
    {Solver::ritz, true, "solve.method", ""},
    {Solver::fe_lemke, false, "solve.method",
     "the dual and primal methods solve a linear complementarity problem (Lemke), linear theory only; expected "
     "\"auto\", \"fast\" or \"ritz\""},
    {Solver::fe_tolerance, false, "solve.tolerance",
     "the limit-fitted meshes of a tolerance are linear theory only; expected no tolerance (the von Karman FE "
     "solve uses [solve] elements)"},
    {Solver::ritz_path, true, "trace.method", ""},
    {Solver::fe_path, true, "trace.method", ""},
};

const Entry& entry(Solver solver) {
  for (const Entry& e : table)
    if (e.solver == solver) return e;
  return table[0];  // unreachable: every solver has an entry
}

// Arches under von Karman: refused by every solver (theory_gate.hpp says why).
std::optional<std::string> arch_refusal(const scene::Scene& scene) {
  if (scene.structure.theory == scene::Theory::linear || scene.structure.kind != scene::StructureKind::arch)
    return std::nullopt;
  return fmt::format(
      "theory = \"{}\" on an arch: its contact solve exists (the seed arch's departure study) but its answers have "
      "no certificate yet, so no command reports them; expected \"linear\" for arches",
      scene::to_string(scene.structure.theory));
}

}  // namespace

bool honours(Solver solver, scene::Theory theory) {
  return theory == scene::Theory::linear || entry(solver).von_karman;
}

std::optional<std::string> theory_refusal(const scene::Scene& scene, Solver solver) {
  if (auto reason = arch_refusal(scene)) return reason;
  if (honours(solver, scene.structure.theory)) return std::nullopt;
  return fmt::format("theory = \"{}\": {}", scene::to_string(scene.structure.theory), entry(solver).reason);
}

void require_honoured_theory(const scene::Scene& scene, Command command, Solver solver,
                             const std::optional<std::string>& key) {
  require_honoured_theory(scene, command);
  const std::optional<std::string> reason = theory_refusal(scene, solver);
  if (!reason) return;
  const std::string where = key ? *key : fmt::format("key '{}'", entry(solver).key);
  throw InputError(fmt::format("{}: {}: {} (liftoff {})", scene.source_name, where, *reason, name(command)));
}

void require_honoured_theory(const scene::Scene& scene, Command command) {
  // Beams: every command has a von Karman solver (trace: both paths); the entry points check the
  // one they run. Arches: none.
  if (auto reason = arch_refusal(scene))
    throw InputError(
        fmt::format("{}: key 'structure.theory': {} (liftoff {})", scene.source_name, *reason, name(command)));
}

}  // namespace liftoff::app
