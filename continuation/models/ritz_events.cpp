#include "continuation/models/ritz_events.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "ritz/ritz_solver.hpp"

namespace liftoff::continuation {

using Eigen::VectorXd;
using ritz::RitzModel;

namespace {
constexpr double infinity = std::numeric_limits<double>::infinity();
}  // namespace

bool RitzEvents::end_supported(bool left) const {
  const double s = left ? member_.foundation_begin : member_.foundation_end;
  const double end = left ? member_.s_begin : member_.s_end;
  if (std::abs(s - end) > 1e-12 * member_.length()) return false;
  return (left ? member_.left : member_.right) != model::EndSupport::free;
}

// --------------------------------------------------------------------------------------------
// Events.

std::vector<RitzEventSpec> RitzEvents::specs(const ritz::RitzModel& model) const {
  std::vector<RitzEventSpec> specs;
  if (!model.tensionless()) return specs;  // a bilateral foundation never lifts off: no events
  const int pieces = model.limits() + 1;
  bool contact = model.topology().first_in_contact;
  for (int p = 0; p < pieces; ++p, contact = !contact) {
    specs.push_back({RitzEventFunction::interior_extreme,
                     contact ? EventKind::lift_off_opens : EventKind::contact_opens, p, false, 0, 0});
    if (pieces > 1) {
      EventKind kind = contact ? EventKind::region_vanishes : EventKind::lift_off_vanishes;
      if (p == 0 || p == pieces - 1)
        kind = end_supported(p == 0) ? EventKind::limit_at_support : EventKind::limit_at_end;
      specs.push_back({RitzEventFunction::length, kind, p, false, 0, 0});
    }
  }
  // Openings at the foundation's ends (member_ tells which end condition holds w there).
  const auto end_kind = [&](bool begin) {
    return end_supported(begin) ? EventKind::limit_at_support : EventKind::limit_at_end;
  };
  specs.push_back({RitzEventFunction::end_value, end_kind(true), 0, false, 0, 0});
  specs.push_back({RitzEventFunction::end_value, end_kind(false), pieces - 1, true, 0, 0});
  // Limits passing load points.
  std::vector<double> points;
  for (const model::MemberLoad& load : member_.loads) {
    if (load.has_extent()) continue;
    if (load.at > member_.foundation_begin && load.at < member_.foundation_end) points.push_back(load.at);
  }
  std::sort(points.begin(), points.end());
  points.erase(std::unique(points.begin(), points.end()), points.end());
  for (int m = 0; m < model.limits(); ++m)
    for (double a : points)
      specs.push_back({RitzEventFunction::limit_at_load, EventKind::limit_at_load, 0, false, m, a});
  return specs;
}

// The extreme of w strictly inside [a, b]: local extrema (roots of w' refined by safeguarded
// Newton) and the grid values between them.
RitzEventValue RitzEvents::extreme(const ritz::RitzModel& model, const VectorXd& x, double a, double b,
                                   bool minimum) const {
  RitzEventValue best;
  if (!(b > a)) return best;
  const double sign = minimum ? 1.0 : -1.0;  // minimise sign * w
  const int samples = std::max(16, static_cast<int>(std::ceil(8.0 * modes_ * (b - a) / member_.length())));
  std::vector<double> w;
  model.w_on_grid(x, a, b, samples,
                  w);  // (a grid of sines by recurrence: a sine per point and mode is 20 times dearer)
  for (int i = 1; i < samples; ++i) {
    const double value = sign * w[i - 1];
    if (value < best.value) best = {value, a + (b - a) * i / samples};
  }
  for (const RitzEventValue& local : local_minima(model, x, a, b, minimum))
    if (local.value < best.value) best = local;
  return best;
}

std::vector<RitzEventValue> RitzEvents::local_minima(const ritz::RitzModel& model, const VectorXd& x, double a,
                                                     double b, bool minimum) const {
  std::vector<RitzEventValue> minima;
  if (!(b > a)) return minima;
  const double sign = minimum ? 1.0 : -1.0;  // minima of sign * w
  const int samples = std::max(16, static_cast<int>(std::ceil(8.0 * modes_ * (b - a) / member_.length())));
  // Sign changes of the slope from - to + between the grid's midpoints (the odd points of the grid
  // of twice as many intervals), refined by safeguarded Newton.
  std::vector<double> slope;
  model.w_on_grid(x, a, b, 2 * samples, slope, 1);
  const auto midpoint = [&](int i) { return a + (b - a) * (2 * i + 1) / (2.0 * samples); };
  double s0 = midpoint(0), d0 = sign * slope[0];
  for (int i = 1; i < samples; ++i) {
    const double s1 = midpoint(i);
    const double d1 = sign * slope[2 * i];
    if (d0 < 0 && d1 >= 0) {
      double lo = s0, hi = s1, s = 0.5 * (s0 + s1);
      for (int k = 0; k < 60; ++k) {
        const double d = sign * model.w(x, s, 1), dd = sign * model.w(x, s, 2);
        (d < 0 ? lo : hi) = s;
        double next = dd > 0 ? s - d / dd : 0.5 * (lo + hi);
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        if (std::abs(next - s) <= 1e-15 * member_.length()) {
          s = next;
          break;
        }
        s = next;
      }
      minima.push_back({sign * model.w(x, s), s});
    }
    s0 = s1, d0 = d1;
  }
  return minima;
}

RitzEventValue RitzEvents::value(const ritz::RitzModel& model, const VectorXd& x, const RitzEventSpec& spec) const {
  const std::vector<ContactRegion> pieces = model.pieces(x);
  switch (spec.function) {
    case RitzEventFunction::interior_extreme: {
      const ContactRegion& p = pieces[spec.piece];
      if (!(p.end > p.begin)) return {infinity, p.begin};  // a piece of negative length: its own event
      // contact: min w > 0; lift-off: -max w > 0.
      return extreme(model, x, p.begin, p.end, p.in_contact);
    }
    case RitzEventFunction::end_value: {
      const bool left = !spec.far_end;
      const ContactRegion& p = pieces[spec.piece];
      const double s = left ? member_.foundation_begin : member_.foundation_end;
      double value = model.w(x, s);
      if (end_supported(left)) {
        const model::EndSupport support = left ? member_.left : member_.right;
        // w = 0 at the end: the sign of w just inside comes from w' (pinned) or w'' (clamped).
        value = support == model::EndSupport::clamped ? model.w(x, s, 2) : (left ? 1.0 : -1.0) * model.w(x, s, 1);
        if (support == model::EndSupport::clamped) value *= member_.length();
      }
      return {p.in_contact ? value : -value, s};
    }
    case RitzEventFunction::length: {
      const ContactRegion& p = pieces[spec.piece];
      // Where it vanishes: at the member's end for an end piece, else between its limits.
      const double at = spec.piece == 0                                     ? member_.foundation_begin
                        : spec.piece == static_cast<int>(pieces.size()) - 1 ? member_.foundation_end
                                                                            : 0.5 * (p.begin + p.end);
      return {p.end - p.begin, at};
    }
    case RitzEventFunction::limit_at_load: {
      const double t = x[model.limit_offset() + spec.limit];
      return {t - spec.position, spec.position};
    }
  }
  return {};
}

double RitzEvents::w_scale(const ritz::RitzModel& model, const VectorXd& x) const {
  const int samples = 8 * modes_;
  std::vector<double> w;
  model.w_on_grid(x, member_.s_begin, member_.s_end, samples, w);
  double scale = std::max(std::abs(model.w(x, member_.s_begin)), std::abs(model.w(x, member_.s_end)));
  for (double value : w) scale = std::max(scale, std::abs(value));
  return scale;
}

// --------------------------------------------------------------------------------------------
// A vanishing piece takes the events of its own degeneracy along (at a shrinking end piece, w
// at the end and the piece's extreme reach zero too): those are no openings. And w at an end
// reaching zero while the end piece is all but gone (shorter than 1e-5 of the member, far
// below what N modes resolve) is that piece vanishing, seen a little early through round-off
// (region_split at 40 modes: w(0) = 0 with the limit 4e-7 L from it, and a contact zone was
// opened at x = 0 instead of the limit removed): its length event replaces the opening. So
// does an interior extreme reaching zero in a piece between two limits that is all but gone
// (culvert: the minimum of w in a contact region 6e-6 of the arch wide, w of the order of its
// width squared, reached zero through round-off just before the region vanished).
// At a pinned end (w = w'' = 0) the end's event is w' there, and an end piece's limit lies
// sqrt(-6 w' / w''') from the end: the piece vanishes together with w' (a double root of w, where
// the limit equation w(t) = 0 meets its trivial root t = end, a pitchfork of the Ritz equations),
// its length going like the square root of the distance to the event. Located on w', the piece is
// still ~1e-4 of the member long (the imperfect arch's zone closing at x = L: 1.4e-4 at 32 modes,
// and a contact zone was opened at the end inside the vanishing lift-off zone, whose limits then
// could not be followed): there the bound is the square root of 1e-5.
double RitzEvents::degenerate_length(const RitzEventSpec& spec) const {
  constexpr double regular = 1e-5;
  if (spec.function != RitzEventFunction::end_value) return regular;
  return pinned_beam_end(!spec.far_end) ? std::sqrt(regular) : regular;
}

double RitzEvents::landed(const ritz::RitzModel& model, const RitzEventSpec& spec) const {
  const bool end_piece = spec.piece == 0 || spec.piece == model.limits();
  return end_piece && vanishes_singularly(model, spec) ? 1e-9 * member_.length() : 0.0;
}

bool RitzEvents::pinned_beam_end(bool left) const {
  return member_.kind == model::StructureKind::beam && end_supported(left) &&
         (left ? member_.left : member_.right) == model::EndSupport::pinned;
}

std::vector<RitzEventSpec> RitzEvents::without_degenerate_openings(const ritz::RitzModel& model, const VectorXd& x,
                                                                   std::vector<RitzEventSpec> events) const {
  const std::vector<ContactRegion> pieces = model.pieces(x);
  for (RitzEventSpec& spec : events) {
    const bool degenerate =
        spec.function == RitzEventFunction::end_value ||
        (spec.function == RitzEventFunction::interior_extreme && spec.piece > 0 && spec.piece < model.limits());
    if (!degenerate || pieces.size() < 2) continue;
    const ContactRegion& piece = pieces[spec.piece];
    if (piece.end - piece.begin > degenerate_length(spec) * member_.length()) continue;
    for (const RitzEventSpec& length : specs(model))
      if (length.function == RitzEventFunction::length && length.piece == spec.piece) spec = length;
  }
  const auto same = [](const RitzEventSpec& a, const RitzEventSpec& b) {
    return a.function == b.function && a.piece == b.piece && a.far_end == b.far_end && a.limit == b.limit &&
           a.position == b.position;
  };
  for (std::size_t i = 0; i < events.size(); ++i)
    for (std::size_t j = events.size(); j-- > i + 1;)
      if (same(events[i], events[j])) events.erase(events.begin() + static_cast<std::ptrdiff_t>(j));
  std::vector<bool> vanishing(model.limits() + 1, false);
  for (const RitzEventSpec& spec : events)
    if (spec.function == RitzEventFunction::length) vanishing[spec.piece] = true;
  std::erase_if(events, [&](const RitzEventSpec& spec) {
    return (spec.function == RitzEventFunction::interior_extreme || spec.function == RitzEventFunction::end_value) &&
           vanishing[spec.piece];
  });
  return events;
}

// The state at an event is a contact solution but for the event itself: w touching zero where
// a zone opens, by what locating it to event_tolerance leaves. That much violation (relative to
// max |w|) is allowed there.
double RitzEvents::event_allowance(const ritz::RitzModel& model, const VectorXd& x,
                                   const std::vector<RitzEventSpec>& events) const {
  const double scale = std::max(w_scale(model, x), 1e-300);
  double allowance = 0.0;
  for (const RitzEventSpec& spec : events) {
    if (spec.function != RitzEventFunction::interior_extreme && spec.function != RitzEventFunction::end_value) continue;
    // The value is w, or at a supported end w' (pinned) or w'' length (clamped): w within a
    // length of the end is at most that times the length.
    const bool slope = spec.function == RitzEventFunction::end_value && end_supported(!spec.far_end);
    allowance += std::abs(value(model, x, spec).value) * (slope ? member_.length() : 1.0) / scale;
  }
  return allowance;
}

std::optional<std::string> RitzEvents::state_failure(const ritz::RitzModel& model, const VectorXd& x,
                                                     double allowance) const {
  if (!model.admissible(x)) return "its contact limits are out of order or outside the foundation";
  const ritz::InequalityCheck check = ritz::check_inequalities(model, x);
  if (check.violation <= inequality_tolerance + allowance) return std::nullopt;
  const model::Scales& scales = member_.scales;
  const std::string where =
      fmt::format("{} = {:.6g}", member_.kind == model::StructureKind::arch ? "theta" : "x", user(check.at));
  if (check.in_contact)
    return fmt::format(
        "w = {:.3e} at {} inside a contact piece: the foundation would pull (reaction {:.3e} force per length), {:.1e} "
        "of max |w|",
        check.w * scales.displacement(), where, member_.k * check.w * scales.force_per_length(), check.violation);
  return fmt::format(
      "w = {:.3e} at {} inside a lift-off piece: the member would penetrate the foundation without "
      "reaction, {:.1e} of max |w|",
      check.w * scales.displacement(), where, check.violation);
}

bool RitzEvents::vanishes_singularly(const ritz::RitzModel& model, const RitzEventSpec& spec) const {
  if (spec.function != RitzEventFunction::length) return false;
  if (spec.piece > 0 && spec.piece < model.limits()) return true;
  // An end piece at a pinned end: w = w'' = 0 there, so next to it w = w'(e) (s - e) + w'''(e)
  // (s - e)^3 / 6 and the piece's limit, the root of w, lies sqrt(-6 w'(e) / w'''(e)) from the
  // end: the piece vanishes with w'(e) at a double root of w, approached like a piece between two
  // limits (there the branch folds; here the limit equation meets its trivial root t = e, and
  // steps past it land on the mirror root outside the foundation: the imperfect arch's zone
  // closing at x = L with 16 modes, "contact limits out of order or outside the foundation").
  // At a clamped or free end the limit moves linearly: regular. Beams only: an arch's pinned end
  // is the same singular point, but the culvert's path then fails its fixed 0.1 steps on the
  // approach instead of on turning back (ritz_path_test, issue 10), not examined further.
  return pinned_beam_end(spec.piece == 0);
}

// The piece's width goes like sqrt(c (lambda* - lambda)) as it vanishes (lambda* beyond p in the
// path's direction), so |lambda* - lambda| = width / (2 |d width / d lambda|), from p's tangent.
// Between limits p - 1 and p the width is their difference; an end piece's, its limit's distance
// to the end.
double RitzEvents::vanishing_gap(const ritz::RitzModel& model, const PathPoint& p, const RitzEventSpec& spec) const {
  if (!(p.tangent_lambda != 0.0)) return infinity;
  const int offset = model.limit_offset(), pieces = model.limits() + 1;
  double width = 0.0, rate = 0.0;
  if (spec.piece == 0) {
    width = p.x[offset] - member_.foundation_begin, rate = p.tangent_x[offset];
  } else if (spec.piece == pieces - 1) {
    const int last = offset + model.limits() - 1;
    width = member_.foundation_end - p.x[last], rate = -p.tangent_x[last];
  } else {
    const int first = offset + spec.piece - 1;
    width = p.x[first + 1] - p.x[first], rate = p.tangent_x[first + 1] - p.tangent_x[first];
  }
  rate /= p.tangent_lambda;  // d width / d lambda
  const double direction = p.tangent_lambda > 0 ? 1.0 : -1.0;
  if (!(width > 0 && rate * direction < 0)) return infinity;
  return width / (2.0 * std::abs(rate));
}

std::optional<PathPoint> RitzEvents::approach_vanishing(const ritz::RitzModel& model, const PathFollower& follower,
                                                        const PathPoint& from, const RitzEventSpec& spec,
                                                        double tolerance) const {
  PathPoint p = from;
  const double direction = from.tangent_lambda > 0 ? 1.0 : -1.0;
  for (int iteration = 0; iteration < 200; ++iteration) {
    const double gap = vanishing_gap(model, p, spec);
    if (!std::isfinite(gap)) return std::nullopt;
    if (gap <= tolerance) return p;
    // Aim short of the estimate (its error is of the order of gap^2 over the model's scale);
    // past lambda* there is no solution of this topology, and a miss shortens the aim.
    bool moved = false;
    for (double fraction = 0.9; fraction > 1e-3 && !moved; fraction *= 0.25) {
      const double lambda = p.lambda + direction * fraction * gap;
      const VectorXd guess = p.x + (lambda - p.lambda) / p.tangent_lambda * p.tangent_x;
      StepOutcome next = follower.step_to_lambda(from, lambda, &guess);
      if (!next.point || !model.admissible(next.point->x) || !(next.point->tangent_lambda * direction > 0) ||
          !(value(model, next.point->x, spec).value > landed(model, spec)))
        continue;
      p = std::move(*next.point);
      moved = true;
    }
    if (!moved) return std::nullopt;
  }
  return std::nullopt;
}

std::optional<std::string> RitzEvents::stepped_over(const ritz::RitzModel& model, const VectorXd& from,
                                                    const VectorXd& to) const {
  const std::vector<ContactRegion> pieces = model.pieces(from);
  const int offset = model.limit_offset();
  for (int m = 0; m < model.limits(); ++m) {
    const double t0 = from[offset + m], t1 = to[offset + m];
    if (t1 == t0) continue;
    // The limit ends piece m and begins piece m + 1; moving right it advances into piece m + 1.
    const ContactRegion& piece = pieces[t1 > t0 ? m + 1 : m];
    const double lo = std::min(t0, t1), hi = std::max(t0, t1);
    for (const RitzEventValue& e : local_minima(model, from, piece.begin, piece.end, piece.in_contact))
      if (e.at > lo && e.at < hi)
        return fmt::format(
            "the contact limit at {} = {:.6g} moved past a local {} of w at {:.6g} ({} = {:.3e}) in one "
            "step, where a zone must have {} first",
            member_.kind == model::StructureKind::arch ? "theta" : "x", user(t0),
            piece.in_contact ? "minimum" : "maximum", user(e.at), "w",
            model.w(from, e.at) * member_.scales.displacement(), piece.in_contact ? "lifted off" : "come into contact");
  }
  return std::nullopt;
}

// The largest lift off the foundation surface (the ground is at w = 0: the Ritz model takes no
// gap) on a grid of the foundation's extent that resolves the modes, and the lift-off pieces'
// total length.
RitzBuckle RitzEvents::buckle(const ritz::RitzModel& model, const VectorXd& x) const {
  RitzBuckle b;
  const double a = member_.foundation_begin, e = member_.foundation_end;
  std::vector<double> w;
  const int intervals = std::max(400, 16 * model.modes());
  model.w_on_grid(x, a, e, intervals, w);
  double lift = 0.0;
  for (std::size_t i = 0; i < w.size(); ++i)
    if (-w[i] > lift) lift = -w[i], b.crown = a + (e - a) * static_cast<double>(i + 1) / intervals;
  for (double s : {a, e})
    if (-model.w(x, s) > lift) lift = -model.w(x, s), b.crown = s;
  b.amplitude = lift * member_.scales.displacement();
  for (const ContactRegion& piece : model.pieces(x))
    if (!piece.in_contact && piece.end > piece.begin) b.lifted_length += user(piece.end) - user(piece.begin);
  return b;
}

}  // namespace liftoff::continuation
