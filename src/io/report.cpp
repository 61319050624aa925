#include "io/report.hpp"

#include <algorithm>
#include <fmt/format.h>

namespace liftoff::io {

using scene::StructureKind;

namespace {

std::vector<double> scaled(const std::vector<double>& values, double factor) {
  std::vector<double> out(values.size());
  std::transform(values.begin(), values.end(), out.begin(), [&](double v) { return v * factor; });
  return out;
}

std::vector<double> to_user(const fe::MemberModel& model, const std::vector<double>& s) {
  std::vector<double> out(s.size());
  std::transform(s.begin(), s.end(), out.begin(), [&](double v) { return model.user_from_s(v); });
  return out;
}

}  // namespace

SolveReport make_report(const scene::Scene& scene, const fe::MemberModel& model, const fe::Discretisation& d,
                        const contact::ContactSolution& solution, const post::Fields& fields,
                        const std::vector<post::Interval>& regions) {
  const fe::Scales& scales = model.scales;
  SolveReport r;
  r.scene_name = scene.source_name;
  r.scene_text = scene.text;
  r.kind = model.kind;
  r.coordinate_name = model.kind == StructureKind::beam ? "x" : "theta_deg";
  r.tensionless = model.tensionless;
  r.foundation_parameter = model.foundation_modulus;
  r.elements = d.mesh.elements();
  r.summary = solution.summary;
  r.gauge_note = d.gauge_note;
  for (const auto& region : regions) r.contact_regions.push_back({model.user_from_s(region.begin), model.user_from_s(region.end)});

  FieldTable& f = r.fields;
  f.coordinate = to_user(model, fields.s);
  f.w = scaled(fields.w, scales.displacement());
  f.u = scaled(fields.u, scales.displacement());
  f.rotation = fields.rotation;
  f.bending_moment = scaled(fields.bending_moment, scales.moment());
  f.shear_force = scaled(fields.shear_force, scales.force());
  f.normal_force = scaled(fields.normal_force, scales.force());
  f.reaction = scaled(fields.reaction, scales.force_per_length());

  const auto [lowest, highest] = std::minmax_element(f.w.begin(), f.w.end());
  r.w_max = *highest;
  r.at_w_max = f.coordinate[highest - f.w.begin()];
  r.w_min = *lowest;
  r.at_w_min = f.coordinate[lowest - f.w.begin()];

  FieldTable& n = r.nodes;
  n.coordinate = to_user(model, d.mesh.nodes);
  n.reaction.assign(d.mesh.nodes.size(), 0.0);
  for (int i = 0; i < d.reactions(); ++i) n.reaction[d.reaction_nodes[i]] = solution.reaction[i] * scales.force_per_length();
  for (int node = 0; node < static_cast<int>(d.mesh.nodes.size()); ++node) {
    const double w = solution.displacement[d.deflection_dof(node)], slope = solution.displacement[d.slope_dof(node)];
    const double u = model.kind == StructureKind::arch ? solution.displacement[d.tangential_dof(node)] : 0.0;
    n.w.push_back(w * scales.displacement());
    n.rotation.push_back(model.kind == StructureKind::arch ? -(u + slope) : -slope);
    if (model.kind == StructureKind::arch) n.u.push_back(u * scales.displacement());
  }
  r.max_reaction = n.reaction.empty() ? 0.0 : *std::max_element(n.reaction.begin(), n.reaction.end());
  return r;
}

nlohmann::json to_json(const SolveReport& r) {
  nlohmann::json j;
  j["scene"] = r.scene_name;
  j["structure"] = scene::to_string(r.kind);
  j["method"] = scene::to_string(r.summary.method);
  if (!r.summary.method_reason.empty()) j["method_reason"] = r.summary.method_reason;
  j["termination"] = contact::to_string(r.summary.termination);
  j["message"] = r.summary.message;
  j["coordinate"] = r.coordinate_name;
  j["tensionless"] = r.tensionless;
  j["k"] = r.foundation_parameter;
  j["contact_regions"] = r.contact_regions;
  j["w_max"] = r.w_max;
  j["at_w_max"] = r.at_w_max;
  j["w_min"] = r.w_min;
  j["at_w_min"] = r.at_w_min;
  j["max_reaction"] = r.max_reaction;
  j["pivots"] = r.summary.pivots;
  j["lcp_size"] = r.summary.lcp_size;
  j["residual"] = r.summary.residual;
  j["elements"] = r.elements;
  j["time_s"] = r.time_s;
  j["sign_convention"] = sign_convention;
  if (!r.gauge_note.empty()) j["gauge"] = r.gauge_note;
  return j;
}

std::string text_summary(const SolveReport& r) {
  const bool arch = r.kind == StructureKind::arch;
  const char* unit = arch ? " deg" : "";
  std::string out = fmt::format("liftoff: {} ({}), {} on a {} foundation, k = {:.6g}\n", r.scene_name,
                                scene::to_string(r.kind), r.elements == 1 ? "1 element" : fmt::format("{} elements", r.elements),
                                r.tensionless ? "tensionless" : "bilateral", r.foundation_parameter);
  out += fmt::format("  method        {}{}\n", scene::to_string(r.summary.method),
                     r.summary.method_reason.empty() ? "" : " (" + r.summary.method_reason + ")");
  out += fmt::format("  result        {}: {}\n", contact::to_string(r.summary.termination), r.summary.message);
  if (r.contact_regions.empty()) out += "  contact       none\n";
  for (const auto& region : r.contact_regions)
    out += fmt::format("  contact       {} = {:.8g}{} .. {:.8g}{}\n", arch ? "theta" : "x", region[0], unit, region[1], unit);
  out += fmt::format("  w max         {:.6e} at {:.6g}{}\n", r.w_max, r.at_w_max, unit);
  out += fmt::format("  w min         {:.6e} at {:.6g}{}\n", r.w_min, r.at_w_min, unit);
  out += fmt::format("  max reaction  {:.6e} (force per unit length)\n", r.max_reaction);
  out += fmt::format("  solver        {} pivots, residual {:.1e}, {:.3f} s\n", r.summary.pivots, r.summary.residual, r.time_s);
  if (!r.gauge_note.empty()) out += "  note          " + r.gauge_note + "\n";
  out += "  sign          w > 0 into the foundation\n";
  return out;
}

}  // namespace liftoff::io
