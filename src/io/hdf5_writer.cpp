#include "io/hdf5_writer.hpp"

#include <fmt/format.h>
#include <hdf5.h>

#include <cmath>
#include <system_error>

#include "core/error.hpp"
#include "io/hdf5_attributes.hpp"
#include "io/hdf5_handle.hpp"
#include "io/hdf5_units.hpp"

namespace liftoff::io {

namespace {

using hdf5::check;
using hdf5::Handle;
using hdf5::write_array;
using hdf5::write_number_attribute;
using hdf5::write_string_attribute;
using hdf5::write_text;

void write_table(hid_t file, const char* group_name, const FieldTable& t) {
  hdf5::write_columns(file, group_name,
                      {{"coordinate", &t.coordinate},
                       {"w", &t.w},
                       {"u", &t.u},
                       {"rotation", &t.rotation},
                       {"bending_moment", &t.bending_moment},
                       {"shear_force", &t.shear_force},
                       {"normal_force", &t.normal_force},
                       {"reaction", &t.reaction},
                       {"w_initial", &t.w_initial},
                       {"buckling_mode", &t.buckling_mode}},
                      hdf5::EmptyColumns::skip);
}

// /certificate (attributes: passed, message, the resultants, <check> and <check>_tolerance per
// check) and /support_reactions (rows at, force, moment; arches also tangential, horizontal,
// vertical).
void write_certificate(hid_t file, const SolveReport& r) {
  const certify::Certificate& c = *r.certificate;
  const certify::UserFigures& u = r.certificate_figures;
  Handle group(H5Gcreate2(file, "certificate", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, "certificate");
  write_number_attribute(group, "passed", static_cast<int>(c.passed));
  write_string_attribute(group, "message", c.message);
  write_number_attribute(group, "foundation_resultant", u.foundation_resultant);
  write_number_attribute(group, "foundation_centroid", u.foundation_centroid);
  write_number_attribute(group, "applied_force", u.applied_force);
  write_number_attribute(group, "applied_moment", u.applied_moment);
  if (r.kind == scene::StructureKind::arch) {
    write_number_attribute(group, "foundation_resultant_x", u.foundation_resultant_x);
    write_number_attribute(group, "applied_force_x", u.applied_force_x);
  }
  for (const certify::Check& check : c.checks) {
    write_number_attribute(group, check.name, check.value);
    write_number_attribute(group, check.name + "_tolerance", check.tolerance);
  }
  // Arches: the tangential reaction, then horizontal and vertical; von Karman beams: the
  // horizontal (axial) one, along +x.
  const bool arch = r.kind == scene::StructureKind::arch, fourth = arch || r.theory == "von_karman";
  std::vector<double> rows;
  for (const certify::SupportReaction& s : u.support_reactions) {
    rows.insert(rows.end(), {s.at, s.force, s.moment});
    if (fourth) rows.push_back(s.tangential);
    if (arch) {
      const certify::HorizontalVertical hv = user_arch_components(s, r.foundation_outside);
      rows.insert(rows.end(), {hv.horizontal, hv.vertical});
    }
  }
  write_array(file, "support_reactions", rows, arch ? 6 : fourth ? 4 : 3);
}

// /design (attributes: <name> and <name>_at for moment_max, moment_min, shear_max_abs,
// pressure_max, uplift_max, NaN where there is no such point; from_statics; shear_closure and
// moment_closure, -1 when not from statics).
void write_design(hid_t file, const DesignTable& t) {
  Handle group(H5Gcreate2(file, "design", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, "design");
  const std::pair<const char*, const DesignValue*> values[] = {{"moment_max", &t.moment_max},
                                                               {"moment_min", &t.moment_min},
                                                               {"shear_max_abs", &t.shear_max_abs},
                                                               {"pressure_max", &t.pressure_max},
                                                               {"uplift_max", &t.uplift_max}};
  for (const auto& [name, v] : values) {
    write_number_attribute(group, name, v->value);
    write_number_attribute(group, std::string(name) + "_at", v->at.value_or(std::nan("")));
  }
  write_number_attribute(group, "from_statics", static_cast<int>(t.from_statics));
  write_number_attribute(group, "shear_closure", t.shear_closure);
  write_number_attribute(group, "moment_closure", t.moment_closure);
}

// scale_<figure> (post/scale.hpp; the stiffest piece's, with _min companions when the modulus
// varies) and warnings (one per line, empty when none).
void write_scale(hid_t object, const SolveReport& r) {
  write_string_attribute(object, "warnings", fmt::format("{}", fmt::join(r.warnings, "\n")));
  if (!r.scale) return;
  const post::ScaleFigures& f = *r.scale;
  write_number_attribute(object, "scale_nondimensional_k", f.k_max);
  write_number_attribute(object, "scale_K", f.K_max);
  write_number_attribute(object, "scale_beta", f.beta_max);
  write_number_attribute(object, "scale_beta_L", f.beta_length_max);
  write_number_attribute(object, "scale_characteristic_length", 1 / f.beta_max);
  if (f.beta_h >= 0) write_number_attribute(object, "scale_beta_h", f.beta_h);
  if (f.varies()) {
    write_number_attribute(object, "scale_nondimensional_k_min", f.k_min);
    write_number_attribute(object, "scale_K_min", f.K_min);
    write_number_attribute(object, "scale_beta_min", f.beta_min);
    write_number_attribute(object, "scale_beta_L_min", f.beta_length_min);
    write_number_attribute(object, "scale_characteristic_length_max", 1 / f.beta_min);
  }
}

// One report under `file` (the file's root, or a group of a sweep).
void write_report(hid_t file, const SolveReport& r) {
  write_string_attribute(file, "scene_name", r.scene_name);
  write_string_attribute(file, "structure", std::string(scene::to_string(r.kind)));
  write_string_attribute(file, "method", r.method);
  write_string_attribute(file, "method_requested", r.method_requested);
  write_string_attribute(file, "termination", r.termination);
  write_string_attribute(file, "message", r.message);
  write_string_attribute(file, "coordinate", r.coordinate_name);
  write_string_attribute(file, "sign_convention", sign_convention);
  write_number_attribute(file, "tensionless", static_cast<int>(r.tensionless));
  write_number_attribute(file, "k", r.k);
  write_string_attribute(file, "theory", r.theory);
  if (r.stable) write_number_attribute(file, "stable", static_cast<int>(*r.stable));
  if (!r.membrane_force.empty()) {  // von Karman beams: rows (at, N) per element, tension positive
    std::vector<double> rows;
    for (std::size_t e = 0; e < r.membrane_force.size(); ++e)
      rows.insert(rows.end(), {r.membrane_force_at[e], r.membrane_force[e]});
    write_array(file, "membrane_force", rows, 2);
  }
  write_units(file, r.units);
  write_scale(file, r);

  write_text(file, "scene", r.scene_text);

  std::vector<double> regions;
  for (const ContactRegion& region : r.contact_regions) regions.insert(regions.end(), {region.begin, region.end});
  write_array(file, "contact_regions", regions, 2);
  write_table(file, "fields", r.fields);

  if (!r.nodes.coordinate.empty()) write_table(file, "nodes", r.nodes);

  if (r.certificate) write_certificate(file, r);
  if (const auto& t = r.stability) {  // the critical load (io/report.hpp's StabilityTable)
    Handle group(H5Gcreate2(file, "stability", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, "stability");
    write_string_attribute(group, "stability", t->stability);
    write_number_attribute(group, "critical_load_factor", t->critical_load_factor);
    write_number_attribute(group, "critical_axial_force", t->critical_axial_force);
    write_number_attribute(group, "lower_bound", t->lower_bound);
    write_number_attribute(group, "upper_bound", t->upper_bound);
    write_string_attribute(group, "method", t->method);
    write_string_attribute(group, "termination", t->termination);
    write_string_attribute(group, "message", t->message);
    write_string_attribute(group, "warning", t->warning);
  }
  if (const auto& c = r.no_equilibrium_certificate) {  // Lemke's ray: the proof of no equilibrium
    Handle group(H5Gcreate2(file, "no_equilibrium_certificate", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose,
                 "no_equilibrium_certificate");
    write_string_attribute(group, "kind", "lemke_ray");
    write_string_attribute(group, "formulation", c->formulation);
    write_number_attribute(group, "q_dot_ray", c->q_dot_ray);
    write_array(group, "ray", c->ray);
  }
  if (r.design) write_design(file, *r.design);

  Handle solver(H5Gcreate2(file, "solver", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, "solver");
  write_number_attribute(solver, "residual", r.residual);
  write_number_attribute(solver, "time_s", r.time_s);
  write_string_attribute(solver, "method_reason", r.method_reason);
  if (r.elements >= 0) {
    write_number_attribute(solver, "elements", r.elements);
    write_number_attribute(solver, "pivots", r.pivots);
    write_number_attribute(solver, "lcp_size", r.lcp_size);
  }
  if (r.modes >= 0) {
    write_number_attribute(solver, "modes", r.modes);
    write_number_attribute(solver, "newton_iterations", r.newton_iterations);
    write_number_attribute(solver, "estimated_limit_error", r.estimated_limit_error);
    write_string_attribute(solver, "topology", r.topology);
    write_array(solver, "amplitudes", r.amplitudes);
    write_array(solver, "residual_history", r.residual_history);
  }
  if (r.tolerance >= 0) {
    write_number_attribute(solver, "tolerance", r.tolerance);
    write_number_attribute(solver, "round_off_floor", r.round_off_floor);
    if (r.elements >= 0) {
      const std::pair<const char*, double> estimates[] = {{"estimated_limit_error", r.estimated_limit_error},
                                                          {"estimated_w_error", r.estimated_w_error},
                                                          {"estimated_reaction_error", r.estimated_reaction_error},
                                                          {"observed_order", r.observed_order}};
      for (const auto& [name, value] : estimates) write_number_attribute(solver, name, value);
      write_number_attribute(solver, "limit_fitted", r.limit_fitted ? 1 : 0);
      write_array(solver, "elements_used",
                  std::vector<double>(r.refinement_elements.begin(), r.refinement_elements.end()));
    }
  }
}

void write_file(const SolveReport& r, const std::filesystem::path& path, const std::string& version) {
  Handle file(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose, path.string());
  write_string_attribute(file, "liftoff_version", version);
  write_string_attribute(file, "kind", "solve");  // what `liftoff plot` draws: solve, trace or sweep
  write_report(file, r);
}

// A sweep file's root: attributes liftoff_version, kind, keys and the units; dataset /values.
Handle write_sweep_root(const std::vector<std::string>& keys, const std::vector<SweepCase>& cases,
                        const std::filesystem::path& path, const std::string& version) {
  Handle file(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose, path.string());
  write_string_attribute(file, "liftoff_version", version);
  write_string_attribute(file, "kind", "sweep");
  std::string joined;
  for (const auto& key : keys) joined += (joined.empty() ? "" : ",") + key;
  write_string_attribute(file, "keys", joined);
  std::vector<double> values;
  for (const SweepCase& c : cases) values.insert(values.end(), c.values.begin(), c.values.end());
  write_array(file, "values", values, keys.size());
  // The scene's units (labels only, the same for every case): from any case's report.
  for (const SweepCase& c : cases)
    if (!c.reports.empty()) {
      write_units(file, c.reports.front().units);
      break;
    }
  return file;
}

// One case under `group` (/cases/NNNN): its error attribute, a group per method.
void write_sweep_case(hid_t group, const SweepCase& c) {
  if (!c.error.empty()) write_string_attribute(group, "error", c.error);
  for (const SolveReport& r : c.reports) {
    // Keyed by the method asked for: a fallback's answer stays under its own request's name.
    const std::string& name = r.method_requested.empty() ? r.method : r.method_requested;
    Handle method(H5Gcreate2(group, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, name);
    write_report(method, r);
  }
}

std::string case_name(std::size_t i) { return fmt::format("{:04d}", i); }

void write_sweep_file(const std::vector<std::string>& keys, const std::vector<SweepCase>& cases,
                      const std::filesystem::path& path, const std::string& version) {
  const Handle file = write_sweep_root(keys, cases, path, version);
  Handle all(H5Gcreate2(file, "cases", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, "cases");
  for (std::size_t i = 0; i < cases.size(); ++i) {
    Handle group(H5Gcreate2(all, case_name(i).c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, case_name(i));
    write_sweep_case(group, cases[i]);
  }
}

// The in-memory files of sweep_case_image: HDF5's core driver, no file on disk.
Handle memory_file_access(const std::vector<char>* image) {
  Handle access(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "file access list");
  check(H5Pset_fapl_core(access, 1 << 16, 0), "in-memory file driver");
  if (image != nullptr) check(H5Pset_file_image(access, const_cast<char*>(image->data()), image->size()), "file image");
  return access;
}

void write_sweep_file(const std::vector<std::string>& keys, const std::vector<SweepCase>& cases,
                      const std::vector<std::vector<char>>& images, const std::filesystem::path& path,
                      const std::string& version) {
  if (images.size() != cases.size())
    throw OutputError(fmt::format("{} case images for {} cases", images.size(), cases.size()));
  const Handle file = write_sweep_root(keys, cases, path, version);
  Handle all(H5Gcreate2(file, "cases", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, "cases");
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const Handle access = memory_file_access(&images[i]);
    Handle image(H5Fopen(("case_image_" + case_name(i)).c_str(), H5F_ACC_RDONLY, access), H5Fclose, case_name(i));
    check(H5Ocopy(image, "case", all, case_name(i).c_str(), H5P_DEFAULT, H5P_DEFAULT), case_name(i).c_str());
  }
}

// Writes under a temporary name, renames when complete; removes the temporary on failure.
template <typename Write>
void write_atomically(const std::filesystem::path& path, Write write) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors become OutputError, not stderr noise
  const std::filesystem::path temporary = temporary_path(path);
  try {
    write(temporary);
    std::error_code error;
    std::filesystem::rename(temporary, path, error);
    if (error) throw OutputError(path.string() + ": cannot rename the finished file (" + error.message() + ")");
  } catch (const OutputError& e) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw OutputError(path.string() + ": " + e.what());
  }
}

}  // namespace

void write_units(hid_t object, const scene::Units& units) {
  write_string_attribute(object, "units_system", units.system);
  for (const auto& [name, label] : scene::unit_labels(units)) write_string_attribute(object, "units_" + name, label);
}

std::filesystem::path temporary_path(const std::filesystem::path& path) {
  std::filesystem::path temporary = path;
  temporary += ".tmp";
  return temporary;
}

void write_hdf5(const SolveReport& report, const std::filesystem::path& path, const std::string& version) {
  write_atomically(path, [&](const std::filesystem::path& temporary) { write_file(report, temporary, version); });
}

void write_sweep_hdf5(const std::vector<std::string>& keys, const std::vector<SweepCase>& cases,
                      const std::filesystem::path& path, const std::string& version) {
  write_atomically(path,
                   [&](const std::filesystem::path& temporary) { write_sweep_file(keys, cases, temporary, version); });
}

std::vector<char> sweep_case_image(const SweepCase& c) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const Handle access = memory_file_access(nullptr);
  Handle file(H5Fcreate("case_image", H5F_ACC_EXCL, H5P_DEFAULT, access), H5Fclose, "case image");
  {
    Handle group(H5Gcreate2(file, "case", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, "case");
    write_sweep_case(group, c);
  }
  check(H5Fflush(file, H5F_SCOPE_GLOBAL), "case image");
  const ssize_t size = H5Fget_file_image(file, nullptr, 0);
  if (size < 0) throw OutputError("case image: cannot take the in-memory file's image");
  std::vector<char> image(static_cast<std::size_t>(size));
  if (H5Fget_file_image(file, image.data(), image.size()) != size)
    throw OutputError("case image: cannot copy the in-memory file's image");
  return image;
}

void write_sweep_hdf5(const std::vector<std::string>& keys, const std::vector<SweepCase>& cases,
                      const std::vector<std::vector<char>>& images, const std::filesystem::path& path,
                      const std::string& version) {
  write_atomically(
      path, [&](const std::filesystem::path& temporary) { write_sweep_file(keys, cases, images, temporary, version); });
}

}  // namespace liftoff::io
