#include "continuation/models/fe_states.hpp"

#include <algorithm>
#include <utility>

#include "certify/certificate.hpp"
#include "contact/contact_solver.hpp"
#include "post/contact_regions.hpp"
#include "post/fields.hpp"

namespace liftoff::continuation::fe_states {

TraceStep step_of(const model::MemberModel& model, const fe::Discretisation& d, const SpecialPoints& points,
                  const TraceOptions& options, double lambda, const Eigen::VectorXd& displacement,
                  const Eigen::VectorXd& reaction, const std::vector<bool>& set) {
  TraceStep step;
  step.load_factor = lambda;
  for (const auto& region : post::contact_regions(model, d, displacement))
    step.contact_regions.push_back({model.user_from_s(region.begin), model.user_from_s(region.end)});
  auto at = [&](double user) {
    const double s = std::clamp(model.s_from_user(user), model.s_begin, model.s_end);
    const int e = d.mesh.element_containing(s);
    return std::pair{e, (s - d.mesh.nodes[e]) / d.mesh.element_size(e)};
  };
  const model::Scales& scales = model.scales;
  const auto [me, mxi] = at(options.monitor);
  step.monitor_deflection = post::evaluate(d, displacement, me, mxi).w * scales.displacement();
  for (double x : options.sample_points) {
    const auto [e, xi] = at(x);
    step.deflection.push_back(post::evaluate(d, displacement, e, xi).w * scales.displacement());
    step.reaction.push_back(post::reaction_at(d, reaction, e, xi) * scales.force_per_length());
  }
  const LiftMeasures lift = lift_measures(model, d, displacement, points);
  step.amplitude = lift.amplitude;
  step.lifted_length = lift.lifted_length;
  step.state_topology = continuation::FeContactSet{};
  step.state.assign(set.begin(), set.end());
  step.state.resize(set.size() + fe_state_tail, 0.0);
  return step;
}

certify::Certificate certificate_of(const model::MemberModel& model, const fe::Discretisation& d, double lambda,
                                    const Eigen::VectorXd& displacement, const Eigen::VectorXd& reaction,
                                    double sign_floor) {
  contact::ContactSolution answer;
  answer.displacement = displacement;
  answer.reaction = reaction;
  certify::CertifyOptions options;
  options.load_factor = lambda;
  options.round_off = false;
  options.backward_tolerance = acceptable_residual;  // the path's own acceptance
  options.pointwise = false;                         // at the nodes (the discrete conditions), see CertifyOptions
  options.sign_floor = std::max(acceptable_residual, sign_floor);  // its states' accuracy decides signs no finer
  options.global_scale = true;                                     // as the path's own scales
  return certify::certify(model, d, answer, options);
}

contact::ContactSolution contact_solve(const fe::Discretisation& d, contact::Method asked, double lambda) {
  contact::ContactOptions options;
  options.method = asked == contact::Method::dual || asked == contact::Method::primal ? asked : contact::Method::fast;
  options.load_factor = lambda;
  return contact::solve_contact(d, options);
}

std::vector<bool> contact_set_of(const fe::Discretisation& d, const contact::ContactSolution& solution) {
  const double r_scale = std::max(solution.reaction.lpNorm<Eigen::Infinity>(), 1e-300);
  const double g_scale = std::max((d.flexibility * solution.reaction).lpNorm<Eigen::Infinity>(), 1e-300);
  std::vector<bool> set(d.reactions());
  for (int i = 0; i < d.reactions(); ++i) set[i] = solution.reaction[i] / r_scale > solution.gap[i] / g_scale;
  return set;
}

}  // namespace liftoff::continuation::fe_states
