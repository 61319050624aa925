#include "io/trace_writer.hpp"

#include <fmt/format.h>
#include <hdf5.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <sstream>
#include <variant>

#include "core/error.hpp"
#include "io/hdf5_attributes.hpp"
#include "io/hdf5_handle.hpp"
#include "io/report.hpp"

namespace liftoff::io {

using continuation::EventKind;
using continuation::TraceEvent;
using continuation::TraceStep;

namespace {

using hdf5::check;
using hdf5::Handle;
using hdf5::read_number_attribute;
using hdf5::read_string_attribute;
using hdf5::string_type;
using hdf5::write_number_attribute;
using hdf5::write_string_attribute;
using hdf5::write_text;

bool exists(hid_t location, const std::string& name) { return H5Lexists(location, name.c_str(), H5P_DEFAULT) > 0; }

// Whether `path` ("a/b/c") exists under `location`, each link in turn (H5Lexists needs the parents).
bool path_exists(hid_t location, const std::string& path) {
  for (std::size_t slash = path.find('/');; slash = path.find('/', slash + 1)) {
    if (!exists(location, path.substr(0, slash))) return false;
    if (slash == std::string::npos) return true;
  }
}

// ---------------------------------------------------------------------------------------------
// Extendible datasets: `columns` == 0 for one value per row.

void create_rows(hid_t group, const char* name, hid_t type, hsize_t columns) {
  const int rank = columns == 0 ? 1 : 2;
  const hsize_t dims[2] = {0, columns};
  const hsize_t max_dims[2] = {H5S_UNLIMITED, columns};
  // Chunks of about 64 KiB of rows: few enough chunks, and a step's write touches one or two.
  const hsize_t row_bytes = 8 * std::max<hsize_t>(1, columns);
  const hsize_t chunk[2] = {std::max<hsize_t>(1, 65536 / row_bytes), std::max<hsize_t>(1, columns)};
  Handle space(H5Screate_simple(rank, dims, max_dims), H5Sclose, name);
  Handle properties(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, name);
  check(H5Pset_chunk(properties, rank, chunk), name);
  // NaN in rows that were made but never written (a kill between extending and writing): such
  // a row belongs to no step and is dropped when the file is read back.
  if (H5Tequal(type, H5T_IEEE_F64LE) > 0) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    check(H5Pset_fill_value(properties, H5T_NATIVE_DOUBLE, &nan), name);
  }
  Handle dataset(H5Dcreate2(group, name, type, space, H5P_DEFAULT, properties, H5P_DEFAULT), H5Dclose, name);
}

hsize_t row_count(hid_t location, const std::string& name) {
  Handle dataset(H5Dopen2(location, name.c_str(), H5P_DEFAULT), H5Dclose, name);
  Handle space(H5Dget_space(dataset), H5Sclose, name);
  hsize_t dims[2] = {0, 0};
  H5Sget_simple_extent_dims(space, dims, nullptr);
  return dims[0];
}

void set_rows(hid_t location, const std::string& name, hsize_t rows) {
  Handle dataset(H5Dopen2(location, name.c_str(), H5P_DEFAULT), H5Dclose, name);
  Handle space(H5Dget_space(dataset), H5Sclose, name);
  hsize_t dims[2] = {0, 0};
  H5Sget_simple_extent_dims(space, dims, nullptr);
  dims[0] = rows;
  check(H5Dset_extent(dataset, dims), name);
}

void append_rows(hid_t location, const std::string& name, hid_t memory_type, const void* data, hsize_t rows) {
  if (rows == 0) return;
  Handle dataset(H5Dopen2(location, name.c_str(), H5P_DEFAULT), H5Dclose, name);
  hsize_t dims[2] = {0, 0};
  int rank = 0;
  {
    Handle space(H5Dget_space(dataset), H5Sclose, name);
    rank = H5Sget_simple_extent_dims(space, dims, nullptr);
  }
  const hsize_t start[2] = {dims[0], 0};
  const hsize_t count[2] = {rows, dims[1]};
  dims[0] += rows;
  check(H5Dset_extent(dataset, dims), name);
  Handle file_space(H5Dget_space(dataset), H5Sclose, name);
  check(H5Sselect_hyperslab(file_space, H5S_SELECT_SET, start, nullptr, count, nullptr), name);
  Handle memory_space(H5Screate_simple(rank, count, nullptr), H5Sclose, name);
  check(H5Dwrite(dataset, memory_type, memory_space, file_space, H5P_DEFAULT, data), name);
}

void append_doubles(hid_t location, const std::string& name, const std::vector<double>& values, hsize_t rows) {
  append_rows(location, name, H5T_NATIVE_DOUBLE, values.data(), rows);
}

void append_string(hid_t location, const std::string& name, const std::string& value) {
  Handle type = string_type(true);
  const char* text = value.c_str();
  append_rows(location, name, type, &text, 1);
}

// Every row of a dataset, flattened.
std::vector<double> read_doubles(hid_t location, const std::string& name) {
  Handle dataset(H5Dopen2(location, name.c_str(), H5P_DEFAULT), H5Dclose, name);
  Handle space(H5Dget_space(dataset), H5Sclose, name);
  std::vector<double> values(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
  if (!values.empty()) check(H5Dread(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), name);
  return values;
}

std::vector<std::string> read_strings(hid_t location, const std::string& name) {
  Handle dataset(H5Dopen2(location, name.c_str(), H5P_DEFAULT), H5Dclose, name);
  Handle space(H5Dget_space(dataset), H5Sclose, name);
  std::vector<char*> texts(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)), nullptr);
  std::vector<std::string> values;
  if (texts.empty()) return values;
  Handle type = string_type(true);
  check(H5Dread(dataset, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, texts.data()), name);
  for (char* t : texts) values.emplace_back(t != nullptr ? t : "");
  H5Dvlen_reclaim(type, space, H5P_DEFAULT, texts.data());
  return values;
}

std::string read_text(hid_t location, const char* name) {
  Handle dataset(H5Dopen2(location, name, H5P_DEFAULT), H5Dclose, name);
  Handle type(H5Dget_type(dataset), H5Tclose, name);
  std::string text(H5Tget_size(type), '\0');
  Handle memory = string_type(false, text.size());
  check(H5Dread(dataset, memory, H5S_ALL, H5S_ALL, H5P_DEFAULT, text.data()), name);
  text.resize(std::strlen(text.c_str()));
  return text;
}

EventKind event_kind(const std::string& name) {
  if (const auto kind = from_string<EventKind>(name)) return *kind;
  throw OutputError("unknown event kind '" + name + "' in the trace file");
}

constexpr const char* fe_contact_set_text = "fe contact set";

// The per-step columns of /PATH/steps, in the order a step is written: the tables keyed by
// step first, the one-row-per-step datasets after (lambda among them). A step counts as written
// only when every one-row-per-step dataset holds it: the reader and the trimming take their
// common length. The writer, the reader, the trimming of an interrupted step, the damage check and
// the upgrade of an older file all go through this table: a new per-step quantity is a TraceStep
// field and one row here.
enum class ColumnKind {
  keyed,    // any number of rows of `width` values per step, each row (step, values...)
  samples,  // one row of a value per sample point per step
  nodes,    // one row of a value per node (FE) or grid point (Ritz) per step, under fields/ (see below)
  text,     // one string per step
  number,   // one value per step
  // One value per step where NaN is a value ("none": no physical load, no design value, no such
  // point), so the damage check (a NaN fill value in a written row) does not look at it.
  optional_number,
};

bool one_number(ColumnKind kind) { return kind == ColumnKind::number || kind == ColumnKind::optional_number; }

struct StepColumn {
  const char* name;  // under /PATH/steps/ ("design/moment_max": in the group design)
  ColumnKind kind;
  hsize_t width;  // keyed: values per row after the step index
  // keyed, samples, nodes, number: the step's values (keyed: its rows, flattened) and back.
  std::vector<double> (*values)(const TraceStep&);
  void (*assign)(TraceStep&, std::vector<double>);
  // text: the step's string and back (parse errors throw OutputError).
  std::string (*text)(const TraceStep&);
  void (*parse)(TraceStep&, const std::string&);
};

constexpr double none = std::numeric_limits<double>::quiet_NaN();

std::vector<double> number(double value) { return {value}; }
std::optional<double> optional_number(const std::vector<double>& v) {
  return std::isnan(v.at(0)) ? std::nullopt : std::optional(v.at(0));
}

// The design values, one number column each for the value and its position (NaN: no design
// values at this step, or no such point). A finite value makes the step's design table.
using DesignMember = post::DesignValue post::DesignTable::*;
template <DesignMember member>
std::vector<double> design_value(const TraceStep& s) {
  return number(s.design ? ((*s.design).*member).value : none);
}
template <DesignMember member>
std::vector<double> design_at(const TraceStep& s) {
  return number(s.design && ((*s.design).*member).at ? *((*s.design).*member).at : none);
}
template <DesignMember member>
void assign_design_value(TraceStep& s, std::vector<double> v) {
  if (std::isnan(v.at(0))) return;
  if (!s.design) s.design.emplace();
  ((*s.design).*member).value = v[0];
}
template <DesignMember member>
void assign_design_at(TraceStep& s, std::vector<double> v) {
  if (std::isnan(v.at(0))) return;
  if (!s.design) s.design.emplace();
  ((*s.design).*member).at = v[0];
}
template <double post::DesignTable::*member>
std::vector<double> design_figure(const TraceStep& s) {
  return number(s.design ? (*s.design).*member : none);
}
template <double post::DesignTable::*member>
void assign_design_figure(TraceStep& s, std::vector<double> v) {
  if (std::isnan(v.at(0))) return;
  if (!s.design) s.design.emplace();
  (*s.design).*member = v[0];
}

#define LIFTOFF_DESIGN_COLUMNS(name)                                                            \
  {"design/" #name,                                                                             \
   ColumnKind::optional_number,                                                                 \
   0,                                                                                           \
   design_value<&post::DesignTable::name>,                                                      \
   assign_design_value<&post::DesignTable::name>,                                               \
   nullptr,                                                                                     \
   nullptr},                                                                                    \
  {                                                                                             \
    "design/" #name "_at", ColumnKind::optional_number, 0, design_at<&post::DesignTable::name>, \
        assign_design_at<&post::DesignTable::name>, nullptr, nullptr                            \
  }

// The nodal fields: one column per field of post::FieldTable (the coordinate is written once per
// path, fields/coordinate).
using FieldMember = std::vector<double> post::FieldTable::*;
template <FieldMember member>
std::vector<double> field_values(const TraceStep& s) {
  return s.fields.*member;
}
template <FieldMember member>
void assign_field(TraceStep& s, std::vector<double> v) {
  s.fields.*member = std::move(v);
}
#define LIFTOFF_FIELD_COLUMN(name)                                                \
  {                                                                               \
    "fields/" #name, ColumnKind::nodes, 0, field_values<&post::FieldTable::name>, \
        assign_field<&post::FieldTable::name>, nullptr, nullptr                   \
  }

const StepColumn step_columns[] = {
    {"contact_regions", ColumnKind::keyed, 2,
     [](const TraceStep& s) {
       std::vector<double> v;
       for (const ContactRegion& r : s.contact_regions) v.insert(v.end(), {r.begin, r.end});
       return v;
     },
     [](TraceStep& s, std::vector<double> v) {
       for (std::size_t k = 0; k + 1 < v.size(); k += 2) s.contact_regions.push_back({v[k], v[k + 1]});
     },
     nullptr, nullptr},
    {"state", ColumnKind::keyed, 1, [](const TraceStep& s) { return s.state; },
     [](TraceStep& s, std::vector<double> v) { s.state = std::move(v); }, nullptr, nullptr},
    // The support reactions: rows (step, at, force, moment, tangential, spring, settlement).
    {"supports", ColumnKind::keyed, 6,
     [](const TraceStep& s) {
       std::vector<double> v;
       for (const certify::SupportReaction& r : s.supports)
         v.insert(v.end(), {r.at, r.force, r.moment, r.tangential, r.spring ? 1.0 : 0.0, r.settlement});
       return v;
     },
     [](TraceStep& s, std::vector<double> v) {
       for (std::size_t k = 0; k + 5 < v.size(); k += 6)
         s.supports.push_back({v[k], v[k + 1], v[k + 2], v[k + 3], v[k + 4] != 0.0, v[k + 5]});
     },
     nullptr, nullptr},
    {"deflection", ColumnKind::samples, 0, [](const TraceStep& s) { return s.deflection; },
     [](TraceStep& s, std::vector<double> v) { s.deflection = std::move(v); }, nullptr, nullptr},
    {"reaction", ColumnKind::samples, 0, [](const TraceStep& s) { return s.reaction; },
     [](TraceStep& s, std::vector<double> v) { s.reaction = std::move(v); }, nullptr, nullptr},
    LIFTOFF_FIELD_COLUMN(w),
    LIFTOFF_FIELD_COLUMN(u),
    LIFTOFF_FIELD_COLUMN(rotation),
    LIFTOFF_FIELD_COLUMN(bending_moment),
    LIFTOFF_FIELD_COLUMN(shear_force),
    LIFTOFF_FIELD_COLUMN(normal_force),
    LIFTOFF_FIELD_COLUMN(reaction),
    LIFTOFF_FIELD_COLUMN(gap),
    {"state_topology", ColumnKind::text, 0, nullptr, nullptr,
     [](const TraceStep& s) { return state_topology_text(s.state_topology); },
     [](TraceStep& s, const std::string& t) { s.state_topology = parse_state_topology(t); }},
    {"iterations", ColumnKind::number, 0,
     [](const TraceStep& s) { return std::vector<double>{static_cast<double>(s.iterations)}; },
     [](TraceStep& s, std::vector<double> v) { s.iterations = static_cast<int>(v.at(0)); }, nullptr, nullptr},
    {"monitor_deflection", ColumnKind::number, 0,
     [](const TraceStep& s) { return std::vector<double>{s.monitor_deflection}; },
     [](TraceStep& s, std::vector<double> v) { s.monitor_deflection = v.at(0); }, nullptr, nullptr},
    {"load", ColumnKind::optional_number, 0, [](const TraceStep& s) { return number(s.load.value_or(none)); },
     [](TraceStep& s, std::vector<double> v) { s.load = optional_number(v); }, nullptr, nullptr},
    {"requested", ColumnKind::number, 0, [](const TraceStep& s) { return number(s.requested ? 1.0 : 0.0); },
     [](TraceStep& s, std::vector<double> v) { s.requested = v.at(0) != 0.0; }, nullptr, nullptr},
    LIFTOFF_DESIGN_COLUMNS(moment_max),
    LIFTOFF_DESIGN_COLUMNS(moment_min),
    LIFTOFF_DESIGN_COLUMNS(shear_max_abs),
    LIFTOFF_DESIGN_COLUMNS(pressure_max),
    LIFTOFF_DESIGN_COLUMNS(uplift_max),
    {"design/from_statics", ColumnKind::optional_number, 0,
     [](const TraceStep& s) { return number(s.design ? (s.design->from_statics ? 1.0 : 0.0) : none); },
     [](TraceStep& s, std::vector<double> v) {
       if (std::isnan(v.at(0))) return;
       if (!s.design) s.design.emplace();
       s.design->from_statics = v[0] != 0.0;
     },
     nullptr, nullptr},
    {"design/shear_closure", ColumnKind::optional_number, 0, design_figure<&post::DesignTable::shear_closure>,
     assign_design_figure<&post::DesignTable::shear_closure>, nullptr, nullptr},
    {"design/moment_closure", ColumnKind::optional_number, 0, design_figure<&post::DesignTable::moment_closure>,
     assign_design_figure<&post::DesignTable::moment_closure>, nullptr, nullptr},
    {"lambda", ColumnKind::number, 0, [](const TraceStep& s) { return std::vector<double>{s.load_factor}; },
     [](TraceStep& s, std::vector<double> v) { s.load_factor = v.at(0); }, nullptr, nullptr},
    {"axial_force", ColumnKind::number, 0, [](const TraceStep& s) { return std::vector<double>{s.axial_force}; },
     [](TraceStep& s, std::vector<double> v) { s.axial_force = v.at(0); }, nullptr, nullptr},
    {"amplitude", ColumnKind::number, 0, [](const TraceStep& s) { return std::vector<double>{s.amplitude}; },
     [](TraceStep& s, std::vector<double> v) { s.amplitude = v.at(0); }, nullptr, nullptr},
    {"lifted_length", ColumnKind::number, 0, [](const TraceStep& s) { return std::vector<double>{s.lifted_length}; },
     [](TraceStep& s, std::vector<double> v) { s.lifted_length = v.at(0); }, nullptr, nullptr},
    {"stability", ColumnKind::text, 0, nullptr, nullptr,
     [](const TraceStep& s) { return std::string(continuation::to_string(s.stability)); },
     [](TraceStep& s, const std::string& t) {
       const std::optional<continuation::Stability> v = from_string<continuation::Stability>(t);
       if (!v) throw OutputError(fmt::format("trace file: stability '{}' is not stable, unstable or unknown", t));
       s.stability = *v;
     }},
};

#undef LIFTOFF_DESIGN_COLUMNS
#undef LIFTOFF_FIELD_COLUMN

// The nodal fields of a path: /PATH/steps/fields/ holds `coordinate` (the nodes, written once,
// with the path's first step that carries fields) and a dataset steps x nodes per field of that
// step (u only where the member has it); attribute first_step: the index of that step, the row
// of step i being i - first_step (a file begun before the fields were recorded resumes with them).
constexpr const char* fields_group = "fields";

struct FieldsLayout {
  bool present = false;
  hsize_t first_step = 0;
  std::vector<double> coordinate;
};

FieldsLayout fields_layout(hid_t id, const std::string& steps_group) {
  FieldsLayout layout;
  const std::string group = steps_group + "/" + fields_group;
  if (!path_exists(id, group)) return layout;
  layout.present = true;
  Handle g(H5Gopen2(id, group.c_str(), H5P_DEFAULT), H5Gclose, group);
  layout.first_step = static_cast<hsize_t>(read_number_attribute(g, "first_step"));
  layout.coordinate = read_doubles(id, group + "/coordinate");
  return layout;
}

// The groups a column's name runs through ("design/x": design), created under `steps` if absent.
void make_column_group(hid_t steps, const std::string& name) {
  const std::size_t slash = name.rfind('/');
  if (slash == std::string::npos) return;
  const std::string group = name.substr(0, slash);
  if (!exists(steps, group))
    Handle made(H5Gcreate2(steps, group.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, group);
}

void create_column(hid_t steps, const StepColumn& column, std::size_t samples) {
  make_column_group(steps, column.name);
  if (column.kind == ColumnKind::text) create_rows(steps, column.name, string_type(true), 0);
  if (one_number(column.kind)) create_rows(steps, column.name, H5T_IEEE_F64LE, 0);
  if (column.kind == ColumnKind::samples) create_rows(steps, column.name, H5T_IEEE_F64LE, samples);
  if (column.kind == ColumnKind::keyed) create_rows(steps, column.name, H5T_IEEE_F64LE, column.width + 1);
}

std::vector<std::string> split_paths(const std::string& joined) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (start <= joined.size() && !joined.empty()) {
    const std::size_t comma = joined.find(',', start);
    parts.push_back(joined.substr(start, comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return parts;
}

// A whole path's part of an open file, read back. Rows of a step that was being written when
// the run stopped are left out (the per-step datasets' common length counts).
TracePathRecord read_path_record(hid_t id, const std::string& name, std::size_t samples) {
  const auto steps = [&](const char* d) { return name + "/steps/" + d; };
  const auto events = [&](const char* d) { return name + "/events/" + d; };
  Handle group(H5Gopen2(id, name.c_str(), H5P_DEFAULT), H5Gclose, name);
  TracePathRecord record;
  record.complete = read_number_attribute(group, "complete") != 0.0;
  record.termination = read_string_attribute(group, "termination");
  record.message = read_string_attribute(group, "message");
  record.monitor = read_number_attribute(group, "monitor");
  const FieldsLayout fields = fields_layout(id, name + "/steps");
  const std::size_t nodes = fields.coordinate.size();
  // Every column read whole; the steps are those that every one-row-per-step column holds. A
  // column a file written by an older liftoff does not have is left at its default.
  std::vector<std::vector<double>> numbers(std::size(step_columns));
  std::vector<std::vector<std::string>> texts(std::size(step_columns));
  std::vector<bool> present(std::size(step_columns), false);
  std::size_t n = std::numeric_limits<std::size_t>::max();
  for (std::size_t c = 0; c < std::size(step_columns); ++c) {
    const StepColumn& column = step_columns[c];
    if (!path_exists(id, steps(column.name))) continue;
    present[c] = true;
    if (column.kind == ColumnKind::text) {
      texts[c] = read_strings(id, steps(column.name));
      n = std::min(n, texts[c].size());
    } else {
      numbers[c] = read_doubles(id, steps(column.name));
      if (one_number(column.kind)) n = std::min(n, numbers[c].size());
      if (column.kind == ColumnKind::samples && samples > 0) n = std::min(n, numbers[c].size() / samples);
      if (column.kind == ColumnKind::nodes && nodes > 0)
        n = std::min(n, static_cast<std::size_t>(fields.first_step) + numbers[c].size() / nodes);
    }
  }
  if (n == std::numeric_limits<std::size_t>::max()) n = 0;
  record.steps.resize(n);
  const auto written_step = [n](double step) { return step >= 0 && step < static_cast<double>(n); };  // NaN: no
  for (std::size_t c = 0; c < std::size(step_columns); ++c) {
    const StepColumn& column = step_columns[c];
    if (!present[c]) continue;
    const std::vector<double>& v = numbers[c];
    if (column.kind == ColumnKind::keyed) {
      const std::size_t row = column.width + 1;
      std::vector<std::vector<double>> per_step(n);
      for (std::size_t r = 0; r + row <= v.size(); r += row)
        if (written_step(v[r]))
          per_step[static_cast<std::size_t>(v[r])].insert(per_step[static_cast<std::size_t>(v[r])].end(),
                                                          v.begin() + static_cast<std::ptrdiff_t>(r + 1),
                                                          v.begin() + static_cast<std::ptrdiff_t>(r + row));
      for (std::size_t i = 0; i < n; ++i) column.assign(record.steps[i], std::move(per_step[i]));
    }
    for (std::size_t i = 0; i < n; ++i) {
      TraceStep& step = record.steps[i];
      if (column.kind == ColumnKind::text) column.parse(step, texts[c][i]);
      if (one_number(column.kind)) column.assign(step, {v[i]});
      if (column.kind == ColumnKind::samples)
        column.assign(step, std::vector<double>(v.begin() + static_cast<std::ptrdiff_t>(i * samples),
                                                v.begin() + static_cast<std::ptrdiff_t>((i + 1) * samples)));
      if (column.kind == ColumnKind::nodes && i >= fields.first_step) {
        const std::size_t row = i - fields.first_step;
        column.assign(step, std::vector<double>(v.begin() + static_cast<std::ptrdiff_t>(row * nodes),
                                                v.begin() + static_cast<std::ptrdiff_t>((row + 1) * nodes)));
      }
    }
  }
  if (fields.present)
    for (std::size_t i = fields.first_step; i < n; ++i) record.steps[i].fields.coordinate = fields.coordinate;
  const std::vector<double> event_lambda = read_doubles(id, events("lambda"));
  const std::vector<std::string> kinds = read_strings(id, events("kind"));
  const std::vector<double> at = read_doubles(id, events("at"));
  const std::vector<double> event_step = read_doubles(id, events("step"));
  const std::vector<std::string> descriptions = read_strings(id, events("description"));
  const std::size_t m =
      std::min({event_lambda.size(), kinds.size(), at.size(), event_step.size(), descriptions.size()});
  for (std::size_t i = 0; i < m; ++i) {
    if (!written_step(event_step[i]) || std::isnan(event_lambda[i]) || std::isnan(at[i])) continue;
    record.events.push_back({event_lambda[i], event_kind(kinds[i]), at[i], descriptions[i]});
    record.event_steps.push_back(static_cast<int>(event_step[i]));
  }
  return record;
}

// A finished step is written in full: a NaN left in one (the fill value of rows that were made
// but never written) means the file was damaged by a kill in the middle of a flush. Columns
// where NaN is a value (ColumnKind::optional_number) say nothing.
bool whole(const TracePathRecord& record) {
  const auto finite = [](const std::vector<double>& v) {
    return std::all_of(v.begin(), v.end(), [](double x) { return !std::isnan(x); });
  };
  return std::all_of(record.steps.begin(), record.steps.end(), [&](const TraceStep& s) {
    return std::all_of(std::begin(step_columns), std::end(step_columns), [&](const StepColumn& column) {
      return column.kind == ColumnKind::text || column.kind == ColumnKind::optional_number || finite(column.values(s));
    });
  });
}

TraceFileInfo read_info(hid_t id) {
  TraceFileInfo info;
  info.version = read_string_attribute(id, "liftoff_version");
  info.scene_name = read_string_attribute(id, "scene_name");
  info.coordinate = read_string_attribute(id, "coordinate");
  info.options = read_string_attribute(id, "options");
  info.paths = split_paths(read_string_attribute(id, "paths"));
  info.scene_text = read_text(id, "scene");
  info.sample_points = read_doubles(id, "sample_points");
  if (H5Aexists(id, "load_reference") > 0) {
    continuation::PhysicalLoad load;
    load.quantity = read_string_attribute(id, "load_quantity");
    load.symbol = read_string_attribute(id, "load_symbol");
    load.reference = read_number_attribute(id, "load_reference");
    load.unit = read_string_attribute(id, "load_unit");
    load.definition = read_string_attribute(id, "load_definition");
    info.physical_load = std::move(load);
  }
  return info;
}

// Tables of rows (step, ...) are appended in step order: the rows of steps >= `steps` are a tail.
void keep_rows_before_step(hid_t id, const std::string& name, hsize_t columns, hsize_t steps) {
  const std::vector<double> rows = read_doubles(id, name);
  hsize_t keep = 0;
  while (keep < rows.size() / columns && rows[keep * columns] < static_cast<double>(steps)) ++keep;
  set_rows(id, name, keep);
}

// Drops the rows of a step (and of events) whose writing was interrupted.
void trim(hid_t id, const std::string& name) {
  const auto steps = [&](const char* d) { return name + "/steps/" + d; };
  const auto events = [&](const char* d) { return name + "/events/" + d; };
  const FieldsLayout fields = fields_layout(id, name + "/steps");
  hsize_t n = row_count(id, steps("lambda"));
  for (const StepColumn& column : step_columns) {
    if (column.kind == ColumnKind::keyed || !path_exists(id, steps(column.name))) continue;
    const hsize_t rows = row_count(id, steps(column.name));
    n = std::min(n, column.kind == ColumnKind::nodes ? fields.first_step + rows : rows);
  }
  for (const StepColumn& column : step_columns) {
    if (!path_exists(id, steps(column.name))) continue;
    if (column.kind == ColumnKind::keyed)
      keep_rows_before_step(id, steps(column.name), column.width + 1, n);
    else
      set_rows(id, steps(column.name),
               column.kind != ColumnKind::nodes ? n
               : n > fields.first_step          ? n - fields.first_step
                                                : 0);
  }
  const std::array<const char*, 5> columns{"lambda", "kind", "at", "step", "description"};
  hsize_t m = row_count(id, events("step"));
  for (const char* d : columns) m = std::min(m, row_count(id, events(d)));
  for (const char* d : columns) set_rows(id, events(d), m);
  keep_rows_before_step(id, events("step"), 1, n);
  const hsize_t kept = row_count(id, events("step"));
  for (const char* d : columns) set_rows(id, events(d), kept);
}

// A path of a file written by an older liftoff, continued: each per-step column it lacks is
// made, its rows for the steps already there those of a step that records nothing of it (no
// physical load, no design values, no supports). The nodal fields begin with the next step.
void upgrade(hid_t id, const std::string& name, std::size_t samples) {
  const std::string steps = name + "/steps";
  Handle group(H5Gopen2(id, steps.c_str(), H5P_DEFAULT), H5Gclose, steps);
  const hsize_t n = row_count(id, steps + "/lambda");
  const TraceStep nothing;
  for (const StepColumn& column : step_columns) {
    if (column.kind == ColumnKind::nodes || path_exists(group, column.name)) continue;
    if (!one_number(column.kind) && column.kind != ColumnKind::keyed)
      throw OutputError(
          fmt::format("{}: no dataset {}/{} (expected a trace file of this version)", name, steps, column.name));
    create_column(group, column, samples);
    if (one_number(column.kind))
      append_doubles(group, column.name, std::vector<double>(n, column.values(nothing).at(0)), n);
  }
}

// A trace file read whole and checked; nullopt if it cannot be read or is damaged.
std::optional<TraceFileRecord> read_checked(const std::filesystem::path& path) {
  if (!std::filesystem::exists(path) || H5Fis_hdf5(path.c_str()) <= 0) return std::nullopt;
  const hid_t id = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (id < 0) return std::nullopt;
  try {
    Handle file(id, H5Fclose, path.string());
    if (H5Aexists(file, "paths") <= 0 || !exists(file, "scene")) return std::nullopt;
    TraceFileRecord record;
    record.info = read_info(file);
    record.complete = read_number_attribute(file, "complete") != 0.0;
    for (const std::string& name : record.info.paths) {
      if (!exists(file, name)) continue;
      record.paths.emplace_back(name, read_path_record(file, name, record.info.sample_points.size()));
      if (!whole(record.paths.back().second)) return std::nullopt;
    }
    return record;
  } catch (const OutputError&) {
    return std::nullopt;
  }
}

std::size_t step_count(const TraceFileRecord& record) {
  std::size_t n = 0;
  for (const auto& [name, path] : record.paths) n += path.steps.size() + path.events.size();
  return n;
}

}  // namespace

std::string state_topology_text(const continuation::StateTopology& topology) {
  if (std::holds_alternative<continuation::FeContactSet>(topology)) return fe_contact_set_text;
  const auto* ritz = std::get_if<continuation::RitzTopology>(&topology);
  if (ritz == nullptr) return "";
  std::string text = fmt::format("{} {} {}", ritz->first_in_contact ? 1 : 0, ritz->limits, ritz->modes);
  if (ritz->at_event) text += fmt::format(" event {} {}", ritz->at_event->direction, ritz->at_event->delta);
  return text;
}

continuation::StateTopology parse_state_topology(const std::string& text) {
  if (text.empty()) return std::monostate{};
  if (text == fe_contact_set_text) return continuation::FeContactSet{};
  std::istringstream words(text);
  int first = -1;
  continuation::RitzTopology ritz;
  bool whole = static_cast<bool>(words >> first >> ritz.limits >> ritz.modes) && (first == 0 || first == 1);
  ritz.first_in_contact = first == 1;
  std::string word;
  if (whole && words >> word) {
    continuation::RitzOpening opening;
    whole = word == "event" && words >> opening.direction >> opening.delta && !(words >> word);
    ritz.at_event = opening;
  }
  if (!whole)
    throw OutputError("state_topology \"" + text +
                      "\": expected \"first_in_contact limits modes [event direction delta]\" or \"" +
                      fe_contact_set_text + "\"");
  return ritz;
}

std::filesystem::path trace_backup_path(const std::filesystem::path& path) {
  std::filesystem::path backup = path;
  backup += ".backup";
  return backup;
}

// The file and its backup, written alike one after the other: a kill in the middle of one's
// flush leaves the other whole.
struct TraceWriter::File {
  struct Copy {
    std::filesystem::path path;
    hid_t id = -1;
  };
  std::filesystem::path path;
  std::array<Copy, 2> copies;
  TraceFileInfo info;
  std::size_t samples = 0;
  bool clean = true;  // no write failed: the backup goes when the file is closed
  // Each path's nodal fields layout, read once (append_step checks every step against it).
  std::map<std::string, FieldsLayout> fields;

  FieldsLayout& fields_of(const std::string& name) {
    const auto it = fields.find(name);
    if (it != fields.end()) return it->second;
    return fields[name] = fields_layout(copies[0].id, name + "/steps");
  }

  ~File() {
    for (const Copy& c : copies)
      if (c.id >= 0) H5Fclose(c.id);
    if (clean && copies[1].id >= 0) {
      std::error_code ignored;
      std::filesystem::remove(copies[1].path, ignored);
    }
  }

  // Runs `write` on each copy and flushes it; a failure is an OutputError naming the file.
  template <class Write>
  void each(Write write) {
    try {
      for (const Copy& c : copies) {
        write(c.id);
        check(H5Fflush(c.id, H5F_SCOPE_GLOBAL), c.path.string());
      }
    } catch (const OutputError& e) {
      clean = false;
      throw OutputError(path.string() + ": " + e.what());
    }
  }
};

TraceWriter::TraceWriter(std::unique_ptr<File> file) : file_(std::move(file)) {}
TraceWriter::TraceWriter(TraceWriter&&) noexcept = default;
TraceWriter::~TraceWriter() = default;

TraceWriter::TraceWriter(const std::filesystem::path& path, const TraceFileInfo& info)
    : file_(std::make_unique<File>()) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors become OutputError, not stderr noise
  File& f = *file_;
  f.path = path;
  f.info = info;
  f.samples = info.sample_points.size();
  f.copies = {File::Copy{path, -1}, File::Copy{trace_backup_path(path), -1}};
  for (File::Copy& c : f.copies) {
    c.id = H5Fcreate(c.path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    if (c.id < 0) {
      f.clean = c.path != f.copies[1].path;
      throw OutputError(c.path.string() + ": cannot create the file");
    }
  }
  f.each([&](hid_t id) {
    write_string_attribute(id, "liftoff_version", info.version);
    write_string_attribute(id, "kind", "trace");  // what `liftoff plot` draws: solve, trace or sweep
    write_string_attribute(id, "scene_name", info.scene_name);
    write_string_attribute(id, "coordinate", info.coordinate);
    write_string_attribute(id, "sign_convention", sign_convention);
    write_string_attribute(id, "options", info.options);
    std::string paths;
    for (const auto& p : info.paths) paths += (paths.empty() ? "" : ",") + p;
    write_string_attribute(id, "paths", paths);
    for (const auto& [name, label] : info.units) write_string_attribute(id, "units_" + name, label);
    if (const auto& load = info.physical_load) {
      write_string_attribute(id, "load_quantity", load->quantity);
      write_string_attribute(id, "load_symbol", load->symbol);
      write_number_attribute(id, "load_reference", load->reference);
      write_string_attribute(id, "load_unit", load->unit);
      write_string_attribute(id, "load_definition", load->definition);
    }
    write_number_attribute(id, "complete", false);
    write_text(id, "scene", info.scene_text);
    const hsize_t n = info.sample_points.size();
    Handle space(H5Screate_simple(1, &n, nullptr), H5Sclose, "sample_points");
    Handle points(H5Dcreate2(id, "sample_points", H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                  H5Dclose, "sample_points");
    check(H5Dwrite(points, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, info.sample_points.data()),
          "sample_points");
  });
}

TraceWriter TraceWriter::resume(const std::filesystem::path& path) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const std::filesystem::path backup = trace_backup_path(path);
  // The whole copy with more finished steps; then the other one made equal to it.
  const std::optional<TraceFileRecord> main = read_checked(path), spare = read_checked(backup);
  if (!main && !spare)
    throw OutputError(path.string() + ": not a liftoff trace file, or damaged (and no whole " + backup.string() + ")");
  const bool from_backup = !main || (spare && step_count(*spare) > step_count(*main));
  std::error_code error;
  std::filesystem::copy_file(from_backup ? backup : path, from_backup ? path : backup,
                             std::filesystem::copy_options::overwrite_existing, error);
  if (error) throw OutputError(path.string() + ": cannot restore the trace from its backup (" + error.message() + ")");

  auto file = std::make_unique<File>();
  file->path = path;
  file->info = from_backup ? spare->info : main->info;
  file->samples = file->info.sample_points.size();
  file->copies = {File::Copy{path, -1}, File::Copy{backup, -1}};
  for (File::Copy& c : file->copies) {
    c.id = H5Fopen(c.path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    if (c.id < 0) throw OutputError(c.path.string() + ": cannot open the file for writing");
  }
  file->each([&](hid_t id) {
    for (const std::string& name : file->info.paths)
      if (exists(id, name)) {
        trim(id, name);
        upgrade(id, name, file->samples);
      }
  });
  return TraceWriter(std::move(file));
}

const TraceFileInfo& TraceWriter::info() const { return file_->info; }

std::optional<TracePathRecord> TraceWriter::read_path(const std::string& name) const {
  const hid_t id = file_->copies[0].id;
  if (!exists(id, name)) return std::nullopt;
  try {
    return read_path_record(id, name, file_->samples);
  } catch (const OutputError& e) {
    throw OutputError(file_->path.string() + ": " + e.what());
  }
}

void TraceWriter::begin_path(const std::string& name, double monitor) {
  if (exists(file_->copies[0].id, name)) return;
  const std::size_t samples = file_->samples;
  file_->each([&](hid_t id) {
    Handle group(H5Gcreate2(id, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, name);
    write_number_attribute(group, "complete", false);
    write_number_attribute(group, "monitor", monitor);
    Handle steps(H5Gcreate2(group, "steps", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, "steps");
    for (const StepColumn& column : step_columns)
      if (column.kind != ColumnKind::nodes) create_column(steps, column, samples);
    Handle events(H5Gcreate2(group, "events", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, "events");
    for (const char* d : {"lambda", "at", "step"}) create_rows(events, d, H5T_IEEE_F64LE, 0);
    for (const char* d : {"kind", "description"}) create_rows(events, d, string_type(true), 0);
  });
}

void TraceWriter::append_step(const std::string& name, const TraceStep& step) {
  for (const StepColumn& column : step_columns)
    if (column.kind == ColumnKind::samples && column.values(step).size() != file_->samples)
      throw OutputError(fmt::format("{}: a step has {} values of {} for {} sample points", file_->path.string(),
                                    column.values(step).size(), column.name, file_->samples));
  const auto steps = [&](const char* d) { return name + "/steps/" + d; };
  // The nodal fields: the path's first step that carries them makes their group (FieldsLayout);
  // every later step must carry as many values of the same fields.
  FieldsLayout& fields = file_->fields_of(name);
  const std::size_t nodes = step.fields.coordinate.size();
  for (const StepColumn& column : step_columns) {
    if (column.kind != ColumnKind::nodes) continue;
    const std::size_t given = column.values(step).size();
    const bool stored = fields.present && path_exists(file_->copies[0].id, steps(column.name));
    const bool expected = fields.present ? stored : nodes > 0 && given > 0;
    const std::size_t width = fields.present ? fields.coordinate.size() : nodes;
    if (given != (expected ? width : 0))
      throw OutputError(fmt::format("{}: a step of path {} has {} values of {}, expected {} (one per node{})",
                                    file_->path.string(), name, given, column.name, expected ? width : 0,
                                    fields.present ? " of the path's earlier steps" : ""));
  }
  if (fields.present && nodes > 0 && step.fields.coordinate != fields.coordinate)
    throw OutputError(fmt::format("{}: a step of path {} has its fields at other nodes than the path's earlier steps",
                                  file_->path.string(), name));
  file_->each([&](hid_t id) {
    const auto index = static_cast<double>(row_count(id, steps("lambda")));
    if (!fields.present && nodes > 0) {  // this path's first step with fields
      Handle group(H5Gcreate2(id, steps(fields_group).c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose,
                   fields_group);
      write_number_attribute(group, "first_step", index);
      hdf5::write_array(group, "coordinate", step.fields.coordinate);
      Handle steps_group(H5Gopen2(id, (name + "/steps").c_str(), H5P_DEFAULT), H5Gclose, name);
      for (const StepColumn& column : step_columns)
        if (column.kind == ColumnKind::nodes && !column.values(step).empty())
          create_rows(steps_group, column.name, H5T_IEEE_F64LE, nodes);
    }
    for (const StepColumn& column : step_columns) {
      if (column.kind == ColumnKind::text) {
        append_string(id, steps(column.name), column.text(step));
        continue;
      }
      const std::vector<double> values = column.values(step);
      if (column.kind == ColumnKind::nodes) {
        if (!values.empty()) append_doubles(id, steps(column.name), values, 1);
        continue;
      }
      if (column.kind != ColumnKind::keyed) {
        append_doubles(id, steps(column.name), values, 1);
        continue;
      }
      std::vector<double> rows;
      for (std::size_t k = 0; k < values.size(); k += column.width) {
        rows.push_back(index);
        rows.insert(rows.end(), values.begin() + static_cast<std::ptrdiff_t>(k),
                    values.begin() + static_cast<std::ptrdiff_t>(k + column.width));
      }
      append_doubles(id, steps(column.name), rows, values.size() / column.width);
    }
  });
  if (!fields.present && nodes > 0) fields = fields_layout(file_->copies[0].id, name + "/steps");
}

void TraceWriter::append_event(const std::string& name, const TraceEvent& event) {
  const auto events = [&](const char* d) { return name + "/events/" + d; };
  file_->each([&](hid_t id) {
    const auto steps = static_cast<double>(row_count(id, name + "/steps/lambda"));
    append_doubles(id, events("lambda"), {event.load_factor}, 1);
    append_string(id, events("kind"), std::string(continuation::to_string(event.kind)));
    append_doubles(id, events("at"), {event.at}, 1);
    append_string(id, events("description"), event.description);
    append_doubles(id, events("step"), {std::max(0.0, steps - 1)}, 1);
  });
}

void TraceWriter::end_path(const std::string& name, const continuation::TraceSummary& summary) {
  file_->each([&](hid_t id) {
    Handle group(H5Gopen2(id, name.c_str(), H5P_DEFAULT), H5Gclose, name);
    write_string_attribute(group, "termination", std::string(continuation::to_string(summary.termination)));
    write_string_attribute(group, "message", summary.message);
    write_number_attribute(group, "complete", summary.termination == continuation::TraceTermination::completed);
  });
}

void TraceWriter::finish() {
  file_->each([&](hid_t id) { write_number_attribute(id, "complete", true); });
}

TraceFileRecord read_trace_file(const std::filesystem::path& path) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  if (std::optional<TraceFileRecord> record = read_checked(path)) return *record;
  // A run killed in the middle of the file's flush: its backup is whole.
  if (std::optional<TraceFileRecord> record = read_checked(trace_backup_path(path))) return *record;
  throw OutputError(path.string() + ": not a liftoff trace file, or damaged");
}

}  // namespace liftoff::io
