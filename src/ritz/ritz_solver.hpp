#pragma once
// Solving the Ritz model (ritz_model.hpp): Newton (KINSOL, nonlinear/newton.hpp) on the
// regularised stationarity conditions, from an initial topology and limits, with the number of
// modes fixed or chosen automatically, and the answer checked against the contact inequalities
// before it is returned.
//
// Automatic modes: N = 4, 8, 16, ... up to max_modes, each solve started from the previous
// limits, until every limit moves by less than mode_tolerance (in s) between two successive
// converged N; the last change is reported as the estimated error of the limits. An N too small
// for the topology (Newton fails or the inequalities do not hold) is passed over.

#include <Eigen/Dense>
#include <optional>
#include <string>
#include <vector>

#include "model/member_model.hpp"
#include "nonlinear/newton.hpp"
#include "ritz/ritz_model.hpp"

namespace liftoff::ritz {

struct RitzOptions {
  int modes = 0;                 // N; 0 means automatic
  int max_modes = 256;           // automatic: the largest N tried
  double mode_tolerance = 1e-5;  // automatic: limits converged when they move less than this (s)
  // Automatic, when > 0: w and the reaction k max(w, 0) must also have settled: their largest
  // change from the previous N, relative to max |w| and to the largest reaction, below this.
  // ([solve] tolerance sets it: a tolerance promises deflections and reactions too.)
  double field_tolerance = 0.0;
  double load_factor = 1.0;  // lambda
  // Contact inequalities on a fine grid after convergence: w >= -tol in contact pieces, w <= tol
  // in lift-off pieces, tol = inequality_tolerance * max |w|.
  double inequality_tolerance = 1e-9;
  Enrichment enrichment = Enrichment::none;  // load-point enrichment of beam bases (basis.hpp)
  nonlinear::NewtonOptions newton;           // residual_tolerance applies to the scaled residual
  void validate() const;                     // throws std::invalid_argument naming the field
};

enum class RitzTermination {
  converged,              // Newton converged and the inequalities hold
  newton_failed,          // KINSOL did not converge; the message says how
  inequalities_violated,  // converged to a point that is not a contact solution (w < 0 in a
                          // contact piece or w > 0 in a lift-off piece): the topology is wrong
  modes_not_converged,    // automatic modes: the limits still moved at max_modes
  no_starting_point,      // K + k G singular for the initial limits: nothing holds the member
  unstable_equilibrium,   // under an axial force or von Karman's membrane term: a contact solution,
                          // but the reduced Hessian (K - N K_g + k G, plus the membrane's) is not
                          // positive definite there (RitzModel::stability_margin <= 0): refused
};
std::string_view to_string(RitzTermination);

// One row of the automatic-modes history.
struct ModeStep {
  int modes = 0;
  std::vector<double> limits;  // s
  int newton_iterations = 0;
};

struct RitzSummary {
  RitzTermination termination = RitzTermination::newton_failed;
  std::string message;
  int modes = -1;
  int newton_iterations = -1;            // of the final solve
  std::vector<double> residual_history;  // of the final solve (scaled max-norm per iterate)
  double estimated_limit_error = -1;     // automatic modes: last change of the limits (s); -1 otherwise
  // Automatic modes: last change of w (relative to max |w|) and of the reaction (to its largest)
  // from the previous N, on a grid of 2048 intervals; -1 otherwise.
  double estimated_w_error = -1;
  double estimated_reaction_error = -1;
  double max_violation = -1;  // worst wrong-sign |w| / max|w| on the check grid
  std::vector<ModeStep> mode_history;
  double time_s = -1;
  bool is_usable() const { return termination == RitzTermination::converged; }
  std::string brief_report() const;
};

struct RitzSolution {
  std::optional<RitzModel> model;  // the model of the final N (absent if none could be built)
  Eigen::VectorXd unknowns;        // amplitudes then limits
  RitzSummary summary;
};

// The contact inequalities of a Ritz state on a grid that sees every piece: w >= 0 in contact
// pieces (there the reaction k w is >= 0), w <= 0 in lift-off pieces. solve_ritz checks every
// answer so before it returns it, and the Ritz load path every state it accepts. The grid has
// max(400, 16 N length/L) intervals per piece (N modes; 16 points per shortest half-wave of the
// basis, whose highest wavenumber is about N pi / L), the limits themselves excluded: w = 0
// there by construction.
struct InequalityCheck {
  double violation = 0.0;   // worst wrong-sign |w| / max |w| (0 when none)
  double at = 0.0;          // s of the worst point (meaningful when violation > 0)
  double w = 0.0;           // w there
  bool in_contact = false;  // whether that point is in a contact piece
  double w_scale = 0.0;     // max |w| on the grid
};
InequalityCheck check_inequalities(const RitzModel& model, const Eigen::VectorXd& x);

// initial_limits: one guess per limit of `topology`, increasing, inside the foundation.
RitzSolution solve_ritz(const model::MemberModel& member, const Topology& topology,
                        const std::vector<double>& initial_limits, const RitzOptions& options = {});

}  // namespace liftoff::ritz
