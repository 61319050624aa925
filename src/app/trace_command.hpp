#pragma once
// `liftoff trace`: the load history F = F_dead + lambda F_live of one scene, lambda from
// [trace] lambda_min to lambda_max, followed by the FE path (exact, parametric pivoting), the
// Ritz path (pseudo-arc-length), or both side by side; every step and event goes to the HDF5
// trace as soon as it is known (io/trace_writer.hpp), and an interrupted trace resumes.
//
// The paths come in as functions so that everything here (options from the scene, the file,
// resume, the comparisons) is tested with a synthetic path as well as the real ones.

#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "continuation/trace.hpp"
#include "model/member_model.hpp"
#include "scene/scene.hpp"

namespace liftoff::app {

// A path runs on the member model, built once per trace from the scene (run_trace).
using TracePath = std::function<continuation::TraceResult(const model::MemberModel&, const continuation::TraceOptions&,
                                                          const continuation::TraceSink&)>;

struct TracePaths {
  TracePath fe;    // continuation::trace_fe by default
  TracePath ritz;  // continuation::trace_ritz by default
};
TracePaths default_trace_paths();

struct TraceProgress {
  std::string path;
  double load_factor = 0.0;
  double lambda_min = 0.0;
  double lambda_max = 0.0;
  int steps = 0;
  int events = 0;
};

struct TraceRequest {
  std::optional<scene::Method> method;  // overrides [trace] method (itself [solve] method by default)
  std::optional<int> elements;          // overrides [solve] elements
  std::optional<int> modes;             // overrides [ritz] modes (0: auto)
  // Overrides [trace] report_at (--at): the loads at which the state is wanted, physical loads in
  // the live load's unit where it is of one kind, else load factors (app/trace_load.hpp).
  std::optional<std::vector<double>> report_at;
  std::filesystem::path output;                        // the HDF5 trace; empty: none
  bool resume = false;                                 // continue `output` from its last finished step
  std::string version;                                 // written into the file
  std::function<void(const TraceProgress&)> progress;  // after every step
};

// One path as run (or read back, when a resumed file already held it complete).
struct PathTrace {
  std::string path;  // "fe", "ritz", "fe_refined"
  continuation::TraceSummary summary;
  std::vector<continuation::TraceStep> steps;    // every step, resumed ones included; without
                                                 // the sampled deflection and reaction and the
                                                 // nodal fields (they are in the HDF5 file)
  std::vector<continuation::TraceEvent> events;  // likewise
  std::vector<int> event_steps;                  // per event, the index of the step it follows
  int resumed_steps = 0;                         // of them, read back from the file
};

// The events of two traces of one scene paired (same kind, nearest load factor); the
// differences are the Ritz-FE discrepancy (`method = "all"`) or the FE discretisation error
// (`refine`, the FE path against itself with twice the elements).
struct EventPair {
  continuation::EventKind kind;
  double load_factor_a = 0.0, load_factor_b = 0.0;
  double at_a = 0.0, at_b = 0.0;
};
struct EventComparison {
  std::string a, b;  // path names
  std::vector<EventPair> pairs;
  std::vector<continuation::TraceEvent> only_a, only_b;
};
EventComparison compare_events(const PathTrace& a, const PathTrace& b);

struct TraceOutcome {
  std::string scene_name;
  std::string output;  // the HDF5 file, if any
  double monitor = 0.0;
  std::vector<double> sample_points;
  std::vector<PathTrace> paths;                         // in the order run: fe, ritz, fe_refined
  std::optional<EventComparison> comparison;            // fe against ritz (method "all")
  std::optional<EventComparison> discretisation_error;  // fe against fe_refined (refine)
  scene::Units units;                                   // the scene's [units] (labels)
  // The live load as a physical quantity (app/trace_load.hpp), or why there is none.
  std::optional<continuation::PhysicalLoad> physical_load;
  std::string no_physical_load;
  std::vector<double> report_at;          // the load factors asked for (TraceOptions::report_at)
  bool arch = false, von_karman = false;  // how the support reactions read (io::support_reactions_json)
  bool foundation_outside = false;        // arches: [foundation] side = "outside"
  std::vector<std::string> warnings;      // the scene reader's and the foundation scale's (post/scale.hpp)
  bool usable() const;                    // every path reached lambda_max
};

// TraceOptions from the scene's [trace] (and [solve], [ritz]) with the request's overrides.
// Throws InputError naming the key (no [trace] table, no lambda_max).
continuation::TraceOptions trace_options(const scene::Scene& scene, const TraceRequest& request);
// The paths `method` asks for: {"fe"}, {"ritz"} or {"fe", "ritz"}, then "fe_refined" if refine.
std::vector<std::string> trace_path_names(const scene::Scene& scene, const TraceRequest& request);

// Runs the trace. Throws InputError (bad request, a resumed file of another scene or other
// options), OutputError (the file). A path that stops short of lambda_max is an outcome: its
// summary says why, and its steps are in the file.
TraceOutcome run_trace(const scene::Scene& scene, const TraceRequest& request,
                       const TracePaths& paths = default_trace_paths());

// Per step: lambda, load (absent without a physical load), monitor_deflection, contact_regions,
// iterations, axial_force, amplitude, lifted_length, stability, requested, design (solve's
// object), supports; per event lambda, load, kind, at, description. No nodal fields (HDF5 only).
nlohmann::json to_json(const TraceOutcome& outcome);
// The events with their physical load and the moment's extremes at each (the state of the step at
// the event), and the steps at the loads asked for.
std::string text_summary(const TraceOutcome& outcome);
// `liftoff trace --csv`: one row per step of every path: path, step, lambda, load (empty without a
// physical load), monitor_deflection, axial_force, amplitude, lifted_length, the design values with
// their positions (io::design_csv_header; empty where a step has none), support_reactions
// ("at:force:moment" joined by ';'), stability, requested (true/false); 17 significant digits
// (the design values and supports 12, as `sweep --csv`).
std::string trace_csv(const TraceOutcome& outcome);

}  // namespace liftoff::app
