#include "continuation/step_state.hpp"

#include <algorithm>
#include <optional>
#include <vector>

#include "contact/contact_solver.hpp"
#include "post/design.hpp"
#include "post/fields.hpp"
#include "post/ritz_fields.hpp"

namespace liftoff::continuation {

namespace {

using FieldMember = std::vector<double> post::Fields::*;
constexpr FieldMember field_members[] = {
    &post::Fields::s,           &post::Fields::w,        &post::Fields::rotation, &post::Fields::bending_moment,
    &post::Fields::shear_force, &post::Fields::reaction, &post::Fields::u,        &post::Fields::normal_force};

// One value per node of post::sample_fields(..., 1 sample per element, ...): a node where the
// reaction jumps has two samples there (the left element's end, then the right one's start): the
// right one's values, but the larger reaction (solve's node table, io::make_report).
post::Fields one_per_node(const post::Fields& samples) {
  post::Fields nodes;
  for (std::size_t i = 0; i < samples.s.size(); ++i) {
    const bool repeated = !nodes.s.empty() && samples.s[i] == nodes.s.back();
    const double reaction = repeated ? std::max(nodes.reaction.back(), samples.reaction[i]) : samples.reaction[i];
    for (FieldMember field : field_members) {
      if ((samples.*field).empty()) continue;
      if (repeated)
        (nodes.*field).back() = (samples.*field)[i];
      else
        (nodes.*field).push_back((samples.*field)[i]);
    }
    nodes.reaction.back() = reaction;
  }
  return nodes;
}

// Every `stride`-th sample (the grid inside solve's finer one).
post::Fields every(const post::Fields& samples, int stride) {
  post::Fields out;
  for (FieldMember field : field_members)
    for (std::size_t i = 0; i < (samples.*field).size(); i += stride) (out.*field).push_back((samples.*field)[i]);
  return out;
}

std::vector<post::PointReaction> point_reactions(const std::vector<certify::SupportReaction>& reactions) {
  std::vector<post::PointReaction> points;
  for (const certify::SupportReaction& r : reactions) points.push_back({r.at, r.force, r.moment});
  return points;
}

// The step's record from nondimensional fields (one value per point), design values and support
// reactions: converted, with the gap and (beams without a membrane force of their own) N = -N(lambda).
void fill(TraceStep& step, const model::MemberModel& model, const post::Fields& fields,
          const std::optional<post::DesignValues>& design, const std::vector<certify::SupportReaction>& supports,
          double lambda) {
  post::FieldTable table = post::user_fields(model, fields);
  const double length = model.scales.displacement();
  table.gap.resize(fields.s.size());
  for (std::size_t i = 0; i < fields.s.size(); ++i)
    table.gap[i] =
        model.k_at(fields.s[i]) > 0.0 ? std::max(0.0, model.ground_gap(fields.s[i]) - fields.w[i]) * length : 0.0;
  if (table.normal_force.empty())
    table.normal_force.assign(fields.s.size(), model.kind == model::StructureKind::beam
                                                   ? -model.axial_force(lambda) * model.scales.force()
                                                   : 0.0);
  step.fields = std::move(table);
  step.design = design ? std::optional(post::user_design(*design, model)) : std::nullopt;
  step.supports = certify::user_support_reactions(supports, model);
}

contact::ContactSolution answer_of(const Eigen::VectorXd& displacement, const Eigen::VectorXd& reaction) {
  contact::ContactSolution solution;
  solution.displacement = displacement;
  solution.reaction = reaction;
  return solution;
}

// Fields sampled as solve samples an FE answer for its arch design values.
post::Fields solve_samples(const model::MemberModel& model, const fe::Discretisation& d,
                           const contact::ContactSolution& solution, double lambda) {
  return post::sample_fields(model, d, solution, post::capped_samples_per_element(d.mesh.elements()), lambda);
}

}  // namespace

void record_fe_state(TraceStep& step, const model::MemberModel& model, const fe::Discretisation& d, double lambda,
                     const Eigen::VectorXd& displacement, const Eigen::VectorXd& reaction,
                     const certify::Certificate& certificate) {
  const contact::ContactSolution solution = answer_of(displacement, reaction);
  post::Fields nodes = post::sample_fields(model, d, solution, 1, lambda);
  // Beams: V and M by the statics of the free body, at the nodes too (as solve's samples).
  const post::DesignValues design =
      model.kind == model::StructureKind::beam
          ? post::recover_beam_statics(model, d, solution, point_reactions(certificate.support_reactions), lambda,
                                       &nodes)
          : post::design_from_samples(model, solve_samples(model, d, solution, lambda));
  fill(step, model, one_per_node(nodes), design, certificate.support_reactions, lambda);
}

void record_von_karman_state(TraceStep& step, const model::MemberModel& model, const fe::Discretisation& d,
                             double lambda, const certify::VonKarmanAnswer& answer,
                             const certify::Certificate* certificate) {
  const contact::ContactSolution solution = answer_of(answer.displacement, answer.reaction);
  post::Fields nodes = one_per_node(post::sample_fields(model, d, solution, 1, lambda));
  post::add_von_karman_membrane(model, d, answer.normal_force, nodes);
  if (model.kind == model::StructureKind::beam)  // u at the nodes (the elements' interior u is condensed out)
    nodes.u.assign(answer.axial.data(), answer.axial.data() + answer.axial.size());
  const post::DesignValues design = post::design_from_samples(model, solve_samples(model, d, solution, lambda));
  fill(step, model, nodes, design,
       certificate ? certificate->support_reactions : std::vector<certify::SupportReaction>{}, lambda);
}

void record_ritz_state(TraceStep& step, const model::MemberModel& member, const ritz::RitzModel& ritz,
                       const Eigen::VectorXd& x, double lambda, int elements) {
  const std::vector<certify::SupportReaction> supports = certify::ritz_support_reactions(member, ritz, x, lambda);
  post::Fields grid;
  std::optional<post::DesignValues> design;
  // As solve: statics for a linear beam free of axial force only (its function-based statics are
  // first order), on solve's samples, of which the grid is every samples_per_element-th.
  if (member.kind == model::StructureKind::beam && !member.has_axial_force() &&
      member.theory == model::Theory::linear) {
    post::Fields samples;
    design = post::ritz_beam_statics(member, ritz, x, point_reactions(supports), lambda,
                                     post::samples_per_element * elements + 1, samples);
    grid = every(samples, post::samples_per_element);
  } else {
    grid = post::sample_fields(member, ritz, x, elements + 1);
  }
  // Von Karman beams: the membrane force, uniform in the Ritz model (as solve reports it).
  if (member.theory == model::Theory::von_karman && member.kind == model::StructureKind::beam)
    grid.normal_force.assign(grid.s.size(), ritz.membrane_force(x));
  fill(step, member, grid, design, supports, lambda);
}

}  // namespace liftoff::continuation
