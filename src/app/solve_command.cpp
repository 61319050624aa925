#include "app/solve_command.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "app/theory_gate.hpp"
#include "app/von_karman_solve_command.hpp"
#include "certify/certificate.hpp"
#include "certify/resultant_check.hpp"
#include "contact/contact_solver.hpp"
#include "contact/fitted_refinement.hpp"
#include "contact/from_scene.hpp"
#include "contact/stability.hpp"
#include "core/error.hpp"
#include "fe/discretisation.hpp"
#include "fe/shape_functions.hpp"
#include "model/from_scene.hpp"
#include "model/member_model.hpp"
#include "post/contact_regions.hpp"
#include "post/design.hpp"
#include "post/fields.hpp"
#include "post/ritz_fields.hpp"
#include "ritz/from_scene.hpp"
#include "ritz/ritz_model.hpp"
#include "ritz/ritz_solver.hpp"
#include "stability/critical_load.hpp"

namespace liftoff::app {

// The FE answers below take the contact solver's method; solve_scene_unscaled converts the
// scene's once (contact/from_scene.hpp).
using contact::Method;

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

fe::Discretisation discretise(const scene::Scene& scene, const model::MemberModel& model, int elements) {
  try {
    return fe::discretise(model, elements);
  } catch (const MechanismError& e) {
    throw MechanismError(scene.source_name + ": " + e.what());
  }
}

struct FeResult {
  fe::Discretisation discretisation;
  contact::ContactSolution solution;
  std::vector<ContactRegion> regions;
  bool solver_ran = true;  // false: the resultant check decided before any solver (contact_answer)
};

// The answer of one formulation on a discretisation: no_equilibrium at once when the resultant
// cannot be balanced by compressive foundation reactions (certify/resultant_check.hpp), else the
// contact solve (`solver_ran` says which). Throws SolverFailure (a refused formulation) with the
// scene's name.
contact::ContactSolution contact_answer(const scene::Scene& scene, const model::MemberModel& model,
                                        const fe::Discretisation& d, Method method,
                                        std::vector<bool> initial_contact = {}, bool* solver_ran = nullptr) {
  const certify::ResultantCheck resultant = certify::check_resultant(model, d);
  if (solver_ran != nullptr) *solver_ran = resultant.balanced;
  if (!resultant.balanced) {
    contact::ContactSolution none;
    none.displacement = Eigen::VectorXd::Zero(d.dofs());
    none.reaction = Eigen::VectorXd::Zero(d.reactions());
    none.gap = Eigen::VectorXd::Zero(d.reactions());
    none.summary.termination = contact::ContactTermination::no_equilibrium;
    none.summary.method = method == Method::automatic ? contact::choose_fe_method(d).method : method;
    none.summary.message = resultant.message;
    none.summary.residual = -1.0;
    none.summary.time_s = 0.0;
    return none;
  }
  contact::ContactOptions options;
  options.method = method;
  options.initial_contact = std::move(initial_contact);
  try {
    return contact::solve_contact(d, options);
  } catch (const SolverFailure& e) {
    throw SolverFailure(scene.source_name + ": " + e.what());
  }
}

// The warm start's first contact set on d: the reaction nodes inside the regions (user
// coordinate, a relative 1e-9 of the length around each end). Empty where it does not apply.
std::vector<bool> warm_start_set(const model::MemberModel& model, const fe::Discretisation& d,
                                 const std::optional<std::vector<ContactRegion>>& regions) {
  if (!regions || !d.tensionless) return {};
  const double margin = 1e-9 * (model.s_end - model.s_begin);
  std::vector<bool> in_contact(d.reactions(), false);
  for (int i = 0; i < d.reactions(); ++i) {
    const double s = d.mesh.nodes[d.reaction_nodes[i]];
    for (const ContactRegion& region : *regions) {
      const double a = model.s_from_user(region.begin), b = model.s_from_user(region.end);
      if (s >= std::min(a, b) - margin && s <= std::max(a, b) + margin) in_contact[i] = true;
    }
  }
  return in_contact;
}

FeResult solve_fe(const scene::Scene& scene, const model::MemberModel& model, Method method, int elements,
                  const std::optional<std::vector<ContactRegion>>& warm_start = std::nullopt) {
  FeResult fe;
  fe.discretisation = discretise(scene, model, elements);
  fe.solution = contact_answer(scene, model, fe.discretisation, method,
                               warm_start_set(model, fe.discretisation, warm_start), &fe.solver_ran);
  fe.regions = post::contact_regions(model, fe.discretisation, fe.solution.displacement);
  return fe;
}

// Where a formulation whose answer failed its certificate falls back: fast (or an auto that ran
// fast) -> Lemke, dual where the structure is stable, else primal, if the dense LCP fits; dual or
// primal -> fast. Nothing when the answer already came from a fallback inside the solver.
std::optional<Method> fallback_for(Method produced, Method requested, const fe::Discretisation& d) {
  if (produced == Method::fast) {
    const bool dual = d.structure_is_stable() && (!d.has_axial_force() || contact::is_positive_definite(d.stiffness));
    const Method lemke = dual ? Method::dual : Method::primal;
    const int size = lemke == Method::dual ? d.reactions() : 2 * d.equations + d.reactions();
    if (size > contact::max_fallback_lcp) return std::nullopt;  // minutes of dense Lemke: report fast's failure
    return lemke;
  }
  if (requested == Method::fast || requested == Method::automatic) return std::nullopt;  // fast already failed
  return Method::fast;
}

std::string check_failure(const contact::ContactSummary& summary, const certify::Certificate& certificate) {
  return fmt::format("the {} answer failed its certificate: {}", to_string(summary.method), certificate.message);
}

// The design values of a certified FE answer: beams by the statics of the free body with the
// certificate's support reactions (V and M of `fields` replaced by the statics' own), arches from
// sampled fields (fields.hpp's V and M).
std::optional<post::DesignValues> design_values(const model::MemberModel& model, const fe::Discretisation& d,
                                                const contact::ContactSolution& solution,
                                                const certify::Certificate& certificate, post::Fields& fields) {
  if (model.kind == model::StructureKind::beam) {
    std::vector<post::PointReaction> supports;
    for (const certify::SupportReaction& s : certificate.support_reactions)
      supports.push_back({s.at, s.force, s.moment});
    return post::recover_beam_statics(model, d, solution, supports, 1.0, fields.s.empty() ? nullptr : &fields);
  }
  // Sampled for the extremes alone when the fields were not asked for (16 per element, capped).
  if (fields.s.empty())
    return post::design_from_samples(
        model, post::sample_fields(model, d, solution, post::capped_samples_per_element(d.mesh.elements())));
  return post::design_from_samples(model, fields);
}

// The critical load of an FE state under an axial force (stability/critical_load.hpp), on the cone
// of its contact state (classify_contact of its reactions and gaps), as the factor on the whole
// axial force N (dead + live at lambda = 1: dead 0, live N): > 1 stable. Run on a solved state
// and on one contact::solve_contact refused as unstable_equilibrium; where the cone and the
// solver's inertia check on the contact set (contact/stability.hpp: springs where r > 0) disagree,
// the report says so. Beams only (the eigen solver's scope).
void attach_critical_load(io::SolveReport& report, const model::MemberModel& model, const fe::Discretisation& d,
                          const contact::ContactSolution& solution) {
  const contact::ContactTermination termination = solution.summary.termination;
  const bool solved = solution.summary.is_usable(),
             refused = termination == contact::ContactTermination::unstable_equilibrium;
  if (model.kind != model::StructureKind::beam || !d.has_axial_force() || !(solved || refused)) return;
  if (solution.reaction.size() != d.reactions() || solution.gap.size() != d.reactions() ||
      solution.displacement.size() != d.dofs() || !solution.reaction.allFinite() || !solution.gap.allFinite() ||
      !solution.displacement.allFinite())
    return;
  // A refusal after a failed search (no state found) leaves the last iterate, no equilibrium: the
  // cone is asked only about a state that satisfies K(N) u + C^T r = F, r >= 0 and gap >= 0 (1e-8
  // of their scales; the solver's own acceptance is far tighter).
  if (refused) {
    const Eigen::VectorXd u = d.on_equations(solution.displacement);
    const Eigen::VectorXd ku = d.stiffness * u, cr = d.coupling.transpose() * solution.reaction, f = d.load(1.0);
    const double scale =
        std::max({ku.lpNorm<Eigen::Infinity>(), cr.lpNorm<Eigen::Infinity>(), f.lpNorm<Eigen::Infinity>()});
    const double r_scale = solution.reaction.lpNorm<Eigen::Infinity>(),
                 g_scale = solution.gap.lpNorm<Eigen::Infinity>();
    const bool balanced = (ku + cr - f).lpNorm<Eigen::Infinity>() <= 1e-8 * scale;
    const bool signs = !d.tensionless ||
                       (solution.reaction.minCoeff() >= -1e-8 * r_scale && solution.gap.minCoeff() >= -1e-8 * g_scale &&
                        solution.reaction.cwiseProduct(solution.gap).cwiseAbs().maxCoeff() <=
                            1e-8 * std::max(r_scale * g_scale, std::numeric_limits<double>::min()));
    if (!balanced || !signs) return;
  }
  // A bilateral foundation holds every node both ways: all in contact (its reactions may be of
  // either sign or zero, which classify_contact would read as lifted or weakly active).
  const std::vector<stability::NodeContact> contact =
      d.tensionless ? stability::classify_contact(solution.reaction, solution.gap)
                    : std::vector<stability::NodeContact>(d.reactions(), stability::NodeContact::in_contact);
  io::StabilityTable t;
  stability::CriticalLoadResult r;
  try {
    r = stability::critical_load(d, 0.0, d.axial_force, contact);
  } catch (const std::invalid_argument& e) {  // misuse would be a bug: reported, not a crash
    t.stability = "undetermined";
    t.message = std::string("the critical load was not computed: ") + e.what();
    report.stability = std::move(t);
    return;
  }
  t.method = std::string(stability::to_string(r.method));
  t.termination = std::string(stability::to_string(r.termination));
  t.message = r.message;
  t.set_iterations = r.set_iterations;
  t.eigen_iterations = r.eigen_iterations;
  t.residual = r.residual;
  t.time_s = r.time_s;
  using stability::StabilityTermination;
  switch (r.termination) {
    case StabilityTermination::critical_load_found:
      t.stability = r.critical_load_factor > 1.0 ? "stable" : "unstable";
      t.critical_load_factor = r.critical_load_factor;
      t.critical_axial_force = r.critical_axial_force() * model.scales.force();
      t.lower_bound = r.lower_bound;
      t.upper_bound = r.upper_bound;
      break;
    case StabilityTermination::stable_for_all_factors:
      t.stability = "stable";
      break;
    case StabilityTermination::unstable_at_zero:
      t.stability = "unstable";
      break;
    case StabilityTermination::not_converged:
      t.stability = "undetermined";
      break;
  }
  if (r.mode.size() == d.equations) {
    // The mode's sign is free where no node is weakly active (every admissible perturbation's
    // negative is admissible too): the largest |w| is then made positive, so the file is the same
    // on every run; elsewhere the solver's admissible orientation stands.
    const Eigen::VectorXd all = d.expand(r.mode);
    std::vector<double> mode;
    double largest = 0.0;
    for (int node = 0; node <= d.mesh.elements(); ++node) {
      mode.push_back(all[d.deflection_dof(node)]);
      if (std::abs(mode.back()) > std::abs(largest)) largest = mode.back();
    }
    const bool sign_free =
        std::none_of(contact.begin(), contact.end(), [](auto c) { return c == stability::NodeContact::weakly_active; });
    if (sign_free && largest < 0.0)
      for (double& w : mode) w = -w;
    report.nodes.buckling_mode = std::move(mode);
  }
  if (t.stability == "unstable" && solved)
    t.warning = fmt::format(
        "the cone of admissible perturbations finds this state unstable ({}) while the contact solver's inertia "
        "check on the contact set (nodes with a positive reaction) passed it: it is unstable against "
        "perturbations that change the contact set",
        std::isfinite(t.critical_load_factor) ? fmt::format("critical load factor {:.6g}", t.critical_load_factor)
                                              : t.termination);
  if (t.stability == "stable" && refused)
    t.warning = fmt::format(
        "the contact solver's inertia check on the contact set (nodes with a positive reaction only) refused this "
        "state, while the cone of admissible perturbations, with the weakly active nodes' springs where a "
        "perturbation pushes in, finds the critical load factor {:.6g} above 1",
        t.critical_load_factor);
  report.stability = std::move(t);
}

io::SolveReport fe_report(const scene::Scene& scene, Method method, const SolveRequest& request) {
  const auto start = std::chrono::steady_clock::now();
  const model::MemberModel model = model::make_member_model(scene);
  FeResult fe =
      solve_fe(scene, model, method, request.elements.value_or(scene.solve.elements), request.initial_contact_regions);
  const fe::Discretisation& d = fe.discretisation;

  // The certificate; a failed one means a fallback, or a failure that names the check.
  std::optional<certify::Certificate> certificate;
  std::string fallback_reason;
  std::vector<std::string> methods_run;
  if (fe.solver_ran) methods_run = io::methods_run(fe.solution.summary);
  if (fe.solution.summary.is_usable()) {
    certificate = certify::certify(model, d, fe.solution);
    if (!certificate->passed) {
      const std::string first_failure = check_failure(fe.solution.summary, *certificate);
      // Round-off alone: another formulation on the same assembled data would not help.
      bool round_off_only = true;
      for (const certify::Check& check : certificate->checks)
        round_off_only &= check.passed || check.name == certify::check_name::round_off;
      const std::optional<Method> fallback =
          round_off_only ? std::nullopt : fallback_for(fe.solution.summary.method, method, d);
      std::string outcome;
      if (fallback) {
        try {
          contact::ContactSolution second = contact_answer(scene, model, d, *fallback);
          for (std::string& m : io::methods_run(second.summary)) methods_run.push_back(std::move(m));
          if (second.summary.is_usable()) {
            certify::Certificate second_certificate = certify::certify(model, d, second);
            if (second_certificate.passed) {
              fallback_reason = fmt::format("{}; fell back to {}", first_failure, to_string(*fallback));
              fe.solution = std::move(second);
              fe.regions = post::contact_regions(model, d, fe.solution.displacement);
              certificate = std::move(second_certificate);
            } else {
              outcome = fmt::format("; the fallback to {} failed its certificate too: {}", to_string(*fallback),
                                    second_certificate.message);
            }
          } else {
            outcome = fmt::format("; the fallback to {} stopped: {}", to_string(*fallback), second.summary.message);
          }
        } catch (const SolverFailure& e) {
          outcome = fmt::format("; the fallback to {} was refused: {}", to_string(*fallback), e.what());
        }
      }
      if (fallback_reason.empty()) {
        fe.solution.summary.message = first_failure + outcome;
      }
    }
  }
  const bool certified = certificate && certificate->passed;

  const int elements = d.mesh.elements();
  const int samples = post::capped_samples_per_element(elements, request.samples_per_element);
  post::Fields fields =
      request.fields && certified ? post::sample_fields(model, d, fe.solution, samples) : post::Fields{};
  // Under an axial force the statics are second-order (post/design.hpp: N's moment at the
  // deflected shape, V normal to the undeformed axis).
  const std::optional<post::DesignValues> design =
      certified ? design_values(model, d, fe.solution, *certificate, fields) : std::nullopt;
  io::SolveReport report = io::make_report(scene, model, d, fe.solution, fields, fe.regions);
  report.methods_run = methods_run;
  if (design) io::attach_design(report, *design, model);
  if (!certificate || certified) attach_critical_load(report, model, d, fe.solution);
  report.method_requested = std::string(to_string(method));
  if (!fallback_reason.empty())
    report.method_reason = fallback_reason + (report.method_reason.empty() ? "" : " (" + report.method_reason + ")");
  if (certificate) io::attach_certificate(report, *certificate, model);
  if (certificate && !certified) {
    report.termination = "certificate_failed";
    report.usable = false;
  }
  if (certified) {
    // The round-off, in words, only when it is within a factor ten of the discretisation error.
    const certify::Check* round_off = certificate->find(certify::check_name::round_off);
    if (round_off && round_off->value > 0.1 * round_off->tolerance)
      report.message += fmt::format(
          " (round-off is close to the discretisation error here: {}; fewer elements "
          "would be as accurate)",
          certificate->round_off_note);
  }
  if (certified) {  // exact, whether or not fields were sampled
    const post::DeflectionExtremes x = post::deflection_extremes(d, fe.solution.displacement);
    report.w_max = x.w_max * model.scales.displacement();
    report.at_w_max = model.user_from_s(x.s_at_w_max);
    report.w_min = x.w_min * model.scales.displacement();
    report.at_w_min = model.user_from_s(x.s_at_w_min);
  }
  if (!fields.s.empty() && samples < request.samples_per_element)
    report.message += fmt::format(" (fields sampled at {} points per element, not {}, to stay under {} points)",
                                  samples, request.samples_per_element, max_field_samples);
  report.time_s = seconds_since(start);
  return report;
}

// A report with no answer (usable false), for a refusal of the tolerance.
io::SolveReport refused_report(const scene::Scene& scene, const model::MemberModel& model, Method method,
                               const std::string& termination, const std::string& message) {
  io::SolveReport r;
  r.scene_name = scene.source_name;
  r.scene_text = scene.text;
  r.kind = scene.structure.kind;
  r.coordinate_name = model.kind == model::StructureKind::beam ? "x" : "theta_deg";
  r.tensionless = model.tensionless;
  r.k = model.k;
  r.method = to_string(method == Method::automatic ? Method::fast : method);
  r.method_requested = to_string(method);
  r.termination = termination;
  r.message = message;
  r.usable = false;
  return r;
}

// An FE answer to a tolerance: the node-based solve of `method` on the scene's mesh gives the
// contact topology, then limit-fitted solves on meshes n, 2n, ... until the estimated errors are
// below it (contact/fitted_refinement.hpp); the finest answer is certified like any other (its
// round-off against the sequence's own estimate) and its round-off must be below the tolerance.
io::SolveReport fitted_report(const scene::Scene& scene, Method method, const SolveRequest& request, double tolerance) {
  const auto start = std::chrono::steady_clock::now();
  const model::MemberModel model = model::make_member_model(scene);
  const int elements = request.elements.value_or(scene.solve.elements);
  FeResult node_based = solve_fe(scene, model, method, elements);
  const fe::Discretisation& d0 = node_based.discretisation;
  const contact::ContactSummary& first = node_based.solution.summary;
  if (!first.is_usable()) {
    io::SolveReport r = io::make_report(scene, model, d0, node_based.solution, post::Fields{}, node_based.regions);
    if (!node_based.solver_ran) r.methods_run.clear();
    r.method_requested = std::string(to_string(method));
    r.tolerance = tolerance;
    r.message = fmt::format("the node-based {} solve on {} elements that gives the contact topology failed: {}",
                            to_string(first.method), d0.mesh.elements(), first.message);
    r.time_s = seconds_since(start);
    return r;
  }
  // The contact regions of the node-based answer (a bilateral foundation: its whole extent).
  std::vector<ContactRegion> regions;
  if (!d0.tensionless) {
    for (const auto& [begin, end] : model.foundation_stretches()) regions.push_back({begin, end});
  } else {
    Eigen::VectorXd on_equations(d0.equations);
    for (int dof = 0; dof < d0.dofs(); ++dof)
      if (d0.equation_of_dof[dof] >= 0) on_equations[d0.equation_of_dof[dof]] = node_based.solution.displacement[dof];
    std::vector<bool> in_contact(d0.reactions());
    for (int i = 0; i < d0.reactions(); ++i) in_contact[i] = node_based.solution.reaction[i] > 0.0;
    regions = contact::contact_intervals(model, d0, on_equations, in_contact);
  }
  contact::ToleranceOptions options;
  options.tolerance = tolerance;
  const contact::ToleranceResult refined = contact::refine_to_tolerance(model, 1.0, regions, options);
  std::vector<int> levels;
  for (const auto& level : refined.summary.levels) levels.push_back(level.elements);
  const double user_length = std::abs(model.user_from_s(model.s_end) - model.user_from_s(model.s_begin));
  auto add_accuracy = [&](io::SolveReport& r) {
    r.tolerance = tolerance;
    r.refinement_elements = levels;
    r.limit_fitted = true;
    // The limits' error in the user's coordinate (tolerance and estimates are relative).
    r.estimated_limit_error =
        refined.summary.estimated_limit_error >= 0 ? refined.summary.estimated_limit_error * user_length : -1.0;
    r.estimated_w_error = refined.summary.estimated_w_error;
    r.estimated_reaction_error = refined.summary.estimated_reaction_error;
    r.observed_order = refined.summary.observed_order;
    r.round_off_floor = refined.summary.round_off_floor;
  };
  const std::string how =
      fmt::format("limit-fitted to tolerance {:.1e}: contact topology from {} on {} elements, then limit-fitted meshes",
                  tolerance, to_string(first.method), d0.mesh.elements());
  if (!refined.summary.is_usable()) {
    io::SolveReport r =
        refused_report(scene, model, first.method, "tolerance_not_reached", "refused: " + refined.summary.message);
    r.methods_run = {r.method};  // the node-based solve ran; the limit-fitted solves did not reach the tolerance
    r.method_requested = std::string(to_string(method));
    r.method_reason = how;
    add_accuracy(r);
    r.time_s = seconds_since(start);
    return r;
  }

  // The answer on the fitted discretisation, as a contact solution.
  const contact::FittedResult& answer = refined.answer;
  const fe::Discretisation& d = answer.discretisation;
  contact::ContactSolution solution;
  solution.displacement = d.expand_displacement(answer.state.displacement);
  solution.reaction = answer.state.reaction;
  solution.gap = d.gap_of(solution.reaction, answer.state.displacement);  // T r - C u + c
  contact::ContactSummary& summary = solution.summary;
  summary.termination = contact::ContactTermination::solved;
  summary.method = first.method;
  summary.method_reason = how;
  summary.message = "equilibrium found: " + refined.summary.message;

  summary.time_s = seconds_since(start);

  certify::CertifyOptions certify_options;
  certify_options.discretisation_error =
      std::max(refined.summary.estimated_w_error, refined.summary.estimated_reaction_error);
  // Newton on the limits stops at a step below 1e-14 of the length (fitted_limits.hpp), leaving
  // |w| = |w' step| at the limit nodes: 4e-14 of max |w| on seed_beam_end_moments_central_load at
  // 8192 elements, above 8 times the answer's round-off (2.8e-14). The sign conditions allow the
  // residual the solve's stopping rule left (the certificate recomputes w there).
  certify_options.sign_floor = std::max(answer.summary.limit_residual, 0.0);
  const certify::Certificate certificate = certify::certify(model, d, solution, certify_options);
  if (const certify::Check* backward = certificate.find(certify::check_name::backward_error))
    summary.residual = backward->value;

  // Displayed: w from the answer, the reaction as k max(w - g, 0) on the contact elements (the
  // continuum's law on the converged w: h^4 like w, where the P1 reaction the certificate checks
  // is an L2 projection, h^2).
  const Eigen::VectorXd& all = solution.displacement;
  const bool certified = certificate.passed;
  const int samples = post::capped_samples_per_element(d.mesh.elements(), request.samples_per_element);
  // Sampled whenever certified: an arch's design values come from these samples with the
  // continuum's reaction, asked for in the output or not (else pressure_max would change with
  // --output: the P1 reaction differs by O(h^2)).
  post::Fields fields = certified ? post::sample_fields(model, d, solution, samples) : post::Fields{};
  for (std::size_t i = 0; i < fields.reaction.size(); ++i) {
    const int e = std::min(static_cast<int>(i) / samples, d.mesh.elements() - 1);
    const double xi = std::clamp((fields.s[i] - d.mesh.nodes[e]) / d.mesh.element_size(e), 0.0, 1.0);
    fields.reaction[i] =
        d.reaction_in(e, xi, fields.w[i] - model.ground_gap_in(d.mesh.nodes[e], d.mesh.element_size(e), xi));
  }
  const std::optional<post::DesignValues> design =
      certified ? design_values(model, d, solution, certificate, fields) : std::nullopt;
  if (!request.fields) fields = post::Fields{};
  io::SolveReport report = io::make_report(scene, model, d, solution, fields, answer.contact);
  if (design) io::attach_design(report, *design, model);
  if (certified) attach_critical_load(report, model, d, solution);
  report.method_requested = std::string(to_string(method));
  add_accuracy(report);
  io::attach_certificate(report, certificate, model);
  // Nodal reactions and the extremes as displayed (above).
  const post::DeflectionExtremes x = post::deflection_extremes(d, all, &model);
  const model::Scales& scales = model.scales;
  // Where the reaction jumps (two soils, a step of the gap) a node has two one-sided values, each
  // with its own side's k and g: the table shows the larger, as make_report does.
  for (int node = 0; node <= d.mesh.elements(); ++node) {
    std::optional<double> reaction;
    for (int e : {node - 1, node}) {
      if (e < 0 || e >= d.mesh.elements() || !(d.foundation_on_element[e] || d.element_tension_k[e] > 0.0)) continue;
      const double xi = e < node ? 1.0 : 0.0, g = model.ground_gap_in(d.mesh.nodes[e], d.mesh.element_size(e), xi);
      reaction = std::max(reaction.value_or(-std::numeric_limits<double>::infinity()),
                          d.reaction_in(e, xi, all[d.deflection_dof(node)] - g));
    }
    report.nodes.reaction[node] = reaction.value_or(0.0) * scales.force_per_length();
  }
  report.w_max = x.w_max * scales.displacement();
  report.at_w_max = model.user_from_s(x.s_at_w_max);
  report.w_min = x.w_min * scales.displacement();
  report.at_w_min = model.user_from_s(x.s_at_w_min);
  report.max_reaction = x.contact_reaction_max * scales.force_per_length();
  if (!certified) {
    report.termination = "certificate_failed";
    report.usable = false;
    report.message = fmt::format("the limit-fitted {} answer failed its certificate: {}", to_string(first.method),
                                 certificate.message);
  } else if (certificate.round_off_estimate > tolerance) {
    // The certificate's measured round-off raises the floor (it is far below it on the seed
    // beams: 1e-16 against 4e-14).
    report.round_off_floor = std::max(report.round_off_floor, certificate.round_off_estimate);
    report.termination = "tolerance_not_reached";
    report.usable = false;
    report.message = fmt::format(
        "refused: the tolerance {:.1e} is below the round-off floor {:.1e} of the answer on {} elements (its "
        "round-off, of max |w| or |r|, measured by the certificate)",
        tolerance, report.round_off_floor, d.mesh.elements());
  }
  report.time_s = seconds_since(start);
  return report;
}

// The Ritz topology and initial limits: from the scene, or from an FE + LCP solution.
struct RitzStart {
  ritz::StartingPoint point;
  std::string how;
};

RitzStart ritz_starting_point(const scene::Scene& scene, const model::MemberModel& model, int elements) {
  if (!scene.ritz.topology.empty())
    return {ritz::starting_point_from_scene(scene.ritz, model), "topology from the scene"};
  if (model.theory == model::Theory::von_karman)  // the von Karman contact pattern, not the linear one's
    return {ritz::starting_point_from_regions(von_karman_fe_regions(scene, elements), model),
            fmt::format("topology and initial limits from a von Karman FE solution with {} elements", elements)};
  // The robust sparse solver gives the start (Lemke only when asked for by name).
  const FeResult fe = solve_fe(scene, model, Method::fast, elements);
  if (fe.solution.summary.termination == contact::ContactTermination::unstable_equilibrium)
    throw UnstableEquilibrium(scene.source_name + ": the FE + LCP solution that gives the Ritz topology is unstable: " +
                              fe.solution.summary.message);
  if (!fe.solution.summary.is_usable())
    throw SolverFailure(scene.source_name +
                        ": the FE + LCP solution that gives the Ritz topology failed: " + fe.solution.summary.message);
  return {ritz::starting_point_from_regions(fe.regions, model),
          fmt::format("topology and initial limits from an FE + LCP solution with {} elements",
                      fe.discretisation.mesh.elements())};
}

io::SolveReport ritz_report(const scene::Scene& scene, const SolveRequest& request) {
  const auto start = std::chrono::steady_clock::now();
  const model::MemberModel model = model::make_member_model(scene);
  // Refused before the FE start is solved, naming the key the user wrote (gap or gap_file, ...).
  if (const auto unsupported =
          ritz::unsupported_input(model, scene.foundation.gap_key(), scene.foundation.tension_key()))
    throw InputError(
        fmt::format("{}: key 'solve.method': the Ritz model cannot take this scene ({}); expected an FE "
                    "method (\"dual\", \"primal\", \"fast\" or \"auto\")",
                    scene.source_name, unsupported->message()));
  const int elements = request.elements.value_or(scene.solve.elements);
  const RitzStart starting_point = ritz_starting_point(scene, model, elements);

  ritz::RitzOptions options = ritz::ritz_options_from_scene(scene.ritz, model, request.modes);
  // A tolerance: automatic modes, settled to it (the change from the previous N, its estimate).
  const std::optional<double> tolerance = request.tolerance ? request.tolerance : scene.solve.tolerance;
  if (tolerance) {
    options.modes = 0;
    options.mode_tolerance = *tolerance * model.length();
    options.field_tolerance = *tolerance;
  }
  ritz::RitzSolution solution;
  try {
    solution = ritz::solve_ritz(model, starting_point.point.topology, starting_point.point.limits, options);
  } catch (const MechanismError& e) {
    throw MechanismError(scene.source_name + ": " + e.what());
  } catch (const std::invalid_argument& e) {
    throw InputError(
        fmt::format("{}: key 'solve.method': the Ritz model cannot take this scene ({}); expected an "
                    "FE method (\"dual\", \"primal\", \"fast\" or \"auto\")",
                    scene.source_name, e.what()));
  }
  io::SolveReport report = io::make_report(scene, model, solution, request.samples_per_element * elements + 1);
  report.method_requested = "ritz";
  report.method_reason = starting_point.how;
  if (tolerance) {
    report.tolerance = *tolerance;
    report.estimated_w_error = solution.summary.estimated_w_error;
    report.estimated_reaction_error = solution.summary.estimated_reaction_error;
    if (!solution.summary.is_usable() && solution.summary.termination == ritz::RitzTermination::modes_not_converged) {
      report.termination = "tolerance_not_reached";
      report.message = fmt::format(
          "refused: the tolerance {:.1e} is not reached by the Ritz model within {} modes "
          "([ritz] max_modes): {}",
          *tolerance, options.max_modes, solution.summary.message);
    }
  }
  if (solution.summary.is_usable()) {
    const certify::Certificate certificate = certify::certify(model, solution, options);
    io::attach_certificate(report, certificate, model);
    if (tolerance && certificate.round_off_estimate >= 0) report.round_off_floor = certificate.round_off_estimate;
    // Round-off alone failed, above the tolerance: the modes the tolerance needs cost more
    // round-off than it allows (eps times the Jacobian's condition grows with the modes), so the
    // Ritz model cannot honour it. Refused as such, with what it can honour.
    bool round_off_only = !certificate.passed;
    for (const certify::Check& check : certificate.checks)
      round_off_only &= check.passed || check.name == certify::check_name::round_off;
    if (tolerance && round_off_only && certificate.round_off_estimate > *tolerance) {
      // What it can honour: the round-off with half the modes (one more solve, certified for
      // its round-off only), where the tolerance's own modes left too much.
      const int modes = solution.summary.modes;
      std::string reachable;
      ritz::RitzOptions half = options;
      half.modes = modes / 2;
      if (half.modes >= 1) {
        try {
          const ritz::RitzSolution fewer =
              ritz::solve_ritz(model, starting_point.point.topology, starting_point.point.limits, half);
          certify::CertifyOptions no_half_modes;
          no_half_modes.round_off = false;
          const double floor =
              fewer.summary.is_usable() ? certify::certify(model, fewer, half, no_half_modes).round_off_estimate : -1.0;
          if (floor >= 0) {
            report.round_off_floor = std::min(report.round_off_floor, floor);
            reachable = fmt::format("; with {} modes its round-off is {:.1e}", half.modes, floor);
          }
        } catch (const std::exception&) {  // nothing more to say
        }
      }
      report.termination = "tolerance_not_reached";
      report.usable = false;
      report.message = fmt::format(
          "refused: the tolerance {:.1e} is below the Ritz model's round-off at the {} modes it needs: {}{} (the "
          "round-off, eps times the Jacobian's condition, grows with the modes: the Ritz model honours only "
          "tolerances above it; an FE method with a tolerance solves limit-fitted meshes, whose round-off floor is "
          "far lower)",
          *tolerance, modes, certificate.round_off_note, reachable);
    } else if (!certificate.passed) {
      report.termination = "certificate_failed";
      report.usable = false;
      report.message = "the ritz answer failed its certificate: " + certificate.message;
    }
    // Beams: V and M by statics with the Ritz reaction and the certificate's support reactions
    // (the modal series' own derivatives do not converge at point loads: on the B70 sleeper they
    // gave |V| 46.9 kN against the statics' 70.0 kN). Arches: none (the same series, no statics).
    // Under an axial force these statics would be first-order (post/design.hpp's function-based
    // form has no N y term): none, rather than a moment without N's share.
    if (report.usable && model.kind == model::StructureKind::beam && !model.has_axial_force() &&
        model.theory == model::Theory::linear) {
      std::vector<post::PointReaction> supports;
      for (const certify::SupportReaction& s : certificate.support_reactions)
        supports.push_back({s.at, s.force, s.moment});
      post::Fields f;
      const post::DesignValues design = post::ritz_beam_statics(model, solution, supports, options.load_factor,
                                                                request.samples_per_element * elements + 1, f);
      io::attach_design(report, design, model);
      if (report.fields.coordinate.size() == f.s.size()) {
        for (std::size_t i = 0; i < f.s.size(); ++i) {
          report.fields.shear_force[i] = f.shear_force[i] * model.scales.force();
          report.fields.bending_moment[i] = f.bending_moment[i] * model.scales.moment();
        }
      }
    }
  }
  // Von Karman: the membrane force, uniform in the Ritz model (one value, at midspan; the fields'
  // normal_force carries it at every sample), and stable (solve_ritz refuses an unstable state).
  if (model.theory == model::Theory::von_karman && solution.summary.is_usable() && solution.model) {
    report.theory = "von_karman";
    report.stable = true;
    const double n = solution.model->membrane_force(solution.unknowns) * model.scales.force();
    report.membrane_force = {n};
    report.membrane_force_at = {model.user_from_s(0.5 * (model.s_begin + model.s_end))};
    report.fields.normal_force.assign(report.fields.coordinate.size(), n);
  }
  report.time_s = seconds_since(start);
  return report;
}

// Von Karman kinematics: the table of app/theory_gate.hpp decides which methods run; FE (auto,
// fast) is the load path of app/von_karman_solve_command.hpp, ritz the Ritz model with its
// membrane term.
io::SolveReport solve_von_karman_scene(const scene::Scene& scene, const SolveRequest& request, scene::Method method) {
  const bool from_option = request.method.has_value();
  if (request.tolerance || scene.solve.tolerance)
    require_honoured_theory(scene, Command::solve, Solver::fe_tolerance,
                            request.tolerance ? std::optional<std::string>("option '--tolerance'") : std::nullopt);
  if (method == scene::Method::dual || method == scene::Method::primal)
    require_honoured_theory(scene, Command::solve, Solver::fe_lemke,
                            from_option ? std::optional<std::string>("option '--method'") : std::nullopt);
  if (method == scene::Method::ritz || (method == scene::Method::automatic && !scene.ritz.topology.empty())) {
    require_honoured_theory(scene, Command::solve, Solver::ritz);
    if (scene.ritz.topology.empty()) {
      // The Ritz model solves at the whole load directly, from the von Karman FE answer's contact
      // pattern: that answer must exist, i.e. the load path must reach the whole load. If it
      // meets a limit point, the Ritz answer is refused the same way (a Ritz Newton from there
      // would find some equilibrium of the load, not the loading's).
      SolveRequest path = request;
      path.fields = false;
      io::SolveReport fe = von_karman_fe_report(scene, path, scene::to_string(method));
      if (!fe.usable) {
        io::SolveReport refused = fe;
        refused.method = "ritz";
        refused.method_requested = std::string(scene::to_string(method));
        refused.certificate.reset();
        refused.message = "the von Karman FE load path that gives the Ritz start: " + fe.message;
        return refused;
      }
    }
    io::SolveReport report = ritz_report(scene, request);
    if (method == scene::Method::automatic) {
      report.method_requested = "auto";
      report.method_reason = "ritz: the scene's [ritz] table gives the contact topology (" + report.method_reason + ")";
    }
    return report;
  }
  require_honoured_theory(scene, Command::solve, Solver::fe_fast);
  io::SolveReport report = von_karman_fe_report(scene, request, scene::to_string(method));
  if (method == scene::Method::automatic)
    report.method_reason = "fast: the von Karman FE solve (" + report.method_reason + ")";
  return report;
}

io::SolveReport solve_scene_unscaled(const scene::Scene& scene, const SolveRequest& request) {
  const scene::Method method = request.method.value_or(scene.solve.method);
  if (method == scene::Method::all) throw std::invalid_argument("solve_scene: use solve_all_methods for Method::all");
  if (scene.structure.theory != scene::Theory::linear) return solve_von_karman_scene(scene, request, method);
  if (method == scene::Method::automatic && !scene.ritz.topology.empty()) {
    io::SolveReport report = ritz_report(scene, request);
    report.method_requested = "auto";
    report.method_reason =
        "ritz: the scene's [ritz] table gives the contact topology, so the moving-limit model "
        "applies directly (" +
        report.method_reason + ")";
    return report;
  }
  if (method == scene::Method::ritz) return ritz_report(scene, request);
  const std::optional<double> tolerance = request.tolerance ? request.tolerance : scene.solve.tolerance;
  const contact::Method fe_method = contact::to_contact(method);  // an FE method from here on
  if (tolerance) return fitted_report(scene, fe_method, request, *tolerance);
  return fe_report(scene, fe_method, request);
}

}  // namespace

io::SolveReport solve_scene(const scene::Scene& scene, const SolveRequest& request) {
  // Every report carries the units, the foundation's scale and the warnings (post/scale.hpp).
  io::SolveReport report = solve_scene_unscaled(scene, request);
  io::attach_scale(report, scene, model::make_member_model(scene));
  return report;
}

std::vector<io::SolveReport> solve_all_methods(const scene::Scene& scene, const SolveRequest& request) {
  std::vector<io::SolveReport> reports;
  auto refused = [&](scene::Method method, const std::exception& e) {
    io::SolveReport r;
    r.scene_name = scene.source_name;
    r.kind = scene.structure.kind;
    r.method = scene::to_string(method);
    r.method_requested = r.method;
    r.outcome = io::SolveOutcome::refused;
    r.termination = dynamic_cast<const UnstableEquilibrium*>(&e) != nullptr ? "unstable_equilibrium"
                                                                            : std::string(io::to_string(r.outcome));
    r.message = e.what();
    r.units = scene.units;
    r.warnings = scene.warnings;
    return r;
  };
  for (scene::Method method : {scene::Method::primal, scene::Method::dual, scene::Method::fast, scene::Method::ritz}) {
    // A method the scene's theory is not served by (app/theory_gate.hpp): refused, with the reason.
    const Solver solver = method == scene::Method::ritz   ? Solver::ritz
                          : method == scene::Method::fast ? Solver::fe_fast
                                                          : Solver::fe_lemke;
    if (const std::optional<std::string> reason = theory_refusal(scene, solver)) {
      reports.push_back(
          refused(method, InputError(scene.source_name + ": key '" + refusal_key(scene, solver) + "': " + *reason)));
      continue;
    }
    try {
      SolveRequest one = request;
      one.method = method;
      reports.push_back(solve_scene(scene, one));
    } catch (const MechanismError&) {
      throw;  // no method can help
    } catch (const SolverFailure& e) {
      reports.push_back(refused(method, e));
    } catch (const InputError& e) {  // a scene the Ritz model cannot take
      if (method != scene::Method::ritz) throw;
      reports.push_back(refused(method, e));
    }
  }
  return reports;
}

}  // namespace liftoff::app
