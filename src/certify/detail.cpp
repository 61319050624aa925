#include "certify/detail.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "fe/shape_functions.hpp"

namespace liftoff::certify::detail {

using Eigen::VectorXd;
using model::EndSupport;
using model::StructureKind;

std::vector<std::array<int, 2>> element_reactions(const fe::Discretisation& d) {
  std::vector<int> first(d.mesh.nodes.size(), -1), last(d.mesh.nodes.size(), -1);
  for (int i = d.reactions() - 1; i >= 0; --i) first[d.reaction_nodes[i]] = i;
  for (int i = 0; i < d.reactions(); ++i) last[d.reaction_nodes[i]] = i;
  std::vector<std::array<int, 2>> out(d.mesh.elements());
  for (int e = 0; e < d.mesh.elements(); ++e) out[e] = {last[e], first[e + 1]};
  return out;
}

std::vector<int> supported_dofs(const model::MemberModel& model, const fe::Discretisation& d) {
  std::vector<int> fixed;
  const bool arch = model.kind == StructureKind::arch;
  auto fix_end = [&](int node, EndSupport support) {
    if (support == EndSupport::free) return;
    fixed.push_back(d.deflection_dof(node));
    if (support == EndSupport::clamped) fixed.push_back(d.slope_dof(node));
    if (arch && (support == EndSupport::pinned || support == EndSupport::clamped))
      fixed.push_back(d.tangential_dof(node));
  };
  fix_end(0, model.left);
  fix_end(d.mesh.elements(), model.right);
  for (double s : model.point_supports) {
    const int node = d.mesh.node_at(s);
    if (node >= 0) fixed.push_back(d.deflection_dof(node));
  }
  std::sort(fixed.begin(), fixed.end());
  fixed.erase(std::unique(fixed.begin(), fixed.end()), fixed.end());
  return fixed;
}

namespace {
// The certificate's own reading of an arch load, from the geometry rather than from the FE's
// fe::arch_load_components: the force of unit value (per unit arc) in global components, x to the
// right and y up, the point at theta being R (sin theta, cos theta) from the centre, projected
// on the directions of w > 0 and of u. Returns (along w, along u).
Eigen::Vector2d arch_force_on_dofs(const model::MemberModel& model, const model::MemberLoad& load, double theta) {
  const Eigen::Vector2d outward(std::sin(theta), std::cos(theta)), tangent(std::cos(theta), -std::sin(theta));
  const Eigen::Vector2d w_direction = model.foundation_outside ? outward : Eigen::Vector2d(-outward);
  Eigen::Vector2d force = Eigen::Vector2d::Zero();
  switch (load.direction) {
    case model::LoadDirection::radial:
      force = w_direction;
      break;
    case model::LoadDirection::tangential:
      force = tangent;
      break;
    case model::LoadDirection::vertical:  // per unit projection: dx = cos theta ds
      force = Eigen::Vector2d(0.0, -1.0) * (load.per == model::LoadBasis::projection ? std::cos(theta) : 1.0);
      break;
    case model::LoadDirection::horizontal:
      force = Eigen::Vector2d(1.0, 0.0);
      break;
  }
  return {force.dot(w_direction), force.dot(tangent)};
}
}  // namespace

VectorXd applied_nodal_loads(const model::MemberModel& model, const fe::Discretisation& d, double load_factor) {
  VectorXd f = VectorXd::Zero(d.dofs());
  const bool arch = model.kind == StructureKind::arch;
  for (const model::MemberLoad& load : model.loads) {
    const double value = load.value * (load.load_case == model::LoadCase::dead ? 1.0 : load_factor);
    if (load.has_extent()) {
      const double factor = load.load_case == model::LoadCase::dead ? 1.0 : load_factor;
      for (int e = 0; e < d.mesh.elements(); ++e) {
        const double h = d.mesh.element_size(e), middle = d.mesh.nodes[e] + 0.5 * h;
        if (middle < load.from || middle > load.to) continue;
        const std::vector<int> dofs = d.element_dofs(e);
        if (load.kind == model::LoadKind::curvature) {
          // An imposed curvature works through the elastic strain: -kappa int N'' = -kappa [N'].
          for (const auto& [xi, sign] : {std::pair{0.0, 1.0}, std::pair{1.0, -1.0}}) {
            const Eigen::Vector4d slope = fe::hermite_cubic(xi, h).d1;
            for (int j = 0; j < 4; ++j) f[dofs[j]] += sign * value * slope[j];
          }
          continue;
        }
        // linear q x cubic N: exact on beams (Gauss 5); a sine to round-off (model::load_quadrature)
        for (const model::LoadQuadraturePoint& g : model::load_quadrature(load, d.mesh.nodes[e], d.mesh.nodes[e] + h)) {
          const double s = g.s, xi = (s - d.mesh.nodes[e]) / h;
          const double q = factor * load.intensity(s);
          const Eigen::Vector2d c = arch ? arch_force_on_dofs(model, load, s) : Eigen::Vector2d(1.0, 0.0);
          const Eigen::Vector4d shape = fe::hermite_cubic(xi, h).value;
          for (int j = 0; j < 4; ++j) f[dofs[j]] += g.weight * q * c[0] * shape[j];
          if (!arch) continue;
          const auto u_shape = fe::lagrange_quartic(xi, h).value;
          for (int j = 0; j < 5; ++j) f[dofs[4 + j]] += g.weight * q * c[1] * u_shape[j];
        }
      }
      continue;
    }
    const int node = d.mesh.node_at(load.at);
    if (node < 0) continue;  // the mesh has a node at every load (mesh.hpp)
    if (load.kind == model::LoadKind::force && arch) {
      const Eigen::Vector2d c = arch_force_on_dofs(model, load, load.at);
      f[d.deflection_dof(node)] += value * c[0];
      f[d.tangential_dof(node)] += value * c[1];
    } else if (load.kind == model::LoadKind::force) {
      f[d.deflection_dof(node)] += value;
    } else {  // a counterclockwise moment works on the rotation -w' (arches -(u + w'), outside -(u - w'))
      f[d.slope_dof(node)] -= (model.foundation_outside ? -1.0 : 1.0) * value;
      if (model.kind == StructureKind::arch) f[d.tangential_dof(node)] -= value;
    }
  }
  return f;
}

std::vector<SupportReaction> support_reactions(const model::MemberModel& model, const fe::Discretisation& d,
                                               const VectorXd& g, const std::vector<bool>& is_supported,
                                               std::vector<int> nodes) {
  if (nodes.empty()) {
    if (model.left != EndSupport::free) nodes.push_back(0);
    for (double s : model.point_supports)
      if (d.mesh.node_at(s) >= 0) nodes.push_back(d.mesh.node_at(s));
    if (model.right != EndSupport::free) nodes.push_back(d.mesh.elements());
  }
  const bool arch = model.kind == StructureKind::arch;
  std::vector<SupportReaction> out;
  for (int node : nodes) {
    auto at = [&](int dof) { return is_supported[dof] ? g[dof] : 0.0; };
    const double g_w = at(d.deflection_dof(node)), g_slope = at(d.slope_dof(node));
    const double g_u = arch ? at(d.tangential_dof(node)) : 0.0;
    // With the foundation outside the rotation is -(u - w'): g_slope is +moment (see the header).
    const double in = model.foundation_outside ? -1.0 : 1.0, moment = 0.0 - in * g_slope;
    out.push_back({d.mesh.nodes[node], 0.0 - g_w, moment, arch ? g_u + moment : 0.0});  // no -0
  }
  return out;
}

std::vector<std::pair<double, double>> settlements(const model::MemberModel& model) {
  std::vector<std::pair<double, double>> out;
  if (model.left != EndSupport::free) out.emplace_back(model.s_begin, model.left_settlement);
  for (std::size_t i = 0; i < model.point_supports.size(); ++i)
    out.emplace_back(model.point_supports[i], i < model.point_settlements.size() ? model.point_settlements[i] : 0.0);
  if (model.right != EndSupport::free) out.emplace_back(model.s_end, model.right_settlement);
  return out;
}

int balance_mode_count(StructureKind kind) { return kind == StructureKind::beam ? 2 : 3; }

Eigen::MatrixXd balance_modes(const model::MemberModel& model, const fe::Discretisation& d) {
  if (model.kind == StructureKind::arch) return fe::rigid_motions(model, d);
  Eigen::MatrixXd modes(d.dofs(), 2);
  for (int dof = 0; dof < d.dofs(); ++dof) {
    const bool slope = d.role_of_dof(dof) == fe::DofRole::slope;
    modes(dof, 0) = slope ? 0.0 : 1.0;
    modes(dof, 1) = slope ? 1.0 : d.position_of_dof(dof) - model.s_begin;
  }
  return modes;
}

Eigen::Vector3d balance_mode_at(const model::MemberModel& model, int mode, double s) {
  if (model.kind == StructureKind::beam)
    return mode == 0 ? Eigen::Vector3d(0, 1, 0) : Eigen::Vector3d(0, s - model.s_begin, 1);
  const double c = std::cos(s), sn = std::sin(s);  // as fe::rigid_motions
  const double in = model.foundation_outside ? -1.0 : 1.0;
  switch (mode) {
    case 0:
      return {c, -in * sn, -in * c};
    case 1:
      return {-sn, -in * c, in * sn};
    default:
      return {1, 0, 0};
  }
}

std::string_view balance_name(StructureKind kind, int mode) {
  if (mode == balance_mode_count(kind) - 1) return check_name::moment_balance;
  if (kind == StructureKind::beam) return check_name::force_balance;
  return mode == 0 ? check_name::force_balance_x : check_name::force_balance_y;
}

void fill_resultants(Certificate& c, const model::MemberModel& model, const std::vector<double>& applied,
                     const std::vector<double>& foundation, double centroid) {
  if (model.kind == StructureKind::beam) {
    c.applied_force = applied[0];
    c.foundation_resultant = foundation[0];
    c.applied_moment = 0.0 - applied[1];  // (no -0)
  } else {                                // "toward the foundation at the crown" is minus mode 1 (w = -cos theta)
    c.applied_force = 0.0 - applied[1];
    c.foundation_resultant = 0.0 - foundation[1];
    c.applied_force_x = applied[0];
    c.foundation_resultant_x = foundation[0];
    c.applied_moment = 0.0 - applied[2];
  }
  c.foundation_centroid = centroid;
}

void conclude(Certificate& c, const model::MemberModel& model) {
  // One order for every certificate: balance, contact, backward error, round-off (the first
  // failure is the one the message names; an imbalance says most to an engineer). A round-off
  // that could not be measured (FE: the answer's contact set leaves it free to move, as a
  // free-free beam on one contact node; its system is singular in the mixed form) comes first:
  // the sign checks then have no round-off to allow and fail at their floor, not for a sign.
  auto rank = [](const Check& check) {
    if (check.name == check_name::round_off && !std::isfinite(check.value)) return -1;
    if (check.name.find("balance") != std::string::npos) return 0;
    if (check.name == check_name::backward_error) return 2;
    if (check.name == check_name::round_off) return 3;
    return 1;
  };
  std::stable_sort(c.checks.begin(), c.checks.end(), [&](const Check& a, const Check& b) { return rank(a) < rank(b); });
  for (Check& check : c.checks)
    check.passed = std::isfinite(check.value) && std::isfinite(check.tolerance) && check.value <= check.tolerance &&
                   check.value <= largest_certifiable_error;
  const Check* failed = c.first_failure();
  c.passed = !c.checks.empty() && failed == nullptr && c.message.empty();
  if (!c.message.empty()) return;  // already says why there is nothing to certify
  if (!failed) {
    c.message = "all checks passed";
    return;
  }
  const bool arch = model.kind == StructureKind::arch;
  const std::string where = failed->at ? fmt::format(" at {} = {:.6g}{}", arch ? "theta" : "x",
                                                     model.user_from_s(*failed->at), arch ? " deg" : "")
                                       : std::string();
  int others = 0;
  for (const Check& check : c.checks) others += !check.passed && &check != failed;
  const std::string against =
      failed->value <= failed->tolerance
          ? fmt::format(
                "above {:.0e}, the most any certified answer may carry (its own round-off or truncation "
                "bound, {:.2e}, is no certificate)",
                largest_certifiable_error, failed->tolerance)
          : fmt::format("against a tolerance of {:.2e}", failed->tolerance);
  c.message = fmt::format("{} failed: {:.2e} {}{}{}", failed->name, failed->value, against, where,
                          others > 0 ? fmt::format(" (and {} more checks)", others) : "");
  if (failed->name == check_name::round_off && !c.round_off_note.empty()) c.message += " (" + c.round_off_note + ")";
  if (failed->name.find("balance") != std::string::npos) {
    const UserFigures u = user_figures(c, model);
    c.message += arch
                     ? fmt::format(" (applied {:.6g} and {:.6g} along, foundation {:.6g} and {:.6g}; moment {:.6g})",
                                   u.applied_force, u.applied_force_x, u.foundation_resultant, u.foundation_resultant_x,
                                   u.applied_moment)
                     : fmt::format(" (applied {:.6g}, moment {:.6g} about x = {:.6g}; foundation {:.6g} at x = {:.6g})",
                                   u.applied_force, u.applied_moment, model.user_from_s(model.s_begin),
                                   u.foundation_resultant, u.foundation_centroid);
  }
}

}  // namespace liftoff::certify::detail
