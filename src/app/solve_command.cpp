#include "app/solve_command.hpp"

#include <chrono>

#include "contact/contact_solver.hpp"
#include "core/error.hpp"
#include "fe/discretisation.hpp"
#include "fe/member_model.hpp"
#include "post/contact_regions.hpp"
#include "post/fields.hpp"

namespace liftoff::app {

io::SolveReport solve_scene(const scene::Scene& scene, const SolveRequest& request) {
  const auto start = std::chrono::steady_clock::now();
  const fe::MemberModel model = fe::make_member_model(scene);
  const int elements = request.elements.value_or(scene.solve.elements);

  fe::Discretisation discretisation;
  try {
    discretisation = fe::discretise(model, elements);
  } catch (const MechanismError& e) {
    throw MechanismError(scene.source_name + ": " + e.what());
  }

  contact::ContactOptions options;
  options.method = request.method.value_or(scene.solve.method);
  contact::ContactSolution solution;
  try {
    solution = contact::solve_contact(discretisation, options);
  } catch (const SolverFailure& e) {
    throw SolverFailure(scene.source_name + ": " + e.what());
  }

  const post::Fields fields = post::sample_fields(model, discretisation, solution, request.samples_per_element);
  const auto regions = post::contact_regions(model, discretisation, solution.displacement);
  io::SolveReport report = io::make_report(scene, model, discretisation, solution, fields, regions);
  report.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace liftoff::app
