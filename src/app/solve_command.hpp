#pragma once
// `liftoff solve`: scene -> member model -> (mesh, assembly, contact LCP) or (Ritz model,
// Newton) -> fields and contact regions -> report. One verb per stage, as in the source.

#include <array>
#include <optional>
#include <vector>

#include "core/contact_region.hpp"
#include "io/report.hpp"
#include "post/fields.hpp"
#include "scene/scene.hpp"

namespace liftoff::app {

struct SolveRequest {
  std::optional<scene::Method> method;                  // overrides [solve] method
  std::optional<int> elements;                          // overrides [solve] elements
  std::optional<int> modes;                             // overrides [ritz] modes (0: auto)
  std::optional<double> tolerance;                      // overrides [solve] tolerance
  int samples_per_element = post::samples_per_element;  // field samples inside each element (Ritz: as many in all)
  bool fields = true;                                   // sample the fields (false: only the extremes they give)
  // A warm start: the contact regions (user coordinate) of a nearby solve, e.g. the previous
  // position of a moving load (app/envelope_command.hpp). Taken by an FE solve on the scene's mesh
  // (no tolerance) that runs fast on a tensionless foundation: its first contact set is the
  // reaction nodes inside these regions. Absent: the solver's default start. It changes the
  // work (report.active_set_iterations, factorisations), never the answer.
  std::optional<std::vector<ContactRegion>> initial_contact_regions;
};

// Sampled fields are capped at this many points (HDF5 and memory stay O(1e7) bytes per field):
// a finer mesh gets fewer samples per element, and the report's message says so.
inline constexpr int max_field_samples = post::max_field_samples;

// method = auto: Ritz when the scene's [ritz] table gives the contact topology (the user has
// described the contact pattern, and the moving-limit model resolves the limits exactly);
// otherwise fast (contact::choose_fe_method: the sparse solver for every FE scene; dense Lemke
// only when asked for by name). The Ritz topology, when the scene does not give it, comes from
// fast too.
//
// Every answer is certified (certify/certificate.hpp) before it is reported solved. A member the
// foundation alone must hold gets the resultant check first (certify/resultant_check.hpp): loads
// that compressive reactions cannot balance are answered no_equilibrium at once. An FE answer that
// fails its certificate falls back once (fast -> Lemke, dual where the structure is stable else
// primal, if the dense LCP fits; dual or primal -> fast) and the fallback's answer is certified;
// if that fails too, termination is "certificate_failed" and the message names the check and by
// how much. A Ritz answer that fails has no fallback. report.method is what produced the answer,
// report.method_requested what was asked for.
//
// One method (dual, primal, fast, auto or ritz). Throws InputError (a mechanism the loads drive; a
// scene the Ritz model cannot take: the message names the scene) and SolverFailure (a
// formulation refused). The solvers' outcomes are in report.usable / termination / message.
io::SolveReport solve_scene(const scene::Scene& scene, const SolveRequest& request);

// Primal, dual, fast and Ritz on one scene (`--method all`), one report per method asked for (a
// fallback's answer appears under the method that was asked for). A method refused for this
// scene appears with termination "refused" and the reason as its message.
std::vector<io::SolveReport> solve_all_methods(const scene::Scene& scene, const SolveRequest& request);

}  // namespace liftoff::app
