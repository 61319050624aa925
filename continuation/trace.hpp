#pragma once
// The options of a load history (its result types: continuation/result.hpp).

#include <optional>
#include <vector>

#include "contact/method.hpp"
#include "continuation/arclength.hpp"
#include "continuation/path_control.hpp"
#include "continuation/result.hpp"

namespace liftoff::continuation {

// The Ritz path's own settings (the scene's [ritz] table, filled by app::trace_options as
// ritz/from_scene.hpp fills `solve`'s): the number of modes and the start's topology.
struct RitzTraceOptions {
  int modes = 0;                 // N; 0: automatic (continuation/models/ritz.hpp says how)
  int max_modes = 256;           // the largest N automatic modes take
  double mode_tolerance = 1e-5;  // automatic modes at lambda_min: limits settled to this * length
  // The pieces of the foundation at lambda_min, in order, true = contact; empty: read off an FE
  // + LCP solution there. limits: their guesses (user coordinate), one per change of piece
  // (empty: evenly spaced).
  std::vector<bool> topology;
  std::vector<double> limits;
};

// The options of one trace, nested as BifurcationKit nests them: the path follower's (which
// hold the corrector's Newton options), then the models' own. One struct, filled once from the
// scene (app/trace_command.hpp), validated once by validate().
struct TraceOptions {
  // The range [lambda_min, lambda_max], the control, the step bounds, max_steps (recorded steps
  // of the whole path) and the corrector. The Ritz path follows its branches with them (its
  // fold_tolerance is event_tolerance, its direction increasing lambda); the FE path, exact, has
  // no step length and takes the range and max_steps alone.
  ArcLengthOptions arc_length;
  double event_tolerance = 1e-10;  // events located to this in lambda
  int elements = 200;              // FE path
  // FE path: the contact solver of its full solves (the start when full contact is infeasible, a
  // degenerate breakpoint): dual or primal, Lemke on that LCP; fast or automatic, the sparse
  // active-set solver (Lemke its own fallback).
  contact::Method contact_method = contact::Method::automatic;
  RitzTraceOptions ritz;              // Ritz path
  double monitor = 0.0;               // user coordinate of the load-displacement curve's w
  std::vector<double> sample_points;  // user coordinates at which w and r are recorded
  // Beam-columns: stop (completed) at the first step whose TraceStep::amplitude (user length)
  // reaches this; absent: no bound (scene::TraceSettings::max_amplitude).
  std::optional<double> max_amplitude;
  // Beam-columns: at a `bifurcation` where the path loses its stability (stable before, unstable
  // after), leave the path for the bifurcated branch along the critical mode, in the direction
  // that meets the contact conditions; false: report the bifurcation and stay on the path
  // (scene::TraceSettings::switch_branch).
  bool switch_branch = true;
  // Load factors at which the state is wanted: each is located on the path wherever the path
  // passes it (a folding path passes a value more than once) and recorded as a step of its own
  // (TraceStep::requested). In the range [lambda_min, lambda_max].
  std::vector<double> report_at;
  // The live load as a physical quantity, where the live case is of one kind (app/trace_load.hpp:
  // a property of the scene, derived once above the paths); absent: lambda only. Each recorded
  // step's and event's `load` is physical_load->at(lambda) (today set where the trace is recorded,
  // app/trace_command.cpp; the paths do not use it).
  std::optional<PhysicalLoad> physical_load;
  // Resume after this step (read back from an interrupted trace's file): the path restarts
  // from its lambda and state. It reports neither that step nor any event at or below its
  // lambda again: they are in the file already.
  std::optional<TraceStep> resume_from;
  // The rules both paths hold to; member_begin, member_end: the member's ends in the user
  // coordinate (the monitor and the sample points lie between them). Throws
  // std::invalid_argument "TraceOptions.<field>: expected ..., got ...".
  void validate(double member_begin, double member_end) const;
};

}  // namespace liftoff::continuation
