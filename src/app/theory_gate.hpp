#pragma once
// Which kinematics ([structure] theory) each command's solvers honour: one table, consulted by
// the library's entry points themselves (app::solve_scene, solve_all_methods, run_sweep through
// them, run_envelope through solve_scene, run_trace), so that no caller, the CLI or a future
// Python API, can get a linear answer for a scene whose theory the solver does not honour. A
// refusal is an InputError before any work and before any output is written (the CLI: exit 2,
// one line naming the key).
//
// The table (theory_gate.cpp), for theory = "von_karman" and beams:
//   solve: auto and fast  -> the FE von Karman solve along the load path (contact/von_karman_solve.hpp)
//          ritz           -> the Ritz model with its membrane term (ritz/ritz_model.hpp)
//          dual, primal   -> refused (key solve.method): Lemke solves an LCP, linear only
//          a tolerance    -> refused (key solve.tolerance): the limit-fitted meshes are linear only
//   sweep, envelope: what solve honours (they solve through solve_scene)
//   trace: the FE path (continuation/models/fe_member.hpp) and the Ritz path (continuation::trace_ritz)
// For circular arches under von Karman (the Marguerre/Donnell element, fe/arch_von_karman_element.hpp):
//   solve: auto and fast  -> the FE von Karman arch solve along the load path from zero (as beams),
//                            its answer certified (certify::certify of a VonKarmanAnswer)
//          every other method, a tolerance -> refused, key structure.theory
//   trace: the FE path (continuation/models/fe_member.hpp: the same equations on its contact sets,
//          every state certified); the Ritz path -> refused (no membrane term for arches)
//   sweep, envelope -> refused, key structure.theory (not served yet: a sweep's or an envelope's
//                            answers would be certified like solve's, but no test covers them). The
//                            refusal is the command's early check (require_honoured_theory(scene,
//                            command), the CLI's): run_sweep and run_envelope solve through
//                            solve_scene, so a library caller of those gets certified arch answers.
// theory = "linear" is honoured by every solver.

#include <optional>
#include <string>

#include "scene/scene.hpp"

namespace liftoff::app {

enum class Command { solve, sweep, trace, envelope };

// The solvers a command may run on a scene.
enum class Solver {
  fe_fast,       // solve: auto (FE) and fast
  fe_lemke,      // solve: dual and primal
  fe_tolerance,  // solve: any FE method with [solve] tolerance (limit-fitted meshes)
  ritz,          // solve: ritz (with or without a tolerance)
  fe_path,       // trace: the FE path (fe, fe_refined)
  ritz_path,     // trace: the Ritz path
};

// Whether `solver` honours `theory`.
bool honours(Solver solver, scene::Theory theory);

// Throws InputError ("SCENE: key 'KEY': ...", KEY the key that chose the solver: structure.theory,
// solve.method, solve.tolerance, trace.method; `key` overrides it, e.g. an option "--method")
// when `solver` does not honour the scene's theory; returns otherwise.
void require_honoured_theory(const scene::Scene& scene, Command command, Solver solver,
                             const std::optional<std::string>& key = std::nullopt);

// The reason, in words, why `solver` does not honour the scene's theory (nullopt: it does): for a
// `--method all` column that is refused rather than thrown.
std::optional<std::string> theory_refusal(const scene::Scene& scene, Solver solver);
// The key such a refusal names: structure.theory for a von Karman arch (its theory is what the
// solver does not serve), else the key that chose the solver (solve.method, solve.tolerance, ...).
std::string refusal_key(const scene::Scene& scene, Solver solver);

// The CLI's early check: throws when no solver of `command` honours the scene's theory (the
// entry points then check the solver they run).
void require_honoured_theory(const scene::Scene& scene, Command command);

}  // namespace liftoff::app
