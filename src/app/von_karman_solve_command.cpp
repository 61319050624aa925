#include "app/von_karman_solve_command.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "certify/certificate.hpp"
#include "contact/von_karman_loading.hpp"
#include "contact/von_karman_solve.hpp"
#include "core/error.hpp"
#include "fe/discretisation.hpp"
#include "model/from_scene.hpp"
#include "model/member_model.hpp"
#include "post/contact_regions.hpp"
#include "post/design.hpp"
#include "post/fields.hpp"

namespace liftoff::app {

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

struct VonKarmanFe {
  model::MemberModel model;
  fe::Discretisation d;
  contact::VonKarmanLoadingResult loading;
  contact::VonKarmanOptions solve_options;
};

VonKarmanFe solve_von_karman(const scene::Scene& scene, int elements) {
  VonKarmanFe out;
  out.model = model::make_member_model(scene);
  if (out.model.has_settlements())
    throw InputError(fmt::format(
        "{}: key 'structure.theory': theory = \"von_karman\" with a settled support is not solved yet (the load "
        "path from zero would impose the settlement at once); expected no settlement",
        scene.source_name));
  try {
    out.d = fe::discretise(out.model, elements);
  } catch (const MechanismError& e) {
    throw MechanismError(scene.source_name + ": " + e.what());
  }
  const contact::VonKarmanSystem system(out.model, out.d);
  const Eigen::VectorXd dead = system.load(0.0), live = system.load(1.0) - dead;
  contact::VonKarmanLoadingOptions options;
  out.solve_options = options.solve;
  out.loading = contact::load_from_zero(system, dead, live, options);
  return out;
}

}  // namespace

std::vector<ContactRegion> von_karman_fe_regions(const scene::Scene& scene, int elements) {
  const VonKarmanFe fe = solve_von_karman(scene, elements);
  if (!fe.loading.is_usable())
    throw SolverFailure(scene.source_name +
                        ": the von Karman FE solution that gives the Ritz topology failed: " + fe.loading.message);
  return post::contact_regions(fe.model, fe.d, fe.d.expand_displacement(fe.loading.result.x.head(fe.d.equations)));
}

io::SolveReport von_karman_fe_report(const scene::Scene& scene, const SolveRequest& request,
                                     std::string_view method_requested) {
  const auto start = std::chrono::steady_clock::now();
  const VonKarmanFe fe = solve_von_karman(scene, request.elements.value_or(scene.solve.elements));
  const model::MemberModel& model = fe.model;
  const fe::Discretisation& d = fe.d;
  const contact::VonKarmanLoadingResult& loading = fe.loading;
  const contact::VonKarmanResult& r = loading.result;
  const model::Scales& scales = model.scales;
  const std::string how =
      fmt::format("the load applied from zero (dead loads first, then the live load) in {} steps, {} solves",
                  loading.steps, loading.solves);

  // The answer as a contact solution (w, w' on every dof; the reactions and gaps), for the
  // report's and the fields' shared code.
  contact::ContactSolution solution;
  solution.displacement = d.expand_displacement(r.x.head(d.equations));
  solution.reaction = r.reaction.size() == d.reactions() ? r.reaction : Eigen::VectorXd::Zero(d.reactions());
  solution.gap = r.gap.size() == d.reactions() ? r.gap : Eigen::VectorXd::Zero(d.reactions());
  contact::ContactSummary& summary = solution.summary;
  summary.method = contact::Method::fast;
  summary.method_reason = how;
  summary.iterations = r.contact_sets;  // of the last step's solve
  summary.termination =
      loading.is_usable() ? contact::ContactTermination::solved : contact::ContactTermination::numerical_failure;
  summary.message = loading.is_usable() ? "equilibrium found: " + loading.message : loading.message;

  std::optional<certify::Certificate> certificate;
  if (loading.is_usable()) {
    certify::VonKarmanAnswer answer{solution.displacement, r.u, solution.reaction, r.normal_force};
    certify::CertifyOptions options;
    options.sign_floor = fe.solve_options.sign_tolerance;
    certificate = certify::certify(model, d, answer, options);
    if (const certify::Check* backward = certificate->find(certify::check_name::backward_error))
      summary.residual = backward->value;
  }
  const bool certified = certificate && certificate->passed;

  const int samples = post::capped_samples_per_element(d.mesh.elements(), request.samples_per_element);
  post::Fields fields = request.fields && certified ? post::sample_fields(model, d, solution, samples) : post::Fields{};
  // The membrane force the linear sampling does not know (arches: the rotation's term; beams: each
  // element's N, u at the nodes only).
  if (!fields.s.empty()) post::add_von_karman_membrane(model, d, r.normal_force, fields);
  // The design values from the fields (M, V their derivatives), extremes at the samples, as for a
  // linear arch (sampled for them alone when the fields were not asked for); a trace's steps
  // report the same (continuation/step_state.hpp).
  const std::optional<post::DesignValues> design =
      certified ? std::optional(post::design_from_samples(
                      model, fields.s.empty() ? post::sample_fields(model, d, solution,
                                                                    post::capped_samples_per_element(d.mesh.elements()))
                                              : fields))
                : std::nullopt;
  const std::vector<ContactRegion> regions =
      loading.is_usable() ? post::contact_regions(model, d, solution.displacement) : std::vector<ContactRegion>{};
  io::SolveReport report = io::make_report(scene, model, d, solution, fields, regions);
  report.termination = loading.is_usable() ? "solved" : std::string(contact::to_string(loading.termination));
  report.method_requested = std::string(method_requested);
  report.theory = "von_karman";
  if (loading.is_usable()) {
    report.stable = r.stable;
    report.nodes.u.clear();
    for (int node = 0; node < static_cast<int>(r.u.size()); ++node)
      report.nodes.u.push_back(r.u[node] * scales.displacement());
    for (int e = 0; e < d.mesh.elements(); ++e) {
      report.membrane_force.push_back(r.normal_force[e] * scales.force());
      report.membrane_force_at.push_back(model.user_from_s(d.mesh.nodes[e] + 0.5 * d.mesh.element_size(e)));
    }
    const post::DeflectionExtremes x = post::deflection_extremes(d, solution.displacement);
    report.w_max = x.w_max * scales.displacement();
    report.at_w_max = model.user_from_s(x.s_at_w_max);
    report.w_min = x.w_min * scales.displacement();
    report.at_w_min = model.user_from_s(x.s_at_w_min);
  } else {
    // No answer: the last accepted state is not the scene's (a smaller load).
    report.nodes = io::FieldTable{};
    report.max_reaction = 0.0;
    report.usable = false;
  }
  if (design) io::attach_design(report, *design, model);
  if (certificate) io::attach_certificate(report, *certificate, model);
  if (certificate && !certified) {
    report.termination = "certificate_failed";
    report.usable = false;
    report.message = "the von Karman FE answer failed its certificate: " + certificate->message;
  }
  report.time_s = seconds_since(start);
  return report;
}

}  // namespace liftoff::app
