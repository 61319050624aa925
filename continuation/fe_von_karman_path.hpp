#pragma once
// The FE load path of a von Karman beam on a tensionless or bilateral foundation (issue 16,
// item 4): the equilibria of contact/von_karman_solve.hpp followed in the load factor through
// contact events, limit points (a shallow arch's snap-through) and bifurcations.
//
// Equations. On a contact set A the unknowns are y = (x, r_A), x the von Karman unknowns
// (VonKarmanSystem: w, w' on the equations, then the free axial u) and r_A the reactions on A:
//   G(y, lambda) = ( f_int(x) + C_A^T r_A - F_dead - lambda F_live ,  C_A w - c_A - T_AA r_A ) = 0,
// whose Jacobian is the symmetric saddle matrix [K_t C_A^T; C_A -T_AA] that VonKarmanSystem's
// Newton factorises (f_int and K_t are its internal_force and tangent_stiffness: nothing is
// assembled twice). Eliminating r_A leaves the set's potential's Hessian S = K_t + C_A^T T_AA^-1 C_A.
// The path is followed by continuation/arclength.hpp's PathFollower (pseudo-arc-length in
// (y, lambda) with the bordered corrector, or load control: TraceOptions::arc_length.control), on
// one contact set at a time. The metric weights w, w' and u by 1 / w_ref (w_ref the rise of an
// initial sine, else 1e-3) and the reactions 1e-3 less, so a step length is comparable to a change
// of lambda and the reactions barely steer it.
//
// Between two accepted steps, in this order (each located between the two points on the path
// parameter, to TraceOptions::event_tolerance in lambda):
//  - contact events (tensionless foundations): a reaction on A reaching zero or a gap off A
//    reaching zero, on the event function min over nodes of r_i / (k w_ref) and gap_i / (h w_ref)
//    (nodes at zero at the step's start left out), secant (Illinois) on the arclength; the crossing
//    node(s) with the least value there (ties within 1e-8) switch, the step at the switch is
//    recorded, and the path continues from it on the new set (its first point solved at that
//    lambda, its tangent oriented as the old one). Events are named from the node set's pieces: a
//    node leaving inside a contact piece opens a lift-off zone (lift_off_opens), the last node of a
//    piece leaving ends it (region_vanishes), and the converse (contact_opens, lift_off_vanishes);
//    the first or last node switching moves a limit onto or off the foundation's end
//    (limit_at_support where a support is, else limit_at_end); otherwise a limit moves on by a node
//    (no event, as in the linear FE path). A supported end's node has w = 0 and a sign that is w'
//    there times h^2: it switches with the rest but has no piece of its own (the end's limit is at
//    its neighbour). A node at zero at a step's start (just switched, or grazing) whose sign fails
//    at once switches back there (an event at that point); twice in a row ends the path
//    (solver_failure). Events.hpp's classification on the cubics' signs is not used: near a pinned
//    end it sees lift-off zones shorter than an element open and close at every node.
//  - limit points: a sign change of the tangent's d lambda / d s, located on it: `limit_point`.
//  - bifurcations: a change of the number of negative eigenvalues of S (the saddle factor's
//    negative pivots less |A|, Sylvester) without a limit point in the step, located by bisection
//    on that count: `bifurcation`. At one where the path loses its stability (none before, some
//    after) and with TraceOptions::switch_branch, the path leaves along the null vector of S there
//    (inverse iteration with the saddle factor; the sign making its largest component positive),
//    as a pseudo-arc-length step whose predictor is that vector: the corrector's hyperplane,
//    orthogonal to it, meets the bifurcated branch and not the path. Once per trace. The switched
//    branch is followed until its amplitude along that vector changes sign (it meets the path it
//    left, or its mirror image begins: a shallow arch's asymmetric branch is a closed loop; zero
//    meaning within 1e-7 of the largest amplitude it reached, the states' accuracy: a step can land
//    on the path itself, where the amplitude's sign is the state's round-off): located on that
//    amplitude, which lands on the path it rejoins but not at the crossing (the amplitude vanishes
//    all along that path), then refined there as the Ritz path does: from the located point less
//    its mode component, re-solved at fixed lambda (PathFollower::step_to_lambda, each point
//    polished bordered by the critical mode), a secant in lambda on the eigenvalue of S nearest
//    zero (inverse iteration with the saddle factor; zero at the crossing and linear in lambda
//    beside it) to event_tolerance in lambda or to that eigenvalue's round-off (eps times the
//    saddle matrix's norm). The crossing is recorded as a `bifurcation` event and a step (polished
//    at its lambda bordered by the critical mode, certified), and the trace ends there (completed,
//    the message says so). If the secant does not converge (or a solve fails or lands off the
//    path) the located point is recorded instead and the event's description says it is not on
//    the crossing.
//    A step that holds a limit point and a stability change, or two changes, is retried shorter
//    (down to 100 min_step) so that each is located on its own.
// Per step: crown (TraceOptions::monitor) deflection, w and r at the sample points, contact regions,
// amplitude and lifted length (fe_states::step_of), the thrust -N as axial_force (user force units,
// compression > 0: N is constant along a member with both ends restrained; the mean otherwise) and
// the stability (S positive definite: stable; the inertia is exact on a set whose reactions and gaps
// are all strictly positive, the states between events).
// Certified: every recorded state passes certify/certificate.hpp's von Karman certificate (balance
// with its support reactions and thrust, the membrane checks, the contact signs at the nodes, the
// backward error) at the path's own accuracy (the corrector's tolerance and the sign values it
// accepts, converted to the certificate's scales: Tracer::certificate says how), as the linear FE
// paths certify theirs: a recorded step is a certified one. The states the path decides its events
// on and records are the corrector's points taken to round-off by Newton corrections of the
// bordered system (Tracer::polished), measured by the certificate's own backward error (its rows'
// terms, the membrane force's included) and continued while it decreases, so that the certificate's
// backward tolerance holds unless round-off stops them short (the path then stops, saying so); the
// corrector's 1e-11 leaves ~1e-7 of w_ref near a limit point, more than the contact signs need.
// This costs a factorisation per evaluation of a contact event's function. A state that fails is not recorded and ends
// the path there (solver_failure, the certificate's message): it is checked once its step's events are located (a step
// ending past a contact event fails its signs by design), so it is not retried shorter. Under a live_load seam (a load
// the member model does not describe, which the certificate's balance cannot see) the states are not certified.
//
// Start: the contact solve at lambda_min (VonKarmanSystem::solve from zero); the unloaded state (every
// node at zero, any set holds) takes the set of a solve at lambda_min + min_step.
// Stops: lambda_max or lambda_min (completed), the switched branch back on the path (completed), the
// first step whose amplitude reaches TraceOptions::max_amplitude (completed), max_steps (step_limit),
// the corrector failing at the minimum step (step_too_small: where load control meets a limit point),
// a start that does not converge, a switch that does not hold or a state failing its certificate
// (solver_failure). Not handled: resume_from (refused: solver_failure, the message names
// TraceOptions.resume_from).
// Misuse (a member that is no von Karman beam) throws std::invalid_argument as VonKarmanSystem does.

#include <Eigen/Dense>
#include <functional>

#include "continuation/trace.hpp"
#include "fe/discretisation.hpp"
#include "model/member_model.hpp"

namespace liftoff::contact {
class VonKarmanSystem;
}

namespace liftoff::continuation {

// A live load on the system's unknowns, built by the caller (a seam for loads the scene cannot
// describe yet, e.g. the sine load q0 sin(pi x / L)): F = lambda * live_load; empty: the member's
// own loads (F_dead + lambda F_live, VonKarmanSystem::load).
using VonKarmanLiveLoad = std::function<Eigen::VectorXd(const fe::Discretisation&, const contact::VonKarmanSystem&)>;

// A seam for tests: called on a copy of every path point's unknowns (x, then the reactions on the
// set) before its certificate checks it (e.g. a reaction made to pull, to see the step refused);
// what is recorded is the path's own state. Empty: none.
using VonKarmanStateSeam = std::function<void(double lambda, Eigen::VectorXd& unknowns)>;

// The path of `member` (theory = von_karman) on TraceOptions::elements equal elements.
TraceResult trace_fe_von_karman(const model::MemberModel& member, const TraceOptions& options,
                                const TraceSink& sink = {}, const VonKarmanLiveLoad& live_load = {},
                                const VonKarmanStateSeam& seam = {});

}  // namespace liftoff::continuation
