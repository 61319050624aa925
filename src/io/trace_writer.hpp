#pragma once
// The HDF5 file of a load history (`liftoff trace --output`), written as the trace runs: every
// accepted step and every event is appended and the file flushed at once, so that a run that is
// killed leaves a readable file with every finished step, and `--resume` continues it.
//
// Why flush rather than SWMR: with HDF5 1.10 a SWMR writer sets the superblock's "open for
// write" flag, and a killed SWMR writer leaves a file that h5py refuses until `h5clear -s`. The
// default (earliest) format has no such flag; after H5Fflush the file on disk is complete, and
// only a kill *during* one step's writes can lose that step (the rows of the step datasets may
// then differ in length: reading back keeps the steps that every dataset holds).
//
// Layout (README, "liftoff trace"):
//   /                attributes: liftoff_version, scene_name, coordinate, sign_convention,
//                    options (JSON), paths ("fe", "ritz" or "fe,ritz"), complete (0 until the
//                    last path ends)
//   /scene           the scene's TOML text
//   /sample_points   the points where w and r are recorded (user coordinate)
//   /PATH/           one group per path run ("fe", "ritz", "fe_refined"); attributes complete,
//                    termination, message, monitor (user coordinate)
//   /PATH/steps/     lambda, monitor_deflection, iterations (steps); deflection, reaction
//                    (steps x samples); state_topology (steps, strings); contact_regions (rows of
//                    step, begin, end); state (rows of step, value)
//   /PATH/events/    lambda, kind (strings), at, step (the step it follows), description

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "continuation/trace.hpp"

namespace liftoff::io {

// What the whole file describes; written when the file is created.
struct TraceFileInfo {
  std::string version;
  std::string scene_name;
  std::string scene_text;
  std::string coordinate;    // "x" or "theta_deg"
  std::string options;       // JSON text: what a resumed run must match
  std::vector<std::string> paths;
  std::vector<double> sample_points;
};

// One path's part of a file, as read back.
struct TracePathRecord {
  bool complete = false;
  std::string termination;   // empty until the path ends
  std::string message;
  double monitor = 0.0;
  std::vector<continuation::TraceStep> steps;
  std::vector<continuation::TraceEvent> events;
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
  friend TraceFileRecord read_trace_file(const std::filesystem::path& path);
  explicit TraceWriter(std::unique_ptr<File> file);
  std::unique_ptr<File> file_;
};

// The whole file, for readers that are not resuming (tests, a finished file). Throws OutputError.
TraceFileRecord read_trace_file(const std::filesystem::path& path);

}  // namespace liftoff::io
