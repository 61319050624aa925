#pragma once
// The FE + LCP load history, traced exactly: for the linear model the discrete solution is
// piecewise linear in lambda, so the path is followed by parametric pivoting from breakpoint
// to breakpoint (a node changing contact status), with no step length and no Newton.
//
// With the contact set A fixed the state is affine in lambda, (u, r, gap)(lambda) =
// state(F_dead) + lambda state(F_live): one factorisation of the fixed-set system
// (contact/active_set_system.hpp) and two solves. The next breakpoint is the first lambda at
// which a reaction in A or a gap outside A reaches zero; the node(s) there change status (ties
// together) and the new set is factorised once. A breakpoint at which the new set would not
// carry the path on (a degenerate one) is resolved by the LCP of the reaction and gap rates of
// the nodes at zero there (Lemke on a problem of their size), failing that by the contact
// solver on the full problem just beyond it; the summary's message says so. The start is the
// full contact set when it is feasible, otherwise the set of the contact solver (solve_contact,
// fast: the sparse active-set solver, Lemke its own fallback), checked feasible by the exact
// fixed-set state.
//
// The state is continuous at a breakpoint, so the sets on either side give it alike up to
// round-off, and their difference there measures it: when it exceeds the path's own motion
// over the last segment, round-off decides the order of what follows, and the trace stops
// (solver_failure, "round-off: ..."), the steps before it valid. (A member about to tip over,
// held by the last nodes of its foundation by a lever of one element: the condition of that
// system grows like N^5.)
//
// A member only the foundation holds (free-free beam) is held only while compressive
// reactions can balance the loads on its free rigid motions; the load beyond which they cannot
// (the lift-off load) is found once, exactly, and the trace stops there with
// TraceTermination::no_equilibrium, its message giving that lambda.
//
// Steps are recorded at lambda_min, at every breakpoint, at every event and at lambda_max.
// Events are changes of the contact topology of w (continuation/events.hpp), located between
// breakpoints, where the path is affine, by bisection on lambda to options.event_tolerance
// with no further solve. TraceStep::state of an FE step holds the contact set that carries
// the path on from it (1 = in contact, one per reaction node; state_topology
// continuation::FeContactSet), so that a resumed trace restarts without a contact solve.
//
// A beam under an axial force (dead or live) is not linear in lambda: trace_fe hands it to
// trace_fe_axial (fe_axial_path.hpp). Steps of both carry amplitude and lifted_length
// (events.hpp's lift_measures); axial_force and stability are the axial path's.

#include <optional>
#include <vector>

#include "continuation/trace.hpp"
#include "model/member_model.hpp"

namespace liftoff::continuation {

TraceResult trace_fe(const model::MemberModel& member, const TraceOptions& options, const TraceSink& sink = {});

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
