#pragma once
// `liftoff solve --csv-fields FILE.csv`: the sampled fields for spreadsheets.
//
// One row per sampled point (the report's fields, io/report.hpp), columns
//   beams:  x,w,rotation,moment,shear,reaction
//   arches: theta_deg,w,rotation,moment,shear,reaction,u,normal_force
// in the user's units and the report's signs (w > 0 into the foundation, rotation
// counterclockwise, moment sagging positive, shear = dM/ds, reaction compression positive,
// normal force tension positive); 17 significant digits. Where the reaction jumps a position
// appears twice (its left value, then its right).
//
// Written under a temporary name (io/hdf5_writer.hpp's temporary_path) and renamed when
// complete: a failure leaves no file and throws OutputError naming the path.

#include <filesystem>
#include <string>

#include "io/report.hpp"

namespace liftoff::io {

std::string fields_csv(const SolveReport& report);

void write_fields_csv(const SolveReport& report, const std::filesystem::path& path);

// Any text file written so (the fields CSV, `liftoff sweep`'s CSV, `liftoff envelope`'s JSON):
// a failure leaves no file and throws OutputError "<path>: cannot write <what>".
void write_text_file(const std::filesystem::path& path, const std::string& text, const std::string& what);

}  // namespace liftoff::io
