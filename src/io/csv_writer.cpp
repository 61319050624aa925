#include "io/csv_writer.hpp"

#include <fmt/format.h>

#include <fstream>
#include <system_error>

#include "core/error.hpp"
#include "io/hdf5_writer.hpp"

namespace liftoff::io {

using scene::StructureKind;

std::string fields_csv(const SolveReport& r) {
  const FieldTable& f = r.fields;
  const bool arch = r.kind == StructureKind::arch;
  std::string out =
      fmt::format("{},w,rotation,moment,shear,reaction{}\n", arch ? "theta_deg" : "x", arch ? ",u,normal_force" : "");
  for (std::size_t i = 0; i < f.coordinate.size(); ++i) {
    out += fmt::format("{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}", f.coordinate[i], f.w[i], f.rotation[i],
                       f.bending_moment[i], f.shear_force[i], f.reaction[i]);
    if (arch) out += fmt::format(",{:.17g},{:.17g}", f.u[i], f.normal_force[i]);
    out += "\n";
  }
  return out;
}

void write_text_file(const std::filesystem::path& path, const std::string& text, const std::string& what) {
  const std::filesystem::path temporary = temporary_path(path);
  std::ofstream file(temporary);
  file << text;
  file.close();
  std::error_code error;
  if (!file || (std::filesystem::rename(temporary, path, error), error)) {
    std::filesystem::remove(temporary, error);
    throw OutputError(path.string() + ": cannot write " + what);
  }
}

void write_fields_csv(const SolveReport& report, const std::filesystem::path& path) {
  write_text_file(path, fields_csv(report), "the fields CSV");
}

}  // namespace liftoff::io
