#include "contact/active_set_solver.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <unordered_set>

#include <fmt/format.h>

namespace liftoff::contact {

using Eigen::VectorXd;

std::string_view to_string(ActiveSetTermination t) {
  switch (t) {
    case ActiveSetTermination::solved: return "solved";
    case ActiveSetTermination::iteration_limit: return "iteration_limit";
    case ActiveSetTermination::cycling: return "cycling";
    case ActiveSetTermination::singular_system: return "singular_system";
  }
  return "unknown";
}

void ActiveSetOptions::validate() const {
  if (max_iterations < 1) throw std::invalid_argument("ActiveSetOptions::max_iterations must be at least 1");
  if (block_retries < -1) throw std::invalid_argument("ActiveSetOptions::block_retries must be -1 (no safeguard) or >= 0");
  if (!(sign_tolerance >= 0.0 && sign_tolerance < 1e-3))
    throw std::invalid_argument("ActiveSetOptions::sign_tolerance must be in [0, 1e-3)");
}

namespace {

// Signs are trusted only beyond this multiple of the solve's estimated relative error.
constexpr double round_off_margin = 10.0;
// A set's solve whose refinement leaves more than this is no basis for a step (as the
// acceptable error of contact_solver.cpp).
constexpr double max_solve_error = 1e-6;

// Nodes on the wrong side: in contact with r < 0, or lifted off with gap < 0 (ascending).
std::vector<int> infeasible_nodes(const fe::Discretisation& d, const ContactState& state,
                                  const std::vector<bool>& in_contact, double tolerance) {
  const double reaction_scale = state.reaction.lpNorm<Eigen::Infinity>();
  const VectorXd coupled = d.coupling * state.displacement;
  const double gap_scale = std::max(coupled.lpNorm<Eigen::Infinity>(), (state.gap).lpNorm<Eigen::Infinity>());
  std::vector<int> nodes;
  for (int i = 0; i < static_cast<int>(in_contact.size()); ++i) {
    const bool wrong = in_contact[i] ? state.reaction[i] < -tolerance * reaction_scale
                                     : state.gap[i] < -tolerance * gap_scale;
    if (wrong) nodes.push_back(i);
  }
  return nodes;
}

}  // namespace

ActiveSetResult solve_active_set(const fe::Discretisation& d, const VectorXd& load, const ActiveSetOptions& options,
                                 std::vector<bool> initial) {
  options.validate();
  const int m = d.reactions();
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
    if (factorised) result.state = system.solve(load);
    if (!factorised || !(result.state.error_estimate <= max_solve_error)) {
      if (last_good.empty() || singular_retry) {
        summary.termination = ActiveSetTermination::singular_system;
        summary.message =
            factorised ? fmt::format("refinement could not solve a contact set's system (relative error {:.1e}): the "
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
    const double tolerance = std::max(options.sign_tolerance, round_off_margin * result.state.error_estimate);
    const std::vector<int> infeasible = infeasible_nodes(d, result.state, in_contact, tolerance);
    summary.infeasible_history.push_back(static_cast<int>(infeasible.size()));
    if (infeasible.empty()) {
      result.round_off_bound = system.data_error(result.state, load);
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

}  // namespace liftoff::contact
