#include "continuation/events.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "fe/shape_functions.hpp"

namespace liftoff::continuation {

namespace {

// A deflection within this fraction of the largest nodal |w| counts as zero (as in
// post::contact_regions), so that w grazing round-off opens nothing.
constexpr double zero_deflection = 1e-12;

struct Sample {
  double s = 0.0;
  double w = 0.0;
  int element = 0;
  double xi = 0.0;
};

Eigen::Vector4d deflection_dofs(const fe::Discretisation& d, const Eigen::VectorXd& displacement, int element) {
  const std::vector<int> dofs = d.element_dofs(element);
  return {displacement[dofs[0]], displacement[dofs[1]], displacement[dofs[2]], displacement[dofs[3]]};
}

double cubic_at(const Eigen::Vector4d& w_dofs, double h, double xi) {
  return fe::hermite_cubic(xi, h).value.dot(w_dofs);
}

// Interior extrema of the element's cubic, xi in (0, 1), ascending.
std::vector<double> extrema(const Eigen::Vector4d& w_dofs, double h) {
  // w(xi) = a0 + a1 xi + a2 xi^2 + a3 xi^3 from the end values and slopes (d/ds, times h).
  const double w0 = w_dofs[0], t0 = h * w_dofs[1], w1 = w_dofs[2], t1 = h * w_dofs[3];
  const double a1 = t0, a2 = 3.0 * (w1 - w0) - 2.0 * t0 - t1, a3 = 2.0 * (w0 - w1) + t0 + t1;
  // w' = a1 + 2 a2 xi + 3 a3 xi^2.
  std::vector<double> roots;
  const double a = 3.0 * a3, b = 2.0 * a2, c = a1;
  const double size = std::abs(a) + std::abs(b) + std::abs(c);
  if (size == 0.0) return roots;
  if (std::abs(a) <= 1e-14 * size) {
    if (b != 0.0) roots.push_back(-c / b);
  } else {
    const double disc = b * b - 4.0 * a * c;
    if (disc >= 0.0) {
      // Stable quadratic roots.
      const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
      roots.push_back(q / a);
      if (q != 0.0) roots.push_back(c / q);
    }
  }
  std::vector<double> inside;
  for (double r : roots)
    if (r > 0.0 && r < 1.0) inside.push_back(r);
  std::sort(inside.begin(), inside.end());
  return inside;
}

std::string coordinate(const model::MemberModel& model, double s) {
  if (model.kind == model::StructureKind::beam) return fmt::format("x = {:.6g}", model.user_from_s(s));
  return fmt::format("theta = {:.6g} deg", model.user_from_s(s));
}

bool overlaps(const ContactRegion& a, const ContactRegion& b) {
  return std::min(a.end, b.end) > std::max(a.begin, b.begin);
}

}  // namespace

SpecialPoints special_points(const model::MemberModel& model) {
  SpecialPoints p;
  p.begin = model.foundation_begin;
  p.end = model.foundation_end;
  const double tol = 1e-12 * model.length();
  auto supported = [&](double s) {
    if (std::abs(s - model.s_begin) <= tol && model.left != model::EndSupport::free) return true;
    if (std::abs(s - model.s_end) <= tol && model.right != model::EndSupport::free) return true;
    return std::any_of(model.point_supports.begin(), model.point_supports.end(),
                       [&](double x) { return std::abs(x - s) <= tol; });
  };
  p.begin_supported = supported(p.begin);
  p.end_supported = supported(p.end);
  std::vector<std::pair<double, bool>> points;
  for (double s : model.point_supports) points.emplace_back(s, true);
  for (const auto& load : model.loads)
    if (!load.has_extent()) points.emplace_back(load.at, false);
  std::sort(points.begin(), points.end());
  for (const auto& [s, support] : points) {
    if (s <= p.begin + tol || s >= p.end - tol) continue;
    if (!p.interior.empty() && std::abs(p.interior.back() - s) <= tol) {
      if (support) p.is_support.back() = true;  // a load on a support: the support is what matters
      continue;
    }
    p.interior.push_back(s);
    p.is_support.push_back(support);
  }
  return p;
}

bool ContactTopology::same_as(const ContactTopology& other) const {
  if (pieces.size() != other.pieces.size() || limit_slots != other.limit_slots) return false;
  return pieces.empty() || pieces.front().region.in_contact == other.pieces.front().region.in_contact;
}

ContactTopology contact_topology(const model::MemberModel& model, const fe::Discretisation& d,
                                 const Eigen::VectorXd& displacement, const SpecialPoints& points) {
  ContactTopology topology;
  if (d.reactions() == 0) return topology;
  if (!d.tensionless) {
    topology.pieces.push_back({{points.begin, points.end, true}});
    return topology;
  }
  // Contact where w > g, g the ground gap (0 without one): the cubics below are of w - g (g is
  // linear in each element, which a Hermite cubic represents exactly; at a step of g each
  // element has its own side's value, so the change across the step shows between its samples).
  double w_scale = 0.0;
  for (int node = 0; node < static_cast<int>(d.mesh.nodes.size()); ++node)
    w_scale = std::max(
        {w_scale, std::abs(displacement[d.deflection_dof(node)]), std::abs(model.ground_gap(d.mesh.nodes[node]))});
  const double threshold = zero_deflection * w_scale;

  // w at the nodes and the cubics' extrema: monotone in between, so the signs there decide.
  std::vector<Sample> samples;
  std::vector<Eigen::Vector4d> element_dofs(d.mesh.elements());
  int last = -1;
  for (int e = 0; e < d.mesh.elements(); ++e) {
    const double s0 = d.mesh.nodes[e], h = d.mesh.element_size(e);
    if (s0 + 0.5 * h < points.begin || s0 + 0.5 * h > points.end) continue;
    element_dofs[e] = deflection_dofs(d, displacement, e);
    if (model.has_ground_gap()) {
      const double g0 = model.ground_gap_in(s0, h, 0.0), g1 = model.ground_gap_in(s0, h, 1.0);
      element_dofs[e] -= Eigen::Vector4d(g0, (g1 - g0) / h, g1, (g1 - g0) / h);
    }
    samples.push_back({s0, cubic_at(element_dofs[e], h, 0.0), e, 0.0});
    for (double xi : extrema(element_dofs[e], h))
      samples.push_back({s0 + xi * h, cubic_at(element_dofs[e], h, xi), e, xi});
    last = e;
  }
  if (last < 0) return topology;
  const double h_last = d.mesh.element_size(last);
  samples.push_back({d.mesh.nodes[last + 1], cubic_at(element_dofs[last], h_last, 1.0), last, 1.0});
  // At a supported end w is 0, and a zone opening there first shows as a dip of the end
  // element's cubic whose depth is quadratic in lambda - lambda_event: compared with the
  // threshold it would place the event late by ~sqrt(zero_deflection) relative (2e-6 on
  // simply_supported_end_moments). The end sample takes instead the cubic's leading term there
  // (h w', or h^2 w''/2 at a clamped end), linear in lambda like the Ritz end event function;
  // only where w - g vanishes at the support (not where the ground or a settlement leaves a gap).
  const auto leading_term = [&](const Eigen::Vector4d& w_dofs, double h, bool at_begin) {
    const double w0 = w_dofs[0], t0 = h * w_dofs[1], w1 = w_dofs[2], t1 = h * w_dofs[3];
    const double a2 = 3.0 * (w1 - w0) - 2.0 * t0 - t1, a3 = 2.0 * (w0 - w1) + t0 + t1;
    // In the distance from the end, xi or 1 - xi: first and second order coefficients.
    const double first = at_begin ? t0 : -t1, second = at_begin ? a2 : a2 + 3.0 * a3;
    return std::abs(first) > threshold ? first : second;
  };
  const double end_tol = 1e-12 * model.length();
  if (points.begin_supported && std::abs(samples.front().s - points.begin) <= end_tol &&
      std::abs(samples.front().w) <= threshold)
    samples.front().w =
        leading_term(element_dofs[samples.front().element], d.mesh.element_size(samples.front().element), true);
  if (points.end_supported && std::abs(samples.back().s - points.end) <= end_tol &&
      std::abs(samples.back().w) <= threshold)
    samples.back().w = leading_term(element_dofs[last], h_last, false);

  auto sign_of = [&](double w) { return w > threshold ? 1 : (w < -threshold ? -1 : 0); };
  // The root of w between two samples of opposite sign (both in the first one's element).
  auto root_between = [&](const Sample& a, const Sample& b) {
    const int e = a.element;
    const double h = d.mesh.element_size(e);
    double lo = a.xi, hi = b.element == e ? b.xi : 1.0;
    const bool lo_positive = cubic_at(element_dofs[e], h, lo) > 0;
    for (int i = 0; i < 60 && hi - lo > 1e-15; ++i) {
      const double mid = 0.5 * (lo + hi);
      if ((cubic_at(element_dofs[e], h, mid) > 0) == lo_positive)
        lo = mid;
      else
        hi = mid;
    }
    return d.mesh.nodes[e] + 0.5 * (lo + hi) * h;
  };

  // Runs of one sign; samples at zero belong to no run: between two runs of one sign they are
  // absorbed (a contact region touching zero at a support stays one region), between runs of
  // opposite signs they are where the limit lies.
  std::vector<double> limits;
  int current = 0;
  std::size_t last_signed = 0;
  bool first_contact = false;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const int sign = sign_of(samples[i].w);
    if (sign == 0) continue;
    if (current == 0) {
      first_contact = sign > 0;
    } else if (sign != current) {
      if (i == last_signed + 1)
        limits.push_back(root_between(samples[last_signed], samples[i]));
      else
        limits.push_back(0.5 * (samples[last_signed + 1].s + samples[i - 1].s));
    }
    current = sign;
    last_signed = i;
  }
  double begin = points.begin;
  bool contact = first_contact;  // all zero: one lift-off piece
  for (double limit : limits) {
    topology.pieces.push_back({{begin, limit, contact}});
    auto slot = std::lower_bound(points.interior.begin(), points.interior.end(), limit - 1e-12 * model.length());
    topology.limit_slots.push_back(static_cast<int>(slot - points.interior.begin()));
    begin = limit;
    contact = !contact;
  }
  topology.pieces.push_back({{begin, points.end, contact}});

  // A piece between two limits inside the elements next to a point load straddles it (header).
  for (std::size_t p = 1; p + 1 < topology.pieces.size(); ++p) {
    Piece& piece = topology.pieces[p];
    for (std::size_t i = 0; i < points.interior.size(); ++i) {
      const int node = points.is_support[i] ? -1 : d.mesh.node_at(points.interior[i]);
      if (node <= 0 || node >= d.mesh.elements()) continue;
      if (piece.region.begin < d.mesh.nodes[node - 1] || piece.region.end > d.mesh.nodes[node + 1]) continue;
      piece.at_load = static_cast<int>(i);
      topology.limit_slots[p - 1] = static_cast<int>(i);
      topology.limit_slots[p] = static_cast<int>(i) + 1;
      break;
    }
  }
  return topology;
}

LiftMeasures lift_measures(const model::MemberModel& model, const fe::Discretisation& d,
                           const Eigen::VectorXd& displacement, const SpecialPoints& points) {
  LiftMeasures measures;
  if (d.reactions() == 0 || !d.tensionless) return measures;
  double lift = 0.0;  // max of g - w (nondimensional)
  for (int e = 0; e < d.mesh.elements(); ++e) {
    const double s0 = d.mesh.nodes[e], h = d.mesh.element_size(e);
    if (s0 + 0.5 * h < points.begin || s0 + 0.5 * h > points.end) continue;
    Eigen::Vector4d w = deflection_dofs(d, displacement, e);
    if (model.has_ground_gap()) {
      const double g0 = model.ground_gap_in(s0, h, 0.0), g1 = model.ground_gap_in(s0, h, 1.0);
      w -= Eigen::Vector4d(g0, (g1 - g0) / h, g1, (g1 - g0) / h);
    }
    lift = std::max({lift, -cubic_at(w, h, 0.0), -cubic_at(w, h, 1.0)});
    for (double xi : extrema(w, h)) lift = std::max(lift, -cubic_at(w, h, xi));
  }
  measures.amplitude = lift * model.scales.displacement();
  for (const Piece& piece : contact_topology(model, d, displacement, points).pieces)
    if (!piece.region.in_contact)
      measures.lifted_length += std::abs(model.user_from_s(piece.region.end) - model.user_from_s(piece.region.begin));
  return measures;
}

std::vector<TraceEvent> classify_events(const model::MemberModel& model, const SpecialPoints& points,
                                        const ContactTopology& before, const ContactTopology& after,
                                        double load_factor) {
  std::vector<TraceEvent> events;
  auto add = [&](EventKind kind, double s, const std::string& what) {
    events.push_back({load_factor, kind, model.user_from_s(s), what + " at " + coordinate(model, s)});
  };
  auto at_end = [&](const ContactRegion& p, const std::string& what) {
    const bool at_begin = p.begin <= points.begin;
    const double s = at_begin ? points.begin : points.end;
    const bool supported = at_begin ? points.begin_supported : points.end_supported;
    add(supported ? EventKind::limit_at_support : EventKind::limit_at_end, s,
        what + (supported ? " at the supported end of the foundation" : " at the end of the foundation"));
  };
  auto touches_end = [&](const ContactRegion& p) { return p.begin <= points.begin || p.end >= points.end; };
  // An interior point support at an end of the piece (w = 0 there, so a limit can sit on it):
  // a piece opening or closing against it is a limit reaching the support.
  auto support_at_end = [&](const ContactRegion& p) -> std::optional<double> {
    const double tol = 1e-9 * model.length();
    for (std::size_t i = 0; i < points.interior.size(); ++i)
      if (points.is_support[i] &&
          (std::abs(points.interior[i] - p.begin) <= tol || std::abs(points.interior[i] - p.end) <= tol))
        return points.interior[i];
    return std::nullopt;
  };
  auto whole = [&](const ContactRegion& p) { return p.begin <= points.begin && p.end >= points.end; };

  // Pieces with no piece of their kind overlapping them on the other side are new (after) or
  // gone (before); every other piece only moved.
  bool changed = false;
  for (const Piece& piece : after.pieces) {
    const ContactRegion& p = piece.region;
    const bool is_new = std::none_of(before.pieces.begin(), before.pieces.end(), [&](const Piece& q) {
      return q.region.in_contact == p.in_contact && overlaps(p, q.region);
    });
    if (!is_new) continue;
    changed = true;
    const double mid = 0.5 * (p.begin + p.end);
    if (whole(p))
      add(p.in_contact ? EventKind::contact_opens : EventKind::region_vanishes, mid,
          p.in_contact ? "the whole foundation comes into contact" : "the member lifts off the whole foundation");
    else if (touches_end(p))
      at_end(p, p.in_contact ? "a contact region forms" : "a lift-off zone opens");
    else if (const auto support = support_at_end(p))
      add(EventKind::limit_at_support, *support,
          p.in_contact ? "a contact region forms against a point support"
                       : "a lift-off zone opens against a point support");
    else if (piece.at_load >= 0)
      add(p.in_contact ? EventKind::contact_opens : EventKind::lift_off_opens, points.interior[piece.at_load],
          p.in_contact ? "a contact region opens at a point load" : "a lift-off zone opens at a point load");
    else if (p.in_contact)
      add(EventKind::contact_opens, mid, "a contact region opens inside a lift-off zone");
    else
      add(EventKind::lift_off_opens, mid, "a lift-off zone opens inside a contact region");
  }
  for (const Piece& piece : before.pieces) {
    const ContactRegion& p = piece.region;
    const bool gone = std::none_of(after.pieces.begin(), after.pieces.end(), [&](const Piece& q) {
      return q.region.in_contact == p.in_contact && overlaps(p, q.region);
    });
    if (!gone || whole(p)) continue;  // a whole piece replaced is reported once, above
    changed = true;
    const double mid = 0.5 * (p.begin + p.end);
    if (touches_end(p))
      at_end(p, p.in_contact ? "a contact region vanishes" : "a lift-off zone closes");
    else if (const auto support = support_at_end(p))
      add(EventKind::limit_at_support, *support,
          p.in_contact ? "a contact region vanishes against a point support"
                       : "a lift-off zone closes against a point support");
    else if (piece.at_load >= 0)
      add(p.in_contact ? EventKind::region_vanishes : EventKind::lift_off_vanishes, points.interior[piece.at_load],
          p.in_contact ? "a contact region vanishes at a point load"
                       : "a lift-off zone closes at a point load: two contact regions merge");
    else if (p.in_contact)
      add(EventKind::region_vanishes, mid, "a contact region vanishes");
    else
      add(EventKind::lift_off_vanishes, mid, "a lift-off zone closes: two contact regions merge");
  }
  if (changed || before.limit_slots.size() != after.limit_slots.size()) return events;

  // Same pieces: a limit crossed a support or a point load.
  for (std::size_t i = 0; i < before.limit_slots.size(); ++i) {
    const int a = before.limit_slots[i], b = after.limit_slots[i];
    if (a == b) continue;
    const int crossed = std::min(a, b);  // the special point between the two slots
    const double s = points.interior[crossed];
    if (points.is_support[crossed])
      add(EventKind::limit_at_support, s, "a contact limit reaches a point support");
    else
      add(EventKind::limit_at_load, s, "a contact limit reaches a point load");
  }
  return events;
}

}  // namespace liftoff::continuation
