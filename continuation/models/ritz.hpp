#pragma once
// The Ritz load history: the Ritz model with moving contact limits (ritz/ritz_model.hpp) as a
// PathModel (continuation/engine.hpp), one configuration per topology (which pieces of the
// foundation are in contact, and how many limits); follow_path drives it.
//
// - Start: the topology and limits at lambda_min from options.ritz.topology, or from an FE + LCP
//   solution there (options.elements, the sparse `fast` solver), as `liftoff solve --method ritz`
//   takes them; for von Karman beams from the FE von Karman contact solve there
//   (contact::VonKarmanSystem from zero: the linear solve knows nothing of a shallow arch's rise);
//   solved by ritz::solve_ritz. Without load at lambda_min (no dead load, lambda_min = 0) the path
//   starts one initial_step later, where the loads define the topology. Modes: options.ritz.modes,
//   else what automatic modes settle on at lambda_min but at least 32 (limits that do not exist
//   yet at lambda_min say nothing about the N they will need) and, for a point force on a
//   tensionless foundation (no load-point enrichment), what its local response needs: the relative
//   error of w there is estimated as e(N) = 8/(3 pi) (beta length / (pi N))^3 (beta = (k/4)^(1/4)),
//   and automatic modes aim at e <= 1e-3, up to options.ritz.max_modes. N with e(N) > 1e-2 is
//   refused before any work (solver_failure, "refused: ...", with the N needed for 1 % and 0.1 %).
//   Beams with beta L <= 10 use the load-point enrichment (ritz::Enrichment::load_points) instead,
//   so w at point forces is accurate to ~N^-8.
// - Crossings (models/ritz_events.hpp lists the event functions): the first event function of the
//   topology that changes sign along a step is located to options.event_tolerance in lambda, its
//   step recorded with the events and the topology switched there (enter): a vanishing piece is
//   removed at the event, a new zone is opened slightly past it (a step recorded there) with the
//   width the old topology's local expansion gives. A limit passing a load point is an event
//   without a switch (the follower goes on from it). An end piece at a beam's pinned end
//   (w = w'' = 0) vanishes with w' there, its length going like the square root of the distance to
//   the event (the limit equation meets its trivial root t = end): it is approached from the side
//   where it exists, as a piece between two limits is, and removed. At an arch's pinned end the
//   same holds but is not treated so (not examined).
// - Screening: every state recorded (start, steps, events, each switch's first state) is a contact
//   solution of the Ritz model (an event's state: but for the event itself; certify holds every
//   recorded state to it), with no event stepped over and, without an axial force or von Karman's
//   membrane term, lambda growing along the path (the linear tensionless problem has one
//   equilibrium per lambda). A step that is not is retried shorter; at min_step the path stops
//   (solver_failure) and its message says which inequality failed where and by how much.
// - Von Karman beams (RitzModel::has_membrane) and beam-columns (an axial force, N = N_dead +
//   lambda N_live) can lose their stability: stability_margin (the reduced Hessian's smallest
//   scaled eigenvalue, > 0 stable) is the engine's margin; folds (limit_point) and bifurcations are
//   the engine's. A von Karman step whose lambda moved against the tangent at both ends jumped
//   across two folds (a shallow arch's snap-through) and is retried shorter. axial_force reports
//   the compressive force, the given axial force less the membrane force.
// - Branch switching (switch_branch): at a bifurcation where the path loses its stability, the
//   path leaves along the critical mode (the reduced Hessian's eigenvector of its smallest
//   eigenvalue), on the side where it lifts the member off first; a lift-off zone opens at each
//   point where it touches at that multiple, the new topology's first point is solved with one new
//   limit held and lambda free, and the branch is followed with the zone widening; or says why
//   not (a mode that lifts first next to an existing limit, one that pushes a lift-off piece into
//   the foundation, a Newton that fails). Von Karman members on a bilateral foundation switch
//   within their topology, and so do those on a tensionless one where the mode lifts nothing off
//   within ten times the first point's offset: the first point holds the mode's largest amplitude
//   1e-3 of w's size off the bifurcation point, lambda free, and the branch is watched (its
//   amplitude along the critical mode back at the bifurcation point's value) for its return to the
//   path it left, refined on stability_margin along that path (refine_return).
// - Steps carry a resumable state: state_topology a RitzTopology (with the opening at a switching
//   event, whose switch a resumed trace redoes) and state = (x, tangent_x, tangent_lambda, next
//   step length, amplitude scale of the metric), so a resumed trace takes exactly the steps the
//   original took. A resumed state that is no contact solution is refused (solver_failure). A
//   trace resumed from a step on a switched branch does not watch for its return.
// - The metric: amplitudes scaled by what the loads make against the foundation and by what
//   lambda_size units of lambda make where a topology starts; rescaled (wants_new_problem) when
//   deflections grow four times faster than that (a lifted span lengthening).
// - summary_note: "N modes", the estimated resolution of point forces where it applies, and the
//   resumed step.
// Misuse throws std::invalid_argument naming the TraceOptions field (a bad range, sample points off
// the member, a resume_from that is no Ritz state); a member the Ritz model cannot take throws as
// ritz::RitzModel does (std::invalid_argument, liftoff::MechanismError).

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "continuation/engine.hpp"
#include "continuation/models/ritz_events.hpp"
#include "continuation/trace.hpp"
#include "model/member_model.hpp"
#include "ritz/basis.hpp"
#include "ritz/ritz_model.hpp"
#include "ritz/ritz_solver.hpp"
#include "ritz/starting_point.hpp"

namespace liftoff::continuation {

// The Ritz path of `member` (nothing of the scene: options.ritz carries its [ritz] table).
TraceResult trace_ritz(const model::MemberModel& member, const TraceOptions& options, const TraceSink& sink = {});

// How well the smooth modes resolve the response to a point force where the member rests on the
// foundation (see the top): e(N), and the N for a target.
struct RitzResolution {
  bool applies = false;
  double beta_length = 0.0;  // beta times the member's length
  double at = 0.0;           // s of the (first) point force it concerns
  double error(int modes) const;
  int modes_for(double target) const;
};

class RitzPath final : public PathModel {
 public:
  RitzPath(model::MemberModel member, const TraceOptions& options);

  PathKind kind() const override { return PathKind::ritz; }
  PathProblem problem() const override;
  Start start(const ArcLengthOptions& options) override;
  Screening screen(const PathPoint& from, PathPoint& to, const PathFollower& follower) override;
  CrossingSearch crossing(const PathPoint& from, const PathPoint& to, const PathFollower& follower,
                          bool may_take) override;
  Entry enter(const Crossing& crossing, const ArcLengthOptions& options) override;
  StabilityMeasure stability_measure() const override;
  StabilityState stability(const PathPoint& point) const override;
  BranchSwitch switch_branch(const PathPoint& at, const PathFollower& follower) override;
  std::optional<PathPoint> refine_return(const PathPoint& located, double peak, const PathFollower& follower) override;
  double event_position(const PathPoint& point) const override;
  std::string describe_state(const PathPoint& point) const override;
  double amplitude(const PathPoint& point) const override;
  std::optional<std::string> certify(const PathPoint& point) const override;
  TraceStep record(const PathPoint& point, const RecordContext& context) const override;
  bool wants_new_problem(PathPoint& point) override;
  std::string summary_note() const override;

  // What a crossing changes (Crossing::transition): the events located together at `point`, how
  // a new zone opens past it, and whether the topology changes at all (a limit passing a load
  // point does not: the follower goes on from the event).
  struct Transition {
    std::vector<RitzEventSpec> events;
    PathPoint point;
    RitzOpening opening;
    bool changes_topology = false;
  };
  // A switched branch that keeps its topology, watched for its return to the path it left: the
  // amplitudes' component along the critical mode (unit length) back at its value at the
  // bifurcation point, where the Hessian is singular again.
  struct ReturnWatch {
    Eigen::VectorXd mode;    // the critical mode's amplitudes, unit length
    double at = 0.0;         // mode . amplitudes at the bifurcation point
    double departure = 0.0;  // the sign of (mode . amplitudes - at) on the branch
    double lambda = 0.0;     // the bifurcation load left from
  };
  struct Branch {
    std::shared_ptr<const ritz::RitzModel> model;
    PathPoint point;
    std::optional<ReturnWatch> watch;
  };

 private:
  // Start (models/ritz.cpp).
  struct ResumeState;
  ResumeState starting_state();
  ResumeState resumed_state(const TraceStep& step);
  ritz::StartingPoint start_topology(double lambda_start) const;
  int modes_for_trace(const ritz::RitzSolution& start) const;
  void check_resolution(int modes) const;
  RitzResolution resolution() const;
  Start resumed_at_event(const ResumeState& state);
  // The follower's metric (see the top) and a follower on `model` for the model's own solves.
  double lambda_size() const;
  double force_scale(const ritz::RitzModel& model) const;
  double load_deflection(const ritz::RitzModel& model) const;
  PathProblem problem_for(std::shared_ptr<const ritz::RitzModel> model) const;
  PathFollower follower_for(std::shared_ptr<const ritz::RitzModel> model) const;
  void rescale(std::shared_ptr<const ritz::RitzModel> model, PathPoint& p);
  double compression(const ritz::RitzModel& model, const Eigen::VectorXd& x, double lambda) const;

  // Along a step (models/ritz_steps.cpp).
  std::vector<double> event_values(const Eigen::VectorXd& x) const;
  std::optional<std::string> jumped_folds(const PathPoint& from, const PathPoint& to) const;
  std::optional<Screening> approach_vanishing(const PathPoint& from, PathPoint& to, const PathFollower& follower);
  std::optional<std::string> turned_back(const PathPoint& from, const PathPoint& to) const;
  std::vector<std::size_t> changed_events(const PathPoint& from, const PathPoint& to) const;
  CrossingSearch located_events(const PathPoint& from, const PathPoint& to, const PathFollower& follower,
                                const std::vector<std::size_t>& changed);
  std::vector<TraceEvent> describe_events(const Transition& transition) const;
  std::optional<std::string> no_contact_solution(const PathPoint& from, const PathPoint& to) const;

  // Switching (models/ritz_switch.cpp).
  struct Openings;
  void adopt(std::shared_ptr<const ritz::RitzModel> model);  // the current topology's model
  Openings openings(const Transition& transition) const;
  Entry switch_topology(const Transition& transition);
  double removal_allowance(const Transition& transition) const;
  Entry open_topology(const Transition& transition, const Openings& openings, double allowance);
  std::optional<std::string> open_guess(const Transition& transition, const Openings& openings, double delta,
                                        PathPoint& base, std::vector<double>& guess) const;
  std::optional<Branch> find_branch(const PathPoint& at, std::string& why) const;
  std::optional<Branch> lift_off_branch(const PathPoint& at, Eigen::VectorXd mode, std::string& why) const;
  std::optional<Branch> switch_in_topology(const PathPoint& at, const Eigen::VectorXd& mode, std::string& why) const;
  double in_topology_offset(const PathPoint& at, const Eigen::VectorXd& mode, Eigen::Index& held) const;
  bool solve_with_held(const ritz::RitzModel& model, int held, const Eigen::VectorXd& residual_scale,
                       Eigen::VectorXd& x, double& lambda) const;
  std::optional<Branch> branch_from(std::shared_ptr<const ritz::RitzModel> model, const Eigen::VectorXd& x,
                                    double lambda, int held, double sense, std::string& why) const;
  std::optional<PathPoint> refined_crossing(const PathFollower& follower, const PathPoint& near) const;

  double user(double s) const { return member_.user_from_s(s); }
  const char* coordinate() const { return member_.kind == model::StructureKind::arch ? "theta" : "x"; }
  void vouch(const PathPoint& point) const { checked_.push_back(point.x); }

  model::MemberModel member_;
  const TraceOptions& options_;
  ritz::Enrichment enrichment_ = ritz::Enrichment::none;
  RitzResolution resolution_;
  bool foundation_only_ = false;  // only the foundation holds the member (it can lift off entirely)
  int modes_ = 0;
  double amplitude_scale_ = 0.0;  // the follower's, see rescale
  std::shared_ptr<const ritz::RitzModel> model_;
  std::optional<RitzEvents> events_;
  std::vector<RitzEventSpec> specs_;  // the event functions of model_'s topology
  std::optional<ReturnWatch> watch_;
  // States checked as contact solutions since the last step began (an event's with its
  // allowance): certify takes them as they are.
  mutable std::vector<Eigen::VectorXd> checked_;
  // The event functions' values at the last states asked for (a step's start is the last one's end).
  mutable std::vector<std::pair<Eigen::VectorXd, std::vector<double>>> values_cache_;
};

}  // namespace liftoff::continuation
