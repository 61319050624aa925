#include "seed_arch/departure.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "contact/contact_solver.hpp"
#include "fe/arch_element.hpp"
#include "model/from_scene.hpp"
#include "post/contact_regions.hpp"

namespace liftoff::study {

namespace {
constexpr double degrees = 180.0 / 3.14159265358979323846;
}

SeedArchStudy::SeedArchStudy(const scene::Scene& scene, int elements) {
  if (scene.structure.kind != scene::StructureKind::arch) throw std::invalid_argument("SeedArchStudy: not an arch");
  if (elements < 2 || elements % 2 != 0) throw std::invalid_argument("SeedArchStudy: an even number of elements");
  linear_model_ = model::make_member_model(scene);
  linear_model_.theory = model::Theory::linear;
  von_karman_model_ = linear_model_;
  von_karman_model_.theory = model::Theory::von_karman;
  discretisation_ = fe::discretise(linear_model_, elements);
  system_ = std::make_unique<contact::VonKarmanSystem>(von_karman_model_, discretisation_);
  crown_node_ = elements / 2;
}

ArchFigures SeedArchStudy::figures(const Eigen::VectorXd& every_dof, double crown_normal_force) const {
  ArchFigures f;
  f.usable = true;
  f.crown_deflection = every_dof[discretisation_.deflection_dof(crown_node_)];
  f.crown_thrust = -crown_normal_force;
  for (int node = 0; node < static_cast<int>(discretisation_.mesh.nodes.size()); ++node)
    f.largest_slope = std::max(f.largest_slope, std::abs(every_dof[discretisation_.slope_dof(node)]));
  const std::vector<ContactRegion> regions = post::contact_regions(von_karman_model_, discretisation_, every_dof);
  f.contact_regions = static_cast<int>(regions.size());
  for (const ContactRegion& r : regions)
    if (r.begin <= 0.0 && r.end >= 0.0) f.half_angle_deg = 0.5 * (r.end - r.begin) * degrees;
  return f;
}

ArchFigures SeedArchStudy::linear(double load_factor) const {
  contact::ContactOptions options;
  options.method = contact::Method::fast;
  options.load_factor = load_factor;
  const contact::ContactSolution solution = contact::solve_contact(discretisation_, options);
  if (!solution.summary.is_usable()) return ArchFigures{false, solution.summary.message};
  // N(0) = EA (u' - sigma w) at the crown, the mean of its two elements' ends (equal to round-off
  // where N is continuous; the FE's N jumps by O(h^3) there).
  double normal_force = 0.0;
  for (const auto& [e, xi] : {std::pair{crown_node_ - 1, 1.0}, std::pair{crown_node_, 0.0}}) {
    const std::vector<int> dofs = discretisation_.element_dofs(e);
    Eigen::Matrix<double, 9, 1> local;
    for (int i = 0; i < 9; ++i) local[i] = solution.displacement[dofs[i]];
    const double h = discretisation_.mesh.element_size(e);
    normal_force += 0.5 * linear_model_.membrane_stiffness *
                    fe::arch_element::membrane_strain_row(xi, h, linear_model_.foundation_outside).dot(local);
  }
  return figures(solution.displacement, normal_force);
}

ArchFigures SeedArchStudy::von_karman(double load_factor, contact::VonKarmanResult* state) const {
  Eigen::VectorXd start;
  std::vector<bool> set;
  if (state != nullptr && state->x.size() == system_->unknowns()) {
    start = state->x;
    set = state->in_contact;
  }
  contact::VonKarmanResult r = system_->solve(load_factor, contact::VonKarmanOptions{}, start, set);
  if (!r.is_usable()) return ArchFigures{false, std::string(contact::to_string(r.termination)) + ": " + r.message};
  const double normal_force =
      0.5 * (system_->normal_force(r.x, crown_node_ - 1, 1.0) + system_->normal_force(r.x, crown_node_, 0.0));
  ArchFigures f = figures(discretisation_.expand_displacement(r.x.head(discretisation_.equations)), normal_force);
  f.stable = r.stable;
  if (state != nullptr) *state = std::move(r);
  return f;
}

double crossing(const SeedArchStudy& study, double (DepartureRow::*difference)() const, double level, double low,
                double high, double resolution, const contact::VonKarmanResult& state_at_low) {
  contact::VonKarmanResult state = state_at_low;
  auto beyond = [&](double lambda, contact::VonKarmanResult* from) {
    const DepartureRow row = study.row(lambda, from);
    if (!row.linear.usable || !row.von_karman.usable)
      throw std::runtime_error("crossing: a solve failed at lambda = " + std::to_string(lambda));
    return std::abs((row.*difference)()) >= level;
  };
  {
    contact::VonKarmanResult probe = state;
    if (beyond(low, &probe)) return std::numeric_limits<double>::quiet_NaN();
    probe = state;
    if (!beyond(high, &probe)) return std::numeric_limits<double>::quiet_NaN();
  }
  while (high - low > resolution) {
    const double middle = 0.5 * (low + high);
    contact::VonKarmanResult trial = state;
    if (beyond(middle, &trial)) {
      high = middle;
    } else {
      low = middle;
      state = std::move(trial);
    }
  }
  return 0.5 * (low + high);
}

}  // namespace liftoff::study
