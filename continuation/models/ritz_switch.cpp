// The Ritz path's switches: of topology at a crossing (enter), and onto a bifurcated branch
// (switch_branch, with the return of a branch that keeps its topology, refine_return).
//
// Switching topology: a vanishing piece is removed at the event itself (its two limits, or the
// end piece's one limit): the same amplitudes solve the new topology there. An opening needs a
// zone of nonzero width: the old topology is continued a little past the event (its solution
// there is the local expansion of the new one, w dipping through zero around the event point),
// the roots of w around the event point give the new limits, and the new topology is solved at
// that lambda; shorter, if the zone so found is not local (it covers another extreme of w).

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include "continuation/models/ritz.hpp"

namespace liftoff::continuation {

using Eigen::MatrixXd;
using Eigen::VectorXd;
using ritz::RitzModel;
using ritz::Topology;

namespace {
constexpr double infinity = std::numeric_limits<double>::infinity();

// The first point from `from` toward `limit_s` where `leaves` holds (a scan of 4096 samples, then
// bisection on the sign of w of x under `model`); limit_s if none.
double first_leaving(const RitzModel& model, const VectorXd& x, double from, double limit_s,
                     const std::function<bool(double)>& leaves, double length) {
  constexpr int samples = 4096;
  double previous = from;
  for (int i = 1; i <= samples; ++i) {
    const double next = from + (limit_s - from) * i / samples;
    if (!leaves(next)) {
      previous = next;
      continue;
    }
    double a = previous, b = next, fa = model.w(x, a);
    for (int k = 0; k < 200 && std::abs(b - a) > 1e-15 * length; ++k) {
      const double m = 0.5 * (a + b), fm = model.w(x, m);
      if ((fm > 0) == (fa > 0))
        a = m, fa = fm;
      else
        b = m;
    }
    return 0.5 * (a + b);
  }
  return limit_s;
}
PathModel::Entry failed(TraceTermination termination, std::string why) {
  PathModel::Entry entry;
  entry.failure = termination;
  entry.why = std::move(why);
  return entry;
}
}  // namespace

// What the events change: limits removed with vanishing pieces, zones to open.
struct RitzPath::Openings {
  std::vector<double> kept;                   // the limits that stay (s)
  std::vector<std::pair<double, int>> zones;  // s; 1 interior (two limits), 0 at the begin, 2 at the end
  Topology topology;
};

void RitzPath::adopt(std::shared_ptr<const RitzModel> model) {
  model_ = std::move(model);
  specs_ = events_->specs(*model_);
  values_cache_.clear();
}

PathModel::Entry RitzPath::enter(const Crossing& crossing, const ArcLengthOptions& /*options*/) {
  const auto& transition = std::any_cast<const Transition&>(crossing.transition);
  if (!transition.changes_topology) {  // a limit passing a load: go on from there
    Entry entry;
    entry.point = transition.point;
    return entry;
  }
  return switch_topology(transition);
}

RitzPath::Openings RitzPath::openings(const Transition& transition) const {
  const RitzModel& old = *model_;
  const PathPoint& at = transition.point;
  Openings o;
  std::vector<double> limits(at.x.data() + old.limit_offset(), at.x.data() + old.unknowns());
  std::vector<bool> remove(limits.size(), false);
  bool flip_first = false;
  for (const RitzEventSpec& spec : transition.events) {
    switch (spec.function) {
      case RitzEventFunction::length: {
        const int p = spec.piece;
        if (p > 0) remove[p - 1] = true;
        if (p < old.limits()) remove[p] = true;
        if (p == 0) flip_first = !flip_first;
        break;
      }
      case RitzEventFunction::interior_extreme: {
        // Every local extreme of the piece that reaches zero here opens a zone (symmetric
        // loads open two at once, and one event function sees only the lower).
        const ContactRegion piece = old.pieces(at.x)[spec.piece];
        const double zero = 1e-6 * events_->w_scale(old, at.x);
        for (const RitzEventValue& local : events_->local_minima(old, at.x, piece.begin, piece.end, piece.in_contact))
          if (local.value <= zero) o.zones.emplace_back(local.at, 1);
        break;
      }
      case RitzEventFunction::end_value:
        o.zones.emplace_back(events_->value(old, at.x, spec).at, spec.far_end ? 2 : 0);
        if (!spec.far_end) flip_first = !flip_first;
        break;
      case RitzEventFunction::limit_at_load:
        break;
    }
  }
  for (std::size_t m = 0; m < limits.size(); ++m)
    if (!remove[m]) o.kept.push_back(limits[m]);
  int added = 0;
  for (const auto& zone : o.zones) added += zone.second == 1 ? 2 : 1;
  o.topology = {old.topology().first_in_contact != flip_first, static_cast<int>(o.kept.size()) + added};
  return o;
}

// The topology after the transition's events, and a first equilibrium in it.
PathModel::Entry RitzPath::switch_topology(const Transition& transition) {
  const Openings o = openings(transition);
  // Nothing holds a free-free member that has lifted off everywhere.
  if (!o.topology.first_in_contact && o.topology.limits == 0 && member_.left == model::EndSupport::free &&
      member_.right == model::EndSupport::free && member_.point_supports.empty())
    return failed(TraceTermination::no_equilibrium,
                  fmt::format("no equilibrium beyond lambda = {:.10g}: the member has lifted off the foundation "
                              "entirely and nothing else holds it",
                              transition.point.lambda));
  return open_topology(transition, o, removal_allowance(transition));
}

// A removed piece leaves what w had over it, of the wrong sign for the merged piece (and as small
// as locating the event left it): that much violation is allowed at the switch.
double RitzPath::removal_allowance(const Transition& transition) const {
  const RitzModel& old = *model_;
  const PathPoint& at = transition.point;
  const std::vector<ContactRegion> pieces = old.pieces(at.x);
  const double scale = std::max(events_->w_scale(old, at.x), 1e-300);
  double allowance = 0.0;
  for (const RitzEventSpec& spec : transition.events) {
    if (spec.function != RitzEventFunction::length) continue;
    const ContactRegion& p = pieces[spec.piece];
    const double lo = std::min(p.begin, p.end), hi = std::max(p.begin, p.end);
    constexpr int samples = 64;
    for (int i = 0; i <= samples; ++i)
      allowance = std::max(allowance, std::abs(old.w(at.x, lo + (hi - lo) * i / samples)) / scale);
  }
  return allowance;
}

// A first equilibrium in the new topology. A removal needs none other than the event's own
// amplitudes. An opening continues the old topology a little past the event (first the
// transition's opening, a tenth of the step in use in lambda); the roots of w around each opening
// point there are the new zone's limits. Should Newton fail from there, the opening step shrinks.
PathModel::Entry RitzPath::open_topology(const Transition& transition, const Openings& o, double allowance) {
  const RitzModel& old = *model_;
  const PathPoint& at = transition.point;
  std::string failure;
  double delta = transition.opening.delta;
  for (int attempt = 0; attempt < 8; ++attempt, delta *= 0.1) {
    PathPoint base = at;
    std::vector<double> guess = o.kept;
    if (!o.zones.empty())
      if (auto why = open_guess(transition, o, delta, base, guess)) {
        failure = *why;
        continue;
      }
    auto candidate = std::make_shared<const RitzModel>(member_, modes_, o.topology, enrichment_);
    VectorXd x(candidate->unknowns());
    x.head(candidate->amplitudes()) = base.x.head(old.amplitudes());
    for (int m = 0; m < o.topology.limits; ++m) x[candidate->limit_offset() + m] = guess[m];
    // The new tangent has lambda growing, as every path of contact solutions (see turned_back). The
    // old tangent cannot tell: at a piece vanishing it is that of a fold (t_lambda = 0), its
    // amplitude part of either sense. Beam-columns may switch on a falling branch: the new
    // tangent keeps the old one's sense.
    std::optional<PathPoint> orientation;
    if (candidate->can_lose_stability()) {
      PathPoint p;
      p.x = x;
      p.lambda = base.lambda;
      p.tangent_x = VectorXd::Zero(candidate->unknowns());
      p.tangent_x.head(candidate->amplitudes()) = base.tangent_x.head(old.amplitudes());
      p.tangent_lambda = base.tangent_lambda;
      orientation = std::move(p);
    }
    nonlinear::NewtonSummary newton;
    std::optional<PathPoint> start = follower_for(candidate).start(x, base.lambda, &newton, orientation);
    if (!start) {
      failure = "Newton: " + newton.message;
    } else if (auto why = events_->state_failure(*candidate, start->x, allowance)) {
      failure = fmt::format("at lambda = {:.10g}: {}", start->lambda, *why);
    } else {
      start->iterations = newton.iterations;
      rescale(candidate, *start);
      adopt(std::move(candidate));
      vouch(*start);
      Entry entry;
      entry.point = std::move(start);
      entry.record = base.lambda != at.lambda;
      return entry;
    }
    if (o.zones.empty()) break;  // nothing to vary
  }
  return failed(TraceTermination::solver_failure,
                fmt::format("no equilibrium found in the topology {} after the event at lambda = {:.10g}: {}",
                            to_string(o.topology), at.lambda, failure));
}

// The old topology continued `delta` past the event (base), and the new limits' guesses there
// appended to `guess`; why not, if it cannot be continued or the zones are not local.
std::optional<std::string> RitzPath::open_guess(const Transition& transition, const Openings& o, double delta,
                                                PathPoint& base, std::vector<double>& guess) const {
  const RitzModel& old = *model_;
  const PathPoint& at = transition.point;
  StepOutcome past = follower_for(model_).step_to_lambda(at, at.lambda + transition.opening.direction * delta);
  if (!past.point) return "the old topology could not be continued past the event: " + past.corrector.message;
  base = *past.point;
  const std::vector<ContactRegion> pieces = old.pieces(base.x);
  std::vector<ContactRegion> zones;  // each new zone (s), for the locality check below
  for (auto [s, where] : o.zones) {
    // The new zone's sign: w's at an interior opening point; at an end, the opposite of the end
    // piece's state (w there is 0 at a supported end, and its sign noise: a scan keyed on it
    // stops at once and Newton settles on a zone of no width).
    const ContactRegion& end_piece = where == 0 ? pieces.front() : pieces.back();
    const double w0 = where == 1 ? old.w(base.x, s) : (end_piece.in_contact ? -1.0 : 1.0);
    // From s toward limit_s, the first point where w has left the sign it has at s.
    const auto scan = [&](double limit_s) {
      return first_leaving(
          old, base.x, s, limit_s, [&](double t) { return (old.w(base.x, t) > 0) != (w0 > 0); }, member_.length());
    };
    if (where == 1) {
      double lo = member_.foundation_begin, hi = member_.foundation_end;
      for (const ContactRegion& p : pieces)
        if (s >= p.begin && s <= p.end) lo = p.begin, hi = p.end;
      guess.push_back(scan(lo));
      guess.push_back(scan(hi));
      zones.push_back({guess.end()[-2], guess.back(), w0 > 0});
    } else {
      guess.push_back(scan(where == 0 ? pieces.front().end : pieces.back().begin));
      zones.push_back(where == 0 ? ContactRegion{member_.foundation_begin, guess.back(), w0 > 0}
                                 : ContactRegion{guess.back(), member_.foundation_end, w0 > 0});
    }
  }
  std::sort(guess.begin(), guess.end());
  // The zones must open locally: one that already covers another local extreme of w at the event
  // (a minimum in a contact piece, a maximum in a lift-off one) has swallowed the events between
  // (culvert: a zone opened at a pinned end reached past a minimum of w that lifted off first), so
  // the opening step is too long.
  const double zero = 1e-6 * events_->w_scale(old, at.x);
  for (const ContactRegion& piece : old.pieces(at.x))
    for (const RitzEventValue& e : events_->local_minima(old, at.x, piece.begin, piece.end, piece.in_contact))
      if (e.value > zero)  // not an opening point itself
        for (const ContactRegion& zone : zones)
          if (e.at > zone.begin && e.at < zone.end)
            return fmt::format(
                "the zone opened {:.3g} past the event in lambda covers another local extreme of w at "
                "{} = {:.6g}",
                delta, coordinate(), user(e.at));
  return std::nullopt;
}

// --------------------------------------------------------------------------------------------
// Branch switching.

BranchSwitch RitzPath::switch_branch(const PathPoint& at, const PathFollower& /*follower*/) {
  std::string why;
  std::optional<Branch> branch = find_branch(at, why);
  if (!branch) return {std::nullopt, "no bifurcated branch found (" + why + ")"};
  adopt(branch->model);
  watch_ = branch->watch;
  rescale(model_, branch->point);
  vouch(branch->point);
  BranchStart start;
  start.point = branch->point;
  if (watch_) {
    const ReturnWatch watch = *watch_;
    const int amplitudes = model_->amplitudes();
    start.amplitude = [watch, amplitudes](const PathPoint& p) {
      return watch.departure * (watch.mode.dot(p.x.head(amplitudes)) - watch.at);
    };
    // Down to round-off in the step: at the crossing's fold a bracket small in lambda says little
    // about the point, and the corrector may land on the crossing path (with event_tolerance the
    // load was 1e-7 off). refine_return then finds the crossing.
    start.return_tolerance = 0.0;
  }
  start.description = fmt::format("{}, lambda = {:.10g}", to_string(model_->topology()), start.point.lambda);
  return {std::move(start), ""};
}

// The bifurcated branch at a bifurcation point `at` (lambda_c) where the path loses its
// stability. The critical mode phi (the amplitudes' eigenvector of the reduced Hessian's smallest
// eigenvalue, zero there) solves the fixed-topology equations at lambda_c for any multiple
// added, as far as the contact conditions allow: x + a phi (lift_off_branch).
std::optional<RitzPath::Branch> RitzPath::find_branch(const PathPoint& at, std::string& why) const {
  const RitzModel& model = *model_;
  // The critical mode, scaled as stability_margin scales the Hessian.
  VectorXd scale = model.stiffness().diagonal();
  for (Eigen::Index i = 0; i < scale.size(); ++i) scale[i] = scale[i] > 0.0 ? 1.0 / std::sqrt(scale[i]) : 1.0;
  const Eigen::SelfAdjointEigenSolver<MatrixXd> eigen(scale.asDiagonal() * model.reduced_hessian(at.x, at.lambda) *
                                                      scale.asDiagonal());
  if (eigen.info() != Eigen::Success) {
    why = "the eigensolver failed";
    return std::nullopt;
  }
  VectorXd mode = VectorXd::Zero(model.unknowns());
  mode.head(model.amplitudes()) = scale.asDiagonal() * eigen.eigenvectors().col(0);
  // Von Karman on a bilateral foundation: nothing lifts off, the bifurcated branch keeps the
  // topology (the shallow arch's asymmetric branch). Its first point: the amplitude the mode
  // moves most held a little off the bifurcation point, lambda free; the tangent leads away from
  // the point. (A linear beam-column's branch is at constant lambda: left as it was, no switch.)
  if (!member_.tensionless && member_.theory == model::Theory::von_karman) return switch_in_topology(at, mode, why);
  return lift_off_branch(at, std::move(mode), why);
}

// The side of the critical mode that lifts the member off first (the least a > 0 at which
// w + a phi touches zero in a contact piece, away from its limits: where the reaction is smallest
// relative to the mode's lift). A tensionless foundation admits that side only once it touches:
// there a lift-off zone opens (at every point that touches at that a), and the branch is that of
// the topology with the new zones. Its first point: w + 1.02 a phi dips below zero near each
// touching point, whose roots guess the new limits; the first zone's one limit held fixed, Newton
// solves the new topology's equations for the other unknowns and lambda (that limit's column of
// the Jacobian replaced by dR/dlambda). The branch is then followed with the zone widening.
// Not handled (why says so): a critical mode that lifts where a lift-off zone already ends (the
// zone would grow in the same topology), one that pushes a lift-off piece into the foundation.
std::optional<RitzPath::Branch> RitzPath::lift_off_branch(const PathPoint& at, VectorXd mode, std::string& why) const {
  const RitzModel& model = *model_;
  const int amplitudes = model.amplitudes();
  // 1. Where and at which amplitude it first lifts the member off, on a grid of the contact
  //    pieces (a foundation end that is free included, the pieces' limits excluded).
  const int samples = std::max(400, 16 * modes_);
  const double h = member_.length() / samples;
  const double w_size = std::max(events_->w_scale(model, at.x), 1e-300);
  double best = infinity, sign = 1.0;
  struct Sample {
    double s, a, sign;
  };
  std::vector<Sample> lifts;  // at each sample, the multiple a of the mode, of the sign that lifts, touching there
  const std::vector<ContactRegion> pieces = model.pieces(at.x);
  for (const ContactRegion& piece : pieces) {
    if (!piece.in_contact) continue;
    const bool begins = piece.begin <= member_.foundation_begin && !events_->end_supported(true);
    const bool ends = piece.end >= member_.foundation_end && !events_->end_supported(false);
    const double lo = begins ? piece.begin : piece.begin + h, hi = ends ? piece.end : piece.end - h;
    const int n = std::max(1, static_cast<int>(std::ceil((hi - lo) / h)));
    for (int i = 0; i <= n && hi >= lo; ++i) {
      const double s = lo + (hi - lo) * i / n;
      const double w = model.w(at.x, s), f = model.w(mode, s);
      if (!(std::abs(f) > 1e-12 * std::abs(w))) continue;
      lifts.push_back({s, w / std::abs(f), f < 0 ? 1.0 : -1.0});
      if (lifts.back().a < best * (1.0 - 1e-12)) best = lifts.back().a, sign = lifts.back().sign;
    }
  }
  // Von Karman on a tensionless foundation: where the mode lifts nothing within ten times the
  // in-topology first point's offset, the branch starts in contact as on a bilateral foundation
  // (the shallow arch's asymmetric branch lifts off at an end only once |A2| = A1 / 2), and its
  // lift-off is a contact event on the branch.
  if (member_.theory == model::Theory::von_karman) {
    Eigen::Index held = 0;
    if (!(best <= 10.0 * in_topology_offset(at, mode, held))) return switch_in_topology(at, mode, why);
  }
  if (!std::isfinite(best) || !(best > 0.0)) {
    why = "the critical mode lifts no contact piece off";
    return std::nullopt;
  }
  // Every point where it touches at that multiple (to 1e-6: a symmetric mode lifts both ends, or
  // two mirror points, at once), one per cluster of samples.
  std::vector<double> touches;
  for (const Sample& sample : lifts)
    if (sample.sign == sign && sample.a <= best * (1.0 + 1e-6) &&
        (touches.empty() || sample.s - touches.back() > 4.0 * h))
      touches.push_back(sample.s);
  // Next to a limit, the mode would only move it (the zone grows in the same topology).
  for (double touch : touches)
    for (const ContactRegion& piece : pieces)
      for (double t : {piece.begin, piece.end})
        if (t > member_.foundation_begin && t < member_.foundation_end && std::abs(touch - t) < 2.0 * h) {
          why = fmt::format("the critical mode lifts the member first next to the contact limit at {:.6g}", user(t));
          return std::nullopt;
        }
  mode *= sign;
  constexpr double overshoot = 1.02;
  VectorXd base = at.x;
  base.head(amplitudes) += overshoot * best * mode.head(amplitudes);
  for (const ContactRegion& piece : pieces)
    if (!piece.in_contact && events_->extreme(model, base, piece.begin, piece.end, false).value < -1e-9 * w_size) {
      why = "the critical mode pushes a lift-off piece into the foundation";
      return std::nullopt;
    }
  // 2. The new zones' limits: the roots of the base's w around each touching point.
  const auto scan = [&](double touch, double limit_s) {  // from touch toward limit_s, the first w >= 0
    return first_leaving(
        model, base, touch, limit_s, [&](double t) { return model.w(base, t) >= 0; }, member_.length());
  };
  std::vector<double> limits(at.x.data() + model.limit_offset(), at.x.data() + model.unknowns());
  bool first_in_contact = model.topology().first_in_contact;
  // The limit held in the Newton below (the first zone's), and its sense as that zone widens.
  std::optional<double> fixed;
  double widening = 1.0;
  for (double touch : touches) {
    ContactRegion host{member_.foundation_begin, member_.foundation_end, true};
    for (const ContactRegion& piece : pieces)
      if (piece.in_contact && touch >= piece.begin && touch <= piece.end) host = piece;
    double limit = 0.0, sense = -1.0;
    if (touch <= member_.foundation_begin + 0.5 * h) {
      limit = scan(touch, host.end), sense = 1.0;
      first_in_contact = !first_in_contact;
    } else if (touch >= member_.foundation_end - 0.5 * h) {
      limit = scan(touch, host.begin);
    } else {
      limit = scan(touch, host.begin);
      limits.push_back(scan(touch, host.end));
    }
    limits.push_back(limit);
    if (!fixed) fixed = limit, widening = sense;
  }
  std::sort(limits.begin(), limits.end());
  const Topology topology{first_in_contact, static_cast<int>(limits.size())};
  auto candidate = std::make_shared<const RitzModel>(member_, modes_, topology, enrichment_);
  VectorXd x(candidate->unknowns());
  x.head(candidate->amplitudes()) = base.head(amplitudes);
  for (int m = 0; m < topology.limits; ++m) x[candidate->limit_offset() + m] = limits[m];
  const int held =
      candidate->limit_offset() + static_cast<int>(std::find(limits.begin(), limits.end(), *fixed) - limits.begin());
  // 3. Newton with that limit held, lambda free.
  double lambda = at.lambda;
  VectorXd residual_scale = VectorXd::Constant(candidate->unknowns(), 1.0 / force_scale(*candidate));
  residual_scale.tail(topology.limits).setConstant(1.0 / w_size);
  if (!solve_with_held(*candidate, held, residual_scale, x, lambda) || !candidate->admissible(x)) {
    why = fmt::format("Newton on the topology {} with the limit at {:.6g} held did not converge", to_string(topology),
                      user(*fixed));
    return std::nullopt;
  }
  // 4. The first point of the branch, its tangent widening the zone.
  std::optional<Branch> branch = branch_from(candidate, x, lambda, held, widening, why);
  if (!branch) return std::nullopt;
  if (auto failure = events_->state_failure(*branch->model, branch->point.x)) {
    why = fmt::format("the branch's first point at lambda = {:.10g} is no contact solution: {}", branch->point.lambda,
                      *failure);
    return std::nullopt;
  }
  return branch;
}

// The branch in the same topology along `mode`, watched for its return (ReturnWatch).
std::optional<RitzPath::Branch> RitzPath::switch_in_topology(const PathPoint& at, const VectorXd& mode,
                                                             std::string& why) const {
  const RitzModel& model = *model_;
  Eigen::Index held = 0;
  const double offset = in_topology_offset(at, mode, held);
  VectorXd x = at.x + offset * mode;
  double lambda = at.lambda;
  const VectorXd residual_scale = VectorXd::Constant(model.unknowns(), 1.0 / force_scale(model));
  if (!solve_with_held(model, static_cast<int>(held), residual_scale, x, lambda)) {
    why = "Newton with the critical mode's amplitude held off the bifurcation point did not converge";
    return std::nullopt;
  }
  std::optional<Branch> branch =
      branch_from(model_, x, lambda, static_cast<int>(held), mode[held] > 0.0 ? 1.0 : -1.0, why);
  if (branch) {
    ReturnWatch watch;
    watch.mode = mode.head(model.amplitudes()).normalized();
    watch.at = watch.mode.dot(at.x.head(model.amplitudes()));
    watch.departure = watch.mode.dot(branch->point.x.head(model.amplitudes())) > watch.at ? 1.0 : -1.0;
    watch.lambda = at.lambda;
    branch->watch = std::move(watch);
  }
  return branch;
}

// The multiple of `mode` the in-topology switch steps off the bifurcation point, and the
// amplitude it holds there (the one the mode moves most).
double RitzPath::in_topology_offset(const PathPoint& at, const VectorXd& mode, Eigen::Index& held) const {
  mode.head(model_->amplitudes()).cwiseAbs().maxCoeff(&held);
  // A step off the point of 1e-3 of w's size along the mode: small beside the branch's own
  // curvature, large beside Newton's tolerance (1e-12).
  const double w_size = std::max(events_->w_scale(*model_, at.x), 1e-300);
  return 1e-3 * w_size / std::abs(mode[held]);
}

std::optional<PathPoint> RitzPath::refine_return(const PathPoint& located, double /*peak*/,
                                                 const PathFollower& follower) {
  if (!watch_) return std::nullopt;
  return refined_crossing(follower, located);
}

// The crossing point of a switched branch with the path it left, from `near` (the branch's return
// located on the mode's component, on either path: on the path it rejoins that component vanishes
// all along, so the locate cannot tell where the crossing is): a secant in lambda on
// stability_margin, zero at the crossing and linear in lambda beside it, each point solved at
// fixed lambda from `near` less its mode component. nullopt if that does not converge.
std::optional<PathPoint> RitzPath::refined_crossing(const PathFollower& follower, const PathPoint& near) const {
  const RitzModel& model = *model_;
  const int amplitudes = model.amplitudes();
  PathPoint guess = near;
  guess.x.head(amplitudes) -= (watch_->mode.dot(near.x.head(amplitudes)) - watch_->at) * watch_->mode;
  const auto solved = [&](double lambda) { return follower.step_to_lambda(guess, lambda, &guess.x).point; };
  std::optional<PathPoint> a = solved(near.lambda);
  if (!a) return std::nullopt;
  double margin_a = model.stability_margin(a->x, a->lambda);
  std::optional<PathPoint> b = solved(near.lambda + 1e-6 * lambda_size());
  for (int iteration = 0; b && iteration < 30; ++iteration) {
    const double margin_b = model.stability_margin(b->x, b->lambda);
    if (std::abs(b->lambda - a->lambda) <= 0.1 * options_.event_tolerance || margin_b == 0.0) return *b;
    if (margin_b == margin_a) break;
    const double lambda = b->lambda - margin_b * (b->lambda - a->lambda) / (margin_b - margin_a);
    a = std::move(b);
    margin_a = margin_b;
    b = solved(lambda);
  }
  return std::nullopt;
}

// Newton on `model` from (x, lambda) with unknown `held` fixed and lambda free in its place
// (false if it does not converge).
bool RitzPath::solve_with_held(const RitzModel& model, int held, const VectorXd& residual_scale, VectorXd& x,
                               double& lambda) const {
  VectorXd r;
  MatrixXd j;
  for (int iteration = 0; iteration < 50; ++iteration) {
    model.residual(x, lambda, r);
    if (!r.allFinite()) return false;
    if (r.cwiseProduct(residual_scale).lpNorm<Eigen::Infinity>() <= 1e-12) return true;
    model.jacobian(x, lambda, j);
    j.col(held) = model.residual_lambda_derivative(x);
    const VectorXd delta =
        (residual_scale.asDiagonal() * j).colPivHouseholderQr().solve(-residual_scale.cwiseProduct(r));
    if (!delta.allFinite()) return false;
    for (int m = 0; m < model.unknowns(); ++m)
      if (m != held) x[m] += delta[m];
    lambda += delta[held];
  }
  return false;
}

// The follower's first point at (x, lambda) on `model`, its tangent oriented along +-held
// (`sense`); nullopt, with why filled, if no tangent.
std::optional<RitzPath::Branch> RitzPath::branch_from(std::shared_ptr<const RitzModel> model, const VectorXd& x,
                                                      double lambda, int held, double sense, std::string& why) const {
  PathPoint orientation;
  orientation.x = x;
  orientation.lambda = lambda;
  orientation.tangent_x = VectorXd::Zero(model->unknowns());
  orientation.tangent_x[held] = sense;
  orientation.tangent_lambda = 0.0;
  nonlinear::NewtonSummary newton;
  std::optional<PathPoint> point = follower_for(model).start(x, lambda, &newton, orientation);
  if (!point) {
    why = "no tangent at the branch's first point: " + newton.message;
    return std::nullopt;
  }
  point->iterations = newton.iterations;
  return Branch{std::move(model), std::move(*point), std::nullopt};
}

}  // namespace liftoff::continuation
