#include "contact/fitted_refinement.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/enum_names.hpp"
#include "core/require.hpp"
#include "fe/mesh.hpp"
#include "fe/shape_functions.hpp"

namespace liftoff::contact {

using Eigen::VectorXd;

namespace {
constexpr EnumName<ToleranceTermination> tolerance_termination_names[] = {
    {ToleranceTermination::reached, "reached"},
    {ToleranceTermination::cap_reached, "cap_reached"},
    {ToleranceTermination::round_off, "round_off"},
    {ToleranceTermination::fitted_failed, "fitted_failed"},
};
}  // namespace

std::string_view to_string(ToleranceTermination t) {
  return name_in<ToleranceTermination>(tolerance_termination_names, t);
}

void ToleranceOptions::validate() const {
  require(tolerance >= 1e-13 && tolerance <= 0.1, "ToleranceOptions::tolerance", "must be in [1e-13, 0.1]");
  require(initial_elements >= 0, "ToleranceOptions::initial_elements", "must be >= 0");
  require(max_elements >= 2, "ToleranceOptions::max_elements", "must be at least 2");
  require(samples_per_element >= 1, "ToleranceOptions::samples_per_element", "must be at least 1");
  fitted.validate();
}

namespace {

// A level's answer, ready to be evaluated anywhere.
struct Level {
  FittedResult fitted;
  VectorXd all;  // displacement on every dof
};

double w_at(const fe::Discretisation& d, const VectorXd& all, int e, double xi) {
  const std::vector<int> dofs = d.element_dofs(e);
  const Eigen::Vector4d w(all[dofs[0]], all[dofs[1]], all[dofs[2]], all[dofs[3]]);
  return fe::hermite_cubic(xi, d.mesh.element_size(e)).value.dot(w);
}

double w_at(const fe::Discretisation& d, const VectorXd& all, double s) {
  const int e = d.mesh.element_containing(s);
  const double xi = std::clamp((s - d.mesh.nodes[e]) / d.mesh.element_size(e), 0.0, 1.0);
  return w_at(d, all, e, xi);
}

struct Changes {
  double limits = 0.0, w = 0.0, reaction = 0.0;
};

// The changes of `fine` from `coarse` (see the header), relative.
Changes changes(const model::MemberModel& model, const Level& coarse, const Level& fine, double length, int samples) {
  Changes c;
  for (std::size_t k = 0; k < fine.fitted.limits.size(); ++k)
    c.limits = std::max(c.limits, std::abs(fine.fitted.limits[k] - coarse.fitted.limits[k]) / length);
  const fe::Discretisation& d = fine.fitted.discretisation;
  double w_scale = 0.0, w_change = 0.0, contact_scale = 0.0, contact_change = 0.0;
  for (int e = 0; e < d.mesh.elements(); ++e)
    for (int i = 0; i <= samples; ++i) {
      const double xi = static_cast<double>(i) / samples, s = d.mesh.nodes[e] + xi * d.mesh.element_size(e);
      const double w = w_at(d, fine.all, e, xi),
                   change = std::abs(w - w_at(coarse.fitted.discretisation, coarse.all, s));
      w_scale = std::max(w_scale, std::abs(w));
      w_change = std::max(w_change, change);
      if (!d.foundation_on_element[e]) continue;
      // The reaction k (w - g) (g the ground gap): its change is w's, its scale w - g's.
      contact_scale = std::max(contact_scale, w - model.ground_gap_in(d.mesh.nodes[e], d.mesh.element_size(e), xi));
      contact_change = std::max(contact_change, change);
    }
  c.w = w_scale > 0 ? w_change / w_scale : 0.0;
  c.reaction = contact_scale > 0 ? contact_change / contact_scale : 0.0;
  return c;
}

// The round-off floor of a level (see the header): the largest of the limits', w's and the
// reaction's, relative like the estimates.
double round_off_floor(const model::MemberModel& model, const Level& level, double length) {
  const fe::Discretisation& d = level.fitted.discretisation;
  const double error = level.fitted.state.error_estimate;
  const double eps_w = std::max(16 * std::numeric_limits<double>::epsilon(), std::isfinite(error) ? error : 0.0);
  double w_scale = 0.0, contact_scale = 0.0;
  for (int e = 0; e < d.mesh.elements(); ++e)
    for (int node : {e, e + 1}) {
      const double w = level.all[d.deflection_dof(node)];
      w_scale = std::max(w_scale, std::abs(w));
      const double g = model.ground_gap_in(d.mesh.nodes[e], d.mesh.element_size(e), node == e ? 0.0 : 1.0);
      if (d.foundation_on_element[e]) contact_scale = std::max(contact_scale, w - g);
    }
  double limits = std::max(level.fitted.summary.last_step, 0.0);
  for (double t : level.fitted.limits) {
    const int node = d.mesh.node_at(t);
    if (node < 0) continue;
    const double slope = std::abs(level.all[d.slope_dof(node)]);
    limits = std::max(limits, slope > 0 ? eps_w * w_scale / (slope * length) : INFINITY);
  }
  const double reaction = contact_scale > 0 ? eps_w * w_scale / contact_scale : eps_w;
  return std::max({limits, eps_w, reaction});
}

// Richardson's estimate of the finer answer's error from its change d and the change before,
// d_before (< 0: none), at the observed order clamped to [1, 4]; `order` gets the observed one.
double estimate(double d, double d_before, double& order) {
  double p = 1.0;
  order = -1.0;
  if (d_before > 0.0 && d > 0.0) {
    order = std::log2(d_before / d);
    p = std::clamp(order, 1.0, 4.0);
  }
  return d / (std::exp2(p) - 1.0);
}

}  // namespace

ToleranceResult refine_to_tolerance(const model::MemberModel& model, double load_factor,
                                    const std::vector<ContactRegion>& initial, const ToleranceOptions& options) {
  options.validate();
  ToleranceResult result;
  ToleranceSummary& summary = result.summary;
  const double length = model.length();
  // beta h <= 1/4 on the first mesh: the decay length of the foundation's response resolved.
  const double beta_length = std::pow(std::max(model.k, 0.0) / 4.0, 0.25) * length;
  int n = options.initial_elements > 0 ? options.initial_elements
                                       : std::max(32, static_cast<int>(std::ceil(4.0 * beta_length)));
  // At least four elements on the shortest segment between breakpoints and region ends on the
  // first mesh: a segment apportioned its minimum of one element at n and at 2n does not change,
  // and its error would go unseen by the changes (clamped ends settled by 1e-3 under a lifting
  // force: a contact region of 0.02 L on one element at 32 and 64 elements, its limit 2.3e-8 off
  // the closed form with a change of 1e-16).
  std::vector<double> points = fe::mesh_breakpoints(model);
  for (const ContactRegion& r : initial) points.insert(points.end(), {r.begin, r.end});
  std::sort(points.begin(), points.end());
  double shortest = length;
  for (std::size_t i = 1; i < points.size(); ++i)
    if (points[i] - points[i - 1] > 1e-12 * length) shortest = std::min(shortest, points[i] - points[i - 1]);
  n = std::max(n, static_cast<int>(std::min(4.0 * length / shortest, 1e9)));
  n = std::min(n, options.max_elements);

  auto solve_level = [&](int elements, const std::vector<ContactRegion>& start, Level& level) {
    FittedOptions fitted = options.fitted;
    fitted.elements = elements;
    level.fitted = solve_fitted_limits(model, load_factor, start, fitted);
    if (!level.fitted.summary.is_usable()) {
      summary.termination = ToleranceTermination::fitted_failed;
      summary.message = fmt::format("the limit-fitted solve on {} elements failed ({}: {})", elements,
                                    to_string(level.fitted.summary.termination), level.fitted.summary.message);
      return false;
    }
    level.all = level.fitted.discretisation.expand_displacement(level.fitted.state.displacement);
    summary.levels.push_back({level.fitted.discretisation.mesh.elements(), -1.0, -1.0, -1.0});
    summary.round_off_floor = round_off_floor(model, level, length);
    return true;
  };
  // A tolerance below the round-off floor: no mesh can reach it.
  auto below_floor = [&](int elements) {
    if (options.tolerance >= summary.round_off_floor) return false;
    summary.termination = ToleranceTermination::round_off;
    summary.message = fmt::format(
        "the tolerance {:.1e} is below the round-off floor {:.1e} of the limit-fitted answer on {} elements (the "
        "smallest tolerance it can honour: its limits, w and reaction are known to no better)",
        options.tolerance, summary.round_off_floor, elements);
    return true;
  };

  Level coarse, fine;
  if (!solve_level(n, initial, coarse) || below_floor(n)) {
    result.answer = std::move(coarse.fitted);
    return result;
  }
  const bool has_limits = !coarse.fitted.limits.empty();
  Changes before{-1.0, -1.0, -1.0};
  int stalled = 0;
  for (;;) {
    if (2 * n > options.max_elements) {
      summary.termination = ToleranceTermination::cap_reached;
      summary.message = fmt::format(
          "the tolerance {:.1e} is not reached within the cap of {} elements (estimated limit error {:.1e}, "
          "deflection {:.1e}, reaction {:.1e})",
          options.tolerance, options.max_elements, summary.estimated_limit_error, summary.estimated_w_error,
          summary.estimated_reaction_error);
      break;
    }
    n *= 2;
    if (!solve_level(n, coarse.fitted.contact, fine)) break;
    if (below_floor(n)) {
      coarse = std::move(fine);
      break;
    }
    if (fine.fitted.limits.size() != coarse.fitted.limits.size()) {
      summary.termination = ToleranceTermination::fitted_failed;
      summary.message = fmt::format("the limit-fitted solves on {} and {} elements found {} and {} limits", n / 2, n,
                                    coarse.fitted.limits.size(), fine.fitted.limits.size());
      break;
    }
    const Changes now = changes(model, coarse, fine, length, options.samples_per_element);
    ToleranceLevel& level = summary.levels.back();
    level.limit_change = now.limits;
    level.w_change = now.w;
    level.reaction_change = now.reaction;
    double order_limits = -1.0, order_w = -1.0, order_r = -1.0;
    // No estimate below the round-off floor (Newton's last step among it).
    const double floor = summary.round_off_floor;
    summary.estimated_limit_error =
        has_limits ? std::max(estimate(now.limits, before.limits, order_limits), floor) : 0.0;
    summary.estimated_w_error = std::max(estimate(now.w, before.w, order_w), floor);
    summary.estimated_reaction_error = std::max(estimate(now.reaction, before.reaction, order_r), floor);
    // Limits pinned at steps of the ground gap do not move: then w's order.
    summary.observed_order = has_limits && order_limits >= 0 ? order_limits : order_w;
    const double worst =
        std::max({summary.estimated_limit_error, summary.estimated_w_error, summary.estimated_reaction_error});
    coarse = std::move(fine);
    if (worst <= options.tolerance) {
      summary.termination = ToleranceTermination::reached;
      summary.message = fmt::format(
          "tolerance {:.1e} reached on {} elements: estimated limit error {:.1e} of the length, deflection {:.1e} "
          "of max |w|, reaction {:.1e} of its largest (observed order {:.2f})",
          options.tolerance, n, summary.estimated_limit_error, summary.estimated_w_error,
          summary.estimated_reaction_error, summary.observed_order);
      break;
    }
    // Round-off: the largest change did not halve twice in a row.
    const double largest = std::max({now.limits, now.w, now.reaction});
    const double largest_before = std::max({before.limits, before.w, before.reaction});
    stalled = largest_before > 0.0 && largest > 0.5 * largest_before ? stalled + 1 : 0;
    if (stalled >= 2) {
      // The changes that stopped decreasing are round-off's: the floor is at least the last.
      summary.round_off_floor = std::max(summary.round_off_floor, largest);
      summary.termination = ToleranceTermination::round_off;
      summary.message = fmt::format(
          "the tolerance {:.1e} cannot be reached: the changes from doubling the mesh stopped decreasing at {} "
          "elements (last change {:.1e}): round-off owns them; the round-off floor is {:.1e}",
          options.tolerance, n, largest, summary.round_off_floor);
      break;
    }
    before = now;
  }
  result.answer = std::move(coarse.fitted);
  return result;
}

}  // namespace liftoff::contact
