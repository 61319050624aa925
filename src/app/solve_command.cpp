#include "app/solve_command.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <optional>
#include <stdexcept>

#include "certify/certificate.hpp"
#include "certify/resultant_check.hpp"
#include "contact/contact_solver.hpp"
#include "core/error.hpp"
#include "fe/discretisation.hpp"
#include "fe/member_model.hpp"
#include "post/contact_regions.hpp"
#include "post/fields.hpp"
#include "ritz/ritz_solver.hpp"
#include "ritz/starting_point.hpp"

namespace liftoff::app {

using scene::Method;

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

fe::Discretisation discretise(const scene::Scene& scene, const fe::MemberModel& model, int elements) {
  try {
    return fe::discretise(model, elements);
  } catch (const MechanismError& e) {
    throw MechanismError(scene.source_name + ": " + e.what());
  }
}

struct FeResult {
  fe::Discretisation discretisation;
  contact::ContactSolution solution;
  std::vector<post::Interval> regions;
};

// The answer of one formulation on a discretisation: no_equilibrium at once when the resultant
// cannot be balanced by compressive foundation reactions (certify/resultant_check.hpp), else the
// contact solve. Throws SolverFailure (a refused formulation) with the scene's name.
contact::ContactSolution contact_answer(const scene::Scene& scene, const fe::MemberModel& model,
                                        const fe::Discretisation& d, Method method) {
  const certify::ResultantCheck resultant = certify::check_resultant(model, d);
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
  try {
    return contact::solve_contact(d, options);
  } catch (const SolverFailure& e) {
    throw SolverFailure(scene.source_name + ": " + e.what());
  }
}

FeResult solve_fe(const scene::Scene& scene, const fe::MemberModel& model, Method method, int elements) {
  FeResult fe;
  fe.discretisation = discretise(scene, model, elements);
  fe.solution = contact_answer(scene, model, fe.discretisation, method);
  fe.regions = post::contact_regions(model, fe.discretisation, fe.solution.displacement);
  return fe;
}

// Where a formulation whose answer failed its certificate falls back: fast (or an auto that ran
// fast) -> Lemke, dual where the structure is stable, else primal, if the dense LCP fits; dual or
// primal -> fast. Nothing when the answer already came from a fallback inside the solver.
std::optional<Method> fallback_for(Method produced, Method requested, const fe::Discretisation& d) {
  if (produced == Method::fast) {
    const Method lemke = d.structure_is_stable() ? Method::dual : Method::primal;
    const int size = lemke == Method::dual ? d.reactions() : 2 * d.equations + d.reactions();
    if (size > contact::max_dense_lcp) return std::nullopt;
    return lemke;
  }
  if (requested == Method::fast || requested == Method::automatic) return std::nullopt;  // fast already failed
  return Method::fast;
}

std::string check_failure(const contact::ContactSummary& summary, const certify::Certificate& certificate) {
  return fmt::format("the {} answer failed its certificate: {}", scene::to_string(summary.method), certificate.message);
}

io::SolveReport fe_report(const scene::Scene& scene, Method method, const SolveRequest& request) {
  const auto start = std::chrono::steady_clock::now();
  const fe::MemberModel model = fe::make_member_model(scene);
  FeResult fe = solve_fe(scene, model, method, request.elements.value_or(scene.solve.elements));
  const fe::Discretisation& d = fe.discretisation;

  // The certificate; a failed one means a fallback, or a failure that names the check.
  std::optional<certify::Certificate> certificate;
  std::string fallback_reason;
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
          if (second.summary.is_usable()) {
            certify::Certificate second_certificate = certify::certify(model, d, second);
            if (second_certificate.passed) {
              fallback_reason = fmt::format("{}; fell back to {}", first_failure, scene::to_string(*fallback));
              fe.solution = std::move(second);
              fe.regions = post::contact_regions(model, d, fe.solution.displacement);
              certificate = std::move(second_certificate);
            } else {
              outcome = fmt::format("; the fallback to {} failed its certificate too: {}", scene::to_string(*fallback),
                                    second_certificate.message);
            }
          } else {
            outcome =
                fmt::format("; the fallback to {} stopped: {}", scene::to_string(*fallback), second.summary.message);
          }
        } catch (const SolverFailure& e) {
          outcome = fmt::format("; the fallback to {} was refused: {}", scene::to_string(*fallback), e.what());
        }
      }
      if (fallback_reason.empty()) {
        fe.solution.summary.message = first_failure + outcome;
      }
    }
  }
  const bool certified = certificate && certificate->passed;

  const int elements = d.mesh.elements();
  const int samples = std::max(1, std::min(request.samples_per_element, max_field_samples / elements));
  const post::Fields fields =
      request.fields && certified ? post::sample_fields(model, d, fe.solution, samples) : post::Fields{};
  io::SolveReport report = io::make_report(scene, model, d, fe.solution, fields, fe.regions);
  report.method_requested = std::string(scene::to_string(method));
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
  if (fields.s.empty() && certified) {
    const post::DeflectionExtremes x =
        post::deflection_extremes(d, fe.solution.displacement, request.samples_per_element);
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

// The Ritz topology and initial limits: from the scene, or from an FE + LCP solution.
struct RitzStart {
  ritz::StartingPoint point;
  std::string how;
};

RitzStart ritz_starting_point(const scene::Scene& scene, const fe::MemberModel& model, int elements) {
  if (!scene.ritz.topology.empty())
    return {ritz::starting_point_from_scene(scene.ritz, model), "topology from the scene"};
  // The robust sparse solver gives the start (Lemke only when asked for by name).
  const FeResult fe = solve_fe(scene, model, Method::fast, elements);
  if (!fe.solution.summary.is_usable())
    throw SolverFailure(scene.source_name +
                        ": the FE + LCP solution that gives the Ritz topology failed: " + fe.solution.summary.message);
  return {ritz::starting_point_from_regions(fe.regions, model),
          fmt::format("topology and initial limits from an FE + LCP solution with {} elements",
                      fe.discretisation.mesh.elements())};
}

io::SolveReport ritz_report(const scene::Scene& scene, const SolveRequest& request) {
  const auto start = std::chrono::steady_clock::now();
  const fe::MemberModel model = fe::make_member_model(scene);
  const int elements = request.elements.value_or(scene.solve.elements);
  const RitzStart starting_point = ritz_starting_point(scene, model, elements);

  ritz::RitzOptions options;
  options.modes = request.modes.value_or(scene.ritz.modes);
  options.max_modes = scene.ritz.max_modes;
  options.mode_tolerance = scene.ritz.mode_tolerance * model.length();
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
  if (solution.summary.is_usable()) {
    const certify::Certificate certificate = certify::certify(model, solution, options);
    io::attach_certificate(report, certificate, model);
    if (!certificate.passed) {
      report.termination = "certificate_failed";
      report.usable = false;
      report.message = "the ritz answer failed its certificate: " + certificate.message;
    }
  }
  report.time_s = seconds_since(start);
  return report;
}

}  // namespace

io::SolveReport solve_scene(const scene::Scene& scene, const SolveRequest& request) {
  const Method method = request.method.value_or(scene.solve.method);
  if (method == Method::all) throw std::invalid_argument("solve_scene: use solve_all_methods for Method::all");
  if (method == Method::automatic && !scene.ritz.topology.empty()) {
    io::SolveReport report = ritz_report(scene, request);
    report.method_requested = "auto";
    report.method_reason =
        "ritz: the scene's [ritz] table gives the contact topology, so the moving-limit model "
        "applies directly (" +
        report.method_reason + ")";
    return report;
  }
  return method == Method::ritz ? ritz_report(scene, request) : fe_report(scene, method, request);
}

std::vector<io::SolveReport> solve_all_methods(const scene::Scene& scene, const SolveRequest& request) {
  std::vector<io::SolveReport> reports;
  auto refused = [&](Method method, const std::exception& e) {
    io::SolveReport r;
    r.scene_name = scene.source_name;
    r.kind = scene.structure.kind;
    r.method = scene::to_string(method);
    r.method_requested = r.method;
    r.termination = "refused";
    r.message = e.what();
    return r;
  };
  for (Method method : {Method::primal, Method::dual, Method::fast, Method::ritz}) {
    try {
      SolveRequest one = request;
      one.method = method;
      reports.push_back(solve_scene(scene, one));
    } catch (const MechanismError&) {
      throw;  // no method can help
    } catch (const SolverFailure& e) {
      reports.push_back(refused(method, e));
    } catch (const InputError& e) {  // a scene the Ritz model cannot take
      if (method != Method::ritz) throw;
      reports.push_back(refused(method, e));
    }
  }
  return reports;
}

}  // namespace liftoff::app
