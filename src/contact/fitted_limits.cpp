#include "contact/fitted_limits.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "core/enum_names.hpp"
#include "core/require.hpp"
#include "fe/mesh.hpp"
#include "fe/shape_functions.hpp"

namespace liftoff::contact {

using Eigen::VectorXd;

namespace {
constexpr EnumName<FittedTermination> fitted_termination_names[] = {
    {FittedTermination::solved, "solved"},
    {FittedTermination::no_convergence, "no_convergence"},
    {FittedTermination::topology_changed, "topology_changed"},
    {FittedTermination::inequalities_violated, "inequalities_violated"},
    {FittedTermination::singular_system, "singular_system"},
};
}  // namespace

std::string_view to_string(FittedTermination t) { return name_in<FittedTermination>(fitted_termination_names, t); }

void FittedOptions::validate() const {
  require(elements >= 1, "FittedOptions::elements", "must be at least 1");
  require(max_iterations >= 1, "FittedOptions::max_iterations", "must be at least 1");
  require(step_tolerance > 0.0 && step_tolerance < 1e-3, "FittedOptions::step_tolerance", "must be in (0, 1e-3)");
  require(inequality_tolerance >= 0.0 && inequality_tolerance < 1e-2, "FittedOptions::inequality_tolerance",
          "must be in [0, 1e-2)");
  require(samples_per_element >= 1, "FittedOptions::samples_per_element", "must be at least 1");
}

namespace {

// w's Hermite dofs of element e (the first four local dofs of both element kinds).
Eigen::Vector4d w_dofs(const fe::Discretisation& d, const VectorXd& all, int e) {
  const std::vector<int> dofs = d.element_dofs(e);
  return {all[dofs[0]], all[dofs[1]], all[dofs[2]], all[dofs[3]]};
}

// w - g at xi of element e: g is the ground gap, linear in the element (its table's points are
// breakpoints; at a step each element has its own side's value). Without a model, g = 0.
double w_at(const fe::Discretisation& d, const VectorXd& all, int e, double xi,
            const model::MemberModel* ground = nullptr) {
  const double w = fe::hermite_cubic(xi, d.mesh.element_size(e)).value.dot(w_dofs(d, all, e));
  return ground ? w - ground->ground_gap_in(d.mesh.nodes[e], d.mesh.element_size(e), xi) : w;
}

// The zero of w - g nearest element e: in e if it changes sign there, else in the nearest element
// (up to three away) where it does; else the middle of e. The discrete contact set follows the
// weighted gaps, not w itself, so w's zero may lie an element or two beside the set's change.
double zero_near_element(const fe::Discretisation& d, const VectorXd& all, int e, const model::MemberModel* ground) {
  for (int distance = 0; distance <= 3; ++distance) {
    for (int candidate : {e - distance, e + distance}) {
      if (candidate < 0 || candidate >= d.mesh.elements()) continue;
      double lo = 0.0, hi = 1.0, w_lo = w_at(d, all, candidate, lo, ground);
      if (!(w_lo * w_at(d, all, candidate, hi, ground) < 0.0)) continue;
      for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (lo + hi), w_mid = w_at(d, all, candidate, mid, ground);
        if ((w_mid > 0.0) == (w_lo > 0.0)) {
          lo = mid;
          w_lo = w_mid;
        } else {
          hi = mid;
        }
      }
      return d.mesh.nodes[candidate] + 0.5 * (lo + hi) * d.mesh.element_size(candidate);
    }
  }
  return d.mesh.nodes[e] + 0.5 * d.mesh.element_size(e);
}

// The steps of the ground gap (a trench wall: two values at one position) inside the foundation.
std::vector<double> ground_steps(const model::MemberModel& model) {
  std::vector<double> steps;
  const auto& at = model.ground_gap_at;
  for (std::size_t i = 1; i < at.size(); ++i)
    if (at[i] - at[i - 1] <= 1e-12 * model.length() && model.ground_gap_value[i] != model.ground_gap_value[i - 1] &&
        !model.is_foundation_edge(at[i]) && at[i] > model.foundation_begin && at[i] < model.foundation_end)
      steps.push_back(at[i]);
  return steps;
}

}  // namespace

namespace {

// contact_intervals with the ground gap of `ground` (null: g = 0).
std::vector<ContactRegion> intervals(const model::MemberModel* ground, const fe::Discretisation& d,
                                     const VectorXd& displacement, const std::vector<bool>& in_contact) {
  if (static_cast<int>(in_contact.size()) != d.reactions())
    throw std::invalid_argument("contact_intervals: one contact flag per reaction node expected");
  const VectorXd all = d.expand_displacement(displacement);
  const std::vector<double> steps = ground ? ground_steps(*ground) : std::vector<double>{};
  std::vector<ContactRegion> regions;
  const int m = d.reactions();
  for (int i = 0; i < m; ++i) {
    if (!in_contact[i]) continue;
    const int node = d.reaction_nodes[i];
    // Neighbours: the next node's reaction, or the other of a node where the reaction jumps.
    const bool starts = i == 0 || !in_contact[i - 1] || d.reaction_nodes[i - 1] < node - 1;
    const bool ends = i == m - 1 || !in_contact[i + 1] || d.reaction_nodes[i + 1] > node + 1;
    // The lifted-off nodes on the foundation beyond the region, walked outwards (direction -1 or
    // +1): the limit is the zero of w - g in the element where it turns negative. A node a support
    // holds (w = 0, or its settlement) or the foundation's end ends the region there (a limit at a
    // support; the foundation's end is no limit). A lifted node may have w > g (its weighted gap
    // integrates w over both its elements, negative on the far one): the zero is then beyond it
    // (the free beam under a central load at 1280 elements: w = +2.4e-7 at the first lifted node,
    // the limit put there was 8.1e-5 of the length off, against 7.8e-7 at 640 elements). w - g is
    // taken on the element walked across (a step of g at a node has a value on each side); where
    // it is negative already at that element's near node, the sign changes across the step there.
    const auto limit_beyond = [&](int direction) {
      int at = node, index = i;
      for (;;) {
        const int next = index + direction;
        if (next >= 0 && next < m && d.reaction_nodes[next] == at) {  // the other reaction of a jump
          index = next;
          continue;
        }
        if (next < 0 || next >= m || d.reaction_nodes[next] != at + direction) return d.mesh.nodes[at];
        at += direction;
        index = next;
        const int crossed = direction < 0 ? at : at - 1;
        const double far = direction < 0 ? 0.0 : 1.0, w = w_at(d, all, crossed, far, ground);
        if (all[d.deflection_dof(at)] == 0.0 || d.equation_of_dof[d.deflection_dof(at)] < 0) return d.mesh.nodes[at];
        if (w < 0.0) {
          const double near = d.mesh.nodes[at - direction];
          const bool step_at_near = std::any_of(steps.begin(), steps.end(), [&](double s) {
            return std::abs(s - near) <= 1e-12 * (d.mesh.nodes.back() - d.mesh.nodes.front());
          });
          if (step_at_near && w_at(d, all, crossed, 1.0 - far, ground) < 0.0) return near;
          return zero_near_element(d, all, crossed, ground);
        }
      }
    };
    if (starts) regions.push_back({limit_beyond(-1), 0.0});
    if (ends) regions.back().end = limit_beyond(+1);
  }
  // Regions that now touch (one lifted node between them, at w >= g) are one region.
  std::vector<ContactRegion> merged;
  for (const auto& r : regions) {
    if (!merged.empty() && r.begin <= merged.back().end)
      merged.back().end = std::max(merged.back().end, r.end);
    else
      merged.push_back(r);
  }
  return merged;
}

}  // namespace

std::vector<ContactRegion> contact_intervals(const fe::Discretisation& d, const VectorXd& displacement,
                                             const std::vector<bool>& in_contact) {
  return intervals(nullptr, d, displacement, in_contact);
}

std::vector<ContactRegion> contact_intervals(const model::MemberModel& model, const fe::Discretisation& d,
                                             const VectorXd& displacement, const std::vector<bool>& in_contact) {
  return intervals(model.has_ground_gap() ? &model : nullptr, d, displacement, in_contact);
}

FittedResult solve_fitted_limits(const model::MemberModel& model, double load_factor,
                                 const std::vector<ContactRegion>& initial, const FittedOptions& options) {
  options.validate();
  const double length = model.length(), tol = 1e-12 * length;
  std::vector<ContactRegion> regions = initial;
  for (std::size_t i = 0; i < regions.size(); ++i) {
    const auto& r = regions[i];
    if (!(r.begin < r.end) || r.begin < model.foundation_begin - tol || r.end > model.foundation_end + tol ||
        (i > 0 && !(regions[i - 1].end < r.begin)))
      throw std::invalid_argument(
          "solve_fitted_limits: contact regions must be disjoint, increasing and inside the foundation's extent");
  }
  // The interior limits: every region end that is not an end of the foundation (its extent's, or
  // a void's). limit_of[k] points at it.
  struct LimitRef {
    std::size_t region;
    bool is_begin;
  };
  std::vector<LimitRef> refs;
  for (std::size_t i = 0; i < regions.size(); ++i) {
    if (!model.is_foundation_edge(regions[i].begin)) refs.push_back({i, true});
    if (!model.is_foundation_edge(regions[i].end)) refs.push_back({i, false});
  }
  auto limit = [&](std::size_t k) -> double& {
    return refs[k].is_begin ? regions[refs[k].region].begin : regions[refs[k].region].end;
  };
  // A limit at a step of the ground gap (a trench wall) is pinned there, not a Newton unknown,
  // while w - g changes sign across the step (>= 0 on its contact side, <= 0 on the other).
  const std::vector<double> steps = ground_steps(model);
  std::vector<bool> pinned(refs.size(), false);
  for (std::size_t k = 0; k < refs.size(); ++k)
    for (double s : steps)
      if (std::abs(limit(k) - s) <= tol) limit(k) = s, pinned[k] = true;

  FittedResult result;
  FittedSummary& summary = result.summary;
  summary.iterations = 0;
  const std::vector<double> fixed_points = fe::mesh_breakpoints(model);
  const std::vector<std::pair<double, double>> stretches = model.foundation_stretches();
  std::vector<bool> layout;  // which mesh points are limits, in order: counts are kept while it holds
  std::vector<int> counts;
  double previous_step = INFINITY;
  summary.termination = FittedTermination::no_convergence;
  std::optional<ActiveSetSystem> system;

  for (int iteration = 0;; ++iteration) {
    // Mesh: the breakpoints and the limits, merged within round-off; the element counts are
    // kept from one iteration to the next while the points keep their order, so the discrete
    // problem changes smoothly with the limits.
    std::vector<std::pair<double, bool>> merged;
    for (double s : fixed_points) merged.emplace_back(s, false);
    for (std::size_t k = 0; k < refs.size(); ++k) merged.emplace_back(limit(k), true);
    std::sort(merged.begin(), merged.end());
    std::vector<double> points;
    std::vector<bool> is_limit;
    for (const auto& [s, from_limit] : merged) {
      if (!points.empty() && s - points.back() <= tol) {
        is_limit.back() = is_limit.back() || from_limit;
        continue;
      }
      points.push_back(s);
      is_limit.push_back(from_limit);
    }
    points.back() = model.s_end;
    if (is_limit != layout) counts = fe::apportion_elements(points, options.elements);
    layout = is_limit;
    fe::Mesh mesh = fe::make_mesh(points, counts);
    std::vector<bool> foundation(mesh.elements(), false);
    for (int e = 0; e < mesh.elements(); ++e) {
      const double middle = mesh.nodes[e] + 0.5 * mesh.element_size(e);
      for (const auto& r : regions)
        if (middle > r.begin && middle < r.end) foundation[e] = true;
    }
    result.discretisation = fe::discretise(model, std::move(mesh), std::move(foundation));
    const fe::Discretisation& d = result.discretisation;
    // One system over the iterations, on result.discretisation as it changes: its storage is
    // reused (allocating and freeing it per step cost more than the step on small meshes).
    if (system)
      system->reassemble();
    else
      system.emplace(d);
    if (!system->factorise(std::vector<bool>(d.reactions(), true))) {
      summary.termination = FittedTermination::singular_system;
      summary.message = "the contact regions leave a rigid motion free (singular system)";
      break;
    }
    // Refined only as far as the Newton step needs (1e-13 of (u, r): one defect on small meshes,
    // where the first solve is at round-off already); the answer is refined to round-off below.
    RefinementOptions refinement;
    refinement.target_error = 1e-13;
    refinement.residual = false;
    result.state = system->solve(d.load(load_factor), d.ground_gap, refinement);
    const VectorXd all = d.expand_displacement(result.state.displacement);
    double w_scale = 0.0;
    for (int node = 0; node <= d.mesh.elements(); ++node)
      w_scale = std::max(w_scale, std::abs(all[d.deflection_dof(node)]));

    // Newton on w(t_k) - g(t_k) = 0 with dF_k/dt_k = w'(t_k) - g'(t_k). g is linear on each
    // element beside the limit node: its value and slope from either side (they differ at a kink,
    // where the mean slope is taken, and at a step, where the limit is pinned).
    std::vector<double> step(refs.size(), 0.0);
    double residual = 0.0, largest = 0.0;
    bool flat = false;
    for (std::size_t k = 0; k < refs.size(); ++k) {
      const int node = d.mesh.node_at(limit(k));
      const double w = all[d.deflection_dof(node)], w_slope = all[d.slope_dof(node)];
      double g_side[2] = {0.0, 0.0}, g_slope[2] = {0.0, 0.0};  // left, right
      for (int side = 0; side < 2; ++side) {
        const int e = std::clamp(node - 1 + side, 0, d.mesh.elements() - 1);
        const double a = d.mesh.nodes[e], h = d.mesh.element_size(e);
        g_side[side] = model.ground_gap_in(a, h, e < node ? 1.0 : 0.0);
        g_slope[side] = (model.ground_gap_in(a, h, 1.0) - model.ground_gap_in(a, h, 0.0)) / h;
      }
      const int contact_side = refs[k].is_begin ? 1 : 0;
      double f = w - 0.5 * (g_side[0] + g_side[1]), slope = w_slope - 0.5 * (g_slope[0] + g_slope[1]);
      if (pinned[k]) {
        const double on_contact = w - g_side[contact_side], beyond = w - g_side[1 - contact_side];
        if (on_contact >= 0.0 && beyond <= 0.0) continue;  // the limit is the step's
        // The contact recedes from the step (w < g on its contact side) or passes it (w > g
        // beyond): Newton on that side's g, from the step.
        const int side = on_contact < 0.0 ? contact_side : 1 - contact_side;
        f = w - g_side[side];
        slope = w_slope - g_slope[side];
        pinned[k] = false;
      }
      residual = std::max(residual, std::abs(f));
      if (!(std::abs(slope) > 0.0)) {
        flat = true;
        continue;
      }
      step[k] = -f / slope;
      // w - g rises into a contact region from its limit: (w - g)' >= 0 at a region's begin, <= 0
      // at its end. With the other sign (a start far from the answer, or a limit whose answer is
      // at a step of g, where w - g need not vanish) Newton's step points away from where the
      // contact must go: step the same length the way the sign of w - g says instead (w > g:
      // the region grows), to a step of g or until the iteration sees its root.
      const double inward = refs[k].is_begin ? 1.0 : -1.0;  // into the region
      if (slope * inward < 0.0) step[k] = (f > 0.0 ? -inward : inward) * std::abs(step[k]);
      largest = std::max(largest, std::abs(step[k]));
    }
    summary.limit_residual = w_scale > 0 ? residual / w_scale : 0.0;
    summary.last_step = largest / length;
    if (flat) {
      summary.termination = FittedTermination::no_convergence;
      summary.message = "w' vanishes at a contact limit (a touching limit): Newton has no direction";
      break;
    }
    // Converged: steps below the tolerance, or stagnating at round-off (no longer halving once
    // below 1e-10 of the length).
    if (largest <= options.step_tolerance * length || (largest <= 1e-10 * length && largest > 0.5 * previous_step)) {
      summary.termination = FittedTermination::solved;
      result.state = system->refine_last_solve();  // to round-off, with its residual
      break;
    }
    if (iteration >= options.max_iterations) {
      summary.message = fmt::format("no convergence in {} Newton steps on the limits (last step {:.1e} of the length)",
                                    options.max_iterations, largest / length);
      break;
    }
    previous_step = largest;
    // Keep each limit within half the distance to its neighbours (limits or the ends of the
    // stretch of foundation it lies on: a limit never enters a void).
    std::vector<double> bound_lo(refs.size()), bound_hi(refs.size());
    for (std::size_t k = 0; k < refs.size(); ++k) {
      bound_lo[k] = model.foundation_begin;
      bound_hi[k] = model.foundation_end;
      for (const auto& [a, b] : stretches)
        if (limit(k) >= a && limit(k) <= b) bound_lo[k] = a, bound_hi[k] = b;
      if (k > 0) bound_lo[k] = std::max(bound_lo[k], limit(k - 1));
      if (k + 1 < refs.size()) bound_hi[k] = std::min(bound_hi[k], limit(k + 1));
    }
    double shrink = 1.0;
    for (std::size_t k = 0; k < refs.size(); ++k) {
      const double room = step[k] > 0 ? 0.5 * (bound_hi[k] - limit(k)) : 0.5 * (limit(k) - bound_lo[k]);
      if (std::abs(step[k]) > room) shrink = std::min(shrink, room / std::abs(step[k]));
    }
    for (std::size_t k = 0; k < refs.size(); ++k) {
      // A limit that would pass a step of the ground gap stops at it, pinned (checked above on
      // the next solve).
      const double from = limit(k), to = from + shrink * step[k];
      limit(k) = to;
      for (double s : steps)
        if ((s - from) * (s - to) <= 0.0 && std::abs(s - from) > tol && std::abs(s - from) <= std::abs(limit(k) - from))
          limit(k) = s, pinned[k] = true;
    }
    ++summary.iterations;
    bool collapsed = false;
    for (const auto& r : regions) collapsed = collapsed || r.end - r.begin < 1e-9 * length;
    for (std::size_t k = 1; k < refs.size(); ++k) collapsed = collapsed || limit(k) - limit(k - 1) < 1e-9 * length;
    if (collapsed) {
      summary.termination = FittedTermination::topology_changed;
      summary.message = "a contact region or a lift-off zone shrank to nothing: the topology is not the answer's";
      break;
    }
  }

  result.contact = regions;
  for (std::size_t k = 0; k < refs.size(); ++k) result.limits.push_back(limit(k));
  if (summary.termination != FittedTermination::solved) return result;

  // The contact inequalities on the answer.
  const fe::Discretisation& d = result.discretisation;
  const VectorXd all = d.expand_displacement(result.state.displacement);
  double w_scale = 0.0, r_scale = result.state.reaction.size() > 0 ? result.state.reaction.cwiseAbs().maxCoeff() : 0.0;
  for (int e = 0; e < d.mesh.elements(); ++e)
    for (int j = 0; j <= options.samples_per_element; ++j)
      w_scale = std::max(w_scale, std::abs(w_at(d, all, e, static_cast<double>(j) / options.samples_per_element)));
  double worst_w = 0.0, worst_r = 0.0;
  for (int e = 0; e < d.mesh.elements(); ++e) {
    // Beyond the foundation's extent nothing constrains w (an overhang, a void).
    const double middle = d.mesh.nodes[e] + 0.5 * d.mesh.element_size(e);
    if (model.k_at(middle) == 0.0) continue;
    const double sign = d.foundation_on_element[e] ? 1.0 : -1.0;  // w >= g in contact, <= g off it
    for (int j = 1; j < options.samples_per_element; ++j)
      worst_w =
          std::max(worst_w, -sign * w_at(d, all, e, static_cast<double>(j) / options.samples_per_element, &model));
  }
  for (int i = 0; i < d.reactions(); ++i) worst_r = std::max(worst_r, -result.state.reaction[i]);
  worst_w = w_scale > 0 ? worst_w / w_scale : 0.0;
  worst_r = r_scale > 0 ? worst_r / r_scale : 0.0;
  summary.worst_violation = std::max(worst_w, worst_r);
  if (worst_w > options.inequality_tolerance) {
    summary.termination = FittedTermination::inequalities_violated;
    summary.message = fmt::format(
        "the limits solve w = g, but w - g has the wrong sign inside an element by {:.1e} of max |w|: the contact "
        "topology is not the answer's",
        worst_w);
    return result;
  }
  summary.message = fmt::format(
      "{} limits fitted in {} Newton steps (last step {:.1e} of the length, w at the limits "
      "{:.1e} of max |w|)",
      refs.size(), summary.iterations, summary.last_step, summary.limit_residual);
  return result;
}

}  // namespace liftoff::contact
