#pragma once
// `liftoff envelope`: a scene's load combinations ([[combinations]]) and the positions of its
// moving load group ([moving]) each solved as its own problem, and the envelopes over them.
//
// The cases: every combination (or, without [[combinations]], the scene's loads at factor 1) at
// every lead position of the moving group (or, without [moving], once). A combination applies
// each load with the factor of its case, 0 for a case it does not name; the moving group is a
// load case like any other (its `case`, "live" by default). Contact is nonlinear, so nothing is
// superposed: each case is a full solve by solve_scene (the scene's method, robust fast by
// default), certified like any solve. A case that fails or is refused is kept with its reason,
// and the envelope is then incomplete.
//
// Warm start: along the positions of one combination, each solve starts its active-set iteration
// from the contact regions of the previous position's answer (SolveRequest::
// initial_contact_regions), where the contact set changes little; the work (contact sets,
// factorisations) is in each case's report and summed in the summary.

#include <functional>

#include "app/solve_command.hpp"
#include "io/envelope_report.hpp"
#include "scene/scene.hpp"

namespace liftoff::app {

struct EnvelopeRequest {
  SolveRequest solve;      // method, elements, ... as for solve (fields are always sampled)
  bool warm_start = true;  // false: every position from the solver's default start (to measure the gain)
  int samples = 401;       // points of the envelope grid, uniform along the member
  void validate() const;   // throws std::invalid_argument naming the field
};

// The scene of one case: the scene's loads with their combination factors (all 1 without a
// combination; a load whose factor is 0 is left out), plus the moving group at `lead` (when
// given); no [[combinations]] or [moving] left in it.
scene::Scene case_scene(const scene::Scene& scene, const scene::Combination* combination, std::optional<double> lead);

// Throws InputError when the scene has neither [[combinations]] nor [moving] (nothing to
// envelope). `progress(done, total)` after each case.
io::EnvelopeReport run_envelope(const scene::Scene& scene, const EnvelopeRequest& request,
                                const std::function<void(int, int)>& progress = {});

}  // namespace liftoff::app
