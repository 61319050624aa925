#include "contact/active_set_solver.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <unordered_set>

#include "core/enum_names.hpp"
#include "core/require.hpp"
#include "fe/shape_functions.hpp"

namespace liftoff::contact {

using Eigen::VectorXd;

namespace {
constexpr EnumName<ActiveSetTermination> active_set_termination_names[] = {
    {ActiveSetTermination::solved, "solved"},
    {ActiveSetTermination::iteration_limit, "iteration_limit"},
    {ActiveSetTermination::cycling, "cycling"},
    {ActiveSetTermination::singular_system, "singular_system"},
};
}  // namespace

std::string_view to_string(ActiveSetTermination t) {
  return name_in<ActiveSetTermination>(active_set_termination_names, t);
}

void ActiveSetOptions::validate() const {
  require(max_iterations >= 1, "ActiveSetOptions::max_iterations", "must be at least 1");
  require(block_retries >= -1, "ActiveSetOptions::block_retries", "must be -1 (no safeguard) or >= 0");
  require(sign_tolerance >= 0.0 && sign_tolerance < 1e-3, "ActiveSetOptions::sign_tolerance", "must be in [0, 1e-3)");
  require(intermediate_error >= 0.0 && intermediate_error <= 1e-6, "ActiveSetOptions::intermediate_error",
          "must be in [0, 1e-6]");
}

namespace {

// Signs are trusted only beyond this multiple of the solve's estimated relative error.
constexpr double round_off_margin = 10.0;
// A set's solve whose refinement leaves more than this is no basis for a step (as the
// acceptable error of contact_solver.cpp).
constexpr double max_solve_error = 1e-6;
// ActiveSetOptions::unrefined_first_set: signs wrong by more than this (relative, as
// sign_tolerance) are trusted from an unrefined solve (the mixed form's round-off before
// refinement is ~eps N^2, 1e-8 at 1e4 elements).
constexpr double unrefined_sign_tolerance = 1e-6;

// Nodes on the wrong side: in contact with r < 0, or lifted off with gap < 0 (ascending).
std::vector<int> infeasible_nodes(const fe::Discretisation& d, const ContactState& state,
                                  const std::vector<bool>& in_contact, double tolerance) {
  const double reaction_scale = state.reaction.lpNorm<Eigen::Infinity>();
  const VectorXd coupled = d.coupling * state.displacement;
  const double gap_scale = std::max({coupled.lpNorm<Eigen::Infinity>(), state.gap.lpNorm<Eigen::Infinity>(),
                                     d.ground_gap.size() == 0 ? 0.0 : d.ground_gap.lpNorm<Eigen::Infinity>()});
  std::vector<int> nodes;
  for (int i = 0; i < static_cast<int>(in_contact.size()); ++i) {
    const bool wrong =
        in_contact[i] ? state.reaction[i] < -tolerance * reaction_scale : state.gap[i] < -tolerance * gap_scale;
    if (wrong) nodes.push_back(i);
  }
  return nodes;
}

}  // namespace

ActiveSetResult solve_active_set(const fe::Discretisation& d, const VectorXd& load, const ActiveSetOptions& options,
                                 std::vector<bool> initial, const VectorXd& gap_offset) {
  options.validate();
  const int m = d.reactions();
  if (gap_offset.size() == 0 && d.has_ground_gap())
    throw std::invalid_argument("solve_active_set: the discretisation has a ground gap, and no gap offset was given");
  const VectorXd offset = gap_offset.size() == 0 ? VectorXd::Zero(m) : gap_offset;
  if (load.size() != d.equations) throw std::invalid_argument("solve_active_set: one load per equation expected");
  if (initial.empty()) initial.assign(m, true);
  if (static_cast<int>(initial.size()) != m)
    throw std::invalid_argument("solve_active_set: one initial contact flag per reaction node expected");

  ActiveSetResult result;
  ActiveSetSummary& summary = result.summary;
  summary.iterations = summary.block_steps = summary.single_steps = 0;
  ActiveSetSystem system(d);
  std::unordered_set<std::vector<bool>> seen;

  std::vector<bool> in_contact = std::move(initial);
  std::vector<bool> last_good;       // the last set that factorised
  std::vector<int> last_infeasible;  // and its infeasible nodes
  int best = std::numeric_limits<int>::max();
  int retries = options.block_retries;
  bool singular_retry = false;

  summary.termination = ActiveSetTermination::iteration_limit;
  while (summary.iterations < options.max_iterations) {
    ++summary.iterations;
    const bool revisit = !seen.insert(in_contact).second;
    if (revisit && options.block_retries < 0) {
      summary.termination = ActiveSetTermination::cycling;
      summary.message = fmt::format("plain block pivoting came back to a contact set after {} sets (cycling)",
                                    summary.iterations - 1);
      break;
    }
    // A set that leaves a rigid motion free (or nearly: refinement cannot solve it) gives no
    // signs to trust: go back and take one single step instead.
    const bool factorised = system.factorise(in_contact);
    RefinementOptions refinement;
    refinement.target_error = options.intermediate_error;
    refinement.residual = false;
    if (factorised && options.unrefined_first_set && summary.iterations == 1) {
      RefinementOptions unrefined;
      unrefined.max_steps = 0;
      unrefined.residual = false;
      const ContactState rough = system.solve(load, offset, unrefined);
      std::vector<int> clearly_wrong = infeasible_nodes(d, rough, in_contact, unrefined_sign_tolerance);
      if (!clearly_wrong.empty()) {
        // A block step on those nodes alone; the count (at this looser tolerance) is no best.
        result.state = rough;
        summary.infeasible_history.push_back(static_cast<int>(clearly_wrong.size()));
        last_good = in_contact;
        last_infeasible = clearly_wrong;
        for (int i : clearly_wrong) in_contact[i] = !in_contact[i];
        ++summary.block_steps;
        continue;
      }
      result.state = system.refine_last_solve(refinement);  // as solve() would have: the same steps
    } else if (factorised) {
      result.state = system.solve(load, offset, refinement);
    }
    if (!factorised || !(result.state.error_estimate <= max_solve_error)) {
      if (last_good.empty() || singular_retry) {
        summary.termination = ActiveSetTermination::singular_system;
        summary.message = factorised
                              ? fmt::format(
                                    "refinement could not solve a contact set's system (relative error {:.1e}): the "
                                    "set leaves a rigid motion nearly free, or round-off owns this mesh",
                                    result.state.error_estimate)
                              : "a contact set left a rigid motion free (singular system) and no single step helped";
        break;
      }
      singular_retry = true;
      in_contact = last_good;
      in_contact[last_infeasible.back()] = !in_contact[last_infeasible.back()];
      ++summary.single_steps;
      continue;
    }
    singular_retry = false;
    // A sign below the solver's round-off is no evidence: such a node touches (r = gap = 0).
    // (The data's round-off, data_error(), is a worst-case bound, far too wide for this.)
    double tolerance = std::max(options.sign_tolerance, round_off_margin * result.state.error_estimate);
    std::vector<int> infeasible = infeasible_nodes(d, result.state, in_contact, tolerance);
    if (infeasible.empty() && options.refine_answer) {
      // The set found: its answer to round-off (refinement continued from where the set's own
      // stopped, unless it is there already), and its signs checked again at that accuracy.
      if (result.state.error_estimate > 1e-13)
        result.state = system.refine_last_solve();
      else
        result.state.residual = system.residual_of_last_solve();
      tolerance = std::max(options.sign_tolerance, round_off_margin * result.state.error_estimate);
      infeasible = infeasible_nodes(d, result.state, in_contact, tolerance);
    }
    summary.infeasible_history.push_back(static_cast<int>(infeasible.size()));
    if (infeasible.empty()) {
      if (options.estimate_round_off) result.round_off_bound = system.data_error(result.state, load);
      summary.termination = ActiveSetTermination::solved;
      summary.message = fmt::format("contact set found after {} sets ({} block, {} single steps)", summary.iterations,
                                    summary.block_steps, summary.single_steps);
      break;
    }
    last_good = in_contact;
    last_infeasible = infeasible;
    const int count = static_cast<int>(infeasible.size());
    bool block = true;
    if (options.block_retries >= 0) {
      if (count < best) {
        best = count;
        retries = options.block_retries;
      } else if (retries > 0 && !revisit) {
        --retries;
      } else {
        block = false;
      }
    }
    if (block) {
      for (int i : infeasible) in_contact[i] = !in_contact[i];
      ++summary.block_steps;
    } else {
      in_contact[infeasible.back()] = !in_contact[infeasible.back()];  // Murty: the largest index
      ++summary.single_steps;
    }
  }
  if (summary.termination == ActiveSetTermination::iteration_limit)
    summary.message = fmt::format("no contact set found in {} sets ({} infeasible nodes left)", summary.iterations,
                                  summary.infeasible_history.empty() ? -1 : summary.infeasible_history.back());
  result.in_contact = system.in_contact();
  summary.factorisations = system.factorisations();
  return result;
}

void NestedOptions::validate() const {
  require(coarsening >= 2, "NestedOptions::coarsening", "must be at least 2");
  require(min_elements >= 1, "NestedOptions::min_elements", "must be at least 1");
  require(elements_per_decay_length > 0.0, "NestedOptions::elements_per_decay_length", "must be positive");
}

namespace {

// The contact set on `fine` that a coarse answer suggests: a reaction node is in contact where the
// coarse deflection (its Hermite cubic, the first four local dofs of both element kinds) exceeds the ground gap g.
// A node where w = g exactly (a support holds w there, e.g. a pinned end on the ground) has no
// sign of its own: its reaction is an O(h^2) artefact of either sign. It takes the coarse answer's
// own status at that node (a support is a node of every mesh; the coarse sign test decided the
// same artefact), or else the sign of the mean of w - g over its half-elements (their midpoints,
// weighted by their lengths: what C and c test). Read as w > g, the long member's pinned ends cost
// a whole second fine set.
std::vector<bool> carried_contact_set(const model::MemberModel& model, const fe::Discretisation& coarse,
                                      const ActiveSetResult& coarse_answer, const fe::Discretisation& fine) {
  const VectorXd all = coarse.expand_displacement(coarse_answer.state.displacement);
  int e = 0;  // the fine reaction nodes are in order along the member: walk the coarse elements once
  std::vector<int> dofs = coarse.element_dofs(e);
  auto w_minus_g = [&](double s) {
    const int containing = coarse.mesh.element_containing(s);
    if (containing != e) {
      e = containing;
      dofs = coarse.element_dofs(e);
    }
    const double h = coarse.mesh.element_size(e);
    const Eigen::Vector4d w_dofs(all[dofs[0]], all[dofs[1]], all[dofs[2]], all[dofs[3]]);
    const double xi = std::clamp((s - coarse.mesh.nodes[e]) / h, 0.0, 1.0);
    return fe::hermite_cubic(xi, h).value.dot(w_dofs) - model.ground_gap(s);
  };
  const std::vector<double>& nodes = fine.mesh.nodes;
  std::vector<bool> in_contact(fine.reactions());
  for (int i = 0; i < fine.reactions(); ++i) {
    const int node = fine.reaction_nodes[i];
    const double s = nodes[node];
    const double here = w_minus_g(s);
    if (here != 0.0) {
      in_contact[i] = here > 0.0;
      continue;
    }
    // A split reaction (a jump of k or g) tests only its own element: the left one first.
    const bool split = fine.reaction_is_split(i);
    const bool left_only = split && i + 1 < fine.reactions() && fine.reaction_nodes[i + 1] == node;
    const bool right_only = split && !left_only;
    const int coarse_node = coarse.mesh.node_at(s);
    const auto first = std::lower_bound(coarse.reaction_nodes.begin(), coarse.reaction_nodes.end(), coarse_node);
    if (coarse_node >= 0 && first != coarse.reaction_nodes.end() && *first == coarse_node) {
      int j = static_cast<int>(first - coarse.reaction_nodes.begin());
      if (right_only && j + 1 < coarse.reactions() && coarse.reaction_nodes[j + 1] == coarse_node) ++j;
      in_contact[i] = coarse_answer.in_contact[j];
      continue;
    }
    double mean = 0.0;
    if (!right_only && node > 0 && nodes[node - 1] >= model.foundation_begin) {
      const double h = s - nodes[node - 1];
      mean += h * w_minus_g(s - 0.5 * h);
    }
    if (!left_only && node + 1 < static_cast<int>(nodes.size()) && nodes[node + 1] <= model.foundation_end) {
      const double h = nodes[node + 1] - s;
      mean += h * w_minus_g(s + 0.5 * h);
    }
    in_contact[i] = mean > 0.0;
  }
  return in_contact;
}

}  // namespace

CoarseStart coarse_start(const model::MemberModel& model, const fe::Discretisation& d, double load_factor,
                         const ActiveSetOptions& options, const NestedOptions& nested) {
  nested.validate();
  CoarseStart out;
  // The coarse mesh still resolves the foundation's decay length 1/beta (beta^4 = k/4).
  const double decay_lengths = std::pow(std::max(model.k, 0.0) / 4.0, 0.25) * model.length();
  const int coarse_elements = std::max({d.mesh.elements() / nested.coarsening, nested.min_elements,
                                        static_cast<int>(std::ceil(nested.elements_per_decay_length * decay_lengths))});
  if (3 * coarse_elements > d.mesh.elements()) return out;
  ActiveSetOptions coarse_options = options;
  coarse_options.estimate_round_off = false;  // only this mesh's answer is reported
  // The coarse set only seeds this mesh's, whose iteration checks every sign: signs at the
  // loosest accuracy a step may rest on (max_solve_error), no refinement to round-off.
  coarse_options.refine_answer = false;
  coarse_options.intermediate_error = max_solve_error;
  const fe::Discretisation coarse = fe::discretise(model, coarse_elements);
  const NestedResult below = solve_active_set_nested(model, coarse, load_factor, coarse_options, nested);
  out.coarse_sets = below.coarse_sets + below.result.summary.iterations;
  out.levels = below.levels + 1;
  // A coarse failure only costs the better start: this mesh starts from every node in contact.
  if (below.result.summary.is_usable()) out.initial = carried_contact_set(model, coarse, below.result, d);
  return out;
}

NestedResult solve_active_set_nested(const model::MemberModel& model, const fe::Discretisation& d, double load_factor,
                                     const ActiveSetOptions& options, const NestedOptions& nested) {
  CoarseStart start = coarse_start(model, d, load_factor, options, nested);
  NestedResult out;
  out.coarse_sets = start.coarse_sets;
  out.levels = start.levels;
  ActiveSetOptions here = options;
  if (!start.initial.empty()) here.unrefined_first_set = true;  // a coarser mesh's set: rarely the answer
  out.result = solve_active_set(d, d.load(load_factor), here, std::move(start.initial), d.ground_gap);
  return out;
}

}  // namespace liftoff::contact
