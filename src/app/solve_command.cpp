#include "app/solve_command.hpp"

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include <fmt/format.h>

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

FeResult solve_fe(const scene::Scene& scene, const fe::MemberModel& model, Method method, int elements) {
  FeResult fe;
  fe.discretisation = discretise(scene, model, elements);
  contact::ContactOptions options;
  options.method = method;
  try {
    fe.solution = contact::solve_contact(fe.discretisation, options);
  } catch (const SolverFailure& e) {
    throw SolverFailure(scene.source_name + ": " + e.what());
  }
  fe.regions = post::contact_regions(model, fe.discretisation, fe.solution.displacement);
  return fe;
}

io::SolveReport fe_report(const scene::Scene& scene, Method method, const SolveRequest& request) {
  const auto start = std::chrono::steady_clock::now();
  const fe::MemberModel model = fe::make_member_model(scene);
  const FeResult fe = solve_fe(scene, model, method, request.elements.value_or(scene.solve.elements));
  const int elements = fe.discretisation.mesh.elements();
  const int samples = std::max(1, std::min(request.samples_per_element, max_field_samples / elements));
  const post::Fields fields = request.fields && fe.solution.summary.is_usable()
                                  ? post::sample_fields(model, fe.discretisation, fe.solution, samples)
                                  : post::Fields{};
  io::SolveReport report = io::make_report(scene, model, fe.discretisation, fe.solution, fields, fe.regions);
  if (fields.s.empty() && fe.solution.summary.is_usable()) {
    const post::DeflectionExtremes x =
        post::deflection_extremes(fe.discretisation, fe.solution.displacement, request.samples_per_element);
    report.w_max = x.w_max * model.scales.displacement();
    report.at_w_max = model.user_from_s(x.s_at_w_max);
    report.w_min = x.w_min * model.scales.displacement();
    report.at_w_min = model.user_from_s(x.s_at_w_min);
  }
  if (!fields.s.empty() && samples < request.samples_per_element)
    report.message += fmt::format(" (fields sampled at {} points per element, not {}, to stay under {} points)", samples,
                                  request.samples_per_element, max_field_samples);
  report.time_s = seconds_since(start);
  return report;
}

// The Ritz topology and initial limits: from the scene, or from an FE + LCP solution.
struct RitzStart {
  ritz::StartingPoint point;
  std::string how;
};

RitzStart ritz_starting_point(const scene::Scene& scene, const fe::MemberModel& model, int elements) {
  if (!scene.ritz.topology.empty()) return {ritz::starting_point_from_scene(scene.ritz, model), "topology from the scene"};
  const FeResult fe = solve_fe(scene, model, Method::automatic, elements);
  if (!fe.solution.summary.is_usable())
    throw SolverFailure(scene.source_name + ": the FE + LCP solution that gives the Ritz topology failed: " +
                        fe.solution.summary.message);
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
    throw InputError(fmt::format("{}: key 'solve.method': the Ritz model cannot take this scene ({}); expected an "
                                 "FE method (\"dual\", \"primal\", \"fast\" or \"auto\")",
                                 scene.source_name, e.what()));
  }
  io::SolveReport report = io::make_report(scene, model, solution, request.samples_per_element * elements + 1);
  report.method_reason = starting_point.how;
  report.time_s = seconds_since(start);
  return report;
}

}  // namespace

io::SolveReport solve_scene(const scene::Scene& scene, const SolveRequest& request) {
  const Method method = request.method.value_or(scene.solve.method);
  if (method == Method::all) throw std::invalid_argument("solve_scene: use solve_all_methods for Method::all");
  if (method == Method::automatic && !scene.ritz.topology.empty()) {
    io::SolveReport report = ritz_report(scene, request);
    report.method_reason = "ritz: the scene's [ritz] table gives the contact topology, so the moving-limit model "
                           "applies directly (" + report.method_reason + ")";
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
