#pragma once
// The FE + LCP load history of a beam under an axial force N = N_dead + lambda N_live (second-order
// theory): trace_fe (models/fe_member.hpp) hands a beam with an axial force, dead or live, to this.
//
// The stiffness K(N) = K - N K_g depends on lambda, so the path is no longer piecewise linear; it is
// curved and has folds. With the contact set A fixed (nodes in contact bilateral, lifted nodes free)
// the equations of contact/active_set_system.hpp are linear in (u, r_A) for each lambda:
//   [ K(N(lambda))  C_A^T ] [ u   ]   [ F_dead + lambda F_live ]
//   [ C_A          -T_AA  ] [ r_A ] = [ -c_A                    ],
// so the fixed-set state is one sparse solve at each lambda and its branch is a graph over lambda
// wherever that matrix is nonsingular: a fixed set has no fold. The path is followed in lambda on
// one set at a time, steps adaptive, each state solved exactly (no predictor, no Newton: the
// pseudo-arc-length corrector has nothing to correct on a system linear in the unknowns); the
// folds of the discrete path are where a set ends. After each step the contact conditions of the
// set are checked in the user's terms (reaction >= 0 on it, gap >= 0 off it, as the exact FE path
// does); where one fails the crossing is located by bisection to options.event_tolerance in lambda,
// the node(s) switch, and the new set's branch through that point is taken on the side where it is
// feasible: ahead in lambda the path goes on, behind it the path has passed a limit point, reported
// as an event `limit_point` at that lambda (an extremum of lambda along the path), and lambda runs
// the other way from there.
//
// Per step: TraceStep::axial_force (user force units), amplitude and lifted_length
// (events.hpp's lift_measures) and stability from the inertia of the tangent on the step's contact
// set (contact::check_tangent): at a state where every reaction in the set is positive and every gap
// off it is positive, small perturbations keep the set, so that tangent is the whole second
// variation and the check is exact (stable iff positive definite); a step with weakly active nodes
// (touching with neither reaction nor gap) gets it from the cone's critical load instead
// (stability/critical_load.hpp: stable when its factor on the step's N exceeds 1). A change of its number of
// negative eigenvalues between two steps on one set (no breakpoint between them; where nodes stay
// weakly active along the branch, of the cone's verdict) is a point where the tangent is singular
// off a fold: located by bisection on the count, its lambda refined by the Rayleigh quotient of
// the critical mode (inverse iteration on the fixed-set system), and reported as `bifurcation`.
//
// Branch switching (TraceOptions::switch_branch, default true). At a bifurcation where the path
// loses its stability (no negative eigenvalue before, some after) the trace leaves it: the
// bifurcated branch of second-order theory is straight at fixed lambda, base + a phi with phi the
// critical mode (at weakly active nodes the cone's mode, whose spring set becomes the set), so
// every reaction in the set and gap off it is linear in a; the sign of phi is the one the contact
// conditions admit (a node at zero may not be pushed through), and the branch runs to the first
// node at zero (switched, and the new set's branch taken on its feasible side in lambda, as at
// any breakpoint) or to max_amplitude. Its steps are reported unstable (the tangent is singular,
// not positive definite); with no node switching and no max_amplitude the branch is unbounded and
// the trace ends there (completed, the message says so). Elsewhere (switch_branch false, or a
// bifurcation on a path already unstable) the event is reported and the path goes on.
//
// Stops: lambda_max (completed), lambda_min on a descending branch (completed), the first step whose
// amplitude reaches TraceOptions::max_amplitude (located on the branch by bisection; completed,
// the message says so), max_steps, or a breakpoint where no side of the new set is feasible
// (solver_failure, saying where). Contact-topology events are located as in the exact path
// (continuation/events.hpp), between steps on one set. The start is the contact solve at lambda_min
// (solve_contact on the member with N(lambda_min) as a dead load), checked feasible by the fixed-set
// state. Settled supports: their load N K_g u_f is split by the axial force's cases
// (fe/discretisation.hpp), so F_dead + lambda F_live holds it at every lambda. Not handled (refused
// with a reason in the summary): a resumed trace.

#include "continuation/trace.hpp"
#include "model/member_model.hpp"

namespace liftoff::continuation {

TraceResult trace_fe_axial(const model::MemberModel& member, const TraceOptions& options, const TraceSink& sink = {});

}  // namespace liftoff::continuation
