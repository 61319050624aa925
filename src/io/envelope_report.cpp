#include "io/envelope_report.hpp"

#include <fmt/format.h>
#include <hdf5.h>

#include <cmath>
#include <limits>
#include <system_error>

#include "core/error.hpp"
#include "io/hdf5_attributes.hpp"
#include "io/hdf5_handle.hpp"
#include "io/hdf5_units.hpp"
#include "io/hdf5_writer.hpp"

namespace liftoff::io {

std::string EnvelopeCase::label() const {
  const std::string at = position ? fmt::format("lead at {:g}", *position) : "";
  if (combination.empty()) return at.empty() ? "loads" : at;
  return at.empty() ? combination : combination + ", " + at;
}

int EnvelopeReport::failed_cases() const {
  int failed = 0;
  for (const EnvelopeCase& c : cases) failed += c.passed() ? 0 : 1;
  return failed;
}

int EnvelopeReport::contact_sets() const {
  int sets = 0;
  for (const EnvelopeCase& c : cases) sets += std::max(c.report.active_set_iterations, 0);
  return sets;
}

int EnvelopeReport::factorisations() const {
  int count = 0;
  for (const EnvelopeCase& c : cases) count += std::max(c.report.factorisations, 0);
  return count;
}

namespace {

// The extremes in the order of the summary and JSON, with their names.
std::vector<std::pair<const char*, const Extreme*>> extremes(const EnvelopeReport& r) {
  const EnvelopeReport::Design& d = r.design;
  return {{"moment_max", &d.moment_max},     {"moment_min", &d.moment_min}, {"shear_max_abs", &d.shear_max_abs},
          {"pressure_max", &d.pressure_max}, {"uplift_max", &d.uplift_max}, {"w_max", &d.w_max}};
}

nlohmann::json optional_number(const std::optional<double>& x) { return x ? nlohmann::json(*x) : nlohmann::json(); }

}  // namespace

nlohmann::json to_json(const EnvelopeReport& r) {
  nlohmann::json j;
  j["kind"] = "envelope";
  j["scene"] = r.scene_name;
  j["coordinate"] = r.coordinate_name;
  j["sign_convention"] = sign_convention;
  j["tensionless"] = r.tensionless;
  j["units"] = units_json(r.units);
  j["complete"] = r.complete();
  j["failed_cases"] = r.failed_cases();
  j["warm_start"] = r.warm_start;
  j["contact_sets"] = r.contact_sets();
  j["factorisations"] = r.factorisations();
  nlohmann::json cases = nlohmann::json::array();
  for (const EnvelopeCase& c : r.cases) {
    nlohmann::json one;
    one["label"] = c.label();
    one["combination"] = c.combination.empty() ? nlohmann::json() : nlohmann::json(c.combination);
    one["position"] = optional_number(c.position);
    one["certified"] = c.passed();
    one["termination"] = c.error.empty() ? c.report.termination : std::string(to_string(SolveOutcome::refused));
    one["message"] = c.error.empty() ? c.report.message : c.error;
    one["contact_regions"] = contact_regions_json(c.report.contact_regions);
    one["warm_started"] = c.warm_started;
    if (c.report.active_set_iterations >= 0) one["contact_sets"] = c.report.active_set_iterations;
    if (c.report.factorisations >= 0) one["factorisations"] = c.report.factorisations;
    if (c.passed()) {
      one["w_max"] = c.report.w_max;
      one["max_reaction"] = c.report.max_reaction;
    }
    cases.push_back(std::move(one));
  }
  j["cases"] = std::move(cases);
  nlohmann::json design;
  for (const auto& [name, e] : extremes(r)) {
    if (e->governing < 0) {
      design[name] = nullptr;
      continue;
    }
    const EnvelopeCase& c = r.cases[e->governing];
    design[name] = {{"value", e->value},
                    {"at", e->at},
                    {"governing", c.label()},
                    {"combination", c.combination.empty() ? nlohmann::json() : nlohmann::json(c.combination)},
                    {"position", optional_number(c.position)}};
  }
  j["design"] = std::move(design);
  j["envelope"] = {{"coordinate", r.coordinate},
                   {"w_max", r.w_max},
                   {"w_min", r.w_min},
                   {"pressure_max", r.pressure_max},
                   {"pressure_min", r.pressure_min},
                   {"moment_max", r.moment_max},
                   {"moment_min", r.moment_min},
                   {"shear_max", r.shear_max},
                   {"shear_min", r.shear_min}};
  return j;
}

std::string text_summary(const EnvelopeReport& r) {
  std::string s = fmt::format("liftoff envelope: {}\n", r.scene_name);
  s += fmt::format("  cases         {} solved, {} certified{}\n", r.cases.size(), r.cases.size() - r.failed_cases(),
                   r.complete() ? "" : fmt::format(" (INCOMPLETE: {} failed, listed below)", r.failed_cases()));
  const bool arch = r.coordinate_name != "x";
  const auto with_unit = [](const std::string& label) { return label.empty() ? label : " " + label; };
  const std::string at_unit = arch ? "" : with_unit(r.units.length);
  for (const auto& [name, e] : extremes(r)) {
    if (e->governing < 0) continue;
    const std::string_view n = name;
    const std::string unit = n.starts_with("moment")     ? r.units.moment()
                             : n.starts_with("shear")    ? r.units.force
                             : n.starts_with("pressure") ? r.units.distributed_force()
                                                         : r.units.length;
    s += fmt::format("  {:<13} {} at {} = {:.6g}{}, governed by {}\n", name,
                     fmt::format("{:.6g}{}", e->value, with_unit(unit)), r.coordinate_name, e->at, at_unit,
                     r.cases[e->governing].label());
  }
  int warm = 0;
  for (const EnvelopeCase& c : r.cases) warm += c.warm_started ? 1 : 0;
  if (r.contact_sets() > 0)
    s += fmt::format(
        "  work          {} contact sets, {} factorisations over {} cases ({:.2f} sets per case; {} warm-started "
        "from the previous position{})\n",
        r.contact_sets(), r.factorisations(), r.cases.size(), double(r.contact_sets()) / r.cases.size(), warm,
        r.warm_start ? "" : ": warm start off");
  // The lift-off map: the contact regions of every case.
  s += "  contact regions by case:\n";
  for (const EnvelopeCase& c : r.cases) {
    std::string regions;
    for (const ContactRegion& region : c.report.contact_regions)
      regions += fmt::format("{}{:.4g}..{:.4g}", regions.empty() ? "" : ", ", region.begin, region.end);
    if (!c.passed())
      regions = fmt::format("FAILED ({}): {}",
                            c.error.empty() ? c.report.termination : std::string(to_string(SolveOutcome::refused)),
                            c.error.empty() ? c.report.message : c.error);
    else if (regions.empty())
      regions = "none";
    s += fmt::format("    {:<24} {}\n", c.label(), regions);
  }
  return s;
}

namespace {

using hdf5::check;
using hdf5::Handle;
using hdf5::write_array;
using hdf5::write_number_attribute;
using hdf5::write_string_attribute;

void write_file(const EnvelopeReport& r, const std::filesystem::path& path, const std::string& version) {
  Handle file(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose, path.string());
  write_string_attribute(file, "kind", "envelope");
  write_string_attribute(file, "liftoff_version", version);
  write_string_attribute(file, "scene_name", r.scene_name);
  write_string_attribute(file, "coordinate", r.coordinate_name);
  write_string_attribute(file, "sign_convention", sign_convention);
  write_number_attribute(file, "complete", r.complete() ? 1.0 : 0.0);
  write_number_attribute(file, "warm_start", r.warm_start ? 1.0 : 0.0);
  write_units(file, r.units);
  {
    Handle type(H5Tcopy(H5T_C_S1), H5Tclose, "string type");
    check(H5Tset_size(type, H5T_VARIABLE), "scene");
    check(H5Tset_cset(type, H5T_CSET_UTF8), "scene");
    Handle space(H5Screate(H5S_SCALAR), H5Sclose, "dataspace");
    Handle dataset(H5Dcreate2(file, "scene", type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose, "scene");
    const char* text = r.scene_text.c_str();
    check(H5Dwrite(dataset, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, &text), "scene");
  }
  hdf5::write_columns(file, "envelope",
                      {{"coordinate", &r.coordinate},
                       {"w_max", &r.w_max},
                       {"w_min", &r.w_min},
                       {"pressure_max", &r.pressure_max},
                       {"pressure_min", &r.pressure_min},
                       {"moment_max", &r.moment_max},
                       {"moment_min", &r.moment_min},
                       {"shear_max", &r.shear_max},
                       {"shear_min", &r.shear_min}},
                      hdf5::EmptyColumns::write);
  {
    Handle group(H5Gcreate2(file, "extremes", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, "extremes");
    for (const auto& [name, e] : extremes(r)) {
      if (e->governing < 0) continue;
      write_number_attribute(group, std::string(name) + "_value", e->value);
      write_number_attribute(group, std::string(name) + "_at", e->at);
      write_string_attribute(group, std::string(name) + "_governing", r.cases[e->governing].label());
      write_number_attribute(group, std::string(name) + "_case", e->governing);
    }
  }
  {
    Handle group(H5Gcreate2(file, "cases", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, "cases");
    std::vector<double> position, certified, sets, factorisations, regions;
    for (std::size_t k = 0; k < r.cases.size(); ++k) {
      const EnvelopeCase& c = r.cases[k];
      position.push_back(c.position.value_or(std::numeric_limits<double>::quiet_NaN()));
      certified.push_back(c.passed() ? 1.0 : 0.0);
      sets.push_back(c.report.active_set_iterations);
      factorisations.push_back(c.report.factorisations);
      write_string_attribute(group, fmt::format("label_{:04d}", k), c.label());
      write_string_attribute(group, fmt::format("termination_{:04d}", k),
                             c.error.empty() ? c.report.termination : std::string(to_string(SolveOutcome::refused)));
      write_string_attribute(group, fmt::format("message_{:04d}", k), c.error.empty() ? c.report.message : c.error);
      if (c.passed())
        for (const ContactRegion& region : c.report.contact_regions)
          regions.insert(regions.end(), {double(k), region.begin, region.end});
    }
    write_array(group, "position", position);
    write_array(group, "certified", certified);
    write_array(group, "contact_sets", sets);
    write_array(group, "factorisations", factorisations);
    // Each certified combination's own samples, for pictures of every case beside the envelope;
    // not a moving load's positions (hundreds of cases, megabytes each hundred: the envelopes say it).
    Handle fields(H5Gcreate2(group, "fields", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, "fields");
    for (std::size_t k = 0; k < r.cases.size(); ++k) {
      const FieldTable& f = r.cases[k].report.fields;
      if (!r.cases[k].passed() || r.cases[k].position || f.coordinate.empty()) continue;
      const std::string name = fmt::format("{:04d}", k);
      Handle one(H5Gcreate2(fields, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, name);
      write_array(one, "coordinate", f.coordinate);
      write_array(one, "w", f.w);
      write_array(one, "reaction", f.reaction);
      write_array(one, "bending_moment", f.bending_moment);
      write_array(one, "shear_force", f.shear_force);
    }
    Handle map(H5Gcreate2(file, "liftoff_map", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, "liftoff_map");
    write_array(map, "regions", regions, 3);
  }
}

}  // namespace

void write_envelope_hdf5(const EnvelopeReport& r, const std::filesystem::path& path, const std::string& version) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors become OutputError, not stderr noise
  const std::filesystem::path temporary = temporary_path(path);
  try {
    write_file(r, temporary, version);
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw;
  }
  std::error_code error;
  std::filesystem::rename(temporary, path, error);
  if (error) {
    std::filesystem::remove(temporary, error);
    throw OutputError(fmt::format("{}: cannot write the envelope file ({})", path.string(), error.message()));
  }
}

}  // namespace liftoff::io
