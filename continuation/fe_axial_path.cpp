#include "continuation/fe_axial_path.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <string_view>

#include "contact/active_set_system.hpp"
#include "contact/contact_solver.hpp"
#include "contact/stability.hpp"
#include "continuation/events.hpp"
#include "continuation/fe_states.hpp"
#include "continuation/step_state.hpp"
#include "fe/discretisation.hpp"
#include "model/member_model.hpp"
#include "stability/critical_load.hpp"

namespace liftoff::continuation {

using Eigen::VectorXd;
using ContactSet = std::vector<bool>;

namespace {

// A reaction (gap) above -tie_tolerance of its scale counts as feasible: the fixed-set states are
// refined to round-off (relative residual ~1e-15), so values that small are zero; nodes that
// physically switch at different loads differ by orders more.
using fe_states::acceptable_residual;
using fe_states::StepNotCertified;
using fe_states::tie_tolerance;
// Bisections: the bracket in lambda is halved at most this often.
constexpr int max_bisections = 200;

// Stable when the cone's critical factor on the present axial force exceeds 1.
continuation::Stability cone_verdict(const stability::CriticalLoadResult& cone);

// The fixed-set state at one lambda.
struct Point {
  double lambda = 0.0;
  contact::ContactState state;
};

// A one-parameter family of fixed-set states: by lambda on one set, or along a critical mode at
// one lambda (a bifurcated branch). Empty where the state cannot be had.
using Family = std::function<std::optional<Point>(double)>;

// What became of a bifurcation (AxialPath::switch_branch).
enum class Switch {
  stayed,    // no branch the contact conditions admit, or switching not asked for: the path goes on
  switched,  // on the bifurcated branch, which goes on in lambda from `current`, on set_
  finished,  // the trace ended on the bifurcated branch (result_ says how)
};

class AxialPath {
 public:
  AxialPath(const model::MemberModel& member, const TraceOptions& options, const TraceSink& sink)
      : options_(options),
        sink_(sink),
        model_(member),
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
  // The cone's critical load at a state with weakly active nodes (empty: there are none).
  // along_branch: only nodes weak along the set's branch count (at zero here and a little
  // further in lambda too, as on a strut that nothing presses down), not one passing zero here.
  std::optional<stability::CriticalLoadResult> cone_at(const Point& p, bool along_branch = false);
  continuation::Stability stability_at(const Point& p);
  // The count the path watches for bifurcations: the negative eigenvalues of set_'s tangent, or
  // where nodes are weakly active, 0 if the cone says stable and at least 1 if not.
  int instability(const Point& p);
  std::optional<ContactSet> start_set(double lambda);
  TraceStep step_at(const Point& p);
  // requested: p is a load of report_at (emit_step reports those passed since the last step).
  void emit_step(const Point& p, bool requested = false);
  void emit_event(const TraceEvent& event);
  ContactTopology topology_of(const Point& p) const;
  // Contact-topology events between a and b on set_ (a graph over lambda there).
  void locate_events(const Point& a, const Point& b, ContactTopology& topology_a);
  // The same along any family, from family(t_a) (whose topology is topology_a) to b = family(t_b).
  void locate_events(const Family& family, double t_a, const Point& b, double t_b, ContactTopology& topology_a);
  // The null vector of the tangent on `set` near a singular point at lambda (inverse iteration):
  // displacement, reactions and gaps of the mode (homogeneous: no load, no ground), max |u| = 1,
  // its largest deflection lifting, and the singular point's lambda (its Rayleigh quotient).
  // Empty if a solve fails.
  struct CriticalMode {
    contact::ContactState mode;
    double lambda = 0.0;
  };
  std::optional<CriticalMode> critical_mode(const ContactSet& set, double lambda);
  // The mode and lambda of the bifurcation located just after `at` on set_, set_ moved to the
  // cone's spring set where nodes are weakly active.
  std::optional<CriticalMode> bifurcation_mode(const Point& at);
  // The side in lambda on which set_'s branch through `lambda` is feasible: +1, -1, 0 (neither).
  double feasible_side(double lambda, double preferred);
  // At a bifurcation located at `at` (on set_, just before the tangent turns singular), follows
  // the bifurcated branch: at fixed lambda along the critical mode, in the direction the contact
  // conditions admit, until a node switches (then on in lambda from there: `current`,
  // `direction`) or the amplitude bound.
  // `event` (the bifurcation) is emitted here, its description completed with what the path does.
  Switch switch_branch(const Point& at, TraceEvent event, ContactTopology& topology, std::optional<Point>& current,
                       double& direction);
  // The bifurcation's stages: the event completed with what the path does and emitted; the
  // path's state at lambda on set_; whether each node's reaction (gap) falls along s times the mode;
  // how far along it the contact conditions hold from base; where the amplitude bound cuts the
  // branch (a_end if it does not); the branch drawn up to a_stop, its events located.
  void announce(TraceEvent& event, std::string_view what);
  Point bifurcation_origin(const Point& at, double lambda);
  std::vector<bool> falling_along(const contact::ContactState& mode, double s) const;
  double branch_reach(const contact::ContactState& base, const contact::ContactState& mode, double s) const;
  double amplitude_stop(const Family& on_branch, double a_end);
  void draw_branch(const Family& on_branch, double a_stop, ContactTopology& topology);
  void finish(TraceTermination termination, std::string message, double lambda);

  // Where the walk along the path stands between steps.
  struct Walk {
    std::optional<Point> current;  // the last point on set_'s branch, recorded
    int negative = 0;              // instability() there; -1: taken at the next step
    ContactTopology topology;      // current's, where its events ended
    double step = 0.0;             // in lambda
    double direction = 1.0;        // +1: lambda grows
    double last_breakpoint = 0.0;  // lambda
  };
  enum class Go { on, stop };  // stop: result_ says how the trace ended
  // The start's contact solve and step (empty: the trace ended there).
  std::optional<Walk> start_walk();
  // One step on set_, or the first thing that happens within it located and handled.
  Go advance(Walk& walk);
  // The first lambda in (walk.current, target] where a contact condition fails, the amplitude
  // bound is reached or (watch_inertia) the tangent's inertia changes, to event_tolerance: the last
  // point before it and the first after (empty: the system is singular there), at lambda hi.
  struct Bracket {
    Point good;
    std::optional<Point> bad;
    double hi = 0.0;
  };
  Bracket first_happening(const Walk& walk, double target, const std::optional<Point>& next, bool watch_inertia);
  // The tangent on set_ turns singular between good and bad: report it, switch where asked.
  Go at_bifurcation(Walk& walk, const Point& good, const Point& bad);
  // A contact condition fails at bad: the nodes switch and the path goes on on the side where the
  // new set is feasible (behind: a limit point).
  Go at_breakpoint(Walk& walk, const Point& bad, double hi);
  std::string ending(double lambda) const;

  // The load range and step lengths, in lambda.
  struct Range {
    double lambda_min = 0.0, lambda_max = 0.0, span = 1.0;
    double max_step = 0.0, initial_step = 0.0, min_step = 0.0;
  };

  TraceOptions options_;
  TraceSink sink_;
  model::MemberModel model_;
  fe::Discretisation d_;
  fe::SparseMatrix stiffness_at_one_;  // K(N(1)), as discretise assembled it
  double axial_at_one_ = 0.0;          // N(1)
  contact::ActiveSetSystem system_;
  SpecialPoints points_;
  Range range_;
  TraceResult result_;
  ContactSet set_;
  ContactSet last_step_set_;  // the set of the last step recorded
  double axial_of_system_ = std::numeric_limits<double>::quiet_NaN();
  int solves_since_step_ = 0;
  int folds_ = 0, bifurcations_ = 0, breakpoints_ = 0;
  bool on_neutral_branch_ = false;  // steps at a bifurcation's lambda along its mode
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
std::optional<stability::CriticalLoadResult> AxialPath::cone_at(const Point& p, bool along_branch) {
  using stability::NodeContact;
  auto weak = [](const std::vector<NodeContact>& contact) {
    return std::any_of(contact.begin(), contact.end(), [](NodeContact c) { return c == NodeContact::weakly_active; });
  };
  std::vector<NodeContact> contact = stability::classify_contact(p.state.reaction, p.state.gap);
  if (!weak(contact)) return std::nullopt;
  if (along_branch) {
    const double span = std::abs(options_.arc_length.lambda_max - options_.arc_length.lambda_min);
    const auto further = solve(set_, p.lambda + 1e-3 * std::max(span, 1e-300));
    if (!further) return std::nullopt;
    // Zero there too, either sign (a node that crosses zero here is far from zero there).
    const VectorXd& r = further->state.reaction;
    const VectorXd& g = further->state.gap;
    const double r_zero = 1e-8 * r.lpNorm<Eigen::Infinity>(), g_zero = 1e-8 * g.lpNorm<Eigen::Infinity>();
    for (std::size_t i = 0; i < contact.size(); ++i) {
      const auto j = static_cast<Eigen::Index>(i);
      if (contact[i] == NodeContact::weakly_active && !(std::abs(r[j]) <= r_zero && std::abs(g[j]) <= g_zero))
        contact[i] = set_[i] ? NodeContact::in_contact : NodeContact::lifted;
    }
    if (!weak(contact)) return std::nullopt;
  }
  set_axial(p.lambda);
  return stability::critical_load(d_, 0.0, d_.axial_force, contact);
}

int AxialPath::instability(const Point& p) {
  // (An infeasible state, beyond a breakpoint, has no cone: its negative reactions are no
  // weakly active nodes.)
  if (const auto cone = feasible(set_, p) ? cone_at(p, true) : std::nullopt) {
    const continuation::Stability verdict = cone_verdict(*cone);
    if (verdict == continuation::Stability::stable) return 0;
    if (verdict == continuation::Stability::unstable) return std::max(negative_eigenvalues(set_, p.lambda), 1);
  }
  return negative_eigenvalues(set_, p.lambda);
}

continuation::Stability AxialPath::stability_at(const Point& p) {
  const auto cone = cone_at(p);
  if (!cone)
    return negative_eigenvalues(set_, p.lambda) == 0 ? continuation::Stability::stable
                                                     : continuation::Stability::unstable;
  return cone_verdict(*cone);
}

continuation::Stability cone_verdict(const stability::CriticalLoadResult& cone) {
  switch (cone.termination) {
    case stability::StabilityTermination::critical_load_found:
      return cone.critical_load_factor > 1.0 ? continuation::Stability::stable : continuation::Stability::unstable;
    case stability::StabilityTermination::stable_for_all_factors:
      return continuation::Stability::stable;
    case stability::StabilityTermination::unstable_at_zero:
      return continuation::Stability::unstable;
    case stability::StabilityTermination::not_converged:
      break;
  }
  return continuation::Stability::unknown;
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
  const contact::ContactSolution solution = fe_states::contact_solve(d, options_.contact_method, lambda);
  ++result_.summary.contact_solves;
  result_.summary.contact_method = solution.summary.method;
  if (!solution.summary.is_usable()) {
    finish(solution.summary.termination == contact::ContactTermination::no_equilibrium
               ? TraceTermination::no_equilibrium
               : TraceTermination::solver_failure,
           fmt::format("the contact solver at lambda = {:.10g}: {}", lambda, solution.summary.message), lambda);
    return std::nullopt;
  }
  const ContactSet set = fe_states::contact_set_of(d, solution);
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
  TraceStep step = fe_states::step_of(model_, d_, points_, options_, p.lambda,
                                      d_.expand_displacement(p.state.displacement), p.state.reaction, set_);
  step.axial_force = model_.axial_force(p.lambda) * model_.scales.force();
  step.stability = on_neutral_branch_ ? continuation::Stability::unstable : stability_at(p);
  return step;
}

void AxialPath::emit_step(const Point& p, bool requested) {
  // The requested loads the path passed since its last step first (report_at; a folding path
  // passes one on each branch): exact on the last step's set or on this one (a breakpoint may lie
  // between), whose branches are graphs over lambda there, and certified as every step. Where
  // neither holds the load is left unreported, as the engine's paths do.
  if (!requested && !result_.steps.empty()) {
    const double from = result_.steps.back().load_factor;
    for (double target : options_.report_at) {
      if (!(target != from && (target - from) * (target - p.lambda) <= 0.0)) continue;
      if (target == p.lambda) {
        requested = true;
        continue;
      }
      for (ContactSet on : {last_step_set_, set_}) {
        const std::optional<Point> at = solve(on, target);
        if (!at || !feasible(on, *at)) continue;
        std::swap(set_, on);  // the step's set while it is recorded
        emit_step(*at, true);
        std::swap(set_, on);
        break;
      }
    }
  }
  TraceStep step = step_at(p);
  step.requested = requested;
  // Certified from its own fields (balance with K(N) at this lambda, the contact inequalities,
  // backward error) as the exact path's states are.
  set_axial(p.lambda);
  const Eigen::VectorXd displacement = d_.expand_displacement(p.state.displacement);
  record_fe_state(step, model_, d_, p.lambda, displacement, p.state.reaction,
                  fe_states::certify_state(model_, d_, p.lambda, displacement, p.state.reaction));
  step.iterations = solves_since_step_;
  solves_since_step_ = 0;
  if (sink_.on_step) sink_.on_step(step);
  result_.steps.push_back(std::move(step));
  ++result_.summary.steps;
  last_step_set_ = set_;
}

void AxialPath::emit_event(const TraceEvent& event) {
  if (sink_.on_event) sink_.on_event(event);
  result_.events.push_back(event);
}

void AxialPath::locate_events(const Point& a, const Point& b, ContactTopology& topology_a) {
  locate_events([this](double lambda) { return solve(set_, lambda); }, a.lambda, b, b.lambda, topology_a);
}

void AxialPath::locate_events(const Family& family, double t_a, const Point& b, double t_b,
                              ContactTopology& topology_a) {
  ContactTopology topology_b = topology_of(b);
  double from = t_a;
  // Along lambda the parameter is located to event_tolerance; along a mode (t from 0 to t_b),
  // to the same fraction of the segment.
  const double tolerance = options_.event_tolerance * std::max(1.0, std::abs(t_b - t_a));
  for (int guard = 0; guard < 64 && !topology_a.same_as(topology_b); ++guard) {
    double lo = from, hi = t_b;
    ContactTopology before = topology_a;
    std::optional<Point> at_hi;
    for (int i = 0; i < max_bisections && std::abs(hi - lo) > tolerance; ++i) {
      const double mid = 0.5 * (lo + hi);
      const auto p = family(mid);
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
    if (!at_hi) at_hi = hi == t_b ? std::optional<Point>(b) : family(hi);
    if (!at_hi) break;
    const ContactTopology after = topology_of(*at_hi);
    const std::vector<TraceEvent> events = classify_events(model_, points_, before, after, at_hi->lambda);
    if (!events.empty()) {
      emit_step(*at_hi);
      for (const auto& event : events) emit_event(event);
    }
    from = hi;
    topology_a = after;
  }
  topology_a = topology_b;
}

std::optional<AxialPath::CriticalMode> AxialPath::critical_mode(const ContactSet& set, double lambda) {
  set_axial(lambda);
  if (!system_.factorise(set)) return std::nullopt;
  // M(lambda) x = N_live K_g u: the singular point lies close to lambda (see below), so the null
  // vector dominates after one solve by orders; the rest clean up the start's other parts.
  const double live = model_.axial_force(1.0) - model_.axial_force(0.0);
  VectorXd u(d_.geometric_stiffness.rows());
  for (Eigen::Index j = 0; j < u.size(); ++j) u[j] = std::sin(1.7 * static_cast<double>(j) + 0.3);  // no symmetry
  contact::ContactState mode;
  for (int iteration = 0; iteration < 4; ++iteration) {
    const VectorXd load = live * (d_.geometric_stiffness * u);
    mode = system_.solve(load);
    ++solves_since_step_;
    const double size = mode.displacement.lpNorm<Eigen::Infinity>();
    if (!std::isfinite(size) || size == 0.0) return std::nullopt;
    u = mode.displacement / size;
  }
  const double size = mode.displacement.lpNorm<Eigen::Infinity>();
  double sign = 1.0 / size;
  // Oriented so that its largest deflection lifts (w > 0 presses into the foundation).
  const VectorXd dofs = d_.expand_displacement(mode.displacement);
  double largest = 0.0;
  for (int node = 0; node <= d_.mesh.elements(); ++node) {
    const double value = dofs[d_.deflection_dof(node)];
    if (std::abs(value) > std::abs(largest)) largest = value;
  }
  if (largest > 0.0) sign = -sign;
  mode.displacement *= sign;
  mode.reaction *= sign;
  mode.gap *= sign;
  // The fixed-set matrix S(lambda) = [K(N) C_A^T; C_A -T_AA] loses N_live K_g per unit lambda:
  // S(lambda_c) x = 0 at lambda_c = lambda + x^T S(lambda) x / (N_live u^T K_g u), stationary
  // in x, so second-order accurate. (The inertia that located the point counts a pivot below
  // 1e-14 of the largest as singular, which on a fine mesh is early by 1e-14 cond(S).)
  const VectorXd& x = mode.displacement;
  const VectorXd& r = mode.reaction;
  const double quadratic = x.dot(d_.stiffness * x) + 2.0 * r.dot(d_.coupling * x) - r.dot(d_.flexibility * r);
  const double curvature = live * x.dot(d_.geometric_stiffness * x);
  if (!(std::abs(curvature) > 0.0)) return std::nullopt;
  return CriticalMode{std::move(mode), lambda + quadratic / curvature};
}

std::optional<AxialPath::CriticalMode> AxialPath::bifurcation_mode(const Point& at) {
  // Weakly active nodes (touching, no reaction): the cone's critical mode says which of them
  // keep a spring (push in) and which lift; the branch lies on that set, whose tangent is the
  // one that turns singular (the path's state is on it too: those nodes carry nothing).
  if (const auto cone = cone_at(at, true); cone && cone->is_usable())
    for (int i = 0; i < d_.reactions(); ++i) set_[i] = cone->spring[i];
  auto critical = critical_mode(set_, at.lambda);
  if (!critical) return std::nullopt;
  // The quotient is trusted near the located point only (else the iteration found another mode).
  const double span = std::abs(options_.arc_length.lambda_max - options_.arc_length.lambda_min);
  if (!(std::abs(critical->lambda - at.lambda) <= 1e-2 * std::max(std::abs(at.lambda), 1e-3 * span)))
    critical->lambda = at.lambda;
  return critical;
}

double AxialPath::feasible_side(double lambda, double preferred) {
  const double span = std::max(std::abs(options_.arc_length.lambda_max - options_.arc_length.lambda_min), 1e-300);
  for (double offset = std::max(1e-6 * span, 100.0 * options_.event_tolerance);
       offset >= 10.0 * options_.event_tolerance; offset *= 1e-2)
    for (double side : {preferred, -preferred}) {
      const auto p = solve(set_, lambda + side * offset);
      if (p && feasible(set_, *p)) return side;
    }
  return 0.0;
}

void AxialPath::announce(TraceEvent& event, std::string_view what) {
  event.description += what;
  emit_event(event);
}

Point AxialPath::bifurcation_origin(const Point& at, double lambda) {
  // Extrapolated from `at` and a point before it on set_ (the matrix is singular at the
  // bifurcation; the path is smooth through it).
  Point origin = at;
  origin.lambda = lambda;
  const double h = std::max(std::abs(lambda - at.lambda), 1e-6 * std::max(std::abs(at.lambda), 1.0));
  const auto here = solve(set_, at.lambda), before = solve(set_, at.lambda - h);
  if (here && before) {
    const double t = (lambda - at.lambda) / h;
    origin.state.displacement = here->state.displacement + t * (here->state.displacement - before->state.displacement);
    origin.state.reaction = here->state.reaction + t * (here->state.reaction - before->state.reaction);
    origin.state.gap = here->state.gap + t * (here->state.gap - before->state.gap);
  }
  return origin;
}

double magnitude(const VectorXd& v) { return std::max(v.lpNorm<Eigen::Infinity>(), 1e-300); }

std::vector<bool> AxialPath::falling_along(const contact::ContactState& mode, double s) const {
  // Falling beyond round-off of the mode's own largest reaction (gap).
  const double r_mode = magnitude(mode.reaction), g_mode = magnitude(mode.gap);
  std::vector<bool> falling(d_.reactions());
  for (int i = 0; i < d_.reactions(); ++i)
    falling[i] = s * (set_[i] ? mode.reaction[i] : mode.gap[i]) < -tie_tolerance * (set_[i] ? r_mode : g_mode);
  return falling;
}

double AxialPath::branch_reach(const contact::ContactState& base, const contact::ContactState& mode, double s) const {
  // Along base + a s phi every reaction (in the set) and gap (off it) is linear in a: the branch
  // meets the contact conditions up to the first that falls to zero, and not at all in a direction
  // that pushes a node already at zero through it (a touching node with no reaction: the cone of
  // admissible perturbations).
  if (!d_.tensionless) return std::numeric_limits<double>::infinity();
  const double r_base = magnitude(base.reaction), g_base = magnitude(base.gap);
  const std::vector<bool> falling = falling_along(mode, s);
  double a_max = std::numeric_limits<double>::infinity();
  for (int i = 0; i < d_.reactions(); ++i) {
    if (!falling[i]) continue;
    const double value = set_[i] ? base.reaction[i] : base.gap[i];
    const double rate = s * (set_[i] ? mode.reaction[i] : mode.gap[i]);
    const bool at_zero = value <= tie_tolerance * (set_[i] ? r_base : g_base);
    a_max = std::min(a_max, at_zero ? 0.0 : value / -rate);
  }
  return a_max;
}

double AxialPath::amplitude_stop(const Family& on_branch, double a_end) {
  // The amplitude bound on the branch, located by bisection on a (the amplitude grows with it).
  if (!options_.max_amplitude || (std::isfinite(a_end) && amplitude(*on_branch(a_end)) < *options_.max_amplitude))
    return a_end;
  double lo = 0.0, hi = std::isfinite(a_end) ? a_end : 1.0;
  for (int i = 0; i < 200 && amplitude(*on_branch(hi)) < *options_.max_amplitude; ++i) lo = hi, hi *= 2.0;
  for (int i = 0; i < max_bisections && hi - lo > 1e-14 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (amplitude(*on_branch(mid)) < *options_.max_amplitude ? lo : hi) = mid;
  }
  return hi;
}

void AxialPath::draw_branch(const Family& on_branch, double a_stop, ContactTopology& topology) {
  // The branch is straight at fixed lambda: a few steps draw it; its events are located along it.
  // Its states are neutral: the tangent is singular along the mode (not positive definite).
  on_neutral_branch_ = true;
  constexpr int branch_steps = 4;
  double a_previous = 0.0;
  for (int k = 1; k <= branch_steps; ++k) {
    const double a = a_stop * k / branch_steps;
    const Point p = *on_branch(a);
    locate_events(on_branch, a_previous, p, a, topology);
    emit_step(p);
    a_previous = a;
  }
  on_neutral_branch_ = false;
}

Switch AxialPath::switch_branch(const Point& at, TraceEvent event, ContactTopology& topology,
                                std::optional<Point>& current, double& direction) {
  const ContactSet path_set = set_;
  const auto critical = bifurcation_mode(at);  // may move set_ to the cone's springs
  if (!critical) {
    set_ = path_set;
    announce(event, "; the critical mode could not be computed: the path goes on");
    return Switch::stayed;
  }
  event.load_factor = critical->lambda;
  const contact::ContactState& mode = critical->mode;
  const Point origin = bifurcation_origin(at, critical->lambda);
  const double up = branch_reach(origin.state, mode, 1.0), down = branch_reach(origin.state, mode, -1.0);
  if (!(up > 0.0) && !(down > 0.0)) {
    set_ = path_set;
    announce(event, "; neither direction of the critical mode meets the contact conditions: the path goes on");
    return Switch::stayed;
  }
  const double s = up >= down ? 1.0 : -1.0;  // ties: the largest deflection lifts
  const double a_end = std::max(up, down);
  const Family on_branch = [&, s](double a) -> std::optional<Point> {
    Point p = origin;
    p.state.displacement += a * s * mode.displacement;
    p.state.reaction += a * s * mode.reaction;
    p.state.gap += a * s * mode.gap;
    return p;
  };
  const double n = model_.axial_force(origin.lambda) * model_.scales.force();
  const double a_stop = amplitude_stop(on_branch, a_end);
  if (!std::isfinite(a_stop)) {
    announce(event,
             fmt::format("; the bifurcated branch stays at N = {:.6g} for every amplitude of the mode with no node "
                         "switching (second-order theory: a neutral branch); set [trace] max_amplitude to follow it",
                         n));
    finish(TraceTermination::completed,
           fmt::format("bifurcation at lambda = {:.10g} onto a neutral branch (no amplitude bound given): {} limit "
                       "point(s), {} bifurcation(s)",
                       origin.lambda, folds_, bifurcations_),
           origin.lambda);
    return Switch::finished;
  }
  if (a_stop < a_end) {
    announce(event, fmt::format("; the path follows the bifurcated branch at N = {:.6g} up to amplitude {:.6g}", n,
                                *options_.max_amplitude));
    draw_branch(on_branch, a_stop, topology);
    finish(TraceTermination::completed,
           fmt::format("amplitude {:.6g} reached (max_amplitude) on the bifurcated branch at lambda = {:.10g}: {} "
                       "limit point(s), {} bifurcation(s), {} event(s)",
                       *options_.max_amplitude, origin.lambda, folds_, bifurcations_, result_.events.size()),
           origin.lambda);
    return Switch::finished;
  }
  // A node switches where the branch ends (every one at zero there and falling along it: ties of
  // a symmetric member together); the new set's branch through that state goes on in lambda.
  const std::vector<double> values = relative_values(set_, *on_branch(a_end));
  const std::vector<bool> falling = falling_along(mode, s);
  ContactSet switched = set_;
  int first_switched = -1;
  for (int i = 0; i < d_.reactions(); ++i)
    if (values[i] <= tie_tolerance && falling[i]) {
      switched[i] = !switched[i];
      if (first_switched < 0) first_switched = i;
    }
  const ContactSet before = set_;
  set_ = switched;
  const auto on = solve(set_, origin.lambda);
  const double side = on && first_switched >= 0 ? feasible_side(origin.lambda, direction) : 0.0;
  const double where = model_.user_from_s(d_.mesh.nodes[d_.reaction_nodes[std::max(first_switched, 0)]]);
  const char* how = before[std::max(first_switched, 0)] ? "lifts off" : "touches down";
  if (side == 0.0) {
    set_ = before;
    announce(event,
             fmt::format("; the bifurcated branch at N = {:.6g} ends where the node at {:.6g} {}, and no path goes "
                         "on from there in lambda",
                         n, where, how));
    draw_branch(on_branch, a_stop, topology);
    finish(TraceTermination::solver_failure,
           fmt::format("the bifurcated branch at lambda = {:.10g} could not be continued past its first switch",
                       origin.lambda),
           origin.lambda);
    return Switch::finished;
  }
  ++breakpoints_;
  announce(event,
           fmt::format("; the path follows the bifurcated branch at N = {:.6g} until the node at {:.6g} {}, then "
                       "goes {} in lambda",
                       n, where, how, side > 0 ? "up" : "down"));
  set_ = before;  // the branch's steps are states of the set it leaves
  draw_branch(on_branch, a_stop, topology);
  set_ = switched;
  current = on;
  direction = side;
  return Switch::switched;
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
  const auto& arc = options_.arc_length;
  range_.lambda_min = std::min(arc.lambda_min, arc.lambda_max);
  range_.lambda_max = std::max(arc.lambda_min, arc.lambda_max);
  range_.span = std::max(range_.lambda_max - range_.lambda_min, 1e-300);
  range_.max_step = arc.max_step * range_.span;
  range_.initial_step = arc.initial_step * range_.span;
  range_.min_step = std::max(arc.min_step * range_.span, 4.0 * options_.event_tolerance);
  try {
    if (std::optional<Walk> walk = start_walk())
      while (advance(*walk) == Go::on) {
      }
  } catch (const StepNotCertified& failure) {
    finish(TraceTermination::solver_failure, failure.message, failure.lambda);
  }
  summary.factorisations = system_.factorisations();
  summary.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return std::move(result_);
}

std::optional<AxialPath::Walk> AxialPath::start_walk() {
  const double lambda_start = options_.arc_length.lambda_min;
  if (options_.resume_from) {
    finish(TraceTermination::solver_failure,
           "a trace in the axial force is not resumed in this version: run it again without the file", lambda_start);
    return std::nullopt;
  }
  const auto start_set_found = start_set(lambda_start);
  if (!start_set_found) return std::nullopt;
  set_ = *start_set_found;
  Walk walk;
  walk.current = solve(set_, lambda_start);
  if (!walk.current) {
    finish(TraceTermination::solver_failure, "the fixed-set system is singular at the start", lambda_start);
    return std::nullopt;
  }
  emit_step(*walk.current);
  walk.negative = instability(*walk.current);
  walk.topology = topology_of(*walk.current);
  walk.step = range_.initial_step;
  walk.direction = options_.arc_length.lambda_max >= options_.arc_length.lambda_min ? 1.0 : -1.0;
  walk.last_breakpoint = walk.current->lambda;
  return walk;
}

std::string AxialPath::ending(double lambda) const {
  return fmt::format("lambda = {:.10g} reached: {} breakpoint(s), {} limit point(s), {} bifurcation(s), {} event(s)",
                     lambda, breakpoints_, folds_, bifurcations_, result_.events.size());
}

AxialPath::Go AxialPath::advance(Walk& walk) {
  Point& current = *walk.current;
  if (result_.summary.steps >= options_.arc_length.max_steps) {
    finish(TraceTermination::step_limit,
           fmt::format("max_steps = {} reached at lambda = {:.10g}", options_.arc_length.max_steps, current.lambda),
           current.lambda);
    return Go::stop;
  }
  // The next point on this set, clamped to the range.
  double target = current.lambda + walk.direction * walk.step;
  const bool at_end = walk.direction > 0 ? target >= range_.lambda_max : target <= range_.lambda_min;
  if (at_end) target = walk.direction > 0 ? range_.lambda_max : range_.lambda_min;
  std::optional<Point> next = solve(set_, target);
  const bool ok = next && feasible(set_, *next);
  const int next_negative = next ? instability(*next) : walk.negative;
  if (walk.negative < 0) walk.negative = next_negative;  // the count of a branch just entered (see below)
  const bool past_amplitude = ok && options_.max_amplitude && amplitude(*next) >= *options_.max_amplitude;
  if (ok && next_negative == walk.negative && !past_amplitude) {
    locate_events(current, *next, walk.topology);
    current = *next;
    emit_step(current);
    if (at_end) {
      finish(TraceTermination::completed, ending(current.lambda), current.lambda);
      return Go::stop;
    }
    walk.step = std::min(2.0 * walk.step, range_.max_step);
    return Go::on;
  }
  if (ok && next_negative != walk.negative && walk.step > range_.min_step) {  // shorter first: a singular
    walk.step *= 0.5;                                                         // tangent inside is located below
    return Go::on;
  }
  // Something happens in (current, target]: the first lambda where it does, to event_tolerance.
  // The inertia is watched inside the step only when it differs at its end (an LDL^T per point); a
  // pair of sign changes within one step is not seen.
  const Bracket bracket = first_happening(walk, target, next, next && next_negative != walk.negative);
  locate_events(current, bracket.good, walk.topology);
  current = bracket.good;
  if (!bracket.bad) {
    emit_step(current);
    finish(TraceTermination::solver_failure,
           fmt::format("the fixed-set system turned singular at lambda = {:.10g}", bracket.hi), current.lambda);
    return Go::stop;
  }
  const Point& bad = *bracket.bad;
  // Which happened at hi: the amplitude bound, a contact condition, a singular tangent.
  if (options_.max_amplitude && feasible(set_, bad) && amplitude(bad) >= *options_.max_amplitude) {
    emit_step(bad);
    finish(TraceTermination::completed,
           fmt::format("amplitude {:.6g} reached (max_amplitude) at lambda = {:.10g}: {} limit point(s), {} "
                       "bifurcation(s), {} event(s)",
                       *options_.max_amplitude, bad.lambda, folds_, bifurcations_, result_.events.size()),
           bad.lambda);
    return Go::stop;
  }
  if (feasible(set_, bad)) return at_bifurcation(walk, bracket.good, bad);
  return at_breakpoint(walk, bad, bracket.hi);
}

AxialPath::Bracket AxialPath::first_happening(const Walk& walk, double target, const std::optional<Point>& next,
                                              bool watch_inertia) {
  double lo = walk.current->lambda, hi = target;
  Point good = *walk.current;
  auto happens = [&](const std::optional<Point>& p) {
    if (!p || !feasible(set_, *p)) return true;
    if (options_.max_amplitude && amplitude(*p) >= *options_.max_amplitude) return true;
    return watch_inertia && instability(*p) != walk.negative;
  };
  std::optional<Point> bad = next;
  // Regula falsi (Illinois) on the smallest margin of the contact conditions and of the amplitude
  // bound, continuous along the set's branch; a bisection whenever a step did not halve the
  // bracket, and throughout when the inertia is watched.
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
  return {good, bad, hi};
}

AxialPath::Go AxialPath::at_bifurcation(Walk& walk, const Point& good, const Point& bad) {
  // The tangent on this set turns singular between good and bad with no breakpoint: a bifurcation
  // point of the fixed-set problem (the path itself passes: the load has no part along the
  // critical mode, else its amplitude would have stopped it).
  const int after = instability(bad);
  TraceEvent event{0.5 * (good.lambda + bad.lambda), EventKind::bifurcation, options_.monitor,
                   fmt::format("the tangent stiffness turns singular (from {} to {} unstable direction(s)) at "
                               "N = {:.6g}: another branch crosses the path",
                               walk.negative, after, model_.axial_force(bad.lambda) * model_.scales.force())};
  // Where the path loses its stability the member leaves it for the bifurcated branch; elsewhere
  // (an unstable path, already left by the member) the crossing is reported.
  if (options_.switch_branch && walk.negative == 0 && after > 0) {
    emit_step(good);
    ++bifurcations_;
    const Switch outcome = switch_branch(good, std::move(event), walk.topology, walk.current, walk.direction);
    if (outcome == Switch::finished) return Go::stop;
    if (outcome == Switch::switched) {  // (topology: the branch's end, where its events ended)
      walk.negative = -1;               // taken at the next step: here a node is at zero
      walk.step = range_.initial_step;
      walk.last_breakpoint = walk.current->lambda;
      return Go::on;
    }
    walk.current = bad;
    emit_step(bad);
  } else {
    const ContactSet path_set = set_;
    if (const auto critical = bifurcation_mode(good)) event.load_factor = critical->lambda;
    set_ = path_set;
    emit_step(bad);
    emit_event(event);
    ++bifurcations_;
    walk.current = bad;
  }
  walk.negative = after;
  walk.topology = topology_of(bad);
  walk.step = range_.initial_step;
  return Go::on;
}

AxialPath::Go AxialPath::at_breakpoint(Walk& walk, const Point& bad, double hi) {
  // The nodes infeasible just beyond switch; the new set's branch through it goes on ahead (no
  // fold) or behind (a limit point).
  ++breakpoints_;
  const int m = d_.reactions();
  // Every node at zero there and falling switches, ties together (mirror nodes of a symmetric
  // member cross at one lambda to round-off, and the located point may lie on either side of one
  // of them): falling as seen a little beyond, far above round-off, far below the spacing of
  // breakpoints.
  const std::vector<double> values = relative_values(set_, bad);
  const auto probe = solve(set_, bad.lambda + walk.direction * 1e-7 * range_.span);
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
  Point& current = *walk.current;
  std::optional<Point> on = solve(set_, current.lambda);
  if (!on) {
    set_ = before;
    emit_step(current);
    finish(TraceTermination::solver_failure,
           fmt::format("at the breakpoint lambda = {:.10g} the new contact set's system is singular", hi),
           current.lambda);
    return Go::stop;
  }
  const double chosen = feasible_side(current.lambda, walk.direction);
  if (chosen == 0.0) {
    set_ = before;
    emit_step(current);
    finish(TraceTermination::solver_failure,
           fmt::format("the degenerate breakpoint at lambda = {:.10g} could not be resolved: the new contact set "
                       "is feasible on neither side",
                       current.lambda),
           current.lambda);
    return Go::stop;
  }
  current = *on;
  emit_step(current);
  if (chosen != walk.direction) {
    ++folds_;
    const double s = d_.mesh.nodes[d_.reaction_nodes[first_switched]];
    emit_event({current.lambda, EventKind::limit_point, model_.user_from_s(s),
                fmt::format("limit point: lambda reaches a {} (N = {:.6g}, amplitude {:.6g}) as the node at {:.6g} "
                            "{}; the path turns back",
                            walk.direction > 0 ? "maximum" : "minimum",
                            model_.axial_force(current.lambda) * model_.scales.force(), result_.steps.back().amplitude,
                            model_.user_from_s(s), before[first_switched] ? "lifts off" : "touches down")});
    walk.direction = chosen;
  }
  // The switched nodes are at zero here (weakly active for the cone) but not on the branch beyond:
  // the set's own count holds there, unless other nodes are weak too.
  const std::vector<stability::NodeContact> contact =
      stability::classify_contact(current.state.reaction, current.state.gap);
  bool others_weak = false;
  for (int i = 0; i < m; ++i)
    others_weak |= contact[i] == stability::NodeContact::weakly_active && set_[i] == before[i];
  walk.negative = others_weak ? -1 : negative_eigenvalues(set_, current.lambda);
  walk.topology = topology_of(current);
  // The next breakpoint is likely as far as this one was from the last.
  walk.step = std::clamp(2.0 * std::abs(current.lambda - walk.last_breakpoint), range_.min_step, range_.initial_step);
  walk.last_breakpoint = current.lambda;
  return Go::on;
}

}  // namespace

TraceResult trace_fe_axial(const model::MemberModel& member, const TraceOptions& options, const TraceSink& sink) {
  options.validate(member.user_from_s(member.s_begin), member.user_from_s(member.s_end));
  AxialPath path(member, options, sink);
  return path.run();
}

}  // namespace liftoff::continuation
