#pragma once
// A load history: the solution of one scene as the live loads grow, F = F_dead + lambda F_live,
// with every change of the contact topology located and reported.
//
// Two paths produce it, both through this one interface so that `liftoff trace`, the HDF5
// trace writer and the tests do not care which one ran:
//  - trace_fe   (models/fe_member.hpp): the FE model on its contact sets (linear, beam-column,
//                                von Karman), followed by the path engine (engine.hpp);
//  - trace_ritz (models/ritz.hpp): the Ritz model with moving limits, followed by the
//                                pseudo-arc-length driver (arclength.hpp), events located by
//                                secant/bisection on their event functions.
// Results are in the user's units and coordinate (x, or theta in degrees), like io::SolveReport,
// with its signs: w > 0 into the foundation, u toward increasing x (theta), rotation
// counterclockwise, bending moment sagging positive, normal force tension positive, reaction
// compression positive (post/user_tables.hpp).
//
// These are the result types alone, a library of their own (liftoff_trace_result) below the
// writers that store them (io/trace_writer.hpp), which link nothing else of continuation/.

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "certify/support_reaction.hpp"
#include "contact/method.hpp"
#include "core/contact_region.hpp"
#include "core/enum_names.hpp"
#include "post/user_tables.hpp"

namespace liftoff::continuation {

enum class EventKind {
  lift_off_opens,     // a lift-off zone opens inside a contact region (w touches 0 from above)
  contact_opens,      // a contact region opens inside a lift-off zone (w touches 0 from below)
  region_vanishes,    // a contact region shrinks to nothing
  lift_off_vanishes,  // a lift-off zone shrinks to nothing (two contact regions merge)
  limit_at_support,   // a contact limit reaches a point support or a supported end, or leaves
                      // it (a zone opening there): both paths name it so
  limit_at_load,      // a contact limit reaches a point load
  limit_at_end,       // a contact limit reaches or leaves the end of the foundation (member end)
  limit_point,        // a fold: lambda reaches a maximum or minimum along the path
  bifurcation,        // the tangent stiffness on the current contact set turns singular away from a fold:
                      // another branch crosses the path here (beam-columns, issue 15)
};
std::string_view to_string(EventKind);

struct TraceEvent {
  double load_factor = 0.0;  // lambda at the event
  EventKind kind = EventKind::lift_off_opens;
  double at = 0.0;          // position along the member, user coordinate
  std::string description;  // one line, in words
};

// The live load as a physical quantity, where the live case is of one kind (app/trace_load.hpp
// derives it from the scene): load = lambda x reference, in `unit`. `definition` says which value
// `reference` is when the live case has several loads of that kind (e.g. the largest of two wheel
// forces). Absent from a trace whose live case mixes kinds (lambda only).
struct PhysicalLoad {
  std::string quantity;    // "point force", "moment", "distributed force", "axial force", "temperature rise",
                           // "imposed curvature"
  std::string symbol;      // "P", "M", "q", "N", "dT", "kappa"
  double reference = 0.0;  // the live load's value at lambda = 1, user units (nonzero)
  std::string unit;        // its unit label (scene::unit_labels; "" when the scene states none)
  std::string definition;  // in words: "lambda x the live axial force (loads[1])"
  double at(double lambda) const { return lambda * reference; }
};

// How a Ritz step's switching event opens the new zone: the old topology is continued this far
// in lambda past the event (direction * delta) before the switch.
struct RitzOpening {
  double direction = 1.0;
  double delta = 0.0;
  bool operator==(const RitzOpening&) const = default;
};

// The Ritz model's topology at a step: whether the first piece is in contact, its interior
// contact limits and its modes; at a switching event, the opening a resumed trace redoes.
struct RitzTopology {
  bool first_in_contact = false;
  int limits = 0;
  int modes = 0;
  std::optional<RitzOpening> at_event;
  bool operator==(const RitzTopology&) const = default;
};

// An FE step: its TraceStep::state is the contact set that carries the path on from it.
struct FeContactSet {
  bool operator==(const FeContactSet&) const = default;
};

// What a step's TraceStep::state is; monostate: a step with no resumable state. Stored as text
// (io/trace_writer.hpp) only in the trace file.
using StateTopology = std::variant<std::monostate, RitzTopology, FeContactSet>;

// Whether the equilibrium of a step is stable: its tangent stiffness, on the cone of admissible
// perturbations of its contact set, positive definite (stable) or not (unstable); unknown where
// the path does not check it (a member without axial force is stable by convexity).
enum class Stability { unknown, stable, unstable };
std::string_view to_string(Stability);

// One recorded point of the path.
struct TraceStep {
  double load_factor = 0.0;
  std::vector<ContactRegion> contact_regions;  // user coordinate
  double monitor_deflection = 0.0;             // w at TraceOptions::monitor (user length units)
  // M at the monitor (user moment units; the crest moment of a buckle), read off `fields` by the
  // output layer before it lets them go (they stay in the HDF5 file); none without fields.
  std::optional<double> monitor_moment;
  std::vector<double> deflection;  // w at TraceOptions::sample_points (user length units)
  std::vector<double> reaction;    // foundation reaction there (force per length, compression > 0)
  int iterations = 0;              // corrector iterations (Ritz) or pivots (FE) since the last step
  bool requested = false;          // recorded at a load asked for (TraceOptions::report_at)
  // The physical load (PhysicalLoad::at of the step's lambda), set where the trace is recorded
  // (app/trace_command.hpp); absent without one.
  std::optional<double> load;
  // The whole state, as `liftoff solve` reports the same scene at this lambda
  // (continuation/step_state.hpp builds it): the fields at every mesh node (FE) or on a uniform grid
  // (Ritz): coordinate, w, rotation, bending moment, shear force, normal force (0 on a beam without
  // an axial force; tension positive), reaction, gap, and u where the member has an axial unknown
  // (arches, von Karman beams on the FE mesh); empty where a path records none. The design values
  // (moment max/min, |V| max, pressure max, uplift max with their positions; absent where solve
  // gives none: a Ritz member that is no linear beam free of axial force). The support reactions
  // (the certificate's, user units; empty where the path does not certify its steps).
  post::FieldTable fields;
  std::optional<post::DesignTable> design;
  std::vector<certify::SupportReaction> supports;
  // Beam-columns: the axial force N = N_dead + lambda N_live (user force units, compression > 0; 0
  // without axial loads), the buckle amplitude (the largest lift of the member off the foundation
  // surface, max of -(w - gap) over the foundation, user length, 0 where nothing lifts) and the lifted
  // length (the total length of lift-off zones on the foundation, user coordinate), and the stability.
  double axial_force = 0.0;
  double amplitude = 0.0;
  double lifted_length = 0.0;
  Stability stability = Stability::unknown;
  // What a resumed trace needs to continue from this step without redoing anything, read by
  // the path that wrote it. Ritz: its topology and (unknowns, tangent, next step length,
  // amplitude scale), so a resumed run takes the same steps; FE: FeContactSet, one 0/1 per
  // reaction node (the set that carries the path on, fe_contact_set()), then the step length the
  // path goes on with, the sense of lambda (+1 or -1) and the metric's reference deflection
  // (fe_state_tail entries; zeros where the path does not resume from it: the beam-column path),
  // so that it restarts without a contact solve and takes the same steps.
  StateTopology state_topology;
  std::vector<double> state;
};

inline constexpr std::size_t fe_state_tail = 3;
// The contact set of an FE step (empty for any other step).
std::vector<bool> fe_contact_set(const TraceStep& step);

enum class TraceTermination {
  completed,       // lambda_max (or lambda_min going down) reached
  no_equilibrium,  // beyond some lambda no equilibrium exists (the loads lift the member off)
  step_too_small,  // the Ritz corrector failed at the minimum step
  step_limit,      // max_steps reached
  solver_failure,  // a solve failed outright; message says how
};
std::string_view to_string(TraceTermination);

// Which path produced a trace (its name, "fe" or "ritz", is the HDF5 group's and the JSON's).
enum class PathKind { fe, ritz };
std::string_view to_string(PathKind);

struct TraceSummary {
  TraceTermination termination = TraceTermination::solver_failure;
  std::string message;
  PathKind path = PathKind::fe;
  int steps = 0;
  int rejected_steps = 0;
  int corrector_iterations = 0;  // Ritz
  int pivots = 0;                // FE
  int factorisations = 0;
  int contact_solves = 0;  // FE: full contact solves (the start, degenerate breakpoints)
  // FE: the formulation the last contact solve used (ContactSummary::method); automatic if none ran.
  contact::Method contact_method = contact::Method::automatic;
  double final_load_factor = 0.0;
  double time_s = 0.0;
  bool is_usable() const { return termination == TraceTermination::completed; }
};

struct TraceResult {
  std::vector<TraceStep> steps;
  std::vector<TraceEvent> events;
  TraceSummary summary;
};

// Called once per accepted step (and once per event, right after the step that ends at it), as
// soon as it is known, so that the caller can write it out incrementally.
struct TraceSink {
  std::function<void(const TraceStep&)> on_step;
  std::function<void(const TraceEvent&)> on_event;
};

}  // namespace liftoff::continuation

namespace liftoff {
// The names' one table is in continuation/result.cpp (core/enum_names.hpp).
template <>
std::optional<continuation::EventKind> from_string(std::string_view);
template <>
std::optional<continuation::TraceTermination> from_string(std::string_view);
template <>
std::optional<continuation::PathKind> from_string(std::string_view);
template <>
std::optional<continuation::Stability> from_string(std::string_view);
}  // namespace liftoff
