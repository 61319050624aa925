#include "contact/von_karman_loading.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace liftoff::contact {

void VonKarmanLoadingOptions::validate() const {
  auto require = [](bool ok, const char* what) {
    if (!ok) throw std::invalid_argument(std::string("VonKarmanLoadingOptions: ") + what);
  };
  require(min_step > 0.0 && min_step <= initial_step && initial_step <= max_step && max_step <= 1.0,
          "expected 0 < min_step <= initial_step <= max_step <= 1");
  require(jump_ratio > 1.0 && std::isfinite(jump_ratio), "jump_ratio must be > 1 and finite");
  require(predictor_ratio > 0.0 && predictor_ratio < 1.0, "predictor_ratio must be in (0, 1)");
  require(jump_floor >= 0.0 && jump_floor < 1.0, "jump_floor must be in [0, 1)");
  require(max_steps >= 1, "max_steps must be >= 1");
  solve.validate();
}

std::string_view to_string(VonKarmanLoadingTermination t) {
  switch (t) {
    case VonKarmanLoadingTermination::solved:
      return "solved";
    case VonKarmanLoadingTermination::limit_point:
      return "limit_point";
    case VonKarmanLoadingTermination::solver_failed:
      return "solver_failed";
    case VonKarmanLoadingTermination::step_limit:
      return "step_limit";
  }
  return "?";
}

VonKarmanLoadingResult load_from_zero(const VonKarmanSystem& system, const Eigen::VectorXd& dead,
                                      const Eigen::VectorXd& live, const VonKarmanLoadingOptions& options) {
  options.validate();
  const int n = system.unknowns();
  if (dead.size() != n || live.size() != n)
    throw std::invalid_argument(
        fmt::format("von Karman loading: loads have {} and {} entries, expected {}", dead.size(), live.size(), n));
  VonKarmanLoadingResult out;
  // The unloaded state: zero, every node in contact (the solver's own default start).
  out.result.x = Eigen::VectorXd::Zero(n);
  out.result.termination = VonKarmanTermination::solved;
  std::vector<bool> contact_set;

  const bool has_dead = dead.lpNorm<Eigen::Infinity>() > 0.0, has_live = live.lpNorm<Eigen::Infinity>() > 0.0;
  for (const bool live_phase : {false, true}) {
    if (!(live_phase ? has_live : has_dead)) {
      if (!live_phase) out.dead_factor = 1.0;  // nothing to apply
      continue;
    }
    double t = 0.0, dt = options.initial_step, dt_previous = 0.0;
    Eigen::VectorXd previous_change;  // the last accepted step's change (empty at a phase's start)
    while (t < 1.0) {
      if (out.solves >= options.max_steps) {
        out.termination = VonKarmanLoadingTermination::step_limit;
        out.message = fmt::format("{} solves without reaching the whole load (dead load factor {:.6g}, live {:.6g})",
                                  out.solves, out.dead_factor, out.load_factor);
        return out;
      }
      const double next = std::min(1.0, t + dt), step = next - t;
      const Eigen::VectorXd load = live_phase ? Eigen::VectorXd(dead + next * live) : Eigen::VectorXd(next * dead);
      VonKarmanResult r = system.solve(load, options.solve, out.result.x, contact_set);
      ++out.solves;
      bool accepted = r.is_usable() && r.stable;
      std::string why = !r.is_usable() ? fmt::format("the solve ended {}: {}", to_string(r.termination), r.message)
                        : !r.stable    ? std::string("the state found is unstable on its contact set")
                                       : std::string();
      if (accepted && previous_change.size() == n) {
        const Eigen::VectorXd change = r.x - out.result.x;
        const double floor = options.jump_floor * r.x.lpNorm<Eigen::Infinity>();
        const double size = change.lpNorm<Eigen::Infinity>();
        const double expected = (step / dt_previous) * previous_change.lpNorm<Eigen::Infinity>();
        const double predictor_error = (change - (step / dt_previous) * previous_change).lpNorm<Eigen::Infinity>();
        if (step > options.min_step * (1 + 1e-12) && predictor_error > options.predictor_ratio * size + floor) {
          accepted = false;  // the path bends (or jumps) within the step: a smaller one
          why = fmt::format("the secant predictor misses by {:.3g} of the step's change", predictor_error / size);
        } else if (size > options.jump_ratio * expected + floor) {
          accepted = false;
          why = fmt::format("the state jumps by {:.3g}, {:.3g} times the previous step's change scaled to the step",
                            size, size / std::max(expected, 1e-300));
        }
      }
      if (!accepted) {
        if (step <= options.min_step * (1 + 1e-12)) {
          const bool first = previous_change.size() != n && t == 0.0;
          out.termination = first && !r.is_usable() ? VonKarmanLoadingTermination::solver_failed
                                                    : VonKarmanLoadingTermination::limit_point;
          out.message = fmt::format(
              "the load path from zero meets a limit point at {} load factor {:.6g} ({}{} at a step of {:.1e}): a "
              "snap-through, not a static answer; use liftoff trace to follow it",
              live_phase ? "live" : "dead", t,
              live_phase ? (has_dead ? "the dead load in full; " : "") : "before any live load; ", why, step);
          if (out.termination == VonKarmanLoadingTermination::solver_failed)
            out.message = fmt::format("the first load step ({:.1e} of the {} load) did not solve: {}", step,
                                      live_phase ? "live" : "dead", why);
          return out;
        }
        dt = std::max(options.min_step, step / 2);
        continue;
      }
      previous_change = r.x - out.result.x;
      dt_previous = step;
      contact_set = r.in_contact;
      out.result = std::move(r);
      ++out.steps;
      t = next;
      (live_phase ? out.load_factor : out.dead_factor) = t;
      dt = std::min(options.max_step, 1.5 * step);
    }
  }
  out.termination = VonKarmanLoadingTermination::solved;
  out.message = fmt::format("the whole load reached from zero in {} steps ({} solves)", out.steps, out.solves);
  return out;
}

}  // namespace liftoff::contact
