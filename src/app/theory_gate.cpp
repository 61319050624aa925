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

// Arches under von Karman (theory_gate.hpp's table): `liftoff solve` with the FE solve (auto, fast)
// only; the reason for every other solver and command, keyed structure.theory (the arch's theory
// is what they do not serve).
bool von_karman_arch(const scene::Scene& scene) {
  return scene.structure.theory != scene::Theory::linear && scene.structure.kind == scene::StructureKind::arch;
}

std::string arch_reason(const scene::Scene& scene, std::string_view what) {
  return fmt::format(
      "theory = \"{}\" on an arch: {}; expected method \"auto\" or \"fast\" with `liftoff solve` or `liftoff "
      "trace` (the FE von Karman arch solve and path), or theory \"linear\"",
      scene::to_string(scene.structure.theory), what);
}

std::optional<std::string> arch_refusal(const scene::Scene& scene, Solver solver) {
  if (!von_karman_arch(scene)) return std::nullopt;
  switch (solver) {
    case Solver::fe_fast:
      return std::nullopt;
    case Solver::fe_lemke:
      return arch_reason(scene, "the dual and primal methods solve a linear complementarity problem (Lemke)");
    case Solver::fe_tolerance:
      return arch_reason(scene,
                         "the limit-fitted meshes of a tolerance are linear theory only (no tolerance: the "
                         "von Karman FE solve uses [solve] elements)");
    case Solver::ritz:
      return arch_reason(scene, "the Ritz model has no von Karman membrane term for arches");
    case Solver::fe_path:
      return std::nullopt;
    case Solver::ritz_path:
      return arch_reason(scene, "the Ritz model has no von Karman membrane term for arches");
  }
  return std::nullopt;
}

}  // namespace

bool honours(Solver solver, scene::Theory theory) {
  return theory == scene::Theory::linear || entry(solver).von_karman;
}

std::optional<std::string> theory_refusal(const scene::Scene& scene, Solver solver) {
  if (auto reason = arch_refusal(scene, solver)) return reason;
  if (honours(solver, scene.structure.theory)) return std::nullopt;
  return fmt::format("theory = \"{}\": {}", scene::to_string(scene.structure.theory), entry(solver).reason);
}

std::string refusal_key(const scene::Scene& scene, Solver solver) {
  return von_karman_arch(scene) ? "structure.theory" : entry(solver).key;
}

void require_honoured_theory(const scene::Scene& scene, Command command, Solver solver,
                             const std::optional<std::string>& key) {
  require_honoured_theory(scene, command);
  const std::optional<std::string> reason = theory_refusal(scene, solver);
  if (!reason) return;
  const std::string where = key && !von_karman_arch(scene) ? *key : fmt::format("key '{}'", refusal_key(scene, solver));
  throw InputError(fmt::format("{}: {}: {} (liftoff {})", scene.source_name, where, *reason, name(command)));
}

void require_honoured_theory(const scene::Scene& scene, Command command) {
  // Beams: every command has a von Karman solver (trace: both paths); the entry points check the
  // one they run. Arches: `liftoff solve` and `liftoff trace` (the FE path).
  if (von_karman_arch(scene) && command != Command::solve && command != Command::trace)
    throw InputError(fmt::format(
        "{}: key 'structure.theory': {} (liftoff {})", scene.source_name,
        arch_reason(scene,
                    fmt::format("`liftoff {}` does not serve it yet (its answers are not certified)", name(command))),
        name(command)));
}

}  // namespace liftoff::app
