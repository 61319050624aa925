#include "continuation/fe_axial_path.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>

#include "certify/certificate.hpp"
#include "contact/active_set_system.hpp"
#include "contact/contact_solver.hpp"
#include "contact/stability.hpp"
#include "continuation/events.hpp"
#include "fe/discretisation.hpp"
#include "model/from_scene.hpp"
#include "model/member_model.hpp"
#include "post/contact_regions.hpp"
#include "post/fields.hpp"
#include "stability/critical_load.hpp"

namespace liftoff::continuation {

using Eigen::VectorXd;
using ContactSet = std::vector<bool>;

namespace {

// A reaction (gap) above -this fraction of its scale counts as feasible: the fixed-set states are
// refined to round-off (relative residual ~1e-15), so values that small are zero; nodes that
// physically switch at different loads differ by orders more (fe_path.cpp's tie_tolerance).
constexpr double tie_tolerance = 1e-9;
// A fixed-set solve whose relative residual exceeds this is not trusted (as fe_path.cpp).
constexpr double acceptable_residual = 1e-8;
// Bisections: the bracket in lambda is halved at most this often.
constexpr int max_bisections = 200;

struct StepNotCertified {
  double lambda;
  std::string message;
};

// The fixed-set state at one lambda.
struct Point {
  double lambda = 0.0;
  contact::ContactState state;
};

class AxialPath {
 public:
  AxialPath(const scene::Scene& scene, const TraceOptions& options, const TraceSink& sink)
      : options_(options),
        sink_(sink),
        model_(model::make_member_model(scene)),
        d_(fe::discretise(model_, options.elements)),
        stiffness_at_one_(d_.stiffness),
        axial_at_one_(d_.axial_force),
        system_(d_),
        points_(special_points(model_)) {}

  TraceResult run();

 private:
  // d_ (K(N), N) at lambda, and the fixed-set system assembled on it.
  void set_axial(double lambda);
  // The state of `set` at lambda (empty: the set's system is singular there or not accurate).
  std::optional<Point> solve(const ContactSet& set, double lambda);
  // Reaction of a node in the set, gap of one out of it, relative to its scale.
  std::vector<double> relative_values(const ContactSet& set, const Point& p) const;
  bool feasible(const ContactSet& set, const Point& p) const;
  double amplitude(const Point& p) const;
  int negative_eigenvalues(const ContactSet& set, double lambda);
  path::Stability stability_at(const Point& p);
  std::optional<ContactSet> start_set(double lambda);
  TraceStep step_at(const Point& p);
  void emit_step(const Point& p);
  void emit_event(const TraceEvent& event);
  ContactTopology topology_of(const Point& p) const;
  // Contact-topology events between a and b on set_ (a graph over lambda there).
  void locate_events(const Point& a, const Point& b, ContactTopology& topology_a);
  void finish(TraceTermination termination, std::string message, double lambda);

  TraceOptions options_;
  TraceSink sink_;
  model::MemberModel model_;
  fe::Discretisation d_;
  fe::SparseMatrix stiffness_at_one_;  // K(N(1)), as discretise assembled it
  double axial_at_one_ = 0.0;          // N(1)
  contact::ActiveSetSystem system_;
  SpecialPoints points_;
  TraceResult result_;
  ContactSet set_;
  double axial_of_system_ = std::numeric_limits<double>::quiet_NaN();
  int solves_since_step_ = 0;
};

void AxialPath::set_axial(double lambda) {
  const double n = model_.axial_force(lambda);
  if (n == axial_of_system_) return;
  // K(N) = K(N(1)) - (N - N(1)) K_g: the assembled K_g, no second element loop.
  d_.stiffness = stiffness_at_one_ - (n - axial_at_one_) * d_.geometric_stiffness;
  d_.axial_force = n;
  system_.reassemble();
  axial_of_system_ = n;
}

std::optional<Point> AxialPath::solve(const ContactSet& set, double lambda) {
  set_axial(lambda);
  if (!system_.factorise(set)) return std::nullopt;
  Point p;
  p.lambda = lambda;
  p.state = system_.solve(d_.load(lambda), d_.ground_gap);
  ++solves_since_step_;
  if (!(p.state.residual <= acceptable_residual)) return std::nullopt;
  return p;
}

std::vector<double> AxialPath::relative_values(const ContactSet& set, const Point& p) const {
  const double r_scale = std::max(p.state.reaction.lpNorm<Eigen::Infinity>(), 1e-300);
  double g_scale = std::max((d_.flexibility * p.state.reaction).lpNorm<Eigen::Infinity>(),
                            (d_.coupling * p.state.displacement).lpNorm<Eigen::Infinity>());
  if (d_.ground_gap.size() > 0) g_scale = std::max(g_scale, d_.ground_gap.lpNorm<Eigen::Infinity>());
  g_scale = std::max(g_scale, 1e-300);
  std::vector<double> v(d_.reactions());
  for (int i = 0; i < d_.reactions(); ++i) v[i] = set[i] ? p.state.reaction[i] / r_scale : p.state.gap[i] / g_scale;
  return v;
}

bool AxialPath::feasible(const ContactSet& set, const Point& p) const {
  if (!d_.tensionless) return true;
  for (double v : relative_values(set, p))
    if (v < -tie_tolerance) return false;
  return true;
}

double AxialPath::amplitude(const Point& p) const {
  return lift_measures(model_, d_, d_.expand_displacement(p.state.displacement), points_).amplitude;
}

int AxialPath::negative_eigenvalues(const ContactSet& set, double lambda) {
  set_axial(lambda);
  const contact::StabilityCheck check = contact::check_tangent(d_, set);
  return check.positive_definite ? 0 : std::max(check.negative_eigenvalues, 1);
}

// The set's tangent decides stability where every node of the set presses and every other one
// stands off: small perturbations keep the set. A node touching with neither reaction nor gap
// (weakly active: a weightless strut lying on its foundation) has a spring only where the
// perturbation pushes in, which no fixed set represents: there the cone's critical load
// (stability/critical_load.hpp) decides, stable when its factor on the present N exceeds 1.
path::Stability AxialPath::stability_at(const Point& p) {
  set_axial(p.lambda);
  const std::vector<stability::NodeContact> contact = stability::classify_contact(p.state.reaction, p.state.gap);
  if (std::none_of(contact.begin(), contact.end(),
                   [](stability::NodeContact c) { return c == stability::NodeContact::weakly_active; }))
    return negative_eigenvalues(set_, p.lambda) == 0 ? path::Stability::stable : path::Stability::unstable;
  const stability::CriticalLoadResult cone = stability::critical_load(d_, 0.0, d_.axial_force, contact);
  switch (cone.termination) {
    case stability::StabilityTermination::critical_load_found:
      return cone.critical_load_factor > 1.0 ? path::Stability::stable : path::Stability::unstable;
    case stability::StabilityTermination::stable_for_all_factors:
      return path::Stability::stable;
    case stability::StabilityTermination::unstable_at_zero:
      return path::Stability::unstable;
    case stability::StabilityTermination::not_converged:
      break;
  }
  return path::Stability::unknown;
}

std::optional<ContactSet> AxialPath::start_set(double lambda) {
  const int m = d_.reactions();
  if (!d_.tensionless) return ContactSet(m, true);
  // Cheapest first: full contact, if every reaction it gives is compressive.
  if (const auto p = solve(ContactSet(m, true), lambda); p && feasible(ContactSet(m, true), *p))
    return ContactSet(m, true);
  // The contact solver on the member with N(lambda) as a dead load (the same equations at this
  // lambda: its initial-shape load is N(lambda) w0, the transverse loads dead + lambda live).
  model::MemberModel fixed = model_;
  fixed.axial_dead = model_.axial_force(lambda);
  fixed.axial_live = 0.0;
  const fe::Discretisation d = fe::discretise(fixed, options_.elements);
  contact::ContactOptions options;
  const contact::Method asked = options_.contact_method;
  options.method = asked == contact::Method::dual || asked == contact::Method::primal ? asked : contact::Method::fast;
  options.load_factor = lambda;
  const contact::ContactSolution solution = contact::solve_contact(d, options);
  ++result_.summary.contact_solves;
  result_.summary.contact_method = solution.summary.method;
  if (!solution.summary.is_usable()) {
    finish(solution.summary.termination == contact::ContactTermination::no_equilibrium
               ? TraceTermination::no_equilibrium
               : TraceTermination::solver_failure,
           fmt::format("the contact solver at lambda = {:.10g}: {}", lambda, solution.summary.message), lambda);
    return std::nullopt;
  }
  const double r_scale = std::max(solution.reaction.lpNorm<Eigen::Infinity>(), 1e-300);
  const double g_scale = std::max((d.flexibility * solution.reaction).lpNorm<Eigen::Infinity>(), 1e-300);
  ContactSet set(m);
  for (int i = 0; i < m; ++i) set[i] = solution.reaction[i] / r_scale > solution.gap[i] / g_scale;
  const auto p = solve(set, lambda);
  if (!p || !feasible(set, *p)) {
    finish(TraceTermination::solver_failure,
           fmt::format("the contact set the contact solver found at lambda = {:.10g} is not feasible there", lambda),
           lambda);
    return std::nullopt;
  }
  return set;
}

ContactTopology AxialPath::topology_of(const Point& p) const {
  return contact_topology(model_, d_, d_.expand_displacement(p.state.displacement), points_);
}

TraceStep AxialPath::step_at(const Point& p) {
  TraceStep step;
  step.load_factor = p.lambda;
  const VectorXd displacement = d_.expand_displacement(p.state.displacement);
  for (const auto& region : post::contact_regions(model_, d_, displacement))
    step.contact_regions.push_back({model_.user_from_s(region.begin), model_.user_from_s(region.end)});
  auto at = [&](double user) {
    const double s = std::clamp(model_.s_from_user(user), model_.s_begin, model_.s_end);
    const int e = d_.mesh.element_containing(s);
    return std::pair{e, (s - d_.mesh.nodes[e]) / d_.mesh.element_size(e)};
  };
  const model::Scales& scales = model_.scales;
  const auto [me, mxi] = at(options_.monitor);
  step.monitor_deflection = post::evaluate(d_, displacement, me, mxi).w * scales.displacement();
  for (double x : options_.sample_points) {
    const auto [e, xi] = at(x);
    step.deflection.push_back(post::evaluate(d_, displacement, e, xi).w * scales.displacement());
    step.reaction.push_back(post::reaction_at(d_, p.state.reaction, e, xi) * scales.force_per_length());
  }
  step.axial_force = model_.axial_force(p.lambda) * scales.force();
  const LiftMeasures lift = lift_measures(model_, d_, displacement, points_);
  step.amplitude = lift.amplitude;
  step.lifted_length = lift.lifted_length;
  step.stability = stability_at(p);
  step.state_topology = path::FeContactSet{};
  step.state.assign(set_.begin(), set_.end());
  return step;
}

void AxialPath::emit_step(const Point& p) {
  TraceStep step = step_at(p);
  // Certified from its own fields (balance with K(N) at this lambda, the contact inequalities,
  // backward error) as the exact path's states are.
  set_axial(p.lambda);
  contact::ContactSolution answer;
  answer.displacement = d_.expand_displacement(p.state.displacement);
  answer.reaction = p.state.reaction;
  certify::CertifyOptions certify_options;
  certify_options.load_factor = p.lambda;
  certify_options.round_off = false;
  certify_options.backward_tolerance = acceptable_residual;
  certify_options.pointwise = false;
  certify_options.sign_floor = acceptable_residual;
  certify_options.global_scale = true;
  const certify::Certificate certificate = certify::certify(model_, d_, answer, certify_options);
  if (!certificate.passed)
    throw StepNotCertified{p.lambda, fmt::format("the state at lambda = {:.10g} failed its certificate: {}", p.lambda,
                                                 certificate.message)};
  step.iterations = solves_since_step_;
  solves_since_step_ = 0;
  if (sink_.on_step) sink_.on_step(step);
  result_.steps.push_back(std::move(step));
  ++result_.summary.steps;
}

void AxialPath::emit_event(const TraceEvent& event) {
  if (sink_.on_event) sink_.on_event(event);
  result_.events.push_back(event);
}

void AxialPath::locate_events(const Point& a, const Point& b, ContactTopology& topology_a) {
  ContactTopology topology_b = topology_of(b);
  double from = a.lambda;
  for (int guard = 0; guard < 64 && !topology_a.same_as(topology_b); ++guard) {
    double lo = from, hi = b.lambda;
    ContactTopology before = topology_a;
    std::optional<Point> at_hi;
    for (int i = 0; i < max_bisections && std::abs(hi - lo) > options_.event_tolerance; ++i) {
      const double mid = 0.5 * (lo + hi);
      const auto p = solve(set_, mid);
      if (!p) break;
      ContactTopology at_mid = topology_of(*p);
      if (at_mid.same_as(topology_a)) {
        lo = mid;
        before = std::move(at_mid);
      } else {
        hi = mid;
        at_hi = p;
      }
    }
    if (!at_hi) at_hi = hi == b.lambda ? std::optional<Point>(b) : solve(set_, hi);
    if (!at_hi) break;
    const ContactTopology after = topology_of(*at_hi);
    const std::vector<TraceEvent> events = classify_events(model_, points_, before, after, hi);
    if (!events.empty()) {
      emit_step(*at_hi);
      for (const auto& event : events) emit_event(event);
    }
    from = hi;
    topology_a = after;
  }
  topology_a = topology_b;
}

void AxialPath::finish(TraceTermination termination, std::string message, double lambda) {
  result_.summary.termination = termination;
  result_.summary.message = std::move(message);
  result_.summary.final_load_factor = lambda;
}

TraceResult AxialPath::run() {
  const auto start = std::chrono::steady_clock::now();
  TraceSummary& summary = result_.summary;
  summary.path = PathKind::fe;
  summary.pivots = 0;
  const int m = d_.reactions();
  const double lambda_min = std::min(options_.arc_length.lambda_min, options_.arc_length.lambda_max);
  const double lambda_max = std::max(options_.arc_length.lambda_min, options_.arc_length.lambda_max);
  const double span = std::max(lambda_max - lambda_min, 1e-300);
  double direction = options_.arc_length.lambda_max >= options_.arc_length.lambda_min ? 1.0 : -1.0;
  const double lambda_start = options_.arc_length.lambda_min;
  const double max_step = options_.arc_length.max_step * span, initial_step = options_.arc_length.initial_step * span;
  const double min_step = std::max(options_.arc_length.min_step * span, 4.0 * options_.event_tolerance);
  int folds = 0, bifurcations = 0, breakpoints = 0;

  auto done = [&]() {
    summary.factorisations = system_.factorisations();
    summary.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return std::move(result_);
  };
  auto ending = [&](double lambda) {
    return fmt::format("lambda = {:.10g} reached: {} breakpoint(s), {} limit point(s), {} bifurcation(s), {} event(s)",
                       lambda, breakpoints, folds, bifurcations, result_.events.size());
  };
  try {
    if (options_.resume_from) {
      finish(TraceTermination::solver_failure,
             "a trace in the axial force is not resumed in this version: run it again without the file", lambda_start);
      return done();
    }
    if (model_.has_settlements() && model_.axial_live != 0.0) {
      finish(TraceTermination::solver_failure,
             "settled supports under a live axial force are not traced in this version (their load N K_g u_f varies "
             "with lambda)",
             lambda_start);
      return done();
    }
    const auto start_set_found = start_set(lambda_start);
    if (!start_set_found) return done();
    set_ = *start_set_found;
    std::optional<Point> current = solve(set_, lambda_start);
    if (!current) {
      finish(TraceTermination::solver_failure, "the fixed-set system is singular at the start", lambda_start);
      return done();
    }
    emit_step(*current);
    int negative = negative_eigenvalues(set_, current->lambda);
    ContactTopology topology = topology_of(*current);
    double step = initial_step;
    double last_breakpoint = current->lambda;

    while (true) {
      if (result_.summary.steps >= options_.arc_length.max_steps) {
        finish(
            TraceTermination::step_limit,
            fmt::format("max_steps = {} reached at lambda = {:.10g}", options_.arc_length.max_steps, current->lambda),
            current->lambda);
        return done();
      }
      // The next point on this set, clamped to the range.
      double target = current->lambda + direction * step;
      const bool at_end = direction > 0 ? target >= lambda_max : target <= lambda_min;
      if (at_end) target = direction > 0 ? lambda_max : lambda_min;
      std::optional<Point> next = solve(set_, target);
      const bool ok = next && feasible(set_, *next);
      const int next_negative = next ? negative_eigenvalues(set_, target) : negative;
      const bool past_amplitude = ok && options_.max_amplitude && amplitude(*next) >= *options_.max_amplitude;
      if (ok && next_negative == negative && !past_amplitude) {
        locate_events(*current, *next, topology);
        current = next;
        emit_step(*current);
        if (at_end) {
          finish(TraceTermination::completed, ending(current->lambda), current->lambda);
          return done();
        }
        step = std::min(2.0 * step, max_step);
        continue;
      }
      if (ok && next_negative != negative && step > min_step) {  // shorter first: a singular tangent
        step *= 0.5;                                             // inside the step is located below
        continue;
      }
      // Something happens in (current, target]: the first lambda where it does, to event_tolerance.
      double lo = current->lambda, hi = target;
      Point good = *current;
      // The inertia is watched inside the step only when it differs at its end (an LDL^T per
      // point); a pair of sign changes within one step is not seen.
      const bool watch_inertia = next && next_negative != negative;
      auto happens = [&](const std::optional<Point>& p) {
        if (!p || !feasible(set_, *p)) return true;
        if (options_.max_amplitude && amplitude(*p) >= *options_.max_amplitude) return true;
        return watch_inertia && negative_eigenvalues(set_, p->lambda) != negative;
      };
      std::optional<Point> bad = next;
      // Regula falsi (Illinois) on the smallest margin of the contact conditions and of the
      // amplitude bound, continuous along the set's branch; a bisection whenever a step did not
      // halve the bracket, and throughout when the inertia is watched.
      auto margin = [&](const Point& p) {
        double smallest = std::numeric_limits<double>::infinity();
        if (d_.tensionless)
          for (double v : relative_values(set_, p)) smallest = std::min(smallest, v + tie_tolerance);
        if (options_.max_amplitude)
          smallest = std::min(smallest, (*options_.max_amplitude - amplitude(p)) / *options_.max_amplitude);
        return smallest;
      };
      const double nan = std::numeric_limits<double>::quiet_NaN();
      double f_lo = margin(good), f_hi = bad ? margin(*bad) : nan;
      int moved = 0;  // +1: lo moved last, -1: hi
      bool bisect = watch_inertia;
      for (int i = 0; i < max_bisections && std::abs(hi - lo) > options_.event_tolerance; ++i) {
        const double width = std::abs(hi - lo);
        double mid = 0.5 * (lo + hi);
        if (!bisect && std::isfinite(f_lo) && std::isfinite(f_hi) && f_lo >= 0.0 && f_hi < 0.0) {
          const double secant = hi - f_hi * (hi - lo) / (f_hi - f_lo);
          if (secant > std::min(lo, hi) && secant < std::max(lo, hi)) mid = secant;
        }
        auto p = solve(set_, mid);
        if (happens(p)) {
          hi = mid;
          bad = p;
          f_hi = p ? margin(*p) : nan;
          if (moved == -1) f_lo *= 0.5;
          moved = -1;
        } else {
          lo = mid;
          good = *p;
          f_lo = margin(*p);
          if (moved == +1) f_hi *= 0.5;
          moved = +1;
        }
        bisect = watch_inertia || std::abs(hi - lo) > 0.5 * width;
      }
      locate_events(*current, good, topology);
      current = good;
      if (!bad) {
        emit_step(*current);
        finish(TraceTermination::solver_failure,
               fmt::format("the fixed-set system turned singular at lambda = {:.10g}", hi), current->lambda);
        return done();
      }
      // Which happened at hi: the amplitude bound, a contact condition, a singular tangent.
      if (options_.max_amplitude && feasible(set_, *bad) && amplitude(*bad) >= *options_.max_amplitude) {
        emit_step(*bad);
        finish(TraceTermination::completed,
               fmt::format("amplitude {:.6g} reached (max_amplitude) at lambda = {:.10g}: {} limit point(s), {} "
                           "bifurcation(s), {} event(s)",
                           *options_.max_amplitude, bad->lambda, folds, bifurcations, result_.events.size()),
               bad->lambda);
        return done();
      }
      if (feasible(set_, *bad)) {
        // The tangent on this set turns singular between good and bad with no breakpoint: a
        // bifurcation point of the fixed-set problem (the path itself passes: the load has no
        // part along the critical mode, else its amplitude would have stopped it).
        emit_step(*bad);
        ++bifurcations;
        emit_event({0.5 * (good.lambda + bad->lambda), EventKind::bifurcation, options_.monitor,
                    fmt::format("the tangent stiffness on the contact set turns singular (from {} to {} negative "
                                "eigenvalue(s)) at N = {:.6g}: another branch crosses the path",
                                negative, negative_eigenvalues(set_, bad->lambda),
                                model_.axial_force(bad->lambda) * model_.scales.force())});
        negative = negative_eigenvalues(set_, bad->lambda);
        current = bad;
        topology = topology_of(*current);
        step = initial_step;
        continue;
      }
      // A breakpoint: the nodes infeasible just beyond switch; the new set's branch through it
      // goes on ahead (no fold) or behind (a limit point).
      ++breakpoints;
      // Every node at zero there and falling switches, ties together (mirror nodes of a symmetric
      // member cross at one lambda to round-off, and the located point may lie on either side of
      // one of them): falling as seen a little beyond, far above round-off, far below the spacing
      // of breakpoints.
      const std::vector<double> values = relative_values(set_, *bad);
      const auto probe = solve(set_, bad->lambda + direction * 1e-7 * span);
      const std::vector<double> beyond = probe ? relative_values(set_, *probe) : values;
      ContactSet switched = set_;
      int first_switched = -1;
      for (int i = 0; i < m; ++i)
        if (values[i] < -tie_tolerance || (values[i] <= tie_tolerance && beyond[i] < -tie_tolerance)) {
          switched[i] = !switched[i];
          if (first_switched < 0) first_switched = i;
        }
      const ContactSet before = set_;
      set_ = switched;
      std::optional<Point> on = solve(set_, current->lambda);
      if (!on) {
        set_ = before;
        emit_step(*current);
        finish(TraceTermination::solver_failure,
               fmt::format("at the breakpoint lambda = {:.10g} the new contact set's system is singular", hi),
               current->lambda);
        return done();
      }
      double chosen = 0.0;
      for (double offset = std::max(1e-6 * span, 100.0 * options_.event_tolerance);
           chosen == 0.0 && offset >= 10.0 * options_.event_tolerance; offset *= 1e-2) {
        for (double side : {direction, -direction}) {
          const auto p = solve(set_, current->lambda + side * offset);
          if (p && feasible(set_, *p)) {
            chosen = side;
            break;
          }
        }
      }
      if (chosen == 0.0) {
        set_ = before;
        emit_step(*current);
        finish(TraceTermination::solver_failure,
               fmt::format("the degenerate breakpoint at lambda = {:.10g} could not be resolved: the new contact set "
                           "is feasible on neither side",
                           current->lambda),
               current->lambda);
        return done();
      }
      current = on;
      emit_step(*current);
      if (chosen != direction) {
        ++folds;
        const double s = d_.mesh.nodes[d_.reaction_nodes[first_switched]];
        emit_event(
            {current->lambda, EventKind::limit_point, model_.user_from_s(s),
             fmt::format("limit point: lambda reaches a {} (N = {:.6g}, amplitude {:.6g}) as the node at {:.6g} "
                         "{}; the path turns back",
                         direction > 0 ? "maximum" : "minimum",
                         model_.axial_force(current->lambda) * model_.scales.force(), result_.steps.back().amplitude,
                         model_.user_from_s(s), before[first_switched] ? "lifts off" : "touches down")});
        direction = chosen;
      }
      negative = negative_eigenvalues(set_, current->lambda);
      topology = topology_of(*current);
      // The next breakpoint is likely as far as this one was from the last.
      step = std::clamp(2.0 * std::abs(current->lambda - last_breakpoint), min_step, initial_step);
      last_breakpoint = current->lambda;
    }
  } catch (const StepNotCertified& failure) {
    finish(TraceTermination::solver_failure, failure.message, failure.lambda);
    return done();
  }
}

}  // namespace

TraceResult trace_fe_axial(const scene::Scene& scene, const TraceOptions& options, const TraceSink& sink) {
  options.validate(scene.begin(), scene.end());
  AxialPath path(scene, options, sink);
  return path.run();
}

}  // namespace liftoff::continuation
