#pragma once
// What `liftoff envelope` produced (app/envelope_command.hpp): every case it solved (a load
// combination, a lead position of the moving group, or both), the envelopes of the fields over
// the cases on a common grid, the extremes with the case that governs each, and the lift-off map
// (the contact regions of every case). In the user's units; signs as in io/report.hpp.
//
// The envelope curves are each case's sampled fields interpolated linearly onto the grid (max and
// min over the cases at each grid point); the extremes are taken from each case's own samples
// (which have nodes at every point load), so a peak under a load is not cut by the grid.
// Only certified cases enter the envelopes; a case that failed is listed with its termination and
// message, and the envelope is then marked incomplete.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "io/report.hpp"

namespace liftoff::io {

struct EnvelopeCase {
  std::string combination;         // empty: the scene has no [[combinations]] (every load at factor 1)
  std::optional<double> position;  // the moving group's lead position (absent: no [moving])
  SolveReport report;
  std::string error;          // the one-line refusal that stopped this case (empty: see report)
  bool warm_started = false;  // the solve started from the previous case's contact set
  bool passed() const { return error.empty() && report.usable && report.certified(); }
  std::string label() const;  // "ULS, lead at 1.8", "lead at 1.8", "ULS" or "loads"
};

// One extreme over the cases: its value, where along the member, and which case governs.
struct Extreme {
  double value = 0.0;
  double at = 0.0;
  int governing = -1;  // index into EnvelopeReport::cases (-1: no certified case)
};

struct EnvelopeReport {
  std::string scene_name;
  std::string scene_text;
  std::string coordinate_name;  // "x" or "theta_deg"
  scene::Units units;           // the scene's [units]: the labels of every output
  bool tensionless = true;
  bool warm_start = true;  // consecutive positions started from the previous contact set
  std::vector<EnvelopeCase> cases;
  // The grid and the envelopes along it (certified cases only).
  std::vector<double> coordinate;
  std::vector<double> w_max, w_min, pressure_max, pressure_min, moment_max, moment_min, shear_max, shear_min;
  // moment_max: largest sagging; moment_min: largest hogging (most negative); shear_max_abs: largest
  // |V| (value signed); pressure_max: largest foundation reaction; uplift_max: largest -w (the
  // member's largest displacement away from the foundation, 0 if it never rises); w_max: largest w.
  struct Design {
    Extreme moment_max, moment_min, shear_max_abs, pressure_max, uplift_max, w_max;
  } design;
  int failed_cases() const;
  bool complete() const { return failed_cases() == 0 && !cases.empty(); }
  // Work of the contact solves (fast: contact sets tried and numeric factorisations), summed over
  // the cases that report them.
  int contact_sets() const;
  int factorisations() const;
};

nlohmann::json to_json(const EnvelopeReport& report);
std::string text_summary(const EnvelopeReport& report);
// Layout (src/io/README.md, "`liftoff envelope`"): root attributes kind = "envelope", liftoff_version,
// scene_name, coordinate, sign_convention, complete, warm_start, units_system and units_<name>
// (as in a solve file); /scene (TOML text);
// /envelope/{coordinate, w_max, w_min, pressure_max, pressure_min, moment_max, moment_min,
// shear_max, shear_min}; /extremes (attributes <name>_value, <name>_at, <name>_governing as the
// case's label, <name>_case its index); /cases: datasets position (n, NaN without [moving]),
// certified (0/1), contact_sets, factorisations, and string attributes label_NNNN,
// termination_NNNN, message_NNNN; /cases/fields/NNNN/{coordinate, w, reaction, bending_moment,
// shear_force}: each certified case's own samples when there is no [moving] (the plot draws
// every combination's curves);
// /liftoff_map: regions (r x 3: case index, begin, end). Written under a temporary name and
// renamed (OutputError on failure).
void write_envelope_hdf5(const EnvelopeReport& report, const std::filesystem::path& path, const std::string& version);

}  // namespace liftoff::io
