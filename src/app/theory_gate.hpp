#pragma once
// Which kinematics ([structure] theory) the commands' solvers honour: the one place where a scene
// whose theory no solver of the command honours is refused, before any work and before any
// output is written (InputError, exit 2), rather than solved by linear theory without a word.
//
// `trace` honours theory = "von_karman" for beams (the FE path: continuation/fe_von_karman_path.hpp;
// the Ritz path has the membrane term); `solve` (every method, `--method all` included), `sweep`
// and `envelope` refuse it with one line naming `structure.theory`; `liftoff plot` draws what these wrote, so it has
// nothing to refuse. The reader has already checked such a scene (scene/scene_reader.hpp: beams only, EA, the ends'
// axial restraint) and the member model carries it (model/member_model.hpp). A von Karman solver
// replaces the refusal here, for the commands it serves.

#include "scene/scene.hpp"

namespace liftoff::app {

enum class Command { solve, sweep, trace, envelope };

// Throws InputError ("SCENE: key 'structure.theory': ...") when no solver of `command` honours the
// scene's theory; returns otherwise.
void require_honoured_theory(const scene::Scene& scene, Command command);

}  // namespace liftoff::app
