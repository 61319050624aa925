#pragma once
// The Ritz load history: the Ritz model with moving contact limits followed by the
// pseudo-arc-length driver (arclength.hpp); topology events located on their event functions
// and the topology switched.
//
// - Start: the topology and limits at lambda_min from the scene's [ritz] topology, or from an
//   FE + LCP solution there (options.elements, method auto: the sparse `fast` solver wherever it
//   applies), as `liftoff solve --method ritz` takes them; for von Karman beams from the FE von
//   Karman contact solve there (contact::VonKarmanSystem from zero: the linear solve knows nothing
//   of a shallow arch's rise); solved by ritz::solve_ritz. Modes:
//   options.modes, else [ritz] modes, else what automatic modes settle on at lambda_min but at
//   least 32 (limits that do not exist yet at lambda_min say nothing about the N they will
//   need) and, for a point force on a tensionless foundation (no load-point enrichment), what
//   its local response needs: the relative error of w there is estimated as
//   e(N) = 8/(3 pi) (beta length / (pi N))^3 (beta = (k/4)^(1/4)), and automatic modes aim at
//   e <= 1e-3, up to [ritz] max_modes. N with e(N) > 1e-2 is refused before any work
//   (solver_failure, "refused: ...", with the N needed for 1 % and 0.1 %). Beams with
//   beta L <= 10 use the load-point enrichment (ritz::Enrichment::load_points) instead, so w at
//   point forces is accurate to ~N^-8.
// - Between accepted steps the event functions of the current topology (ritz_path.cpp lists
//   them) are checked; the first that changed sign is located to options.event_tolerance in
//   lambda, recorded (with the step at it) and the topology switched: a vanishing piece is
//   removed at the event, a new zone is opened slightly past it with the width the old
//   topology's local expansion gives. An end piece at a beam's pinned end (w = w'' = 0) vanishes
//   with w' there, its length going like the square root of the distance to the event (the limit
//   equation meets its trivial root t = end): it is approached from the side where it exists, as
//   a piece between two limits is, and removed (a lift-off zone closing at a pinned end). At an
//   arch's pinned end the same holds but is not treated so (not examined).
// - Every state recorded (start, steps, events, each switch's first state) is a contact solution
//   of the Ritz model: w >= 0 in contact pieces (reaction >= 0), w <= 0 in lift-off pieces on
//   ritz::check_inequalities' grid, to 1e-9 of max |w| (an event's state: but for the event
//   itself), with lambda growing along the path and no event stepped over. A step that is not
//   is retried shorter; at min_step the path stops (solver_failure) and its message says which
//   inequality failed where and by how much. The steps before stay valid. Without an axial force
//   or von Karman's membrane term the path never turns back in lambda, so it reports no
//   limit_point (nor bifurcation).
// - Von Karman beams (RitzModel::has_membrane: theory = von_karman, both ends axially
//   restrained): the membrane term makes the energy non-convex like an axial force, and the path
//   treats them alike: folds (a shallow arch's snap-through) are limit_point events, stability is
//   checked and reported per step, bifurcations are watched; axial_force reports the compressive
//   force, the given axial force less the membrane force (the thrust).
// - Beam-columns (an axial force, N = N_dead + lambda N_live): the residual depends on lambda
//   through N too (RitzModel::residual_lambda_derivative). The path passes folds: each sign
//   change of the tangent's lambda component is located to event_tolerance and recorded as a
//   limit_point event (its description gives lambda, the axial force, amplitude and lifted
//   length), a switch keeps the branch's sense, and the path follows the descending branch until
//   TraceOptions::max_amplitude (completed), lambda_min or lambda_max. Every step carries
//   axial_force, amplitude (largest lift off the foundation), lifted_length (lift-off pieces'
//   total length), all in user units, and under an axial force its stability
//   (RitzModel::stability_margin > 0: stable).
// - Bifurcations (beam-columns): a sign change of stability_margin between two accepted steps
//   of one topology while tangent_lambda keeps its sign is located on the margin to
//   event_tolerance and recorded as a `bifurcation` event (lambda, axial force, amplitude,
//   lifted length; at the crown if the member has lifted, else at options.monitor). A sign
//   change at a fold is the fold's (the reduced Hessian turns singular there too): only the
//   limit_point is recorded. A sign change across a topology switch, or two within one step
//   (a fold and a bifurcation together), is not seen.
// - Branch switching: at a bifurcation where the path turns from stable to unstable, with
//   options.switch_branch, the path leaves along the critical mode (the reduced Hessian's
//   eigenvector of its smallest eigenvalue), on the side where it lifts the member off first
//   (the least multiple at which w + a mode touches zero in a contact piece); a lift-off zone
//   opens at each point where it touches at that multiple (at a free foundation end, or inside
//   the piece; a symmetric mode lifts both ends at once), the new topology's first point
//   is solved with one new limit held and lambda free, and the branch is followed with the zone
//   widening. The event's description ends "the path switches to the bifurcated branch (...)", or
//   says why the path stays on its branch: a mode that lifts first next to an existing limit (the
//   zone would grow in its own topology), one that pushes a lift-off piece into the foundation, a
//   Newton that fails. The bifurcation point itself is no step (a trace resumed from the step
//   before finds the switch again). Von Karman members on a bilateral foundation switch within
//   their topology (nothing lifts off), and so do those on a tensionless one where the mode
//   lifts nothing off within ten times the first point's offset below (the shallow arch's
//   asymmetric branch lifts off at an end only at |A2| = A1 / 2: a limit_at_support event on the
//   branch, and the zone closes again where the branch is back in contact; tested against the
//   closed form's two roots): the first point holds the mode's largest amplitude 1e-3
//   of w's size off the bifurcation point, lambda free (the shallow arch's asymmetric branch,
//   tested against its closed form). Such a branch is watched (across its topology switches) for its return to the path
//   it left: its amplitude along the critical mode back at the bifurcation point's value, located on that amplitude and
//   then on stability_margin along the path it rejoins (the crossing, a second bifurcation point). It is recorded as a
//   step and a `bifurcation` event ("... meets the path it left again at lambda = ...; the switched branch ends here")
//   and the trace ends there, completed, its message saying so: beyond the crossing the branch is its own mirror image
//   back to the first point (followed on, the path shuttled between the two), and the path it rejoins is the one a
//   trace without switch_branch follows. (The shallow arch: the asymmetric branch rejoins the symmetric path at t = +tB
//   if the load is positive there; tested against both closed-form loads, unstable branch for kappa < 4, stable for
//   kappa > 4.) A trace resumed from a step on the branch does not watch (it does not know the mode).
// - Steps carry a resumable state: state_topology a continuation::RitzTopology (with the opening at a
//   switching event, whose switch a resumed trace redoes) and
//   state = (x, tangent_x, tangent_lambda, next step length, amplitude scale of the metric),
//   so a resumed trace takes exactly the steps the original took. A resumed state that is no
//   contact solution is refused (solver_failure).
// - summary.message: "lambda = ... reached: S steps (R rejected), E events, N modes" (beam-columns
//   add ", F limit point(s), B bifurcation(s)") and the estimated resolution of point forces
//   where it applies; a failure's reason otherwise, with the same figures.
// Outcomes are in summary.termination: no_equilibrium when the member has lifted off entirely
// and nothing else holds it, solver_failure when no equilibrium is found at lambda_min or after
// a switch, when no step satisfies the checks above, or for a refused number of modes. Misuse
// throws std::invalid_argument naming the TraceOptions field (a bad range, sample points off
// the member, a resume_from that is no Ritz state); a scene the Ritz model cannot take throws
// as ritz::RitzModel does (std::invalid_argument, liftoff::MechanismError).

#include "continuation/trace.hpp"
#include "model/member_model.hpp"
#include "scene/scene.hpp"

namespace liftoff::continuation {

TraceResult trace_ritz(const scene::Scene& scene, const TraceOptions& options, const TraceSink& sink = {});
// The same with the member given, in place of model::make_member_model(scene) (the scene still
// gives the [ritz] settings, the start's topology and the user coordinate): a seam for members
// the scene cannot describe yet, e.g. a von Karman beam under a sine load built field by field.
TraceResult trace_ritz(const scene::Scene& scene, const model::MemberModel& member, const TraceOptions& options,
                       const TraceSink& sink = {});

}  // namespace liftoff::continuation
