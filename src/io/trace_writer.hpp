#pragma once
// The HDF5 file of a load history (`liftoff trace --output`), written as the trace runs: every
// accepted step and every event is appended and the file flushed at once, so that a run that is
// killed leaves a readable file with every finished step, and `--resume` continues it.
//
// Why two copies: with HDF5 1.10, a file flushed after every step is readable after a SIGKILL
// only if the kill did not land inside a flush (a flush writes metadata and chunks in no
// guaranteed order); killed at random while writing, about 1 run in 75 left a damaged file.
// SWMR would keep the file consistent, but a killed SWMR writer leaves the superblock marked
// "open for write" (h5py refuses it until `h5clear -s`), and SWMR forbids new groups and
// attributes once writing starts. So the trace keeps PATH.backup beside PATH, written alike one
// after the other: a kill damages at most the one being flushed. Resume and read_trace_file
// take the whole copy with more steps; the backup is removed when the writer closes normally.
// Rows of a step that was being written when the run stopped are dropped on reading back.
//
// Layout (src/io/README.md, "`liftoff trace`"):
//   /                attributes: liftoff_version, scene_name, coordinate, sign_convention,
//                    options (JSON), paths ("fe", "ritz" or "fe,ritz"), complete (0 until the
//                    last path ends), units_<name> (TraceFileInfo::units), and where the live load
//                    is of one kind load_quantity, load_symbol, load_reference (the live load's
//                    value at lambda = 1), load_unit, load_definition (continuation::PhysicalLoad)
//   /scene           the scene's TOML text
//   /sample_points   the points where w and r are recorded (user coordinate)
//   /PATH/           one group per path run ("fe", "ritz", "fe_refined"); attributes complete,
//                    termination, message, monitor (user coordinate)
//   /PATH/steps/     lambda, load (lambda x load_reference; NaN without a physical load),
//                    requested (1: a step at a load asked for, [trace] report_at / --at),
//                    monitor_deflection, iterations, axial_force, amplitude, lifted_length
//                    (steps); stability (steps, strings); deflection, reaction
//                    (steps x samples); state_topology (steps, strings: state_topology_text);
//                    contact_regions (rows of step, begin, end); state (rows of step, value);
//                    supports (rows of step, at, force, moment, tangential, spring (0/1),
//                    settlement: the support reactions, certify::SupportReaction in user units)
//   /PATH/steps/design/  moment_max, moment_min, shear_max_abs, pressure_max, uplift_max and each's
//                    <name>_at, from_statics (0/1), shear_closure, moment_closure (steps; NaN: no
//                    design values at the step, or no such point: post::DesignTable)
//   /PATH/steps/fields/  the whole state at every node (FE) or grid point (Ritz): coordinate
//                    (nodes, once), and w, rotation, bending_moment, shear_force, normal_force,
//                    reaction, gap (and u where the member has it) as steps x nodes, chunked
//                    (TraceStep::fields, continuation/step_state.hpp); attribute first_step: the
//                    step of the first row (0 but in a file an older liftoff began)
//   /PATH/events/    lambda, kind (strings), at, step (the step it follows), description
// The per-step datasets are one table in trace_writer.cpp (step_columns): writing, reading back,
// trimming an interrupted step, the damage check and the upgrade of an older file's path on
// resume (the columns it lacks made, its steps recording none of them) all iterate it, so a new
// per-step quantity is the TraceStep field its path fills and one row of that table.

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "continuation/result.hpp"

namespace liftoff::io {

// What the whole file describes; written when the file is created.
struct TraceFileInfo {
  std::string version;
  std::string scene_name;
  std::string scene_text;
  std::string coordinate;  // "x" or "theta_deg"
  std::string options;     // JSON text: what a resumed run must match
  std::vector<std::string> paths;
  std::vector<double> sample_points;
  // The scene's units (scene::unit_labels: name, label), written as root attributes units_<name>
  // (the solve file's); not read back.
  std::vector<std::pair<std::string, std::string>> units;
  // The live load as a physical quantity (continuation::PhysicalLoad), root attributes
  // load_quantity, load_symbol, load_reference, load_unit, load_definition; none without one.
  std::optional<continuation::PhysicalLoad> physical_load;
};

// One path's part of a file, as read back.
struct TracePathRecord {
  bool complete = false;
  std::string termination;  // empty until the path ends
  std::string message;
  double monitor = 0.0;
  std::vector<continuation::TraceStep> steps;
  std::vector<continuation::TraceEvent> events;
  std::vector<int> event_steps;  // per event, the index of the step it follows (/PATH/events/step)
};

// The whole file as read back.
struct TraceFileRecord {
  TraceFileInfo info;
  bool complete = false;
  std::vector<std::pair<std::string, TracePathRecord>> paths;  // in the order of info.paths
};
class TraceWriter {
 public:
  // A new file at `path` (replacing one that is there). Throws OutputError.
  TraceWriter(const std::filesystem::path& path, const TraceFileInfo& info);
  // An existing file, to continue: rows of a step that was being written when the run stopped
  // are dropped, so every path holds whole steps only. Throws OutputError (not a trace file).
  static TraceWriter resume(const std::filesystem::path& path);
  TraceWriter(TraceWriter&&) noexcept;
  ~TraceWriter();

  const TraceFileInfo& info() const;
  // What the file holds of one path; nullopt if the path has not started.
  std::optional<TracePathRecord> read_path(const std::string& name) const;

  // Creates the path's group if it is not there yet.
  void begin_path(const std::string& name, double monitor);
  void append_step(const std::string& name, const continuation::TraceStep& step);
  void append_event(const std::string& name, const continuation::TraceEvent& event);
  void end_path(const std::string& name, const continuation::TraceSummary& summary);
  // Sets the root's `complete` attribute (every path ended).
  void finish();

 private:
  struct File;
  explicit TraceWriter(std::unique_ptr<File> file);
  std::unique_ptr<File> file_;
};

// A step's StateTopology as the text of /PATH/steps/state_topology, and back: Ritz
// "first_in_contact limits modes" (plus " event direction delta" at a switching event), FE
// "fe contact set", "" for none. Files written before the topology was typed read back alike.
// parse_state_topology throws OutputError for text that is none of these.
std::string state_topology_text(const continuation::StateTopology& topology);
continuation::StateTopology parse_state_topology(const std::string& text);

// The whole file, for readers that are not resuming (tests, a finished file): the file, or its
// backup if the file was damaged by a kill. Throws OutputError.
TraceFileRecord read_trace_file(const std::filesystem::path& path);
// PATH.backup: the second copy that a running trace keeps beside PATH.
std::filesystem::path trace_backup_path(const std::filesystem::path& path);

}  // namespace liftoff::io
