#include "continuation/fe_path.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "contact/active_set_system.hpp"
#include "contact/contact_solver.hpp"
#include "continuation/events.hpp"
#include "continuation/fe_axial_path.hpp"
#include "continuation/fe_states.hpp"
#include "continuation/models/fe_member.hpp"
#include "continuation/step_state.hpp"
#include "fe/discretisation.hpp"
#include "lcp/lemke.hpp"
#include "model/member_model.hpp"

namespace liftoff::continuation {

using Eigen::VectorXd;
using ContactSet = std::vector<bool>;

namespace {

// A rate that would move a reaction (or gap) by less than this fraction of its scale (the
// largest reaction, or the largest term of T r - C u, over the rest of the path with the
// current set) over the whole load range is no rate: the node is not moving toward zero.
constexpr double zero_tolerance = 1e-10;
using fe_states::acceptable_residual;
using fe_states::StepNotCertified;
using fe_states::tie_tolerance;
// Degenerate breakpoints: the contact solver is asked for the set this far (times the load range)
// beyond the breakpoint, then 100 times closer, at most this many times.
constexpr double beyond_offset = 1e-6;
constexpr int beyond_attempts = 4;

// The state along one segment of the path: affine in lambda for a fixed contact set.
struct AffineState {
  contact::ContactState dead, live;
  VectorXd coupled_dead, coupled_live;    // C u
  VectorXd flexible_dead, flexible_live;  // T r
  VectorXd displacement(double lambda) const { return dead.displacement + lambda * live.displacement; }
  VectorXd reaction(double lambda) const { return dead.reaction + lambda * live.reaction; }
};

class FePath {
 public:
  FePath(const model::MemberModel& member, const TraceOptions& options, const TraceSink& sink)
      : options_(options),
        sink_(sink),
        model_(member),
        d_(fe::discretise(model_, options.elements)),
        system_(d_),
        points_(special_points(model_)) {}

  TraceResult run();

 private:
  // One factorisation of the fixed-set system for `set`, and the dead and live solves.
  bool load_set(const ContactSet& set);
  // The contact set the contact solver finds at lambda: options.contact_method's Lemke LCP
  // when it names one (dual, primal), else the sparse active-set solver (fast), with Lemke as
  // its own fallback. Dense Lemke first, as method auto would pick for a member only the
  // foundation holds, fails numerically at some meshes (region_split at 195 to 199, 269 to 271
  // and 295 to 299 elements: "z0 left the basis ... residual 4.7e-06"), and the set is all the
  // path takes from it. Empty on failure (termination_ and message_ set).
  std::optional<ContactSet> solved_set(double lambda);
  bool establish_start(double lambda);
  // Reaction of a node in the set, gap of one out of it, at lambda; and its rate along the path.
  double value(int node, double lambda) const;
  double rate(int node) const;
  void update_scales(double lambda);
  double scale(int node) const { return set_[node] ? reaction_scale_ : gap_scale_; }
  bool at_zero_and_falling(int node, double lambda) const;
  // None of `nodes` (all nodes if empty) is at zero and falling.
  bool carries_on(double lambda, const std::vector<int>& nodes = {}) const;
  bool feasible_at(double lambda) const;
  bool resolve_by_solve(double lambda);
  // A degenerate breakpoint resolved on the nodes at zero there (`at_zero`, the rest keeping
  // their status in `before`): the LCP of their reaction and gap rates.
  bool resolve_by_rates(double lambda, const ContactSet& before, const std::vector<int>& at_zero);
  // For a member only the foundation holds: can compressive reactions balance the loads' work
  // on its free rigid motions at lambda? If not, no equilibrium exists (a certificate that does
  // not depend on the primal LCP, which round-off spoils on fine meshes).
  bool rigid_motions_balanced(double lambda);
  // The rigid motions only the foundation resists, on the equations (empty if not found).
  const Eigen::MatrixXd& free_motions();
  // Whether the nodes of `set` resist every such motion (the fixed-set system is nonsingular).
  // A check of our own: the factorisation's pivot test misses a one-node set on a fine mesh.
  bool holds_member(const ContactSet& set);
  // The load beyond which the loads cannot be balanced, between `from` and lambda_end (none if
  // they can up to the end), by bisection on rigid_motions_balanced.
  std::optional<double> lift_off_load(double from);
  std::string lift_off_message(double lambda) const;

  TraceStep step_at(double lambda);
  void emit_step(TraceStep step);
  void emit_event(const TraceEvent& event);
  ContactTopology topology_at(double lambda) const;
  // Events between a and b (same contact set, so the path is affine there).
  void locate_events(double a, double b, ContactTopology& topology_a);
  // locate_events from a to b on this segment, with the requested loads strictly between
  // (report_at) recorded in order on the way: the segment's affine state there, exact.
  void advance(double a, double b, ContactTopology& topology_a);
  // A step at lambda, flagged requested if report_at asks for that load.
  TraceStep reported_step_at(double lambda);
  void finish(TraceTermination termination, std::string message, double lambda);
  // The distance in lambda to the next breakpoint from lambda on set_ (infinite: none ahead).
  double distance_to_breakpoint(double lambda);
  // The path at the breakpoint it reached from lambda: the nodes at zero and falling switch (ties
  // together), degenerate breakpoints resolved, the step recorded. at_once: at no distance from
  // the last one. False: the trace ended there (result_ says how).
  bool cross_breakpoint(double lambda, double breakpoint, bool at_once);
  // The state is continuous at a breakpoint: the sets on either side give it alike, up to
  // round-off. A jump (the new set's state at the breakpoint against the old one's) larger than
  // the path's own motion over the last segment of nonzero length means round-off decides the
  // order of breakpoints and events from here: a message saying so, or none if it is smaller.
  std::optional<std::string> state_jump(double lambda, const VectorXd& u_before, const VectorXd& r_before) const;

  TraceOptions options_;
  TraceSink sink_;
  model::MemberModel model_;
  fe::Discretisation d_;
  contact::ActiveSetSystem system_;
  SpecialPoints points_;
  TraceResult result_;

  double direction_ = 1.0, lambda_end_ = 1.0, span_ = 1.0;
  ContactSet set_;
  AffineState state_;
  double reaction_scale_ = 0.0, gap_scale_ = 0.0;
  int pivots_since_step_ = 0;
  int solve_resolutions_ = 0;
  int rate_resolutions_ = 0;
  int breakpoints_ = 0, breakpoints_here_ = 0;  // all, and in a row at one lambda
  Eigen::MatrixXd free_motions_;                // rigid motions only the foundation resists (on the equations)
  bool free_motions_failed_ = false;
  // |du| and |dr| over the last segment of nonzero length; none yet: nothing to compare with.
  std::pair<double, double> segment_motion_{std::numeric_limits<double>::infinity(),
                                            std::numeric_limits<double>::infinity()};
  std::vector<bool> held_;               // nodes kept in the set through a split final tie
  std::optional<double> floating_load_;  // the load beyond which nothing balances the loads
  TraceTermination termination_ = TraceTermination::solver_failure;
  std::string message_;
};

bool FePath::load_set(const ContactSet& set) {
  if (!holds_member(set) || !system_.factorise(set)) return false;
  set_ = set;
  // A held node stays held while it is in the set (until the lift-off load).
  held_.resize(set.size(), false);
  for (std::size_t i = 0; i < set.size(); ++i) held_[i] = held_[i] && set[i];
  // The constant part of the path: the dead load and the gap offset c (the ground gap and the
  // settled supports' -C u_f; their dead load -K u_f is in the dead load), not scaled by lambda.
  state_.dead = system_.solve(d_.dead_load, d_.ground_gap);
  state_.live = system_.solve(d_.live_load);
  if (!(std::max(state_.dead.residual, state_.live.residual) <= acceptable_residual)) return false;
  state_.coupled_dead = d_.coupling * state_.dead.displacement;
  state_.coupled_live = d_.coupling * state_.live.displacement;
  state_.flexible_dead = d_.flexibility * state_.dead.reaction;
  state_.flexible_live = d_.flexibility * state_.live.reaction;
  return true;
}

std::optional<ContactSet> FePath::solved_set(double lambda) {
  const contact::ContactSolution solution = fe_states::contact_solve(d_, options_.contact_method, lambda);
  ++result_.summary.contact_solves;
  result_.summary.contact_method = solution.summary.method;
  result_.summary.pivots += std::max(solution.summary.pivots, 0);
  pivots_since_step_ += std::max(solution.summary.pivots, 0);
  if (solution.summary.termination == contact::ContactTermination::no_equilibrium) {
    termination_ = TraceTermination::no_equilibrium;
    message_ = solution.summary.message;
    return std::nullopt;
  }
  if (!solution.summary.is_usable()) {
    termination_ = TraceTermination::solver_failure;
    message_ = fmt::format("the contact solver at lambda = {:.10g}: {}", lambda, solution.summary.message);
    return std::nullopt;
  }
  return fe_states::contact_set_of(d_, solution);
}

double FePath::value(int node, double lambda) const {
  return set_[node] ? state_.dead.reaction[node] + lambda * state_.live.reaction[node]
                    : state_.dead.gap[node] + lambda * state_.live.gap[node];
}

double FePath::rate(int node) const {
  return direction_ * (set_[node] ? state_.live.reaction[node] : state_.live.gap[node]);
}

void FePath::update_scales(double lambda) {
  reaction_scale_ = gap_scale_ = 1e-300;
  for (double at : {lambda, lambda_end_}) {
    reaction_scale_ = std::max(reaction_scale_, state_.reaction(at).lpNorm<Eigen::Infinity>());
    gap_scale_ = std::max({gap_scale_, (state_.coupled_dead + at * state_.coupled_live).lpNorm<Eigen::Infinity>(),
                           (state_.flexible_dead + at * state_.flexible_live).lpNorm<Eigen::Infinity>(),
                           d_.ground_gap.size() > 0 ? d_.ground_gap.lpNorm<Eigen::Infinity>() : 0.0});
  }
}

bool FePath::at_zero_and_falling(int node, double lambda) const {
  return std::abs(value(node, lambda)) <= tie_tolerance * scale(node) &&
         rate(node) * span_ < -zero_tolerance * scale(node);
}

bool FePath::carries_on(double lambda, const std::vector<int>& nodes) const {
  if (nodes.empty()) {
    for (int i = 0; i < d_.reactions(); ++i)
      if (at_zero_and_falling(i, lambda)) return false;
  }
  for (int i : nodes)
    if (at_zero_and_falling(i, lambda)) return false;
  return true;
}

bool FePath::feasible_at(double lambda) const {
  for (int i = 0; i < d_.reactions(); ++i)
    if (value(i, lambda) < -tie_tolerance * scale(i)) return false;
  return true;
}

// The rates just beyond lambda: the nodes off `at_zero` keep their status (their values are
// away from zero), those at zero satisfy complementarity on their rates, dr >= 0, dg >= 0,
// dr dg = 0. With the base set A0 = before minus at_zero, the reaction rates z of those nodes
// act as loads -C^T z, and their gap rates are q + M z with q from the live load and
// M_ij = gap_i(-C^T e_j) + T_ij (symmetric, positive semidefinite): an LCP of their size.
bool FePath::resolve_by_rates(double lambda, const ContactSet& before, const std::vector<int>& at_zero) {
  ContactSet base = before;
  for (int i : at_zero) base[i] = false;
  if (!load_set(base)) return false;
  const int b = static_cast<int>(at_zero.size());
  const contact::ContactState live = system_.solve(d_.live_load);
  Eigen::MatrixXd m(b, b);
  VectorXd q(b);
  for (int j = 0; j < b; ++j) {
    q[j] = direction_ * live.gap[at_zero[j]];
    const VectorXd unit_reaction = -(d_.coupling.transpose() * VectorXd::Unit(d_.reactions(), at_zero[j]));
    const contact::ContactState response = system_.solve(unit_reaction);
    for (int i = 0; i < b; ++i) m(i, j) = response.gap[at_zero[i]] + d_.flexibility.coeff(at_zero[i], at_zero[j]);
  }
  const lcp::LemkeResult rates = lcp::solve_lemke(m, q, {});
  result_.summary.pivots += std::max(rates.summary.pivots, 0);
  pivots_since_step_ += std::max(rates.summary.pivots, 0);
  if (rates.summary.termination != lcp::LemkeTermination::solution) return false;
  const VectorXd gap_rates = q + m * rates.z;
  const double z_scale = std::max(rates.z.lpNorm<Eigen::Infinity>(), 1e-300);
  const double g_scale = std::max(gap_rates.lpNorm<Eigen::Infinity>(), 1e-300);
  ContactSet after = base;
  for (int j = 0; j < b; ++j) after[at_zero[j]] = rates.z[j] / z_scale > gap_rates[j] / g_scale;
  if (!load_set(after)) return false;
  update_scales(lambda);
  return feasible_at(lambda) && carries_on(lambda);
}

// A degenerate breakpoint (or a set that no longer holds the member): the set just beyond it
// from the contact solver, accepted only if it is feasible at the breakpoint and carries the
// path on.
bool FePath::resolve_by_solve(double lambda) {
  ++solve_resolutions_;
  double offset = beyond_offset * span_;
  for (int attempt = 0; attempt < beyond_attempts; ++attempt, offset *= 1e-2) {
    if (!rigid_motions_balanced(lambda + direction_ * offset)) {
      termination_ = TraceTermination::no_equilibrium;
      message_ = lift_off_message(lambda);
      return false;
    }
    const auto set = solved_set(lambda + direction_ * offset);
    if (!set) {
      if (termination_ == TraceTermination::no_equilibrium)
        message_ = fmt::format(
            "no equilibrium beyond lambda = {:.10g}: the live loads lift the member off the foundation and the "
            "supports cannot hold it ({})",
            lambda, message_);
      return false;
    }
    if (!load_set(*set)) continue;
    update_scales(lambda);
    if (feasible_at(lambda) && carries_on(lambda)) return true;
  }
  termination_ = TraceTermination::solver_failure;
  message_ = fmt::format(
      "the degenerate breakpoint at lambda = {:.10g} could not be resolved: no contact set from "
      "the contact solver just beyond it is feasible there",
      lambda);
  return false;
}

const Eigen::MatrixXd& FePath::free_motions() {
  const int k = d_.unstable_rigid_motions, n = d_.equations;
  if (k == 0 || free_motions_.cols() == k || free_motions_failed_) return free_motions_;
  // The member's rigid motions that leave every fixed dof (supports, gauge) and spring at rest, on
  // the equations, as discretise found them once (fe/discretisation.hpp). Built from the exact
  // motions, not from K's kernel: near the load that lifts the member off, the loads' work on
  // these motions is a tiny residue of large, nearly balancing terms, which a kernel computed to
  // eps cond(K) would drown.
  const Eigen::MatrixXd& z = d_.free_rigid_motions;
  const double largest = std::max(1.0, d_.stiffness.diagonal().cwiseAbs().maxCoeff());
  if (z.cols() != k ||
      !((d_.stiffness * z).lpNorm<Eigen::Infinity>() <= 1e-8 * largest * z.lpNorm<Eigen::Infinity>())) {
    free_motions_failed_ = true;
    free_motions_.resize(n, 0);
  } else {
    free_motions_ = Eigen::HouseholderQR<Eigen::MatrixXd>(z).householderQ() * Eigen::MatrixXd::Identity(n, k);
  }
  return free_motions_;
}

bool FePath::holds_member(const ContactSet& set) {
  const int k = d_.unstable_rigid_motions;
  if (k == 0) return true;
  const Eigen::MatrixXd& z = free_motions();
  if (z.cols() != k) return true;  // unknown: the factorisation decides
  // The fixed-set system is nonsingular iff no free rigid motion leaves every node of the set
  // where it is: C_A Z of full column rank.
  const Eigen::MatrixXd seen = d_.coupling * z;
  std::vector<int> rows;
  for (int i = 0; i < d_.reactions(); ++i)
    if (set[i]) rows.push_back(i);
  if (static_cast<int>(rows.size()) < k) return false;
  Eigen::MatrixXd seen_by_set(rows.size(), k);
  for (std::size_t r = 0; r < rows.size(); ++r) seen_by_set.row(r) = seen.row(rows[r]);
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(seen_by_set);
  qr.setThreshold(1e-8);
  return qr.rank() == k;
}

bool FePath::rigid_motions_balanced(double lambda) {
  const int k = d_.unstable_rigid_motions;
  if (k == 0) return true;
  const Eigen::MatrixXd& z = free_motions();
  if (z.cols() != k) return true;  // undecided: let Lemke say
  // Is b = Z^T F in the cone of the columns a_i = Z^T C^T e_i (what a compressive reaction at
  // node i does on the motions)? Both sides normalised: near the lift-off load b is a tiny
  // residue of loads that nearly balance. One or two motions (beams): the cone's directions
  // decide exactly; three (a free arch): non-negative least squares as an LCP (A^T A positive
  // semidefinite, so Lemke solves it), and its residual decides.
  Eigen::MatrixXd a = (d_.coupling * z).transpose();  // k x m
  VectorXd b = z.transpose() * d_.load(lambda);
  if (b.lpNorm<Eigen::Infinity>() == 0.0) return true;
  a /= std::max(a.lpNorm<Eigen::Infinity>(), 1e-300);
  b /= b.lpNorm<Eigen::Infinity>();
  if (k == 1) return ((a.array() * b[0]) > 0.0).any();
  if (k == 2) {
    // A cone in the plane is the plane, or the sector opposite the widest gap between the
    // directions of its generators: test the angle of b against it.
    std::vector<double> angles;
    for (Eigen::Index i = 0; i < a.cols(); ++i)
      if (a.col(i).lpNorm<Eigen::Infinity>() > 1e-14) angles.push_back(std::atan2(a(1, i), a(0, i)));
    if (angles.empty()) return false;
    std::sort(angles.begin(), angles.end());
    double widest = angles.front() + 2 * std::numbers::pi - angles.back();  // the gap across +-pi
    double sector_begin = angles.front(), sector_end = angles.back();
    for (std::size_t i = 1; i < angles.size(); ++i)
      if (angles[i] - angles[i - 1] > widest) {
        widest = angles[i] - angles[i - 1];
        sector_begin = angles[i];
        sector_end = angles[i - 1] + 2 * std::numbers::pi;
      }
    if (widest < std::numbers::pi) return true;  // the generators span the plane positively
    double angle = std::atan2(b[1], b[0]);
    if (angle < sector_begin - 1e-10) angle += 2 * std::numbers::pi;
    return angle >= sector_begin - 1e-10 && angle <= sector_end + 1e-10;
  }
  const lcp::LemkeResult nnls = lcp::solve_lemke(a.transpose() * a, -(a.transpose() * b), {});
  if (nnls.summary.termination != lcp::LemkeTermination::solution) return true;  // undecided: let Lemke say
  return (a * nnls.z - b).lpNorm<Eigen::Infinity>() <= 1e-8;
}

std::optional<double> FePath::lift_off_load(double from) {
  if (rigid_motions_balanced(lambda_end_)) return std::nullopt;
  double lo = from, hi = lambda_end_;
  for (int i = 0; i < 200 && std::abs(hi - lo) > options_.event_tolerance; ++i) {
    const double mid = 0.5 * (lo + hi);
    (rigid_motions_balanced(mid) ? lo : hi) = mid;
  }
  return lo;
}

std::string FePath::lift_off_message(double lambda) const {
  return fmt::format(
      "no equilibrium beyond lambda = {:.10g}: the live loads lift the member off the foundation (compressive "
      "reactions can no longer balance the loads on its free rigid motions, {}), and no support holds it",
      lambda, d_.stability_note);
}

bool FePath::establish_start(double lambda) {
  const int m = d_.reactions();
  if (options_.resume_from &&
      std::holds_alternative<continuation::FeContactSet>(options_.resume_from->state_topology) &&
      static_cast<int>(options_.resume_from->state.size()) == m) {
    ContactSet set(m);
    for (int i = 0; i < m; ++i) set[i] = options_.resume_from->state[i] > 0.5;
    if (load_set(set)) return true;
  }
  if (!d_.tensionless) {
    if (load_set(ContactSet(m, true))) return true;
    termination_ = TraceTermination::solver_failure;
    message_ = "the bilateral system is singular: the structure is a mechanism even on the foundation";
    return false;
  }
  // Unloaded: no load, and no gap offset (a hump, a settlement) that decides a supported
  // member's state at lambda_min (a member only the foundation holds floats at no load whatever
  // the ground: the ray below gives its set).
  const bool unloaded =
      d_.load(lambda).lpNorm<Eigen::Infinity>() == 0.0 && (!d_.has_ground_gap() || !d_.structure_is_stable());
  if (!unloaded) {
    // Cheapest first: full contact, if every reaction it gives is compressive.
    if (load_set(ContactSet(m, true))) {
      update_scales(lambda);
      if (feasible_at(lambda)) return true;
    }
  }
  // Unloaded at the start, F(lambda_min + t) = t F_live: the set along that ray.
  // With a ground gap the set changes along the ray (its shape is not scale-free): the set
  // just beyond lambda_min, where the gap keeps whatever it lifts lifted.
  const double ray = d_.has_ground_gap() ? 1e-6 * span_ : 1.0;
  const auto set = solved_set(unloaded ? lambda + ray * direction_ : lambda);
  if (!set) {
    if (termination_ == TraceTermination::no_equilibrium)
      message_ = fmt::format("no equilibrium at lambda = {:.10g}: {}", lambda, message_);
    return false;
  }
  if (load_set(*set)) {
    // The solver's set is used only if the exact fixed-set state agrees with it.
    update_scales(lambda);
    if (feasible_at(lambda)) return true;
    termination_ = TraceTermination::solver_failure;
    message_ =
        fmt::format("the contact set the contact solver found at lambda = {:.10g} is not feasible there", lambda);
    return false;
  }
  termination_ = TraceTermination::solver_failure;
  message_ =
      fmt::format("the contact set the contact solver found at lambda = {:.10g} does not hold the member", lambda);
  return false;
}

ContactTopology FePath::topology_at(double lambda) const {
  return contact_topology(model_, d_, d_.expand_displacement(state_.displacement(lambda)), points_);
}

TraceStep FePath::step_at(double lambda) {
  return fe_states::step_of(model_, d_, points_, options_, lambda, d_.expand_displacement(state_.displacement(lambda)),
                            state_.reaction(lambda), set_);
}

void FePath::emit_step(TraceStep step) {
  // Every state is certified from its own fields before it is reported: one that fails ends
  // the path there, the steps before it valid.
  const double lambda = step.load_factor;
  const VectorXd displacement = d_.expand_displacement(state_.displacement(lambda)), reaction = state_.reaction(lambda);
  record_fe_state(step, model_, d_, lambda, displacement, reaction,
                  fe_states::certify_state(model_, d_, lambda, displacement, reaction));
  step.iterations = pivots_since_step_;
  pivots_since_step_ = 0;
  if (sink_.on_step) sink_.on_step(step);
  result_.steps.push_back(std::move(step));
  ++result_.summary.steps;
}

void FePath::advance(double a, double b, ContactTopology& topology_a) {
  std::vector<double> inside;
  for (double r : options_.report_at)
    if (direction_ * (r - a) > 0.0 && direction_ * (b - r) > 0.0) inside.push_back(r);
  std::sort(inside.begin(), inside.end(), [&](double x, double y) { return direction_ * x < direction_ * y; });
  for (double r : inside) {
    locate_events(a, r, topology_a);
    emit_step(reported_step_at(r));
    a = r;
  }
  locate_events(a, b, topology_a);
}

TraceStep FePath::reported_step_at(double lambda) {
  TraceStep step = step_at(lambda);
  step.requested = std::find(options_.report_at.begin(), options_.report_at.end(), lambda) != options_.report_at.end();
  return step;
}

void FePath::emit_event(const TraceEvent& event) {
  if (sink_.on_event) sink_.on_event(event);
  result_.events.push_back(event);
}

// Why events are located on w and not at breakpoints: contact in the reports (and in the Ritz
// model, which the events are compared with) is w > 0 of the element cubic, while a breakpoint
// is a nodal reaction or gap reaching zero. A lift-off zone opens inside a region where w first
// touches zero, which is generally inside an element and a little after the breakpoint at which
// the nearest node's reaction reached zero (its neighbours still press it down). Between
// breakpoints the path is exactly affine, so w(x, lambda) is known in closed form there and the
// event is located by bisection on lambda to event_tolerance, with no solve.
//
// The change is classified between the last topology found equal to topology_a and the first
// found different, never topology_at(a) recomputed: at a breakpoint topology_a comes from the
// previous contact set, and an event that falls on the breakpoint shows in one set's round-off
// and not in the other's. (A heel lifting off a free end: w(0) and the end node's reaction
// vanish together, to O(h^5), as w is linear to third order at a free end.) Recomputed with the
// new set, the lift-off sliver was there already, so the bisection saw the change and then
// classified it between two topologies that both had it: the event was lost (the footing trace,
// continuation/scenes/footing_trace.toml, on 152 of the meshes from 50 to 400 elements).
void FePath::locate_events(double a, double b, ContactTopology& topology_a) {
  ContactTopology topology_b = topology_at(b);
  for (int guard = 0; guard < 64 && !topology_a.same_as(topology_b); ++guard) {
    double lo = a, hi = b;
    ContactTopology before = topology_a;
    for (int i = 0; i < 200 && std::abs(hi - lo) > options_.event_tolerance; ++i) {
      const double mid = 0.5 * (lo + hi);
      ContactTopology at_mid = topology_at(mid);
      if (at_mid.same_as(topology_a)) {
        lo = mid;
        before = std::move(at_mid);
      } else {
        hi = mid;
      }
    }
    const ContactTopology after = topology_at(hi);
    const std::vector<TraceEvent> events = classify_events(model_, points_, before, after, hi);
    if (!events.empty()) {
      emit_step(step_at(hi));
      for (const auto& event : events) emit_event(event);
    }
    a = hi;
    topology_a = after;
  }
  topology_a = topology_b;
}

std::optional<std::string> FePath::state_jump(double lambda, const VectorXd& u_before, const VectorXd& r_before) const {
  const double jump_u = (state_.displacement(lambda) - u_before).lpNorm<Eigen::Infinity>();
  const double jump_r = (state_.reaction(lambda) - r_before).lpNorm<Eigen::Infinity>();
  const auto [moved_u, moved_r] = segment_motion_;
  if (!(jump_u > moved_u) && !(jump_r > moved_r)) return std::nullopt;
  int in_contact = 0;
  for (bool in : set_) in_contact += in;
  const bool displacement = jump_u > moved_u;
  return fmt::format(
      "round-off: at the breakpoint lambda = {:.10g} the contact sets on either side give states that differ by "
      "{:.2g} (relative, {}), more than the path moved over the segment before it ({:.2g}): the system of the "
      "{} node(s) in contact is too ill-conditioned at {} elements for the path to go on; fewer elements are safer",
      lambda,
      (displacement ? jump_u / std::max(u_before.lpNorm<Eigen::Infinity>(), 1e-300)
                    : jump_r / std::max(r_before.lpNorm<Eigen::Infinity>(), 1e-300)),
      displacement ? "deflection" : "reaction",
      (displacement ? moved_u / std::max(u_before.lpNorm<Eigen::Infinity>(), 1e-300)
                    : moved_r / std::max(r_before.lpNorm<Eigen::Infinity>(), 1e-300)),
      in_contact, d_.mesh.elements());
}

void FePath::finish(TraceTermination termination, std::string message, double lambda) {
  result_.summary.termination = termination;
  result_.summary.message = std::move(message);
  result_.summary.final_load_factor = lambda;
}

double FePath::distance_to_breakpoint(double lambda) {
  update_scales(lambda);
  double next = std::numeric_limits<double>::infinity();
  if (d_.tensionless)
    for (int i = 0; i < d_.reactions(); ++i) {
      const double v = value(i, lambda), rho = rate(i);
      if (!held_[i] && rho * span_ < -zero_tolerance * scale(i)) next = std::min(next, std::max(v, 0.0) / -rho);
    }
  return next;
}

bool FePath::cross_breakpoint(double lambda, double breakpoint, bool at_once) {
  const int m = d_.reactions();
  // Every node at zero there and falling switches, ties together.
  TraceStep step = reported_step_at(breakpoint);  // the state is continuous: either set gives it
  const VectorXd u_before = state_.displacement(breakpoint), r_before = state_.reaction(breakpoint);
  const double moved_u = (u_before - state_.displacement(lambda)).lpNorm<Eigen::Infinity>(),
               moved_r = (r_before - state_.reaction(lambda)).lpNorm<Eigen::Infinity>();
  if (moved_u > 0.0) segment_motion_.first = moved_u;
  if (moved_r > 0.0) segment_motion_.second = moved_r;
  const ContactSet before = set_;
  ContactSet switched = set_;
  std::vector<int> pivoted, at_zero;
  for (int i = 0; i < m; ++i) {
    if (std::abs(value(i, breakpoint)) <= tie_tolerance * scale(i)) at_zero.push_back(i);
    if (value(i, breakpoint) <= tie_tolerance * scale(i) && rate(i) * span_ < -zero_tolerance * scale(i)) {
      switched[i] = !switched[i];
      pivoted.push_back(i);
    }
  }
  if (!holds_member(switched) && (!floating_load_ || direction_ * (*floating_load_ - breakpoint) > 0.0)) {
    // The nodes leaving would leave the member floating while the loads can still be balanced:
    // round-off has split the final tie, in which every remaining reaction vanishes together at
    // the load beyond which the loads cannot be balanced (the lift-off load). Those nodes are held
    // in the set, the path goes on with it, and it stops at that load.
    for (int i : pivoted)
      if (set_[i]) {
        switched[i] = true;
        held_[i] = true;
      }
    pivoted.erase(std::remove_if(pivoted.begin(), pivoted.end(), [&](int i) { return held_[i]; }), pivoted.end());
  }
  const int pivots = static_cast<int>(pivoted.size());
  result_.summary.pivots += pivots;
  pivots_since_step_ += pivots;
  ++breakpoints_;
  breakpoints_here_ = at_once ? breakpoints_here_ + 1 : 0;
  if (breakpoints_here_ > m + 1) {
    emit_step(std::move(step));
    finish(TraceTermination::solver_failure,
           fmt::format("the pivoting cycles at lambda = {:.10g} (degenerate breakpoint)", breakpoint), breakpoint);
    return false;
  }
  if (pivoted.empty()) {  // only held nodes: nothing switches, nothing to refactorise
    step.state.assign(set_.begin(), set_.end());
    emit_step(std::move(step));
    return true;
  }
  bool carried = load_set(switched);
  if (carried) {
    // Degenerate if a node just switched would switch straight back. Another node found at zero
    // and falling (a tie that round-off split) is simply the next breakpoint, at once.
    update_scales(breakpoint);
    carried = carries_on(breakpoint, pivoted);
  }
  if (!carried && resolve_by_rates(breakpoint, before, at_zero)) {
    carried = true;
    ++rate_resolutions_;
  }
  if (!carried && !resolve_by_solve(breakpoint)) {
    emit_step(std::move(step));
    finish(termination_, message_, breakpoint);
    return false;
  }
  if (const auto jump = state_jump(breakpoint, u_before, r_before)) {
    emit_step(std::move(step));
    finish(TraceTermination::solver_failure, *jump, breakpoint);
    return false;
  }
  step.state.assign(set_.begin(), set_.end());
  emit_step(std::move(step));
  if (result_.summary.steps >= options_.arc_length.max_steps) {
    finish(TraceTermination::step_limit,
           fmt::format("max_steps = {} reached at lambda = {:.10g}", options_.arc_length.max_steps, breakpoint),
           breakpoint);
    return false;
  }
  return true;
}

TraceResult FePath::run() {
  const auto start = std::chrono::steady_clock::now();
  TraceSummary& summary = result_.summary;
  summary.path = PathKind::fe;
  summary.pivots = 0;

  direction_ = options_.arc_length.lambda_max >= options_.arc_length.lambda_min ? 1.0 : -1.0;
  lambda_end_ = options_.arc_length.lambda_max;
  span_ = std::max(std::abs(options_.arc_length.lambda_max - options_.arc_length.lambda_min), 1e-300);
  double lambda = options_.resume_from ? options_.resume_from->load_factor : options_.arc_length.lambda_min;

  auto done = [&]() {
    summary.factorisations = system_.factorisations();
    if (rate_resolutions_ > 0 && summary.termination == TraceTermination::completed)
      summary.message += fmt::format(
          "; {} degenerate breakpoint(s) resolved by the LCP of the rates of the nodes at "
          "zero there",
          rate_resolutions_);
    if (solve_resolutions_ > 0 && summary.termination == TraceTermination::completed)
      summary.message +=
          fmt::format("; {} degenerate breakpoint(s) resolved by a contact solve just beyond them", solve_resolutions_);
    summary.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return std::move(result_);
  };
  try {
    if (options_.resume_from && !(direction_ * (lambda_end_ - lambda) > 0.0)) {
      finish(TraceTermination::completed, "the resumed step is already at the end of the load range", lambda);
      return done();
    }
    if (!establish_start(lambda)) {
      finish(termination_, message_, lambda);
      return done();
    }
    if (!options_.resume_from) emit_step(reported_step_at(lambda));
    // A member only the foundation holds can be held only while compressive reactions can
    // balance the loads on its free rigid motions: up to the lift-off load, found once here (the
    // loads' work on those motions is affine in lambda and the reactions' span a convex cone, so
    // the loads are balanced on one interval of lambda).
    if (!d_.structure_is_stable() && d_.tensionless) floating_load_ = lift_off_load(lambda);
    // Unloaded at the start, the member touches nothing, but along the first segment the state
    // is (lambda - lambda_min) times the live one: its topology is that of the live state.
    ContactTopology topology =
        state_.displacement(lambda).lpNorm<Eigen::Infinity>() == 0.0
            ? contact_topology(model_, d_, d_.expand(direction_ * state_.live.displacement), points_)
            : topology_at(lambda);

    while (true) {
      // The next breakpoint: the first reaction in the set or gap outside it to reach zero.
      const double next = distance_to_breakpoint(lambda);
      const double breakpoint = lambda + direction_ * next;
      if (floating_load_ && !(direction_ * (breakpoint - *floating_load_) < 0.0)) {
        // The held nodes' reactions vanish together here and nothing balances the loads beyond.
        advance(lambda, *floating_load_, topology);
        emit_step(reported_step_at(*floating_load_));
        finish(TraceTermination::no_equilibrium, lift_off_message(*floating_load_), *floating_load_);
        return done();
      }
      if (!(direction_ * (breakpoint - lambda_end_) < 0.0)) {
        advance(lambda, lambda_end_, topology);
        if (result_.steps.empty() || result_.steps.back().load_factor != lambda_end_)
          emit_step(reported_step_at(lambda_end_));
        finish(TraceTermination::completed,
               fmt::format("lambda = {:.10g} reached: {} breakpoint(s), {} event(s)", lambda_end_, breakpoints_,
                           result_.events.size()),
               lambda_end_);
        return done();
      }
      advance(lambda, breakpoint, topology);
      if (!cross_breakpoint(lambda, breakpoint, next == 0.0)) return done();
      lambda = breakpoint;
    }
  } catch (const StepNotCertified& failure) {
    finish(TraceTermination::solver_failure, failure.message, failure.lambda);
    return done();
  }
}

}  // namespace

TraceResult trace_fe(const model::MemberModel& member, const TraceOptions& options, const TraceSink& sink) {
  // A beam under an axial force, dead or live: K(N) varies along the path, no longer piecewise linear.
  if (member.kind == model::StructureKind::beam && member.has_axial_force())
    return trace_fe_axial(member, options, sink);
  // A von Karman beam: the membrane force makes the path curve and fold (models/fe_member.hpp).
  if (member.theory == model::Theory::von_karman) return trace_fe_von_karman(member, options, sink);
  options.validate(member.user_from_s(member.s_begin), member.user_from_s(member.s_end));
  FePath path(member, options, sink);
  return path.run();
}

EventErrors estimate_event_errors(const model::MemberModel& member, const TraceOptions& options,
                                  const TraceResult& base) {
  TraceOptions refined_options = options;
  refined_options.elements = 2 * options.elements;
  refined_options.resume_from.reset();
  const TraceResult refined = trace_fe(member, refined_options);
  EventErrors errors;
  errors.elements = options.elements;
  errors.refined_elements = refined_options.elements;
  errors.refined_summary = refined.summary;
  // Match each event with the refined run's unmatched event of its kind nearest in load, then
  // in position (mirror-image events share a load).
  std::vector<bool> used(refined.events.size(), false);
  const double length = std::abs(member.user_from_s(member.s_end) - member.user_from_s(member.s_begin));
  for (const TraceEvent& event : base.events) {
    EventErrorEstimate estimate;
    estimate.event = event;
    double best = std::numeric_limits<double>::infinity();
    std::size_t best_index = 0;
    for (std::size_t j = 0; j < refined.events.size(); ++j) {
      if (used[j] || refined.events[j].kind != event.kind) continue;
      const double distance =
          std::abs(refined.events[j].load_factor - event.load_factor) /
              std::max(std::abs(options.arc_length.lambda_max - options.arc_length.lambda_min), 1e-300) +
          std::abs(refined.events[j].at - event.at) / length;
      if (distance < best) {
        best = distance;
        best_index = j;
      }
    }
    if (std::isfinite(best)) {
      used[best_index] = true;
      estimate.refined = refined.events[best_index];
      estimate.load_factor_error = std::abs(event.load_factor - estimate.refined->load_factor);
    }
    errors.events.push_back(estimate);
  }
  return errors;
}

}  // namespace liftoff::continuation
