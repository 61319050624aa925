#pragma once
// The state a von Karman beam reaches when its load is applied from zero (issue 16, `liftoff
// solve`): load increments, each solved by VonKarmanSystem::solve from the previous step's answer
// and its contact set, so that the answer is the equilibrium on the loading's own branch and not
// some other equilibrium of the same load (past a limit point there are several, and a solve
// from zero may find any of them).
//
// The loading. Dead loads first (the factor mu on F_dead from 0 to 1, no live load), then the live
// load (lambda from 0 to 1 with F_dead in full): F = mu F_dead + lambda F_live. Self-weight and
// other permanent loads act before the service load, and an answer under the whole load does not
// depend on which comes first unless the path meets a limit point, which it refuses. A scene
// with only live (or only dead) loads has one phase.
//
// Steps, and the limit point. A step's answer x(t + dt) is accepted when the solve is `solved`,
// the state is stable on its contact set (VonKarmanResult::stable: the condensed Hessian positive
// definite), and it continues the path:
//  - the secant predictor x(t) + (dt / dt_prev) (x(t) - x(t - dt_prev)) misses it by at most
//    predictor_ratio of the step's change |x(t + dt) - x(t)| (a smooth path: O(dt^2) against
//    O(dt)); otherwise the step is halved. At min_step this test is waived (a kink, where a contact
//    node lifts off or lands, bends the path by a finite angle however small the step);
//  - the change is at most jump_ratio (dt / dt_prev) |x(t) - x(t - dt_prev)|_inf (+ jump_floor
//    |x|_inf): a kink changes the slope by a bounded factor, while a snap-through is a finite
//    jump whatever dt, so near it halving dt makes the ratio grow without bound.
// (A first version without the predictor test let a snap-through of the issue 16 shallow arch
// through at steps of 0.2: the jump was 8 times the previous step's change, under a jump_ratio of
// 10.) A step that fails is halved; at min_step the path has met a limit point (or a state the
// solver cannot follow) and the loading ends there: termination `limit_point`, with the load
// factor reached (a snap-through is not a static answer: `liftoff trace` follows it). Steps grow
// by 1.5 after an accepted step, up to max_step.
//
// The first step of each phase has no previous change to compare with: it is accepted when it
// is solved and stable (a step of dt from the unloaded or dead-loaded state; with a jump there
// min_step's step would still be accepted, so the first step is capped at initial_step).

#include <Eigen/Dense>
#include <string>
#include <string_view>
#include <vector>

#include "contact/von_karman_solve.hpp"

namespace liftoff::contact {

struct VonKarmanLoadingOptions {
  double initial_step = 0.05;  // of the phase's factor (0..1)
  double min_step = 1e-4;
  double max_step = 0.2;
  double predictor_ratio = 0.5;  // the secant predictor's miss against the step's change
  double jump_ratio = 10.0;      // the step's change against the previous step's (scaled by dt)
  double jump_floor = 1e-10;     // relative to |x|_inf: round-off changes are never jumps
  int max_steps = 2000;          // solves in all (rejected ones too)
  VonKarmanOptions solve;        // each step's solve
  void validate() const;         // throws std::invalid_argument naming the field
};

enum class VonKarmanLoadingTermination {
  solved,         // the whole load reached on the loading's branch; `result` is the answer at it
  limit_point,    // a step could not continue the path at min_step: a limit point (snap-through) or
                  // an unstable state; `result` is the last accepted state, dead_factor/load_factor reached
  solver_failed,  // the first step (min_step) of a phase did not solve; result.message says why
  step_limit,     // max_steps solves
};
std::string_view to_string(VonKarmanLoadingTermination);

struct VonKarmanLoadingResult {
  VonKarmanLoadingTermination termination = VonKarmanLoadingTermination::step_limit;
  std::string message;
  bool is_usable() const { return termination == VonKarmanLoadingTermination::solved; }
  VonKarmanResult result;    // the last accepted state (the answer when solved)
  double dead_factor = 0.0;  // mu reached
  double load_factor = 0.0;  // lambda reached
  int steps = 0;             // accepted
  int solves = 0;            // all
};

// system: the member and its mesh; `dead` and `live`: the loads on the unknowns
// (VonKarmanSystem::load(0) and load(1) - load(0) give the scene's).
VonKarmanLoadingResult load_from_zero(const VonKarmanSystem& system, const Eigen::VectorXd& dead,
                                      const Eigen::VectorXd& live, const VonKarmanLoadingOptions& options = {});

}  // namespace liftoff::contact
