#include "ritz/ritz_solver.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/enum_names.hpp"
#include "core/require.hpp"

namespace liftoff::ritz {

using Eigen::VectorXd;

namespace {
constexpr EnumName<RitzTermination> ritz_termination_names[] = {
    {RitzTermination::converged, "converged"},
    {RitzTermination::newton_failed, "newton_failed"},
    {RitzTermination::inequalities_violated, "inequalities_violated"},
    {RitzTermination::modes_not_converged, "modes_not_converged"},
    {RitzTermination::no_starting_point, "no_starting_point"},
    {RitzTermination::unstable_equilibrium, "unstable_equilibrium"},
};
}  // namespace

std::string_view to_string(RitzTermination t) { return name_in<RitzTermination>(ritz_termination_names, t); }

void RitzOptions::validate() const {
  require(modes >= 0, "RitzOptions::modes", "must be >= 0 (0: automatic)");
  require(max_modes >= 1, "RitzOptions::max_modes", "must be >= 1");
  require(mode_tolerance > 0, "RitzOptions::mode_tolerance", "must be > 0");
  require(field_tolerance >= 0, "RitzOptions::field_tolerance", "must be >= 0");
  require(std::isfinite(load_factor), "RitzOptions::load_factor", "must be finite");
  require(inequality_tolerance > 0, "RitzOptions::inequality_tolerance", "must be > 0");
}

std::string RitzSummary::brief_report() const {
  return fmt::format("{}: {} modes, {} Newton iterations, final residual {:.1e}, {:.3f} s", to_string(termination),
                     modes, newton_iterations, residual_history.empty() ? -1.0 : residual_history.back(), time_s);
}

InequalityCheck check_inequalities(const RitzModel& model, const VectorXd& x) {
  InequalityCheck check;
  double worst = 0.0;
  std::vector<double> w;
  const std::vector<ContactRegion> pieces = model.pieces(x);
  const double length = pieces.empty() ? 0.0 : pieces.back().end - pieces.front().begin;
  for (const ContactRegion& piece : pieces) {
    const double share = length > 0 ? std::max(piece.end - piece.begin, 0.0) / length : 1.0;
    const int intervals = std::max(400, static_cast<int>(std::ceil(16.0 * model.modes() * share)));
    // Open pieces: the ends are the limits, where w = 0 by construction.
    model.w_on_grid(x, piece.begin, piece.end, intervals, w);
    for (std::size_t i = 0; i < w.size(); ++i) {
      check.w_scale = std::max(check.w_scale, std::abs(w[i]));
      // A bilateral foundation (one piece, in contact) resists both ways: no sign is wrong.
      const double wrong = !model.tensionless() ? 0.0 : piece.in_contact ? -w[i] : w[i];
      if (wrong > worst) {
        worst = wrong;
        check.at = piece.begin + (piece.end - piece.begin) * static_cast<double>(i + 1) / intervals;
        check.w = w[i];
        check.in_contact = piece.in_contact;
      }
    }
  }
  check.violation = check.w_scale == 0.0 ? 0.0 : worst / check.w_scale;
  return check;
}

namespace {

// The residual's round-off floor in the scaled max norm: each row is a sum of n products, so
// evaluating it at the root leaves up to n eps (sum_j |J_ij x_j| + |load_i|) (Higham's gamma_n),
// over the amplitude columns whose terms these are (limit rows are linear in the amplitudes too).
double scaled_round_off_floor(const RitzModel& model, const VectorXd& x, double lambda,
                              const VectorXd& residual_scale) {
  const int n = model.unknowns(), a = model.amplitudes();
  Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(n, n);
  model.jacobian(x, lambda, jacobian);
  VectorXd terms = jacobian.leftCols(a).cwiseAbs() * x.head(a).cwiseAbs();
  terms.head(a) += (model.dead_load() + lambda * model.live_load()).cwiseAbs();
  terms.head(model.modes()) += std::abs(model.axial_force(lambda)) * model.imperfection_load().cwiseAbs();
  const double eps = std::numeric_limits<double>::epsilon();
  return n * eps * terms.cwiseProduct(residual_scale).lpNorm<Eigen::Infinity>();
}

struct Attempt {
  VectorXd x;
  nonlinear::NewtonSummary newton;
  RitzTermination termination = RitzTermination::newton_failed;
  std::string message;
  double max_violation = -1;
};

Attempt solve_once(const RitzModel& model, const VectorXd& limits, const RitzOptions& options,
                   const model::Scales& scales) {
  Attempt attempt;
  const double lambda = options.load_factor;
  const std::optional<VectorXd> start = model.minimiser_for_limits(limits, lambda);
  if (!start) {
    attempt.termination = RitzTermination::no_starting_point;
    attempt.message =
        "the Ritz stiffness K + k G is singular for the initial contact limits: nothing holds the member in place";
    return attempt;
  }
  attempt.x = *start;

  // Scale rows and unknowns to unit size, so one tolerance serves forces and deflections.
  const int n = model.unknowns(), a = model.amplitudes();
  const double force_scale =
      std::max({(model.dead_load() + lambda * model.live_load()).lpNorm<Eigen::Infinity>(),
                std::abs(model.axial_force(lambda)) * model.imperfection_load().lpNorm<Eigen::Infinity>(), 1e-300});
  const double amplitude_scale = std::max(attempt.x.head(a).lpNorm<Eigen::Infinity>(), 1e-300);
  nonlinear::NewtonOptions newton = options.newton;
  newton.residual_scale = VectorXd::Constant(n, 1.0 / force_scale);
  newton.residual_scale.tail(n - a).setConstant(1.0 / amplitude_scale);
  newton.unknown_scale = VectorXd::Constant(n, 1.0 / amplitude_scale);
  newton.unknown_scale.tail(n - a).setConstant(1.0);

  // Under an axial force, a start that already solves the equations (no limits: the linear
  // minimiser is the answer) is taken as it is: KINSOL, handed a residual at round-off zero (a
  // member loaded by its initial shape alone), has been seen to step off to 1e274 (not understood).
  // Near a critical load the linear solve's residual is the condition times eps: its round-off
  // floor, not the tolerance, is what it can meet.
  bool exact_start = false;
  double r0_scaled = 0.0;
  if (model.has_axial_force() && model.limits() == 0) {
    VectorXd r0;
    model.residual(attempt.x, lambda, r0);
    r0_scaled = r0.cwiseAbs().cwiseProduct(newton.residual_scale).maxCoeff();
    exact_start = r0_scaled <= std::max(newton.residual_tolerance,
                                        scaled_round_off_floor(model, attempt.x, lambda, newton.residual_scale));
  }
  if (exact_start) {
    attempt.newton.termination = nonlinear::NewtonTermination::converged;
    attempt.newton.message = "the linear minimiser solves the equations";
    attempt.newton.iterations = 0;
    attempt.newton.residual_evaluations = 1;
    attempt.newton.jacobian_evaluations = 0;
    attempt.newton.backtracks = 0;
    attempt.newton.residual_history = {r0_scaled};
    attempt.newton.final_residual = r0_scaled;
    attempt.newton.time_s = 0.0;
  } else {
    attempt.newton = nonlinear::solve_newton(
        [&](const VectorXd& x, VectorXd& r) {
          if (!model.admissible(x)) return false;
          model.residual(x, lambda, r);
          return true;
        },
        [&](const VectorXd& x, const VectorXd&, Eigen::MatrixXd& j) {
          model.jacobian(x, lambda, j);
          return true;
        },
        attempt.x, newton);
  }
  std::string accepted = "equilibrium found";
  if (!attempt.newton.is_usable()) {
    // A line search that stalls just above the tolerance may be at the round-off floor of the
    // residual's own terms (many modes, large stiffness terms cancelling): accept it there, and say so.
    const double floor = scaled_round_off_floor(model, attempt.x, lambda, newton.residual_scale);
    const bool stalled = attempt.newton.termination == nonlinear::NewtonTermination::line_search_failed ||
                         attempt.newton.termination == nonlinear::NewtonTermination::step_below_tolerance;
    if (!stalled || !(attempt.newton.final_residual <= floor)) {
      attempt.message = "Newton did not converge: " + attempt.newton.message;
      return attempt;
    }
    accepted = fmt::format(
        "equilibrium found to round-off: residual {:.2e} above the tolerance {:.1e} but within the round-off floor "
        "{:.2e} of its terms",
        attempt.newton.final_residual, newton.residual_tolerance, floor);
  }
  attempt.max_violation = check_inequalities(model, attempt.x).violation;
  if (attempt.max_violation > options.inequality_tolerance) {
    attempt.termination = RitzTermination::inequalities_violated;
    attempt.message = fmt::format(
        "Newton converged, but the answer violates the contact inequalities (wrong-sign deflection {:.1e} of max |w|): "
        "the topology {} cannot hold here",
        attempt.max_violation, to_string(model.topology()));
    return attempt;
  }
  if (model.can_lose_stability()) {
    // Second-order theory answers stable states only: K - N K_g + k G must be positive definite
    // (von Karman: plus the membrane term's Hessian).
    const double margin = model.stability_margin(attempt.x, lambda);
    if (!(margin > 0.0) && !model.has_axial_force()) {
      attempt.termination = RitzTermination::unstable_equilibrium;
      attempt.message = fmt::format(
          "refused: the equilibrium found is unstable (von Karman: the reduced Hessian of the topology {} with the "
          "membrane term, membrane force {:.6g}, is not positive definite, smallest scaled eigenvalue {:.3e}): past "
          "a limit or bifurcation point the member snaps away from it; trace the path to follow it",
          to_string(model.topology()), model.membrane_force(attempt.x) * scales.force(), margin);
      return attempt;
    }
    if (!(margin > 0.0)) {
      attempt.termination = RitzTermination::unstable_equilibrium;
      attempt.message = fmt::format(
          "refused: the axial force {:.6g} exceeds the critical load of the configuration found (the reduced "
          "Hessian K - N K_g + k G of the topology {} is not positive definite, smallest scaled eigenvalue {:.3e}): "
          "the equilibrium is unstable, and the member buckles away from it",
          model.axial_force(lambda) * scales.force(), to_string(model.topology()), margin);
      return attempt;
    }
  }
  attempt.termination = RitzTermination::converged;
  attempt.message = accepted;
  return attempt;
}

}  // namespace

RitzSolution solve_ritz(const model::MemberModel& member, const Topology& topology,
                        const std::vector<double>& initial_limits, const RitzOptions& options) {
  options.validate();
  if (static_cast<int>(initial_limits.size()) != topology.limits)
    throw std::invalid_argument("solve_ritz: one initial guess per contact limit is needed");
  const auto start = std::chrono::steady_clock::now();
  RitzSolution solution;
  RitzSummary& summary = solution.summary;

  std::vector<int> sequence;
  if (options.modes > 0) {
    sequence = {options.modes};
  } else {
    for (int n = 4; n <= options.max_modes; n *= 2) sequence.push_back(n);
    if (sequence.empty() || sequence.back() != options.max_modes) sequence.push_back(options.max_modes);
  }

  VectorXd limits = Eigen::Map<const VectorXd>(initial_limits.data(), topology.limits);
  std::optional<VectorXd> previous_limits;
  // w and the reaction of each converged N on a fixed grid, for their change from the previous N.
  constexpr int field_intervals = 2048;
  VectorXd w_now(field_intervals + 1), r_now(field_intervals + 1), w_before, r_before;
  for (int modes : sequence) {
    RitzModel model(member, modes, topology, options.enrichment);
    Attempt attempt = solve_once(model, limits, options, member.scales);
    summary.modes = modes;
    summary.termination = attempt.termination;
    summary.message = attempt.message;
    summary.newton_iterations = attempt.newton.iterations;
    summary.residual_history = attempt.newton.residual_history;
    summary.max_violation = attempt.max_violation;
    solution.unknowns = attempt.x;
    solution.model = std::move(model);
    if (attempt.termination == RitzTermination::unstable_equilibrium) break;  // more modes only soften it
    if (attempt.termination != RitzTermination::converged) {
      // Automatic modes: a few modes may be too coarse for the topology (a free-free beam at
      // N = 4 has three rigid-like functions and one cosine); try more, from the initial limits.
      if (options.modes > 0 || modes == sequence.back()) break;
      limits = Eigen::Map<const VectorXd>(initial_limits.data(), topology.limits);
      previous_limits.reset();
      continue;
    }

    limits = attempt.x.tail(topology.limits);
    summary.mode_history.push_back({modes, {limits.data(), limits.data() + limits.size()}, attempt.newton.iterations});
    if (options.modes > 0) break;
    const bool fields = options.field_tolerance > 0;
    if (fields) {
      const std::vector<ContactRegion> pieces = solution.model->contact_pieces(attempt.x);
      for (int i = 0; i <= field_intervals; ++i) {
        const double s = member.s_begin + member.length() * i / field_intervals;
        w_now[i] = solution.model->w(attempt.x, s);
        r_now[i] = solution.model->reaction(attempt.x, s, pieces);
      }
    }
    bool settled = false;
    if (previous_limits) {
      summary.estimated_limit_error =
          topology.limits == 0 ? 0.0 : (limits - *previous_limits).lpNorm<Eigen::Infinity>();
      settled = summary.estimated_limit_error < options.mode_tolerance;
      if (fields) {
        const double w_scale = w_now.cwiseAbs().maxCoeff(), r_scale = r_now.cwiseAbs().maxCoeff();
        summary.estimated_w_error = w_scale > 0 ? (w_now - w_before).cwiseAbs().maxCoeff() / w_scale : 0.0;
        summary.estimated_reaction_error = r_scale > 0 ? (r_now - r_before).cwiseAbs().maxCoeff() / r_scale : 0.0;
        settled = settled && summary.estimated_w_error < options.field_tolerance &&
                  summary.estimated_reaction_error < options.field_tolerance;
      }
      if (settled) break;
    }
    previous_limits = limits;
    if (fields) {
      w_before = w_now;
      r_before = r_now;
    }
    if (modes == sequence.back()) {
      summary.termination = RitzTermination::modes_not_converged;
      const int previous_modes = summary.mode_history.size() > 1 ? summary.mode_history.end()[-2].modes : modes;
      summary.message = fmt::format("the contact limits still moved by {:.1e} between {} and {} modes",
                                    summary.estimated_limit_error, previous_modes, modes);
      if (fields)
        summary.message += fmt::format(", w by {:.1e} of max |w| and the reaction by {:.1e} of its largest",
                                       summary.estimated_w_error, summary.estimated_reaction_error);
    }
  }
  summary.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return solution;
}

}  // namespace liftoff::ritz
