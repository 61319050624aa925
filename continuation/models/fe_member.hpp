#pragma once
// The FE member on its contact sets: the path model (continuation/engine.hpp) of the FE load paths.
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
// Kinematics (MemberKinematics, fe_member.cpp): von Karman beams and arches (f = f_int(x) - F,
// contact/von_karman_solve.hpp's internal_force and tangent_stiffness: nothing is assembled twice).
// The metric weighs w, w' and u by 1 / w_ref (w_ref the rise of an initial sine, else 1e-3) and
// the reactions 1e-3 less, so that a step length is comparable to a change of lambda and the
// reactions barely steer it.
//
// Constraints (tensionless foundations): r_i >= 0 on A, gap_i >= 0 off A, watched on
// r_i / (k w_ref) and gap_i / (h w_ref) (nodes at zero at the step's start left out), the first
// crossing located by secant (Illinois) on their minimum along the step; the crossing node(s) with
// the least value there (ties within 1e-8) switch, and the path continues from the crossing on the
// new set, its first point solved at that lambda and its tangent oriented as the old one. Events
// are named from the node set's pieces: a node leaving inside a contact piece opens a lift-off
// zone (lift_off_opens), the last node of a piece leaving ends it (region_vanishes), and the
// converse (contact_opens, lift_off_vanishes); the first or last node switching moves a limit onto
// or off the foundation's end (limit_at_support where a support is, else limit_at_end); otherwise a
// limit moves on by a node: no event. A supported end's node has w = 0 and a sign that is w' there
// times h^2: it switches with the rest but has no piece of its own. A node at zero at a step's
// start (just switched, or grazing) whose sign fails at once switches back there; twice in a row
// ends the path (solver_failure). (The cubics' signs, events.hpp, see lift-off zones shorter than
// an element open and close at every node near a pinned end: the nodes decide.)
//
// Stability: the count of negative eigenvalues of S (StabilityMeasure::count), exact on a set
// whose reactions and gaps are all strictly positive. At a bifurcation where the path loses its
// stability the model leaves along the null vector of S (inverse iteration with the saddle factor;
// the sign making its largest component positive) as a pseudo-arc-length step whose predictor is
// that vector: the corrector's hyperplane, orthogonal to it, meets the bifurcated branch and not
// the path. The branch is watched by its amplitude along that vector; its return to the path is
// refined onto the crossing by a secant in lambda on the eigenvalue of S nearest zero, each point
// solved at fixed lambda from the located point less its mode component and polished bordered by
// the critical mode (refine_return).
//
// Certified: every recorded state passes certify/certificate.hpp's von Karman certificate (balance
// with its support reactions and thrust, the membrane checks, the contact signs at the nodes, the
// backward error) at the path's own accuracy: the states the path decides on and records are the
// corrector's points taken to round-off by Newton corrections of the bordered system (refine),
// measured by the certificate's own backward error and continued while it decreases. Under a
// live-load seam (a load the member model does not describe, which the certificate's balance
// cannot see) the states are not certified.
//
// Start: the contact solve at lambda_min (VonKarmanSystem::solve from zero); the unloaded state
// (every node at zero, any set holds) takes the set of a solve at lambda_min + min_step. Not handled:
// resume_from (refused: solver_failure, the message names TraceOptions.resume_from).

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

// The path of `member` (theory = von_karman, beam or circular arch) on TraceOptions::elements equal
// elements, followed by the path engine.
TraceResult trace_fe_von_karman(const model::MemberModel& member, const TraceOptions& options,
                                const TraceSink& sink = {}, const VonKarmanLiveLoad& live_load = {},
                                const VonKarmanStateSeam& seam = {});

}  // namespace liftoff::continuation
