#include "io/report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "post/ritz_fields.hpp"

namespace liftoff::io {

namespace {
constexpr EnumName<SolveOutcome> solve_outcome_names[] = {
    {SolveOutcome::ran, "ran"},
    {SolveOutcome::refused, "refused"},
};
}  // namespace

std::string_view to_string(SolveOutcome outcome) { return name_in<SolveOutcome>(solve_outcome_names, outcome); }

using scene::StructureKind;

namespace {

std::vector<double> to_user(const model::MemberModel& model, const std::vector<double>& s) {
  std::vector<double> out(s.size());
  std::transform(s.begin(), s.end(), out.begin(), [&](double v) { return model.user_from_s(v); });
  return out;
}

// What every method shares: the scene, fields in user units, extremes, contact regions.
SolveReport common_report(const scene::Scene& scene, const model::MemberModel& model, const post::Fields& fields,
                          const std::vector<ContactRegion>& regions) {
  SolveReport r;
  r.scene_name = scene.source_name;
  r.scene_text = scene.text;
  r.comparison = scene.compare;
  r.kind = scene.structure.kind;
  r.coordinate_name = model.kind == model::StructureKind::beam ? "x" : "theta_deg";
  r.tensionless = model.tensionless;
  r.foundation_outside = model.foundation_outside;
  r.k = model.k;
  for (const auto& region : regions)
    r.contact_regions.push_back({model.user_from_s(region.begin), model.user_from_s(region.end)});

  r.fields = post::user_fields(model, fields);
  const FieldTable& f = r.fields;

  if (f.w.empty()) return r;  // fields not sampled: the caller fills the extremes
  const auto [lowest, highest] = std::minmax_element(f.w.begin(), f.w.end());
  r.w_max = *highest;
  r.at_w_max = f.coordinate[highest - f.w.begin()];
  r.w_min = *lowest;
  r.at_w_min = f.coordinate[lowest - f.w.begin()];
  r.max_reaction = f.reaction.empty() ? 0.0 : *std::max_element(f.reaction.begin(), f.reaction.end());
  return r;
}

}  // namespace

std::vector<std::string> methods_run(const contact::ContactSummary& summary) {
  // The fast solver's count of contact sets under a Lemke method: fast ran first and fell back
  // inside the solver (contact/contact_solver.cpp).
  std::vector<std::string> run;
  if (summary.method != contact::Method::fast && summary.iterations >= 0) run.emplace_back("fast");
  run.emplace_back(contact::to_string(summary.method));
  return run;
}

SolveReport make_report(const scene::Scene& scene, const model::MemberModel& model, const fe::Discretisation& d,
                        const contact::ContactSolution& solution, const post::Fields& fields,
                        const std::vector<ContactRegion>& regions) {
  SolveReport r = common_report(scene, model, fields, regions);
  const contact::ContactSummary& summary = solution.summary;
  r.method = contact::to_string(summary.method);
  r.methods_run = methods_run(summary);
  r.method_reason = summary.method_reason;
  r.termination = contact::to_string(summary.termination);
  r.message = summary.message;
  r.usable = summary.is_usable();
  r.residual = summary.residual;
  r.elements = d.mesh.elements();
  r.pivots = summary.pivots;
  r.lcp_size = summary.lcp_size;
  r.active_set_iterations = summary.iterations;
  r.factorisations = summary.factorisations;
  r.gauge_note = d.gauge_note;
  if (const auto& c = solution.no_equilibrium_certificate)
    r.no_equilibrium_certificate =
        SolveReport::RayCertificate{std::string(contact::to_string(c->formulation)),
                                    std::vector<double>(c->ray.data(), c->ray.data() + c->ray.size()), c->q_dot_ray};

  const model::Scales& scales = model.scales;
  FieldTable& n = r.nodes;
  n.coordinate = to_user(model, d.mesh.nodes);
  n.reaction.assign(d.mesh.nodes.size(), 0.0);
  // Where the reaction jumps a node has two: the table shows the larger (max_reaction too).
  for (int i = 0; i < d.reactions(); ++i) {
    double& at_node = n.reaction[d.reaction_nodes[i]];
    const double value = solution.reaction[i] * scales.force_per_length();
    at_node = i > 0 && d.reaction_nodes[i - 1] == d.reaction_nodes[i] ? std::max(at_node, value) : value;
  }
  for (int node = 0; node < static_cast<int>(d.mesh.nodes.size()); ++node) {
    const double w = solution.displacement[d.deflection_dof(node)], slope = solution.displacement[d.slope_dof(node)];
    const double u = model.kind == model::StructureKind::arch ? solution.displacement[d.tangential_dof(node)] : 0.0;
    n.w.push_back(w * scales.displacement());
    const double in = model.foundation_outside ? -1.0 : 1.0;  // w > 0 outward outside (arch_element.hpp)
    n.rotation.push_back(model.kind == model::StructureKind::arch ? -(u + in * slope) : -slope);
    if (model.kind == model::StructureKind::arch) n.u.push_back(u * scales.displacement());
    // A bilinear foundation's Winkler part K_t (w - g) adds to the LCP's reaction: the total.
    double tension_modulus = 0.0;
    for (int e : {node - 1, node})
      if (e >= 0 && e < d.mesh.elements()) tension_modulus = std::max(tension_modulus, d.element_tension_k[e]);
    if (tension_modulus > 0.0)
      n.reaction[node] += tension_modulus * (w - model.ground_gap(d.mesh.nodes[node])) * scales.force_per_length();
  }
  // The nodal reactions are the LCP's unknowns (plus the Winkler part's K_t (w - g), linear in the
  // nodal w): report their largest, not an interpolation's.
  r.max_reaction = *std::max_element(n.reaction.begin(), n.reaction.end());
  if (model.has_axial_force()) r.axial_force = model.axial_force(1.0) * scales.force();
  if (model.has_initial_shape())
    for (const double s : d.mesh.nodes) n.w_initial.push_back(model.initial_shape(s) * scales.displacement());
  return r;
}

SolveReport make_report(const scene::Scene& scene, const model::MemberModel& model, const ritz::RitzSolution& solution,
                        int samples) {
  const ritz::RitzSummary& summary = solution.summary;
  std::vector<ContactRegion> regions;
  post::Fields fields;
  if (solution.model && solution.unknowns.size() > 0) {
    regions = post::contact_regions(solution);
    fields = post::sample_fields(model, solution, samples);
  }
  SolveReport r = fields.s.empty() ? SolveReport{} : common_report(scene, model, fields, regions);
  if (fields.s.empty()) {
    r.scene_name = scene.source_name;
    r.scene_text = scene.text;
    r.comparison = scene.compare;
    r.kind = scene.structure.kind;
    r.foundation_outside = model.foundation_outside;
  }
  r.method = "ritz";
  r.methods_run = {r.method};
  r.termination = ritz::to_string(summary.termination);
  r.message = summary.message;
  r.usable = summary.is_usable();
  r.residual = summary.residual_history.empty() ? -1.0 : summary.residual_history.back();
  r.modes = summary.modes;
  r.newton_iterations = summary.newton_iterations;
  r.residual_history = summary.residual_history;
  const double user_length = model.user_from_s(model.s_end) - model.user_from_s(model.s_begin);
  if (summary.estimated_limit_error >= 0)
    r.estimated_limit_error = summary.estimated_limit_error * user_length / (model.s_end - model.s_begin);
  if (solution.model) {
    r.topology = ritz::to_string(solution.model->topology());
    const int amplitudes = solution.model->amplitudes();
    const Eigen::VectorXd a = solution.unknowns.head(std::min<int>(amplitudes, solution.unknowns.size()));
    r.amplitudes.assign(a.data(), a.data() + a.size());
    for (double& v : r.amplitudes) v *= model.scales.displacement();
  }
  return r;
}

void attach_scale(SolveReport& report, const scene::Scene& scene, const model::MemberModel& model) {
  report.units = scene.units;
  report.theory = std::string(scene::to_string(scene.structure.theory));
  std::vector<double> mesh;  // FE: the nodes in s (Ritz: none)
  for (const double x : report.nodes.coordinate) mesh.push_back(model.s_from_user(x));
  report.scale = post::scale_figures(model, mesh);
  report.warnings = scene.warnings;
  for (std::string& w : post::scale_warnings(scene, model, *report.scale)) report.warnings.push_back(std::move(w));
  const double w_extreme = std::max(std::abs(report.w_max), std::abs(report.w_min));
  for (std::string& w : post::deflection_warnings(scene, *report.scale, w_extreme))
    report.warnings.push_back(std::move(w));
  // The critical load's disagreement with the contact solver's check (StabilityTable::warning).
  if (report.stability && !report.stability->warning.empty()) report.warnings.push_back(report.stability->warning);
}

void attach_certificate(SolveReport& report, const certify::Certificate& certificate, const model::MemberModel& model) {
  certify::Certificate c = certificate;
  for (certify::Check& check : c.checks)
    if (check.at) check.at = model.user_from_s(*check.at);
  report.certificate_figures = certify::user_figures(certificate, model);
  report.certificate = std::move(c);
}

void attach_design(SolveReport& report, const post::DesignValues& design, const model::MemberModel& model) {
  report.design = post::user_design(design, model);
}

nlohmann::json design_json(const DesignTable& t) {
  auto one = [](const DesignValue& v) {
    return nlohmann::json{{"value", v.value}, {"at", v.at ? nlohmann::json(*v.at) : nlohmann::json()}};
  };
  nlohmann::json j{{"moment_max", one(t.moment_max)},       {"moment_min", one(t.moment_min)},
                   {"shear_max_abs", one(t.shear_max_abs)}, {"pressure_max", one(t.pressure_max)},
                   {"uplift_max", one(t.uplift_max)},       {"from_statics", t.from_statics}};
  if (t.from_statics) j["closure"] = {{"shear", t.shear_closure}, {"moment", t.moment_closure}};
  return j;
}

certify::HorizontalVertical user_arch_components(const certify::SupportReaction& reaction, bool outside) {
  return certify::arch_components(reaction.at * std::numbers::pi / 180.0, reaction.force, reaction.tangential, outside);
}

nlohmann::json support_reactions_json(const std::vector<certify::SupportReaction>& reactions, bool arch,
                                      bool von_karman, bool outside) {
  nlohmann::json all = nlohmann::json::array();
  for (const certify::SupportReaction& s : reactions) {
    nlohmann::json one{{"at", s.at}, {"force", s.force}, {"moment", s.moment}};
    if (arch) {
      one["tangential"] = s.tangential;
      const certify::HorizontalVertical hv = user_arch_components(s, outside);
      one["horizontal"] = hv.horizontal;
      one["vertical"] = hv.vertical;
    }
    if (von_karman && !arch)
      one["horizontal"] = s.tangential;  // a beam's axial reaction, along +x (arches: `tangential`)
    if (s.spring) one["spring"] = true;  // an elastic support: its springs' force
    if (s.settlement != 0.0) one["settlement"] = s.settlement;  // the support's prescribed w
    all.push_back(one);
  }
  return all;
}

namespace {

nlohmann::json number_or_null(double value) { return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(); }

// The nested critical_load object (the two factors and the stability word are top-level).
nlohmann::json critical_load_json(const StabilityTable& t) {
  nlohmann::json j{{"lower_bound", number_or_null(t.lower_bound)},
                   {"upper_bound", number_or_null(t.upper_bound)},
                   {"method", t.method},
                   {"termination", t.termination},
                   {"message", t.message},
                   {"set_iterations", t.set_iterations},
                   {"eigen_iterations", t.eigen_iterations},
                   {"residual", t.residual},
                   {"time_s", t.time_s}};
  if (!t.warning.empty()) j["warning"] = t.warning;
  return j;
}

nlohmann::json report_support_reactions(const SolveReport& r) {
  return support_reactions_json(r.certificate_figures.support_reactions, r.kind == StructureKind::arch,
                                r.theory == "von_karman", r.foundation_outside);
}

// {"system", "length", "force", "moment", ...}: the labels (empty strings when none are stated).

// The stiffest piece's figures (the shortest 1/beta), with every figure's range when the modulus
// varies; beta_L is beta times the member's length (arches: the arc's, 2 gamma R).
nlohmann::json scale_json(const post::ScaleFigures& f) {
  nlohmann::json j{{"nondimensional_k", f.k_max},
                   {"K", f.K_max},
                   {"beta", f.beta_max},
                   {"beta_L", f.beta_length_max},
                   {"characteristic_length", 1 / f.beta_max},
                   {"member_length", f.member_length}};
  if (f.arch) j["beta_R"] = f.beta_radius_max;
  if (f.beta_h >= 0) {
    j["beta_h"] = f.beta_h;
    j["element_size"] = f.element_size;
  }
  if (f.varies())
    j["range"] = {{"nondimensional_k", {f.k_min, f.k_max}},
                  {"K", {f.K_min, f.K_max}},
                  {"beta", {f.beta_min, f.beta_max}},
                  {"beta_L", {f.beta_length_min, f.beta_length_max}},
                  {"characteristic_length", {1 / f.beta_max, 1 / f.beta_min}}};
  return j;
}

nlohmann::json certificate_json(const SolveReport& r) {
  const certify::Certificate& c = *r.certificate;
  const certify::UserFigures& u = r.certificate_figures;
  nlohmann::json j;
  j["passed"] = c.passed;
  j["message"] = c.message;
  j["checks"] = nlohmann::json::array();
  for (const certify::Check& check : c.checks)
    j["checks"].push_back({{"name", check.name},
                           {"value", number_or_null(check.value)},
                           {"tolerance", number_or_null(check.tolerance)},
                           {"passed", check.passed},
                           {"at", check.at ? nlohmann::json(*check.at) : nlohmann::json()}});
  j["foundation_resultant"] = u.foundation_resultant;
  j["foundation_centroid"] = u.foundation_centroid;
  j["applied_force"] = u.applied_force;
  j["applied_moment"] = u.applied_moment;
  if (r.kind == StructureKind::arch) {
    j["foundation_resultant_x"] = u.foundation_resultant_x;
    j["applied_force_x"] = u.applied_force_x;
  }
  if (c.limit_element_defect >= 0) j["limit_element_defect"] = c.limit_element_defect;
  if (c.round_off_estimate >= 0) j["round_off_estimate"] = c.round_off_estimate;
  if (!c.round_off_note.empty()) j["round_off_note"] = c.round_off_note;
  return j;
}

}  // namespace

nlohmann::json contact_regions_json(const std::vector<ContactRegion>& regions) {
  nlohmann::json pairs = nlohmann::json::array();
  for (const ContactRegion& region : regions) pairs.push_back({region.begin, region.end});
  return pairs;
}

nlohmann::json units_json(const scene::Units& units) {
  nlohmann::json j{{"system", units.system}};
  for (const auto& [name, label] : scene::unit_labels(units)) j[name] = label;
  return j;
}

namespace {
// A report without an answer: every answer field null, so that a script cannot take a failed or
// refused solve's figures (zeros, a residual of -1, a state that failed its certificate) for a
// result, and `method` names a solver only if one ran, with the whole list in `methods_run`. The
// evidence of the failure stays: termination, message, the certificate, the ray, the stability,
// the residual history, the counters of the solvers that ran (the -1 of one that did not: null).
void without_answer(nlohmann::json& j, const SolveReport& r) {
  for (const char* key : answer_keys) j[key] = nullptr;
  for (const char* key : {"support_reactions", "foundation_resultant", "amplitudes", "membrane_force", "u"})
    if (j.contains(key)) j[key] = nullptr;
  for (const char* key : {"pivots", "lcp_size", "modes", "newton_iterations"})
    if (j.contains(key) && j[key].is_number_integer() && j[key].get<int>() < 0) j[key] = nullptr;
  j["method"] = r.methods_run.empty() ? nlohmann::json() : nlohmann::json(r.methods_run.back());
  j["methods_run"] = r.methods_run;
}
}  // namespace

nlohmann::json to_json(const SolveReport& r) {
  nlohmann::json j;
  j["scene"] = r.scene_name;
  j["structure"] = scene::to_string(r.kind);
  j["method"] = r.method;
  j["method_requested"] = r.method_requested;
  if (!r.method_reason.empty()) j["method_reason"] = r.method_reason;
  j["termination"] = r.termination;
  j["message"] = r.message;
  j["coordinate"] = r.coordinate_name;
  j["tensionless"] = r.tensionless;
  j["k"] = r.k;
  if (r.axial_force) j["axial_force"] = *r.axial_force;
  j["theory"] = r.theory;
  if (r.stable) j["stable"] = *r.stable;
  if (!r.membrane_force.empty())
    j["membrane_force"] = {{"per", "element"}, {"at", r.membrane_force_at}, {"value", r.membrane_force}};
  if (r.theory == "von_karman" && !r.nodes.u.empty())
    j["u"] = {{"coordinate", r.nodes.coordinate}, {"value", r.nodes.u}};
  if (!r.nodes.w_initial.empty()) j["w_initial"] = {{"coordinate", r.nodes.coordinate}, {"value", r.nodes.w_initial}};
  if (const auto& t = r.stability) {
    j["stability"] = t->stability;
    j["critical_load_factor"] = number_or_null(t->critical_load_factor);
    j["critical_axial_force"] = number_or_null(t->critical_axial_force);
    j["critical_load"] = critical_load_json(*t);
    if (!r.nodes.buckling_mode.empty())
      j["buckling_mode"] = {{"coordinate", r.nodes.coordinate}, {"w", r.nodes.buckling_mode}};
  }
  j["contact_regions"] = contact_regions_json(r.contact_regions);
  j["w_max"] = r.w_max;
  j["at_w_max"] = r.at_w_max;
  j["w_min"] = r.w_min;
  j["at_w_min"] = r.at_w_min;
  j["max_reaction"] = r.max_reaction;
  j["residual"] = r.residual;
  j["time_s"] = r.time_s;
  if (r.elements >= 0) {
    j["elements"] = r.elements;
    j["pivots"] = r.pivots;
    j["lcp_size"] = r.lcp_size;
    if (r.active_set_iterations >= 0) j["active_set_iterations"] = r.active_set_iterations;
    if (r.factorisations >= 0) j["factorisations"] = r.factorisations;
    if (r.limit_fitted) j["limit_fitted"] = true;
  }
  if (const auto& c = r.no_equilibrium_certificate)
    j["no_equilibrium_certificate"] = {
        {"kind", "lemke_ray"}, {"formulation", c->formulation}, {"q_dot_ray", c->q_dot_ray}, {"ray", c->ray}};
  if (r.tolerance >= 0) {
    j["tolerance"] = r.tolerance;
    j["round_off_floor"] = r.round_off_floor >= 0 ? nlohmann::json(r.round_off_floor) : nullptr;
    if (r.elements >= 0) {  // FE: the limit-fitted sequence's estimates
      j["estimated_limit_error"] = r.estimated_limit_error >= 0 ? nlohmann::json(r.estimated_limit_error) : nullptr;
      j["estimated_w_error"] = r.estimated_w_error >= 0 ? nlohmann::json(r.estimated_w_error) : nullptr;
      j["estimated_reaction_error"] =
          r.estimated_reaction_error >= 0 ? nlohmann::json(r.estimated_reaction_error) : nullptr;
      j["observed_order"] = r.observed_order >= 0 ? nlohmann::json(r.observed_order) : nullptr;
      j["elements_used"] = r.refinement_elements;
    }
  }
  if (r.modes >= 0) {
    j["modes"] = r.modes;
    j["newton_iterations"] = r.newton_iterations;
    j["topology"] = r.topology;
    j["amplitudes"] = r.amplitudes;
    j["residual_history"] = r.residual_history;
    if (r.estimated_limit_error >= 0) j["estimated_limit_error"] = r.estimated_limit_error;
    if (r.tolerance >= 0) {  // a tolerance settles w and the reaction too
      j["estimated_w_error"] = r.estimated_w_error >= 0 ? nlohmann::json(r.estimated_w_error) : nullptr;
      j["estimated_reaction_error"] =
          r.estimated_reaction_error >= 0 ? nlohmann::json(r.estimated_reaction_error) : nullptr;
    }
  }
  if (r.certificate) {
    j["support_reactions"] = report_support_reactions(r);
    j["certificate"] = certificate_json(r);
    j["foundation_resultant"] = {{"force", r.certificate_figures.foundation_resultant},
                                 {"centroid", r.certificate_figures.foundation_centroid}};
  }
  if (r.design) j["design"] = design_json(*r.design);
  j["sign_convention"] = sign_convention;
  if (!r.gauge_note.empty()) j["gauge"] = r.gauge_note;
  j["units"] = units_json(r.units);
  if (r.scale) j["scale"] = scale_json(*r.scale);
  j["warnings"] = r.warnings;
  if (!r.usable) without_answer(j, r);
  return j;
}

namespace {
std::string solver_line(const SolveReport& r) {
  if (r.modes >= 0)
    return fmt::format("{} modes, {} Newton iterations, residual {:.1e}, {:.3f} s", r.modes, r.newton_iterations,
                       r.residual, r.time_s);
  if (r.limit_fitted)
    return fmt::format("{} elements (limit-fitted: every contact limit a node), residual {:.1e}, {:.3f} s", r.elements,
                       r.residual, r.time_s);
  if (r.active_set_iterations >= 0 && r.factorisations < 0)  // von Karman: no factorisation count
    return fmt::format("{} elements, {} contact sets, residual {:.1e}, {:.3f} s", r.elements, r.active_set_iterations,
                       r.residual, r.time_s);
  if (r.active_set_iterations >= 0)
    return fmt::format("{} elements, {} contact sets, {} factorisations, residual {:.1e}, {:.3f} s", r.elements,
                       r.active_set_iterations, r.factorisations, r.residual, r.time_s);
  return fmt::format("{} elements, {} pivots, residual {:.1e}, {:.3f} s", r.elements, r.pivots, r.residual, r.time_s);
}
// The published result the scene names ([compare]) beside ours: the half-width of the contact
// region around the crown.
std::string comparison_line(const SolveReport& r) {
  const scene::Comparison& c = *r.comparison;
  const auto crown = std::find_if(r.contact_regions.begin(), r.contact_regions.end(),
                                  [](const ContactRegion& region) { return region.begin <= 0.0 && 0.0 <= region.end; });
  if (crown == r.contact_regions.end())
    return fmt::format("  compare       no contact at the crown; {} gives a contact half-angle of {:.4g} deg\n",
                       c.source, c.contact_half_angle_deg);
  const double here = crown->length() / 2;
  const double percent = 100 * (c.contact_half_angle_deg - here) / here;
  return fmt::format("  compare       contact half-angle {:.4g} deg; {} gives {:.4g} deg, {:.2g} % {}\n", here,
                     c.source, c.contact_half_angle_deg, std::abs(percent), percent < 0 ? "less" : "more");
}
}  // namespace

namespace {

// " kN" after a figure, nothing when no units are stated.
std::string with_unit(const std::string& label) { return label.empty() ? std::string() : " " + label; }

// The units and the foundation's scale, a line each (post/scale.hpp says what the figures are).
std::string scale_lines(const SolveReport& r) {
  std::string out;
  const scene::Units& u = r.units;
  if (u.stated())
    out += fmt::format("  units         {}force {}, length {}, moment {}, distributed force {}, modulus {}\n",
                       u.system.empty() ? "" : u.system + ": ", u.force, u.length, u.moment(), u.distributed_force(),
                       u.modulus());
  if (!r.scale) return out;
  const post::ScaleFigures& f = *r.scale;
  const bool arch = r.kind == StructureKind::arch;
  // "a" or "a..b" when the modulus varies (least..largest).
  const auto range = [&](double least, double largest, const std::string& unit) {
    return (f.varies() ? fmt::format("{:.4g}..{:.4g}", least, largest) : fmt::format("{:.4g}", largest)) +
           with_unit(unit);
  };
  out +=
      fmt::format("  scale         K = {}, beta = (K/4EI)^(1/4) = {}, beta {} = {}{}, 1/beta = {}\n",
                  range(f.K_min, f.K_max, u.modulus()), range(f.beta_min, f.beta_max, u.inverse_length()),
                  arch ? "S" : "L", range(f.beta_length_min, f.beta_length_max, ""),
                  arch ? fmt::format(" (S = 2 gamma R), beta R = {}", range(f.beta_radius_min, f.beta_radius_max, ""))
                       : std::string(),
                  range(1 / f.beta_max, 1 / f.beta_min, u.length));
  out += fmt::format(
      "                nondimensional k = {} = {}{}\n", arch ? "K R^4/EI" : "K L^4/EI", range(f.k_min, f.k_max, ""),
      f.beta_h >= 0
          ? fmt::format("; mesh: beta h <= {:.3g} (h = {:.4g}{})", f.beta_h, f.element_size, with_unit(u.length))
          : std::string());
  return out;
}

// The certificate in two or three lines: the verdict with its largest figures, the resultants,
// the support reactions.
std::string certificate_lines(const SolveReport& r) {
  const certify::Certificate& c = *r.certificate;
  const certify::UserFigures& u = r.certificate_figures;
  const bool arch = r.kind == StructureKind::arch;
  std::string out;
  if (c.passed) {
    double balance = 0, contact = 0;
    for (const certify::Check& check : c.checks) {
      if (check.name.find("balance") != std::string::npos) balance = std::max(balance, check.value);
      if (check.name == "reaction_sign" || check.name == "penetration" || check.name == "separation" ||
          check.name == "complementarity")
        contact = std::max(contact, check.value);
    }
    const certify::Check* round_off = c.find(certify::check_name::round_off);
    out += fmt::format(
        "  certificate   passed, {} checks: balance {:.1e} and contact {:.1e} of their terms{}\n", c.checks.size(),
        balance, contact,
        round_off ? fmt::format(", round-off {:.1e} < discretisation {:.1e}", round_off->value, round_off->tolerance)
                  : std::string());
  } else {
    out += "  certificate   FAILED: " + c.message + "\n";
  }
  const std::string unit = arch ? " deg" : with_unit(r.units.length);
  const std::string force = with_unit(r.units.force), moment = with_unit(r.units.moment());
  out +=
      fmt::format("  resultants    applied {:.6g}{}, moment {:.6g}{} about {}; foundation {:.6g}{} at {} = {:.6g}{}\n",
                  u.applied_force, force, u.applied_moment, moment, arch ? "the centre" : "the begin",
                  u.foundation_resultant, force, arch ? "theta" : "x", u.foundation_centroid, unit);
  if (!u.support_reactions.empty()) {
    std::string supports;
    for (const certify::SupportReaction& s : u.support_reactions) {
      supports += fmt::format("{}{} = {:.6g}{}: {}force {:.6g}{}", supports.empty() ? "" : "; ", arch ? "theta" : "x",
                              s.at, unit, s.spring ? "spring " : "", s.force, force);
      if (s.settlement != 0.0)
        supports += fmt::format(", settlement {:.6g}{}", s.settlement, with_unit(r.units.length));
      if (r.theory == "von_karman" && !arch && s.tangential != 0.0)
        supports += fmt::format(", horizontal {:.6g}{}", s.tangential, force);
      if (s.moment != 0.0) supports += fmt::format(", moment {:.6g}{}", s.moment, moment);
      if (arch && s.tangential != 0.0) supports += fmt::format(", tangential {:.6g}{}", s.tangential, force);
      if (arch) {
        const certify::HorizontalVertical hv = user_arch_components(s, r.foundation_outside);
        supports += fmt::format(" (H {:.6g}{}, V {:.6g}{})", hv.horizontal, force, hv.vertical, force);
      }
    }
    out += "  supports      " + supports + "\n";
  }
  return out;
}

// The design values: the extremes with their positions, and how well the statics closed.
std::string design_lines(const SolveReport& r) {
  const DesignTable& t = *r.design;
  const bool arch = r.kind == StructureKind::arch;
  const std::string length = arch ? " deg" : with_unit(r.units.length);
  auto where = [&](const DesignValue& v) {
    return v.at ? fmt::format(" at {} = {:.6g}{}", arch ? "theta" : "x", *v.at, length) : std::string();
  };
  const std::string moment = with_unit(r.units.moment()), force = with_unit(r.units.force),
                    pressure =
                        r.units.force.empty() ? " (force per unit length)" : with_unit(r.units.distributed_force()),
                    gap = with_unit(r.units.length);
  std::string out;
  // The smallest moment is a hogging one only when it is negative (a member sagging throughout
  // has its least moment, 0, at a free end).
  out += fmt::format("  moment        max {:.6g}{}{}; min {:.6g}{}{} (sagging > 0)\n", t.moment_max.value, moment,
                     where(t.moment_max), t.moment_min.value, moment, where(t.moment_min));
  out += fmt::format("  shear         max |V| {:.6g}{}{}\n", t.shear_max_abs.value, force, where(t.shear_max_abs));
  out += fmt::format("  pressure      max {:.6g}{}{}\n", t.pressure_max.value, pressure, where(t.pressure_max));
  out += t.uplift_max.at ? fmt::format("  uplift        max {:.6g}{}{} (gap between member and ground, g - w)\n",
                                       t.uplift_max.value, gap, where(t.uplift_max))
                         : std::string("  uplift        none (the member does not lift off the foundation)\n");
  if (t.from_statics)
    out += fmt::format(
        "  statics       V and M from the free body; closure at the far end {:.1e} (shear), {:.1e} (moment)\n",
        t.shear_closure, t.moment_closure);
  else
    out += "  statics       V and M from the fields' derivatives; extremes at the samples\n";
  return out;
}

}  // namespace

std::string text_summary(const SolveReport& r) {
  const bool arch = r.kind == StructureKind::arch;
  const std::string unit = arch ? " deg" : with_unit(r.units.length);
  std::string out = fmt::format("liftoff: {} ({}) on a {} foundation, nondimensional k = {:.6g}\n", r.scene_name,
                                scene::to_string(r.kind), r.tensionless ? "tensionless" : "bilateral", r.k);
  for (const std::string& warning : r.warnings) out += "  WARNING       " + warning + "\n";
  out += scale_lines(r);
  std::string why = r.method_reason;
  if (!r.method_requested.empty() && r.method_requested != r.method)
    why = "asked for " + r.method_requested + (why.empty() ? "" : "; " + why);
  out += fmt::format("  method        {}{}\n", r.method, why.empty() ? "" : " (" + why + ")");
  out += fmt::format("  result        {}: {}\n", r.termination, r.message);
  if (const auto& c = r.no_equilibrium_certificate)
    out += fmt::format("  certificate   Lemke ray of the {} LCP ({} unknowns, q.ray = {:.3e} < 0): no equilibrium\n",
                       c->formulation, c->ray.size(), c->q_dot_ray);
  if (r.contact_regions.empty()) out += "  contact       none\n";
  // Digits enough for the tolerance asked for (8 significant by default).
  const int digits = r.tolerance > 0 ? std::max(8, static_cast<int>(std::ceil(-std::log10(r.tolerance))) + 2) : 8;
  for (const auto& region : r.contact_regions)
    out += fmt::format("  contact       {} = {:.{}g}{} .. {:.{}g}{}\n", arch ? "theta" : "x", region.begin, digits,
                       unit, region.end, digits, unit);
  if (r.comparison && r.usable && arch) out += comparison_line(r);
  const std::string length = with_unit(r.units.length);
  out += fmt::format("  w max         {:.6e}{} at {:.6g}{}\n", r.w_max, length, r.at_w_max, unit);
  out += fmt::format("  w min         {:.6e}{} at {:.6g}{}\n", r.w_min, length, r.at_w_min, unit);
  out += fmt::format("  max reaction  {:.6e} {}\n", r.max_reaction,
                     r.units.stated() ? r.units.distributed_force() : "(force per unit length)");
  out += fmt::format("  solver        {}\n", solver_line(r));
  if (r.estimated_limit_error >= 0 && r.modes >= 0)
    out += fmt::format("  modes         limits settled to {:.1e}{} (change from the previous N){}\n",
                       r.estimated_limit_error, unit,
                       r.estimated_w_error >= 0 ? fmt::format(", w to {:.1e} of max |w|, reaction to {:.1e}",
                                                              r.estimated_w_error, r.estimated_reaction_error)
                                                : std::string());
  if (r.tolerance >= 0 && r.elements >= 0 && r.estimated_limit_error >= 0) {
    std::string meshes;
    for (int n : r.refinement_elements) meshes += fmt::format("{}{}", meshes.empty() ? "" : ", ", n);
    out += fmt::format(
        "  accuracy      tolerance {:.1e}: estimated errors: limits {:.1e}{}, w {:.1e} of max |w|, reaction {:.1e} of "
        "its largest (limit-fitted meshes {}; observed order {:.2f}); round-off floor {:.1e}\n",
        r.tolerance, r.estimated_limit_error, unit, r.estimated_w_error, r.estimated_reaction_error, meshes,
        r.observed_order, r.round_off_floor);
  }
  if (r.certificate) out += certificate_lines(r);
  if (r.design) out += design_lines(r);
  if (const auto& t = r.stability) {
    const std::string force = with_unit(r.units.force);
    out += std::isfinite(t->critical_load_factor)
               ? fmt::format(
                     "  stability     {}: critical load factor {:.6g} on the axial force (N_cr = {:.6g}{}; "
                     "bounds [{:.6g}, {:.6g}], {} eigen solve)\n",
                     t->stability, t->critical_load_factor, t->critical_axial_force, force, t->lower_bound,
                     t->upper_bound, t->method)
               : fmt::format("  stability     {}: {} ({})\n", t->stability, t->termination, t->message);
  }
  if (!r.membrane_force.empty()) {
    const auto [lowest, highest] = std::minmax_element(r.membrane_force.begin(), r.membrane_force.end());
    out += fmt::format("  membrane      N = {:.6g}{} (tension positive; {:.6g} to {:.6g} over the elements), {}\n",
                       0.5 * (*lowest + *highest), with_unit(r.units.force), *lowest, *highest,
                       r.stable && *r.stable ? "stable" : "not stable");
  }
  if (!r.gauge_note.empty()) out += "  note          " + r.gauge_note + "\n";
  out += "  sign          w > 0 into the foundation\n";
  return out;
}

std::string side_by_side(const std::vector<SolveReport>& reports) {
  if (reports.empty()) return {};
  const bool arch = reports.front().kind == StructureKind::arch;
  // The scene's k from a method that ran (a refused method's report may not know it; k > 0 in
  // every valid scene); without one, the header leaves it out.
  const auto known = std::find_if(reports.begin(), reports.end(), [](const SolveReport& r) { return r.k > 0; });
  std::string out = fmt::format(
      "liftoff: {} ({}) on a {} foundation{}\n", reports.front().scene_name, scene::to_string(reports.front().kind),
      (known != reports.end() ? known->tensionless : reports.front().tensionless) ? "tensionless" : "bilateral",
      known != reports.end() ? fmt::format(", nondimensional k = {:.6g}", known->k) : std::string());
  std::vector<std::string> warnings;  // every method's, each once
  for (const SolveReport& r : reports)
    for (const std::string& w : r.warnings)
      if (std::find(warnings.begin(), warnings.end(), w) == warnings.end()) warnings.push_back(w);
  for (const std::string& warning : warnings) out += "  WARNING       " + warning + "\n";
  auto row = [&](const std::string& label, auto cell) {
    out += fmt::format("  {:<16}", label);
    for (const auto& r : reports) out += fmt::format("{:>24}", cell(r));
    out += "\n";
  };
  // A counter a method did not produce (a refused method's, the FE counters of Ritz) is -1: "-".
  const auto counted = [](int n, const char* unit) {
    return n >= 0 ? fmt::format("{} {}", n, unit) : std::string("-");
  };
  row("method", [](const SolveReport& r) { return r.method_requested.empty() ? r.method : r.method_requested; });
  row("answer from",
      [](const SolveReport& r) { return r.outcome == SolveOutcome::refused ? std::string("-") : r.method; });
  row("result", [](const SolveReport& r) { return r.termination; });
  row("certified", [](const SolveReport& r) {
    return r.certificate ? std::string(r.certificate->passed ? "yes" : "no") : std::string("-");
  });
  std::size_t regions = 0;
  for (const auto& r : reports) regions = std::max(regions, r.contact_regions.size());
  for (std::size_t i = 0; i < regions; ++i) {
    for (int end = 0; end < 2; ++end)
      row(fmt::format("contact {} {}", i + 1, end == 0 ? "begin" : "end"), [&](const SolveReport& r) {
        return i < r.contact_regions.size()
                   ? fmt::format("{:.10f}", end == 0 ? r.contact_regions[i].begin : r.contact_regions[i].end)
                   : std::string("-");
      });
  }
  row("w max", [](const SolveReport& r) { return r.usable ? fmt::format("{:.10e}", r.w_max) : std::string("-"); });
  row("max reaction",
      [](const SolveReport& r) { return r.usable ? fmt::format("{:.10e}", r.max_reaction) : std::string("-"); });
  row("size",
      [&](const SolveReport& r) { return r.modes >= 0 ? counted(r.modes, "modes") : counted(r.elements, "elements"); });
  row("iterations", [&](const SolveReport& r) {
    if (r.modes >= 0) return counted(r.newton_iterations, "Newton");
    if (r.active_set_iterations >= 0) return counted(r.active_set_iterations, "sets");
    return counted(r.pivots, "pivots");
  });
  row("residual",
      [](const SolveReport& r) { return r.residual >= 0 ? fmt::format("{:.1e}", r.residual) : std::string("-"); });
  row("time (s)", [](const SolveReport& r) {
    return r.outcome == SolveOutcome::refused ? std::string("-") : fmt::format("{:.3f}", r.time_s);
  });
  out += fmt::format("  (contact limits: {}; w > 0 into the foundation)\n", arch ? "theta in degrees" : "x");
  return out;
}

std::string design_csv_header() {
  return "moment_max,at_moment_max,moment_min,at_moment_min,shear_max_abs,at_shear_max_abs,pressure_max,"
         "at_pressure_max,uplift_max,at_uplift_max";
}

std::string design_csv_cells(const DesignTable* design) {
  if (design == nullptr) return std::string(9, ',');
  std::string out;
  for (const DesignValue* v :
       {&design->moment_max, &design->moment_min, &design->shear_max_abs, &design->pressure_max, &design->uplift_max})
    out += fmt::format("{}{:.12g},{}", out.empty() ? "" : ",", v->value,
                       v->at ? fmt::format("{:.12g}", *v->at) : std::string());
  return out;
}

std::string support_reactions_csv(const std::vector<certify::SupportReaction>& reactions) {
  std::string supports;
  for (const certify::SupportReaction& s : reactions)
    supports += fmt::format("{}{:.12g}:{:.12g}:{:.12g}", supports.empty() ? "" : ";", s.at, s.force, s.moment);
  return supports;
}

namespace {
// The sweep's design columns (sweep_csv): empty without a certified answer.
std::string design_columns(const SolveReport& r) {
  if (!r.usable || !r.design) return std::string(10, ',');
  return design_csv_cells(&*r.design) + "," + support_reactions_csv(r.certificate_figures.support_reactions);
}
}  // namespace

std::string sweep_csv(const std::vector<std::string>& keys, const std::vector<SweepCase>& cases) {
  std::string out;
  for (const auto& key : keys) out += key + ",";
  out += "method,termination,certified,contact_regions,w_max,w_min,max_reaction,iterations,time_s,";
  out += design_csv_header() + ",support_reactions\n";
  for (const SweepCase& c : cases) {
    std::string prefix;
    for (double v : c.values) prefix += fmt::format("{:.17g},", v);
    if (!c.error.empty()) {
      std::string error = c.error;
      std::replace(error.begin(), error.end(), '"', '\'');
      out += prefix + fmt::format(",\"error: {}\",,,,,,,{}\n", error, std::string(11, ','));
      continue;
    }
    for (const SolveReport& r : c.reports) {
      std::string regions;
      for (const auto& region : r.contact_regions)
        regions += fmt::format("{}{:.12g}..{:.12g}", regions.empty() ? "" : ";", region.begin, region.end);
      const int iterations = r.modes >= 0                   ? r.newton_iterations
                             : r.active_set_iterations >= 0 ? r.active_set_iterations
                                                            : r.pivots;
      // A case without an answer leaves the answer's columns empty: a refused solver's last
      // iterate (Lemke's wrong contact set) is not a result.
      const std::string answer =
          r.usable ? fmt::format("{},{:.12g},{:.12g},{:.12g}", regions, r.w_max, r.w_min, r.max_reaction)
                   : std::string(",,,");
      out += prefix + fmt::format("{},{},{},{},{},{:.6f},{}\n",
                                  r.method_requested.empty() ? r.method : r.method_requested, r.termination,
                                  r.certified() ? "true" : "false", answer, iterations, r.time_s, design_columns(r));
    }
  }
  return out;
}

}  // namespace liftoff::io

namespace liftoff {
template <>
std::optional<io::SolveOutcome> from_string(std::string_view name) {
  return value_in<io::SolveOutcome>(io::solve_outcome_names, name);
}
}  // namespace liftoff
