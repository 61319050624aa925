#pragma once
// The FE member on its contact sets: the path model (continuation/engine.hpp) of every FE load path.
//
// Configuration: a contact set A, the reaction nodes in contact. Unknowns y = (x, r_A): x the
// member's unknowns (MemberKinematics: the equations of the discretisation, and a von Karman
// beam's free axial displacements), r_A the reactions on A. The equations are the same for every
// kinematics:
//   G(y, lambda) = ( f(x, lambda) + C_A^T r_A ,  C_A w - c_A - T_AA r_A ) = 0,
// f the member's internal force less the loads; their Jacobian is the symmetric saddle matrix
// [K_t C_A^T; C_A -T_AA], and eliminating r_A leaves the set's potential's Hessian
// S = K_t + C_A^T T_AA^-1 C_A, whose inertia is the state's stability on the set (the saddle
// factor's negative pivots less |A|, Sylvester).
//
// Kinematics (member_kinematics.hpp): linear (f = K x - F(lambda)), second order (f = K(N(lambda)) x
// - F(lambda)), both in the mixed form of the contact system (x = (u, m), well conditioned on fine
// meshes), and von Karman beams and arches (f = f_int(x) - F). The metric weighs the displacement
// by 1 / w_ref (slopes by h / w_ref) and the reactions 1e-3 less, so that a step length is
// comparable to a change of lambda relative to the range and the reactions barely steer it; w_ref
// is a von Karman member's initial sine's rise (else 1e-3), and for the others the largest
// deflection the path has reached (at first the start's and its rate over the range: the follower
// is rebuilt on the new metric when it doubles).
//
// Constraints (tensionless foundations): r_i >= 0 on A, gap_i >= 0 off A, watched on
// r_i / (k w_ref) and gap_i / (h w_ref) (nodes at zero at the step's start left out). A node switch
// that changes no event is taken at the step's end: the state solved on the new set on the step's
// hyperplane, every node's sign checked, the failing ones switched too (at most 8 rounds), each
// set tried keeping the start's count of negative eigenvalues; where the step's end is not the
// path's (past a fold at a set change, a change of the node set's pieces, the amplitude bound or
// a load asked for), the furthest state of the step that is (bisection on the arclength, 12
// halvings); unless a change of stability lies between (then the first crossing is located by secant
// (Illinois) on the nodes' least value along the step; the crossing node(s) with the least value
// there, ties within 1e-8, switch, and the path continues from the crossing on the new set, on the
// side where the switched nodes' values grow: where lambda's sense turns there, a `limit_point`).
// A node at zero at a step's start whose sign fails at once switches back there; twice in a row
// ends the path (solver_failure).
//
// Events, by the kinematics' naming policy:
//  - cubics (linear, second order): the changes of the contact topology of the element cubics
//    (events.hpp), located by bisection on the arclength to event_tolerance in lambda, on one set
//    or across node switches (states solved as above), each classified between the last topology
//    equal to the one before and the first different one; a switch carries its topology over
//    from the set before (see topology_events).
//  - nodes (von Karman): from the node set's pieces: a node leaving inside a contact piece opens a
//    lift-off zone (lift_off_opens), the last node of a piece leaving ends it (region_vanishes), and
//    the converse (contact_opens, lift_off_vanishes); the first or last node switching moves a
//    limit onto or off the foundation's end (limit_at_support where a support is, else
//    limit_at_end); otherwise a limit moves on by a node: no event. A supported end's node has
//    w = 0 and a sign that is w' there times h^2: it switches with the rest but has no piece of
//    its own.
//
// Stability: the count of negative eigenvalues of S (StabilityMeasure::count; the primal form's
// LDL^T), exact on a set whose reactions and gaps are all strictly positive; at nodes weakly active
// along the path (zero reaction and gap, not moving off zero), the cone's verdict (second order,
// stability/critical_load.hpp). A linear member is stable by convexity: no count (none).
// Bifurcations where the path loses its stability: second order, the singular point's lambda
// refined by the Rayleigh quotient of the critical mode, and the branch, straight at fixed lambda,
// followed along the mode (at weakly active nodes, from the cone's spring set) in the sense the
// contact conditions admit, its steps unstable, to max_amplitude or its first switch (located;
// the new set's branch goes on in lambda); von Karman, the branch leaves along the null vector of
// S (inverse iteration with the saddle factor) as a pseudo-arc-length step, is watched by its
// amplitude along that vector, and its return to the path is refined onto the crossing by a
// secant in lambda on the eigenvalue of S nearest zero (refine_return).
//
// A member only the foundation holds (linear): the lift-off load (member_kinematics.hpp) is a
// crossing located on the step that reaches it; the path ends there, no_equilibrium. The unloaded
// state inside a step (linear, a load reversal: every reaction and gap zero, any set holds) is a
// crossing to the set of a contact solve beyond it. A kinematics linear at fixed lambda (linear,
// second order) locates its crossings on polished, exact states; a state recorded where the set
// changes reports the stability of the set it carries on with (stability_at_crossing).
//
// Certified: every recorded state passes its kinematics' certificate (certify/certificate.hpp:
// balance with its support reactions, the contact signs at the nodes, the backward error) at the
// path's own accuracy: the states the path decides on and records are the corrector's points
// (linear: exact to round-off), corrected once at their lambda (second order), or polished by
// Newton corrections of the bordered system (von Karman, refine), measured by the certificate's
// own backward error and continued while it decreases. Under a live-load seam (a load the member
// model does not describe, which the certificate's balance cannot see) the states are not
// certified.
//
// Start: the contact solve at lambda_min (the kinematics'); the unloaded state (every node at zero,
// any set holds) takes the set of a solve at lambda_min + min_step. Resume (linear and second
// order): from a step's state, the set that carries the path on from it, the step length taken
// from it, its sense of lambda and the metric's w_ref; von Karman refuses resume_from
// (solver_failure, the message names TraceOptions.resume_from).

#include <Eigen/Dense>
#include <functional>
#include <optional>
#include <vector>

#include "continuation/models/member_kinematics.hpp"
#include "continuation/trace.hpp"
#include "fe/discretisation.hpp"
#include "model/member_model.hpp"

namespace liftoff::continuation {

// A seam for tests: called on a copy of every path point's unknowns (x, then the reactions on the
// set) before its certificate checks it (e.g. a reaction made to pull, to see the step refused);
// what is recorded is the path's own state. Empty: none.
using VonKarmanStateSeam = std::function<void(double lambda, Eigen::VectorXd& unknowns)>;

// The FE path of `member` on TraceOptions::elements equal elements, followed by the path engine:
// its kinematics (linear, second order, von Karman) from its theory and axial force.
TraceResult trace_fe(const model::MemberModel& member, const TraceOptions& options, const TraceSink& sink = {});

// The same for a von Karman member (theory = von_karman, beam or circular arch), with the seams.
TraceResult trace_fe_von_karman(const model::MemberModel& member, const TraceOptions& options,
                                const TraceSink& sink = {}, const VonKarmanLiveLoad& live_load = {},
                                const VonKarmanStateSeam& seam = {});

// The discretisation error of the event loads, estimated from a second trace on twice the
// elements: per event of `base` (a trace_fe of the same member and options), the refined run's
// event of the same kind nearest to it, and the difference of their loads.
struct EventErrorEstimate {
  TraceEvent event;                   // from `base`
  std::optional<TraceEvent> refined;  // its match in the refined run, if any
  double load_factor_error = -1.0;    // |lambda - lambda_refined|; -1 without a match
};
struct EventErrors {
  int elements = 0;          // of the base run
  int refined_elements = 0;  // 2 x elements
  std::vector<EventErrorEstimate> events;
  TraceSummary refined_summary;
};
EventErrors estimate_event_errors(const model::MemberModel& member, const TraceOptions& options,
                                  const TraceResult& base);

}  // namespace liftoff::continuation
