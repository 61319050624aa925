#include "continuation/models/fe_member.hpp"

// Why things are done the way they are:
//  - The states the path decides its events on are polished to round-off (FeMemberPath::refine): the
//    corrector stops at 1e-11 of each equation's size at the unloaded state, which near a limit
//    point leaves the state off by ~1e-7 of w_ref, more than the signs the events decide. This
//    costs a factorisation per evaluation of a contact event's function.
//  - The switched branch's return is located on its amplitude along the mode, which vanishes all
//    along the path it rejoins, so the locate lands on that path but not at the crossing (16 / 32
//    elements, kappa = 2: 13.4290 / 13.4329, kappa = 8: 88.6184 / 89.3594, against 13.46827 /
//    88.61662): refine_return takes it onto the crossing (see there).

#include <fmt/format.h>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "certify/certificate.hpp"
#include "contact/von_karman_solve.hpp"
#include "continuation/engine.hpp"
#include "continuation/events.hpp"
#include "continuation/models/fe_states.hpp"
#include "continuation/models/member_kinematics.hpp"
#include "continuation/step_state.hpp"
#include "post/fields.hpp"
#include "stability/critical_load.hpp"

namespace liftoff::continuation {

namespace {

using Eigen::VectorXd;
using SparseMatrix = Eigen::SparseMatrix<double>;
using Triplets = std::vector<Eigen::Triplet<double>>;
using ContactSet = contact::ContactSelection;

// Nodes whose normalised sign value is within this of zero at a located contact event switch
// together (mirror nodes of a symmetric member reach zero at one lambda up to round-off).
constexpr double tie_tolerance = 1e-8;
// The switched branch has met the path it left once its amplitude is within the corrector's
// relative accuracy (1e-7 of w_ref) of the largest it reached: closer, the two are not told apart.
constexpr double branch_accuracy = 1e-7;
// A state of a kinematics linear in its unknowns is taken as it is when its residual is below this
// fraction of its terms (the certificate's backward error tolerance is 1e-8 of the same terms).
constexpr double linear_accuracy = 1e-12;

// The transition of the crossing at the lift-off load (the path ends there).
struct LiftOff {};

// The eigenvalue of S nearest zero and its eigenvector (with its reactions' response).
struct Eigenpair {
  VectorXd vector;
  double value = std::numeric_limits<double>::quiet_NaN();
  double round_off = std::numeric_limits<double>::quiet_NaN();
};

class FeMemberPath final : public PathModel {
 public:
  FeMemberPath(std::unique_ptr<MemberKinematics> kinematics, const TraceOptions& options, VonKarmanStateSeam seam);

  PathKind kind() const override { return PathKind::fe; }
  PathProblem problem() const override { return problem_on(set_); }
  Start start(const ArcLengthOptions& options) override;
  PathPoint refine(const PathPoint& point, bool fixed_lambda) const override {
    PathPoint p = polished(set_, point, fixed_lambda);
    // On a straight bifurcated branch lambda is constant: its tangent's lambda component is zero
    // (round-off of either sign would read as folds).
    if (on_straight_branch_) p.tangent_lambda = 0.0;
    return p;
  }
  CrossingSearch crossing(const PathPoint& from, const PathPoint& to, const PathFollower& follower,
                          bool may_take) override;
  Entry enter(const Crossing& crossing, const ArcLengthOptions& options) override;
  StabilityMeasure stability_measure() const override {
    return kin_->convex() ? StabilityMeasure::none : StabilityMeasure::count;
  }
  StabilityState stability(const PathPoint& point) const override;
  StabilityState stability_at_crossing(const PathPoint& point, const Crossing& crossing) const override;
  BranchSwitch switch_branch(const PathPoint& at, const PathFollower& follower) override;
  PathPoint refine_bifurcation(const PathPoint& point) const override;
  std::optional<PathPoint> refine_return(const PathPoint& located, double peak, const PathFollower& follower) override;
  double event_position(const PathPoint&) const override { return options_.monitor; }
  std::string describe_state(const PathPoint& point) const override;
  double amplitude(const PathPoint& point) const override;
  std::optional<std::string> certify(const PathPoint& point) const override;
  TraceStep record(const PathPoint& point, const RecordContext& context) const override;
  std::string summary_note() const override { return fmt::format("{} elements", options_.elements); }
  bool wants_new_problem(PathPoint& point) override;
  void fill_summary(TraceSummary& summary) const override {
    summary.factorisations = factorisations_;
    summary.contact_solves = contact_solves_;
    summary.contact_method = contact_method_;
  }

 private:
  // The bordered equations of a set.
  PathProblem problem_on(const ContactSet& set) const;
  bool residual(const ContactSet& set, const VectorXd& y, double lambda, VectorXd& g) const;
  // primal: on the displacement alone, the tangent stiffness K_t (S's inertia: no -H block).
  SparseMatrix saddle(const ContactSet& set, const VectorXd& y, double lambda, bool primal = false) const;
  VectorXd unknown_scale(const ContactSet& set) const;
  VectorXd residual_scale(const ContactSet& set) const;
  // The point with Newton corrections of the bordered system (see refine; `mode`: at fixed lambda
  // on a bifurcation point, bordered by the critical mode).
  PathPoint polished(const ContactSet& set, const PathPoint& point, bool fixed_lambda,
                     const VectorXd* mode = nullptr) const;
  VectorXd reactions(const ContactSet& set, const VectorXd& y) const;
  // One Newton correction at the point's lambda (kept if it reduces the residual).
  PathPoint corrected_at_lambda(const ContactSet& set, const PathPoint& point) const;
  bool holds_ahead(const ContactSet& next, const PathPoint& point, const PathFollower& follower) const;
  std::optional<PathPoint> first_zero_in_lambda(const PathPoint& from, const PathPoint& to,
                                                const std::function<double(const PathPoint&)>& least,
                                                const PathFollower& follower) const;
  std::optional<PathPoint> first_zero(const PathPoint& from, const PathPoint& to,
                                      const std::function<double(const PathPoint&)>& least,
                                      const PathFollower& follower) const;
  // Per reaction unknown: r_i / (k w_ref) on the set, gap_i / (h w_ref) off it (>= 0: the sign holds).
  VectorXd sign_values(const ContactSet& set, const VectorXd& y) const;
  int negative_eigenvalues(const ContactSet& set, const VectorXd& y, double lambda) const;
  Eigenpair nearest_eigenpair(const VectorXd& y, double lambda) const;
  // The cone's verdict where nodes are weakly active along the path (second order; else nullopt).
  std::optional<ConeVerdict> cone_at(const PathPoint& point) const;
  certify::Certificate certificate(VectorXd y, double lambda) const;
  certify::Check backward_error(const ContactSet& set, const VectorXd& y, double lambda) const;
  double user_position(int reaction) const { return member_.user_from_s(d_.mesh.nodes[d_.reaction_nodes[reaction]]); }
  double axial_force(const PathPoint& p) const { return kin_->axial_force(p.x.head(n_), p.lambda); }
  VectorXd displacement(const VectorXd& y) const { return d_.expand_displacement(y.head(d_.equations)); }
  ContactTopology topology_of(const VectorXd& y) const {
    return contact_topology(member_, d_, displacement(y), points_);
  }
  // The contact topology at `from` (as found on the set before, if `from` began this set).
  ContactTopology topology_at_start(const PathPoint& from) const;
  // Cubic naming: the changes of the contact topology on the segment from `from` to `end` (on set_,
  // end = step(from, its arclength)), located by bisection, as crossings that do not switch.
  std::vector<Crossing> topology_events(const PathPoint& from, const PathPoint& end, const PathFollower& follower);
  // The unloaded state inside the step (a load reversal, a linear member with no ground gap and no
  // settlement): at it every node has zero reaction and zero gap, any set holds, and round-off of
  // the signs cannot choose the set beyond it; the crossing there switches to the set of a contact
  // solve beyond it (the path there is one ray: the loads and the state are proportional to the
  // distance from it).
  std::optional<Crossing> unloaded_crossing(const PathPoint& from, const PathPoint& to, const PathFollower& follower);
  // A member only the foundation holds: the crossing at the lift-off load, if the step reaches it.
  std::optional<Crossing> lift_off_crossing(const PathPoint& from, const PathPoint& to, const PathFollower& follower);
  // The path's sign values' rates along the tangent of `p` on `set` (sign_values is affine in y).
  VectorXd sign_rates(const ContactSet& set, const PathPoint& p) const {
    return sign_values(set, p.x + p.tangent_x) - sign_values(set, p.x);
  }
  // The reference deflection of a kinematics that has none: the start's state and its rate over the range.
  double reference_deflection(const ContactSet& set, const PathPoint& start) const;
  void set_units(double w_ref);
  TraceEvent fold_at_switch(const Crossing& crossing, const ContactSet& next, double new_tangent_lambda)
      const;  // The events of switching `flipped` in the node set `before`, from the set's pieces.
  std::vector<TraceEvent> set_events(const std::vector<bool>& before, const std::vector<int>& flipped,
                                     double lambda) const;
  // The contact event inside the step (nodes at zero at its start left out), located.
  std::optional<Crossing> contact_event(const PathPoint& from, const PathPoint& to, const VectorXd& start_values,
                                        const PathFollower& follower, std::string& failure) const;
  // The nodes of `failing` switched at the step's end without locating where (the pieces of the
  // node set keep their number and order: a limit moves on by a node or a few), the state solved
  // there on the new set; nullopt where that state is not the path's (see crossing()).
  std::optional<Crossing> taken_at_end(const PathPoint& from, const PathPoint& to, std::vector<int> failing,
                                       const PathFollower& follower);
  struct Across {
    PathPoint point;
    std::vector<bool> in_contact;
  };
  // at_lambda: the state at that lambda (the range's end, landed on exactly), not on the hyperplane.
  // with_tangent false: the state alone (its tangent a stand-in, a factorisation less).
  // count >= 0: every set tried must have that many negative eigenvalues at its state there (a
  // set on the way whose stability changed before the step's end: nullopt).
  std::optional<Across> solved_across(const PathPoint& from, double sigma, std::vector<int> failing,
                                      const PathFollower& follower, std::optional<double> at_lambda = std::nullopt,
                                      bool with_tangent = true, int count = -1) const;
  // The furthest state of the step solved across that `holds` (bisection on the arclength, 12
  // halvings); nullopt: none past the step's start's own set.
  std::optional<Across> furthest_across(const PathPoint& from, double ds, const PathFollower& follower,
                                        const std::function<bool(const Across&)>& holds, int count) const;

  std::unique_ptr<MemberKinematics> kin_;
  const model::MemberModel& member_;
  const TraceOptions& options_;
  const fe::Discretisation& d_;
  VonKarmanStateSeam seam_;
  const bool certified_;
  const SpecialPoints points_;
  const bool cubics_;  // events named from the element cubics' topology (else from the node set)
  int n_ = 0;
  double w_ref_ = 1e-3, reaction_unit_ = 1.0, gap_unit_ = 1.0;
  std::optional<double> lift_off_;  // the load beyond which nothing balances the loads
  // Topologies found at the ends of segments (from the set before), by the lambda of the point.
  std::vector<std::pair<double, ContactTopology>> known_topologies_;
  bool on_straight_branch_ = false;
  int straight_branch_count_ = 1;  // switched onto a straight bifurcated branch (until a set change)
  mutable int factorisations_ = 0;
  int contact_solves_ = 0;  // the kinematics' contact solves (the start)
  contact::Method contact_method_ = contact::Method::automatic;
  ContactSet set_;
  int immediate_switches_ = 0;  // switches back at a step's start, in a row
  // The sets solved_across visits within one step's search, with their followers (a bisection
  // visits the same few sets again and again: their equations and solvers are set up once).
  mutable std::map<std::vector<bool>, std::pair<ContactSet, std::shared_ptr<const PathFollower>>> across_followers_;
  // The certificate of the point certify() saw last: record() follows it on the same point (the
  // engine's keep), and the step's supports are that certificate's.
  mutable std::optional<certify::Certificate> last_certificate_;
  // The switched branch: its critical mode (x part) and origin.
  VectorXd branch_mode_, branch_origin_;
};

FeMemberPath::FeMemberPath(std::unique_ptr<MemberKinematics> kinematics, const TraceOptions& options,
                           VonKarmanStateSeam seam)
    : kin_(std::move(kinematics)),
      member_(kin_->member()),
      options_(options),
      d_(kin_->discretisation()),
      seam_(std::move(seam)),
      certified_(kin_->certified()),
      points_(special_points(member_)),
      cubics_(kin_->naming() == EventNaming::cubics),
      n_(kin_->unknowns()) {
  set_units(kin_->reference_deflection() > 0.0 ? kin_->reference_deflection() : 1e-3);
}

void FeMemberPath::set_units(double w_ref) {
  w_ref_ = w_ref;
  double h = std::numeric_limits<double>::infinity();
  for (int e = 0; e < d_.mesh.elements(); ++e) h = std::min(h, d_.mesh.element_size(e));
  reaction_unit_ = std::max(d_.k, 1e-300) * w_ref_;
  gap_unit_ = h * w_ref_;
}

PathProblem FeMemberPath::problem_on(const ContactSet& on) const {
  // The follower keeps its own copy of the set: the model's changes when it enters another.
  const auto set = std::make_shared<const ContactSet>(on);
  const int m = set->size();
  PathProblem p;
  p.unknowns = n_ + m;
  p.residual = [this, set](const VectorXd& y, double lambda, VectorXd& g) { return residual(*set, y, lambda, g); };
  p.sparse_jacobian = [this, set](const VectorXd& y, double lambda, SparseMatrix& g_y) {
    if (!y.allFinite()) return false;
    g_y = saddle(*set, y, lambda);
    ++factorisations_;
    return true;
  };
  p.lambda_derivative = [this, m](const VectorXd& y, double lambda, VectorXd& g_lambda) {
    g_lambda = VectorXd::Zero(n_ + m);
    g_lambda.head(n_) = kin_->lambda_derivative(y.head(n_), lambda);
    return true;
  };
  p.unknown_scale = unknown_scale(*set);
  p.jacobian_constant = kin_->linear_in_state();  // (the linear member's saddle matrix on a set)
  // The corrector's test relative to each equation's size: |G_i| against sum_j |dG_i/dy_j| y_ref_j
  // at the unloaded state (the membrane terms of EA and the h^-3 of bending included), so that its
  // tolerance means the same on every mesh.
  p.residual_scale = residual_scale(*set);
  return p;
}

bool FeMemberPath::residual(const ContactSet& set, const VectorXd& y, double lambda, VectorXd& g) const {
  if (!y.allFinite()) return false;
  const int m = set.size(), neq = d_.equations;
  g.resize(n_ + m);
  VectorXd f;
  if (!kin_->force(y.head(n_), lambda, f)) return false;
  g.head(n_) = f;
  if (m > 0) {
    g.head(neq) += set.coupling.transpose() * y.tail(m);
    g.tail(m) = set.coupling * y.head(neq) - set.ground_gap - set.flexibility * y.tail(m);
  }
  return g.allFinite();
}

SparseMatrix FeMemberPath::saddle(const ContactSet& set, const VectorXd& y, double lambda, bool primal) const {
  const int m = set.size();
  const SparseMatrix kt = primal ? kin_->stiffness(y.head(n_), lambda) : kin_->tangent(y.head(n_), lambda);
  const int n = static_cast<int>(kt.rows());  // the primal form's unknowns: the displacement alone
  Triplets t;
  t.reserve(kt.nonZeros() + 2 * set.coupling.nonZeros() + set.flexibility.nonZeros());
  for (int k = 0; k < kt.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(kt, k); it; ++it) t.emplace_back(it.row(), it.col(), it.value());
  for (int k = 0; k < set.coupling.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(set.coupling, k); it; ++it) {
      t.emplace_back(n + it.row(), it.col(), it.value());
      t.emplace_back(it.col(), n + it.row(), it.value());
    }
  for (int k = 0; k < set.flexibility.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(set.flexibility, k); it; ++it)
      t.emplace_back(n + it.row(), n + it.col(), -it.value());
  SparseMatrix a(n + m, n + m);
  a.setFromTriplets(t.begin(), t.end());
  return a;
}

VectorXd FeMemberPath::residual_scale(const ContactSet& set) const {
  const int m = set.size();
  VectorXd typical(n_ + m);
  typical.head(n_) = kin_->typical(w_ref_);
  if (m > 0) typical.tail(m).setConstant(reaction_unit_);
  const SparseMatrix j0 = saddle(set, VectorXd::Zero(n_ + m), options_.arc_length.lambda_min);
  const VectorXd size = SparseMatrix(j0.cwiseAbs()) * typical;
  return size.cwiseMax(std::numeric_limits<double>::min()).cwiseInverse();
}

// The metric's weights: the root mean square of the change of the member's unknowns over w_ref
// (the kinematics' metric), times the load range (a change of the shape by w_ref weighs as a change
// of lambda over the whole range: neither dominates the step's length, which stays in units of
// lambda), the reactions 1e-3 less. (Divided by sqrt(n): a plain sum over the nodes would make a
// step's length grow like the square root of the number of elements for the same change of shape,
// and the steps shrink with the mesh.)
VectorXd FeMemberPath::unknown_scale(const ContactSet& set) const {
  const double range = std::abs(options_.arc_length.lambda_max - options_.arc_length.lambda_min);
  const double rms = range / std::sqrt(static_cast<double>(n_));
  VectorXd scale(n_ + set.size());
  scale.head(n_) = range * kin_->metric(w_ref_);
  scale.tail(set.size()).setConstant(rms * 1e-3 / reaction_unit_);
  return scale;
}

// Newton corrections of the bordered system (G = 0 and the hyperplane through the point normal to
// its tangent in the path's metric; fixed_lambda: at its lambda) while its backward error is above
// the certificate's tolerance and they reduce it, at most 6. The backward error is the
// certificate's own (each row against the terms summed into it, the membrane force's included), so
// a polished state that stops short of it has stagnated at its round-off, and the certificate's
// message says so; where the states are not certified (a live load), |G| against |J| |y| and the
// loads. Not at fixed lambda on an arc-length path: near a limit point G_y is nearly singular and
// such a correction would move the state along its null vector; the bordered matrix is regular
// there. With `mode` (at fixed lambda on a bifurcation point, where G_y is singular along the
// critical mode phi), the border is phi instead, [G_y phi; phi^T 0] (dy, mu) = (-G, 0): regular
// there (phi spans G_y's null space, so it is not in its range), lambda fixed.
PathPoint FeMemberPath::polished(const ContactSet& set, const PathPoint& point, bool fixed_lambda,
                                 const VectorXd* mode) const {
  // Linear in the unknowns at fixed lambda (second order): one Newton correction at the point's
  // lambda is exact; a fixed set's branch is a graph over lambda (no fold), so it is regular there.
  // (Not on the straight bifurcated branch itself, at the singular lambda.)
  if (kin_->straight_bifurcated_branch() && !mode) return on_straight_branch_ ? point : corrected_at_lambda(set, point);
  PathPoint best = point;
  VectorXd g;
  if (!residual(set, best.x, best.lambda, g)) return point;
  VectorXd weight;
  const bool by_certificate = certified_ && kin_->measured_by_certificate();
  if (!by_certificate) {
    VectorXd terms = SparseMatrix(saddle(set, best.x, best.lambda).cwiseAbs()) * best.x.cwiseAbs();
    terms.head(n_) += kin_->load(best.lambda).cwiseAbs();
    terms.tail(set.size()) += set.ground_gap.cwiseAbs();
    weight = terms.cwiseMax(std::numeric_limits<double>::min()).cwiseInverse();
  }
  // Certified: the backward error relative to its tolerance (<= 1 passes); else the weighted |G|.
  const auto measure = [&](const PathPoint& p, const VectorXd& g_p) {
    if (!by_certificate) return g_p.cwiseProduct(weight).lpNorm<Eigen::Infinity>();
    const certify::Check backward = backward_error(set, p.x, p.lambda);
    return backward.value / backward.tolerance;
  };
  double norm = measure(best, g);
  // Linear in the unknowns at fixed lambda (the mixed form): the corrector's Newton step is exact
  // up to the solve's round-off, which on a stiff arch's fine mesh (EA h^2 / EI ~ 1e3 at 400
  // elements) left the balance 10 times above the certificate's tolerance: corrected only then.
  if (kin_->linear_in_state() && !mode && norm <= linear_accuracy) return point;
  VectorXd normal = VectorXd::Zero(best.x.size());
  if (point.tangent_x.size() == best.x.size() && !fixed_lambda)
    normal = point.tangent_x.cwiseProduct(unknown_scale(set).array().square().matrix());
  VectorXd g_lambda = VectorXd::Zero(best.x.size());
  g_lambda.head(n_) = kin_->lambda_derivative(best.x.head(n_), best.lambda);
  if (mode) {
    if (mode->size() != best.x.size()) return best;
    fixed_lambda = true;
    g_lambda = normal = *mode;
  }
  const int size = static_cast<int>(best.x.size());
  if (!(norm > 0.0)) return best;
  // [J G_lambda; normal^T t_lambda] (dy, dl) = (-G, 0) as one sparse system: eliminating dy
  // through J loses, at a limit point, what the bordering gains (measured: the arch's limit
  // point stalled at 3e-13, against the certificate's 1.1e-13). Factorised once, at the
  // corrector's point: the corrections are at its accuracy, where J changes by less than they
  // need (chord steps then converge as fast as Newton's, at the cost of one factorisation).
  const SparseMatrix j = saddle(set, best.x, best.lambda);
  Triplets t;
  t.reserve(j.nonZeros() + 2 * size + 1);
  for (int k = 0; k < j.outerSize(); ++k)
    for (SparseMatrix::InnerIterator e(j, k); e; ++e) t.emplace_back(e.row(), e.col(), e.value());
  for (int i = 0; i < size; ++i) {
    if (g_lambda[i] != 0.0) t.emplace_back(i, size, g_lambda[i]);
    if (normal[i] != 0.0) t.emplace_back(size, i, normal[i]);
  }
  t.emplace_back(size, size, mode ? 0.0 : fixed_lambda ? 1.0 : point.tangent_lambda);
  SparseMatrix bordered(size + 1, size + 1);
  bordered.setFromTriplets(t.begin(), t.end());
  Eigen::SparseLU<SparseMatrix> lu(bordered);
  if (lu.info() != Eigen::Success) return best;
  for (int it = 0; it < 6 && norm > 0.0; ++it) {
    VectorXd rhs = VectorXd::Zero(size + 1);
    rhs.head(size) = -g;
    const VectorXd step = lu.solve(rhs);
    if (lu.info() != Eigen::Success || !step.allFinite()) break;
    PathPoint next = best;
    next.x = best.x + step.head(size);
    if (!mode) next.lambda = best.lambda + step[size];
    VectorXd g_next;
    if (!residual(set, next.x, next.lambda, g_next)) break;
    const double norm_next = measure(next, g_next);
    if (!(norm_next < norm)) break;
    best = std::move(next), g = std::move(g_next), norm = norm_next;
  }
  return best;
}

PathPoint FeMemberPath::corrected_at_lambda(const ContactSet& set, const PathPoint& point) const {
  VectorXd g;
  if (!residual(set, point.x, point.lambda, g)) return point;
  Eigen::SparseLU<SparseMatrix> lu(saddle(set, point.x, point.lambda));
  ++factorisations_;
  if (lu.info() != Eigen::Success) return point;
  PathPoint next = point;
  const VectorXd step = lu.solve(g);
  if (lu.info() != Eigen::Success || !step.allFinite()) return point;
  next.x -= step;
  VectorXd g_next;
  if (!residual(set, next.x, next.lambda, g_next)) return point;
  const VectorXd& weight = residual_scale(set);
  return g_next.cwiseProduct(weight).lpNorm<Eigen::Infinity>() < g.cwiseProduct(weight).lpNorm<Eigen::Infinity>()
             ? next
             : point;
}

VectorXd FeMemberPath::reactions(const ContactSet& set, const VectorXd& y) const {
  VectorXd r = VectorXd::Zero(d_.reactions());
  for (int a = 0; a < set.size(); ++a) r[set.members[a]] = y[n_ + a];
  return r;
}

VectorXd FeMemberPath::sign_values(const ContactSet& set, const VectorXd& y) const {
  const VectorXd r = reactions(set, y), g = d_.gap_of(r, y.head(d_.equations));
  VectorXd v(d_.reactions());
  for (int i = 0; i < d_.reactions(); ++i) v[i] = set.in_contact[i] ? r[i] / reaction_unit_ : g[i] / gap_unit_;
  return v;
}

int FeMemberPath::negative_eigenvalues(const ContactSet& set, const VectorXd& y, double lambda) const {
  Eigen::SimplicialLDLT<SparseMatrix> ldlt(saddle(set, y, lambda, true));
  ++factorisations_;
  if (ldlt.info() != Eigen::Success || !ldlt.vectorD().allFinite()) return -1;
  int negative = 0;
  for (Eigen::Index i = 0; i < ldlt.vectorD().size(); ++i) negative += ldlt.vectorD()[i] < 0.0;
  return negative - set.size();
}

// The eigenvalue of S nearest zero and its eigenvector, with its reactions' response (the full
// tangent direction (phi, T_AA^-1 C_A phi)), by inverse iteration with the saddle factor: a solve
// with (v, 0) gives (S^-1 v, T_AA^-1 C_A S^-1 v). The eigenvalue is the Rayleigh quotient of the
// last iterate u = S^-1 v, u.S u / u.u = u.v / u.u, signed (NaN if the factor fails); its
// round-off is about eps |A|_inf, A the saddle matrix (a backward-stable solve is exact for a
// matrix that close to A; the secant of refine_return saw 0.02 to 0.1 of it, at 16 to 64 elements).
Eigenpair FeMemberPath::nearest_eigenpair(const VectorXd& y, double lambda) const {
  const SparseMatrix a = saddle(set_, y, lambda);
  Eigen::SparseLU<SparseMatrix> lu(a);
  Eigenpair pair;
  VectorXd& full = pair.vector;
  full = VectorXd::Zero(a.rows());
  if (lu.info() != Eigen::Success) return pair;
  pair.round_off =
      std::numeric_limits<double>::epsilon() * (SparseMatrix(a.cwiseAbs()) * VectorXd::Ones(a.cols())).maxCoeff();
  VectorXd v(n_);  // deterministic, not orthogonal to a mode
  for (int i = 0; i < n_; ++i) v[i] = std::sin(1.0 + 0.7 * i);
  v.normalize();
  for (int it = 0; it < 60; ++it) {
    VectorXd rhs = VectorXd::Zero(a.rows());
    rhs.head(n_) = v;
    full = lu.solve(rhs);
    pair.value = full.head(n_).dot(v) / full.head(n_).squaredNorm();
    const VectorXd next = full.head(n_).normalized();
    const double change = std::min((next - v).norm(), (next + v).norm());
    v = next;
    if (change < 1e-13) break;
  }
  full /= full.head(n_).norm();
  Eigen::Index largest = 0;
  full.head(n_).cwiseAbs().maxCoeff(&largest);
  if (full[largest] < 0) full = -full;
  return pair;
}

// The certificate of a path point (the kinematics' own, from its fields alone) at the path's own
// accuracy:
//  - backward error: the certificate's own tolerance, for y polished to round-off.
//  - signs: the path accepts a node's value r_i / (k w_ref) or gap_i / (h w_ref) down to
//    -max(tie_tolerance, event_tolerance) (below, an event is located or a node switches at
//    once); the certificate's are r_i / max r and gap_i / (h max |w|) or larger: the floor is
//    that bound in its units, max(k w_ref / max r, w_ref / max |w|) times it, at most 1e-4 (the
//    certificate takes floors below 1e-3 / 8; a larger one is a state within 1e-4 w_ref of the
//    unloaded one, whose nodes' signs the certificate then checks more finely than the path).
certify::Certificate FeMemberPath::certificate(VectorXd y, double lambda) const {
  if (seam_) seam_(lambda, y);
  const VectorXd reaction = reactions(set_, y), all = displacement(y);
  double w_largest = 0.0;
  for (int node = 0; node <= d_.mesh.elements(); ++node)
    w_largest = std::max(w_largest, std::abs(all[d_.deflection_dof(node)]));
  const double r_largest = reaction.size() > 0 ? reaction.cwiseAbs().maxCoeff() : 0.0;
  const double tiny = std::numeric_limits<double>::min();
  const double w_ratio = std::max(1.0, w_ref_ / std::max(w_largest, tiny));
  const double floor = std::min(1e-4, std::max(tie_tolerance, options_.event_tolerance) *
                                          std::max(w_ratio, r_largest > 0.0 ? reaction_unit_ / r_largest : 0.0));
  return kin_->certificate(y.head(n_), reaction, lambda, floor);
}

certify::Check FeMemberPath::backward_error(const ContactSet& set, const VectorXd& y, double lambda) const {
  const certify::Certificate c = kin_->certificate(y.head(n_), reactions(set, y), lambda, 0.0);
  if (const certify::Check* check = c.find(certify::check_name::backward_error)) return *check;
  certify::Check none;  // no answer to certify (not finite): infinitely far
  none.value = std::numeric_limits<double>::infinity(), none.tolerance = 1.0;
  return none;
}

std::optional<std::string> FeMemberPath::certify(const PathPoint& point) const {
  if (!certified_) return std::nullopt;
  last_certificate_ = certificate(point.x, point.lambda);
  const certify::Certificate& c = *last_certificate_;
  if (c.passed) return std::nullopt;
  const certify::Check* backward = c.find(certify::check_name::backward_error);
  return c.message +
         (backward && !backward->passed ? " (the Newton corrections of the state stagnated above its tolerance)" : "");
}

// The step records the set that carries the path on from the point (after a crossing there: the
// set after it), then the step length the follower takes from it, the sense of lambda there and
// the metric's reference deflection, so that a resumed trace takes the same steps.
TraceStep FeMemberPath::record(const PathPoint& point, const RecordContext& context) const {
  std::vector<bool> carries_on = set_.in_contact;
  if (context.crossing && context.crossing->switches &&
      context.crossing->transition.type() == typeid(std::vector<bool>))
    carries_on = std::any_cast<std::vector<bool>>(context.crossing->transition);
  TraceStep step = fe_states::step_of(member_, d_, points_, options_, point.lambda, displacement(point.x),
                                      reactions(set_, point.x), carries_on);
  const std::size_t m = carries_on.size();
  step.state[m] = context.next_step;
  step.state[m + 1] = point.tangent_lambda < 0.0 ? -1.0 : 1.0;
  step.state[m + 2] = w_ref_;
  step.axial_force = axial_force(point);
  step.iterations = point.iterations;
  // The whole state, with the certificate the engine certified it with just before (certify()).
  kin_->record_state(step, point.x.head(n_), reactions(set_, point.x), point.lambda,
                     certified_ && last_certificate_ ? &*last_certificate_ : nullptr);
  return step;
}

double FeMemberPath::amplitude(const PathPoint& point) const {
  return lift_measures(member_, d_, displacement(point.x), points_).amplitude;
}

std::string FeMemberPath::describe_state(const PathPoint& point) const {
  const model::Scales& scales = member_.scales;
  const VectorXd all = displacement(point.x);
  const double s = std::clamp(member_.s_from_user(options_.monitor), member_.s_begin, member_.s_end);
  const int e = d_.mesh.element_containing(s);
  const double w =
      post::evaluate(d_, all, e, (s - d_.mesh.nodes[e]) / d_.mesh.element_size(e)).w * scales.displacement();
  if (!cubics_) return fmt::format("crown deflection {:.6g}, thrust {:.6g}", w, axial_force(point));
  return fmt::format("deflection {:.6g} at {:.6g}, axial force {:.6g}, amplitude {:.6g}", w, options_.monitor,
                     axial_force(point), amplitude(point));
}

// A kinematics with no reference deflection of its own measures steps in the largest deflection
// the path has reached (the start's and its rate over the range, at first): a linear member's
// deflection can grow by orders after the first lift-off (the pipeline's uplift: 3e3 times from
// lambda = 0.2 to 3), and a metric fixed at the start made the steps shrink in proportion.
bool FeMemberPath::wants_new_problem(PathPoint& point) {
  if (kin_->reference_deflection() > 0.0) return false;
  const VectorXd all = displacement(point.x);
  double w = 0.0;
  for (int node = 0; node <= d_.mesh.elements(); ++node) w = std::max(w, std::abs(all[d_.deflection_dof(node)]));
  if (!(w > 2.0 * w_ref_)) return false;
  set_units(w);
  // The point's unit tangent in the new metric (its sense kept): measured in the old one, the next
  // step's tangent would look turned back.
  const VectorXd scale = unknown_scale(set_);
  const double norm =
      std::sqrt((scale.array() * point.tangent_x.array()).square().sum() + point.tangent_lambda * point.tangent_lambda);
  if (norm > 0.0) {
    point.tangent_x /= norm;
    point.tangent_lambda /= norm;
  }
  return true;
}

double FeMemberPath::reference_deflection(const ContactSet& set, const PathPoint& start) const {
  // The start's deflection and its rate over the load range (one solve with the saddle factor).
  const VectorXd all = displacement(start.x);
  double w = 0.0;
  for (int node = 0; node <= d_.mesh.elements(); ++node) w = std::max(w, std::abs(all[d_.deflection_dof(node)]));
  Eigen::SparseLU<SparseMatrix> lu(saddle(set, start.x, start.lambda));
  if (lu.info() == Eigen::Success) {
    VectorXd rhs = VectorXd::Zero(start.x.size());
    rhs.head(n_) = -kin_->lambda_derivative(start.x.head(n_), start.lambda);
    const VectorXd rate = displacement(lu.solve(rhs));
    const double span = std::abs(options_.arc_length.lambda_max - options_.arc_length.lambda_min);
    if (rate.allFinite())
      for (int node = 0; node <= d_.mesh.elements(); ++node)
        w = std::max(w, span * std::abs(rate[d_.deflection_dof(node)]));
  }
  return w > 0.0 ? w : 1e-3;
}

PathModel::Start FeMemberPath::start(const ArcLengthOptions& options) {
  Start out;
  const double lambda0 = options_.resume_from ? options_.resume_from->load_factor : options.lambda_min;
  const int m = d_.reactions();
  std::vector<bool> first_set;
  VectorXd x0 = VectorXd::Zero(n_), r0 = VectorXd::Zero(m);
  if (options_.resume_from) {
    const TraceStep& from = *options_.resume_from;
    if (!kin_->resumable()) {
      out.why =
          "TraceOptions.resume_from: refused: the FE von Karman path does not resume yet (run the trace again from "
          "the start)";
      return out;
    }
    if (!std::holds_alternative<FeContactSet>(from.state_topology) ||
        from.state.size() != static_cast<std::size_t>(m) + fe_state_tail) {
      out.why = "TraceOptions.resume_from: the step holds no FE contact set of this mesh";
      return out;
    }
    first_set = fe_contact_set(from);
    out.record = false;
    out.first_step = from.state[m];
    set_units(from.state[m + 2]);
  } else {
    // The contact solve at lambda_min.
    const KinematicsStart first = kin_->solve(lambda0, options_.contact_method);
    contact_solves_ += first.contact_solves;
    if (first.contact_solves > 0) contact_method_ = first.method;
    if (first.x.size() == 0) {
      out.failure = first.no_equilibrium ? TraceTermination::no_equilibrium : TraceTermination::solver_failure;
      out.why =
          first.no_equilibrium ? fmt::format("no equilibrium at lambda = {:.10g}: {}", lambda0, first.why) : first.why;
      return out;
    }
    first_set = first.in_contact;
    x0 = first.x, r0 = first.reaction;
    if (d_.tensionless && first.x.lpNorm<Eigen::Infinity>() == 0.0) {
      // The unloaded state: every node is at zero reaction and zero gap, so any set holds there; the
      // one the path leaves on is that of the first loads (near zero the response is linear in
      // lambda, so the set of a small step is the set of every small step).
      const KinematicsStart near = kin_->solve(lambda0 + options.direction * options.min_step, options_.contact_method);
      contact_solves_ += near.contact_solves;
      if (near.x.size() > 0) first_set = near.in_contact;
    }
  }
  set_ = contact::select_contact_set(d_, first_set);
  VectorXd y(n_ + set_.size());
  y.head(n_) = x0;
  for (int a = 0; a < set_.size(); ++a) y[n_ + a] = first_set[set_.members[a]] ? r0[set_.members[a]] : 0.0;
  std::optional<PathPoint> orientation;
  if (options_.resume_from) {  // the sense of lambda the step had
    orientation = PathPoint{};
    orientation->x = y;
    orientation->tangent_x = VectorXd::Zero(y.size());
    orientation->tangent_lambda = options_.resume_from->state[m + 1];
  }
  for (int pass = 0; pass < 2; ++pass) {
    const PathFollower follower(problem(), options);
    nonlinear::NewtonSummary summary;
    std::optional<PathPoint> point = follower.start(y, lambda0, &summary, orientation);
    if (!point) {
      out.why = fmt::format("the start at lambda = {:.10g} did not converge on its contact set: {}", lambda0,
                            summary.message);
      return out;
    }
    out.point = polished(set_, *point, true);
    // A kinematics with no reference deflection of its own takes the start's: the metric and the
    // sign units are set, and the start solved again in them.
    if (pass > 0 || kin_->reference_deflection() > 0.0 || options_.resume_from) break;
    set_units(reference_deflection(set_, *out.point));
    y = out.point->x;
  }
  lift_off_ = kin_->lift_off_load(lambda0, options.lambda_max, options_.event_tolerance);
  return out;
}

std::vector<TraceEvent> FeMemberPath::set_events(const std::vector<bool>& before, const std::vector<int>& flipped,
                                                 double lambda) const {
  std::vector<TraceEvent> events;
  if (cubics_) return events;  // named from the cubics' topology instead (topology_events)
  // A supported end's node has w = 0: its sign is that of w' there (times h^2), no piece of its
  // own; the pieces are counted on the nodes inside, the end's limit at its neighbour.
  const int first = points_.begin_supported ? 1 : 0;
  const int last = d_.reactions() - 1 - (points_.end_supported ? 1 : 0);
  for (int i : flipped) {
    if (i < first || i > last) continue;
    const bool leaving = before[i];
    const double at = user_position(i);
    const bool left_same = i > first && before[i - 1] == before[i];
    const bool right_same = i < last && before[i + 1] == before[i];
    EventKind kind;
    std::string what;
    if (i == first || i == last) {
      const bool supported = i == first ? points_.begin_supported : points_.end_supported;
      kind = supported ? EventKind::limit_at_support : EventKind::limit_at_end;
      if (i == first ? right_same : left_same)  // the neighbour stays as the node was
        what = leaving ? "a lift-off zone opens at the end" : "a contact region opens at the end";
      else
        what = leaving ? "the contact region at the end vanishes" : "a lift-off zone closes at the end";
    } else if (left_same && right_same) {
      kind = leaving ? EventKind::lift_off_opens : EventKind::contact_opens;
      what =
          leaving ? "a lift-off zone opens inside a contact region" : "a contact region opens inside a lift-off zone";
    } else if (!left_same && !right_same) {
      kind = leaving ? EventKind::region_vanishes : EventKind::lift_off_vanishes;
      what = leaving ? "a contact region vanishes" : "a lift-off zone vanishes";
    } else {
      continue;  // a limit moves on by a node
    }
    events.push_back({lambda, kind, at, fmt::format("{} (node at {:.6g}, lambda = {:.10g})", what, at, lambda)});
  }
  return events;
}

// A path point of one set carried to another: the same x, the reactions of the nodes in both.
PathPoint carry(const PathPoint& p, const ContactSet& from, const ContactSet& to, int n) {
  PathPoint q = p;
  const auto map = [&](const VectorXd& v) {
    VectorXd out = VectorXd::Zero(n + to.size());
    out.head(n) = v.head(n);
    for (int b = 0; b < to.size(); ++b) {
      const auto it = std::find(from.members.begin(), from.members.end(), to.members[b]);
      if (it != from.members.end()) out[n + b] = v[n + (it - from.members.begin())];
    }
    return out;
  };
  q.x = map(p.x);
  q.tangent_x = map(p.tangent_x);
  return q;
}

// The pieces of a node set (runs of equal status over the nodes that have one: a supported end's
// node has none, see set_events): whether `after` has the pieces of `before`, each overlapping its
// own, so that only limits moved between them (no event).
bool same_pieces(const std::vector<bool>& before, const std::vector<bool>& after, int first, int last) {
  struct Run {
    bool in_contact;
    int begin, end;
  };
  const auto runs = [&](const std::vector<bool>& set) {
    std::vector<Run> out;
    for (int i = first; i <= last; ++i)
      if (out.empty() || out.back().in_contact != set[i])
        out.push_back({set[i], i, i});
      else
        out.back().end = i;
    return out;
  };
  const std::vector<Run> a = runs(before), b = runs(after);
  if (a.size() != b.size()) return false;
  for (std::size_t j = 0; j < a.size(); ++j)
    if (a[j].in_contact != b[j].in_contact || a[j].end < b[j].begin || b[j].end < a[j].begin) return false;
  return true;
}

// The first crossing of `least` below zero (positive at `from`, negative at `to`) on the step: on
// a set a node's value is linear in lambda for a linear kinematics, but rational (second order) or
// nonlinear otherwise, and on a long step it may cross zero and come back, or touch zero and turn
// back up: the secant's zero is then not the first crossing. Samples at a quarter, half and three
// quarters of the way to the zero found look for an earlier one (on the perfect pipeline's
// descending branch a step of 0.2 in lambda passed three node switches 1e-3 apart); one a little
// beyond it tells a touch (the value is positive again: the node's gap closed to zero and opens
// again, as the old exact path found there) from a crossing, and the search goes on past a touch.
std::optional<PathPoint> FeMemberPath::first_zero(const PathPoint& from, const PathPoint& to,
                                                  const std::function<double(const PathPoint&)>& least,
                                                  const PathFollower& follower) const {
  PathPoint start = from, end = to;
  std::optional<PathPoint> located;
  for (int round = 0; round < 8; ++round) {
    located = follower.locate(start, end, least, options_.event_tolerance, false);
    if (!located || kin_->linear_in_state()) return located;
    const double sigma = located->arclength - start.arclength;
    std::optional<PathPoint> earlier;
    for (int k = 1; k <= 3 && !earlier; ++k) {
      StepOutcome sample = follower.step(start, 0.25 * k * sigma, false);
      if (sample.point && least(*sample.point) < -options_.event_tolerance) earlier = std::move(sample.point);
    }
    if (earlier) {
      end = std::move(*earlier);
      continue;
    }
    StepOutcome beyond = follower.step(start, sigma + 0.02 * (end.arclength - located->arclength));
    if (!beyond.point || !(least(*beyond.point) > tie_tolerance)) return located;
    start = std::move(*beyond.point);
  }
  return located;
}

// The same for a second-order kinematics, in lambda: a set's branch is a graph over lambda (no fold
// on a fixed set) and its state at lambda is exact after one fixed-lambda correction (one
// factorisation), where a point of the arc-length corrector costs its iterations and a polish on
// top. Illinois on lambda between the step's ends, the earlier zero and the touch as first_zero;
// the located state is then the path's point at its lambda (its arclength and tangent).
std::optional<PathPoint> FeMemberPath::first_zero_in_lambda(const PathPoint& from, const PathPoint& to,
                                                            const std::function<double(const PathPoint&)>& least,
                                                            const PathFollower& follower) const {
  const auto state_at = [&](double lambda) {
    PathPoint guess = from;
    const double t = (lambda - from.lambda) / (to.lambda - from.lambda);
    guess.x = from.x + t * (to.x - from.x);
    guess.lambda = lambda;
    return corrected_at_lambda(set_, guess);
  };
  if (!(to.lambda != from.lambda)) return first_zero(from, to, least, follower);
  double la = from.lambda, lb = to.lambda, fa = least(from), fb = least(to);
  for (int round = 0; round < 8; ++round) {
    if (!(fa > 0.0) || !(fb < 0.0)) return std::nullopt;
    PathPoint best = to;
    int stale_side = 0;
    const double start = la;
    for (int iteration = 0; iteration < 200 && std::abs(lb - la) > options_.event_tolerance; ++iteration) {
      double lc = lb - fb * (lb - la) / (fb - fa);
      if (!(lc > std::min(la, lb) && lc < std::max(la, lb))) lc = 0.5 * (la + lb);
      best = state_at(lc);
      const double fc = least(best);
      if (fc == 0.0) break;
      if (fc < 0.0) {
        lb = lc, fb = fc;
        if (stale_side == -1) fa *= 0.5;  // (Illinois: a kept twice)
        stale_side = -1;
      } else {
        la = lc, fa = fc;
        if (stale_side == 1) fb *= 0.5;
        stale_side = 1;
      }
    }
    if (std::abs(lb - la) <= options_.event_tolerance && fb < 0.0 && best.lambda != lb) best = state_at(lb);
    // An earlier zero (samples between the start and the zero found), or a touch (positive again
    // a little beyond it): searched again.
    std::optional<std::pair<double, double>> earlier;
    for (int k = 1; k <= 3 && !earlier; ++k) {
      const double lambda = start + 0.25 * k * (best.lambda - start);
      const double value = least(state_at(lambda));
      if (value < -options_.event_tolerance) earlier = {lambda, value};
    }
    if (earlier) {
      la = start, fa = least(state_at(start)), lb = earlier->first, fb = earlier->second;
      continue;
    }
    const double past = best.lambda + 0.02 * (to.lambda - best.lambda);
    const double beyond = least(state_at(past));
    if (beyond > tie_tolerance) {
      la = past, fa = beyond, lb = to.lambda, fb = least(to);
      continue;
    }
    StepOutcome at = follower.step_to_lambda(from, best.lambda, &best.x);
    return at.point;
  }
  return std::nullopt;
}

std::optional<Crossing> FeMemberPath::contact_event(const PathPoint& from, const PathPoint& to,
                                                    const VectorXd& start_values, const PathFollower& follower,
                                                    std::string& failure) const {
  // The least sign value of the nodes not at zero at the step's start; polished: of the point
  // taken to round-off first (a factorisation per evaluation).
  const auto least_of = [&](bool polish) {
    return [&, polish](const PathPoint& p) {
      const VectorXd v = sign_values(set_, polish ? polished(set_, p, false).x : p.x);
      double smallest = 1.0;
      for (int i = 0; i < d_.reactions(); ++i)
        if (start_values[i] > tie_tolerance) smallest = std::min(smallest, v[i]);
      return smallest;
    };
  };
  // (`to` is refined already: its values as they are.)
  if (!(least_of(false)(to) < -options_.event_tolerance)) return std::nullopt;
  // Which node crosses first needs the corrector's points only; where it names an event, the
  // crossing is located again on polished points (near a limit point the corrector's 1e-11 leaves
  // the state off by ~1e-7 of w_ref, which moved an event by 5e-7 in lambda), else (a limit moving
  // on by a node: no event) where it lies needs no more than a state that holds.
  // The nodes at the located zero of the least value: not those failing at the step's end, which
  // on a beam-column's long step may be others (a node's value is rational in lambda, and one went
  // below zero and back within a step of the perfect pipeline's descending branch).
  const auto crossing_at = [&](const PathPoint& located, std::vector<int>& flipped) {
    const VectorXd at = sign_values(set_, located.x);
    double smallest = std::numeric_limits<double>::infinity();
    for (int i = 0; i < d_.reactions(); ++i)
      if (start_values[i] > tie_tolerance) smallest = std::min(smallest, at[i]);
    flipped.clear();
    for (int i = 0; i < d_.reactions(); ++i)
      if (start_values[i] > tie_tolerance && at[i] <= smallest + tie_tolerance) flipped.push_back(i);
  };
  // (A kinematics linear in its unknowns at fixed lambda polishes a state exactly, with one
  // factorisation: its crossings are located on polished points from the start. Near the
  // beam-column's limit point the set's tangent is nearly singular and the corrector's points
  // leave a node's value off by 1e-6 of its scale.)
  // Second order off a straight branch: located in lambda on exact states (below).
  const bool in_lambda = kin_->straight_bifurcated_branch() && !on_straight_branch_;
  const bool exact = kin_->linear_in_state() || in_lambda;
  std::optional<PathPoint> located = in_lambda ? first_zero_in_lambda(from, to, least_of(false), follower)
                                               : first_zero(from, to, least_of(exact), follower);
  std::vector<int> flipped;
  if (located) {
    *located = polished(set_, *located, false);
    crossing_at(*located, flipped);
    // Polishing moves the point along the step's hyperplane (on a bifurcated branch by 7e-7 in
    // lambda): where the node is then past zero (penetrating by 1e-7 of a gap), the certificate
    // on the set would fail: located again on polished points too (located on exact states
    // already: nothing to gain).
    const bool past = sign_values(set_, located->x).minCoeff() < -tie_tolerance;
    if (!exact && !flipped.empty() && (past || !set_events(set_.in_contact, flipped, located->lambda).empty())) {
      located = follower.locate(from, to, least_of(true), options_.event_tolerance, false);
      if (located) {
        *located = polished(set_, *located, false);
        crossing_at(*located, flipped);
      }
    }
  }
  if (!located) {
    failure = fmt::format("a contact event between lambda = {:.10g} and {:.10g} could not be located", from.lambda,
                          to.lambda);
    return std::nullopt;
  }
  if (flipped.empty()) {
    failure = fmt::format("a contact event located at lambda = {:.10g} names no node", located->lambda);
    return std::nullopt;
  }
  std::vector<bool> in_contact = set_.in_contact;
  for (int i : flipped) in_contact[i] = !in_contact[i];
  Crossing c;
  c.point = *located;
  c.events = set_events(set_.in_contact, flipped, located->lambda);
  c.transition = std::move(in_contact);
  return c;
}

// The path's state at arclength sigma from `from` across node switches: the state solved on the
// new set on the same hyperplane, its sign values checked, the nodes still failing switched too, at
// most 8 rounds (node naming: the pieces kept throughout). It is the path's state there (an
// equilibrium of the tensionless problem: every reaction on its set and gap off it holds) if
// nothing the engine watches happened on the way (checked by the caller). nullopt: none found.
std::optional<FeMemberPath::Across> FeMemberPath::solved_across(const PathPoint& from, double sigma,
                                                                std::vector<int> failing, const PathFollower& follower,
                                                                std::optional<double> at_lambda, bool with_tangent,
                                                                int count) const {
  const int first = points_.begin_supported ? 1 : 0;
  const int last = d_.reactions() - 1 - (points_.end_supported ? 1 : 0);
  std::vector<bool> in_contact = set_.in_contact;
  for (int round = 0; round < 8 && !failing.empty(); ++round) {
    for (int i : failing) in_contact[i] = !in_contact[i];
    if (!cubics_ && !same_pieces(set_.in_contact, in_contact, first, last)) return std::nullopt;
    auto& cached = across_followers_[in_contact];
    if (!cached.second)
      cached = {contact::select_contact_set(d_, in_contact),
                std::make_shared<const PathFollower>(problem_on(contact::select_contact_set(d_, in_contact)),
                                                     follower.options())};
    const ContactSet& next = cached.first;
    const PathFollower& on_next = *cached.second;
    const PathPoint start = carry(from, set_, next, n_);
    StepOutcome step = at_lambda ? on_next.step_to_lambda(start, *at_lambda) : on_next.step(start, sigma, with_tangent);
    if (!step.point) return std::nullopt;
    PathPoint p = polished(next, *step.point, at_lambda.has_value());
    if (count >= 0 && negative_eigenvalues(next, p.x, p.lambda) != count) return std::nullopt;
    const VectorXd values = sign_values(next, p.x);
    failing.clear();
    for (int i = 0; i < d_.reactions(); ++i)
      if (values[i] < -tie_tolerance) failing.push_back(i);
    if (failing.empty()) return Across{std::move(p), std::move(in_contact)};
  }
  return std::nullopt;
}

// Where the step's end is not the path's (past a limit point at a set change, where no set holds
// on: the upheaval buckle's rising branch ends at a node pair lifting, and each step of it located
// one node pair's switch, a step per pair, more as the mesh is refined; or a piece of the node set
// opening or vanishing, an event), the path goes on across the switches as far as a state holds:
// bisection on the arclength, deciding on whether a state solved across holds (12 halvings leave
// the boundary within 1/4096 of the step ahead, located from there as any crossing).
std::optional<FeMemberPath::Across> FeMemberPath::furthest_across(const PathPoint& from, double ds,
                                                                  const PathFollower& follower,
                                                                  const std::function<bool(const Across&)>& holds,
                                                                  int count) const {
  double lo = 0.0, hi = ds;
  std::optional<Across> furthest;
  for (int i = 0; i < 12; ++i) {
    const double mid = 0.5 * (lo + hi);
    std::optional<PathPoint> plain = follower.step(from, mid).point;
    if (!plain) break;
    const VectorXd values = sign_values(set_, plain->x);
    std::vector<int> failing;
    for (int k = 0; k < d_.reactions(); ++k)
      if (values[k] < -tie_tolerance) failing.push_back(k);
    std::optional<Across> at_mid = failing.empty()
                                       ? std::optional<Across>(Across{std::move(*plain), set_.in_contact})
                                       : solved_across(from, mid, failing, follower, std::nullopt, true, count);
    if (at_mid && holds(*at_mid))
      lo = mid, furthest = std::move(at_mid);
    else
      hi = mid;
  }
  // (On the start's own set: nothing to take across, the crossing is located from the start.)
  if (!furthest || furthest->in_contact == set_.in_contact) return std::nullopt;
  return furthest;
}

// Taken at the step's end (solved_across) where nothing the engine watches happened on the way, as
// far as its ends tell: lambda's tangent keeps its sign (no fold) and the count of negative
// eigenvalues is the step start's (no change of stability); with cubic naming, a change of the
// contact topology on the way is located by bisection on the arclength of such states and the
// step taken to the first state past it, its events with it. Where the step's end does not hold,
// the furthest state that does (furthest_across). Otherwise nullopt: the crossing is located
// (contact_event).
std::optional<Crossing> FeMemberPath::taken_at_end(const PathPoint& from, const PathPoint& to, std::vector<int> failing,
                                                   const PathFollower& follower) {
  // A straight bifurcated branch ends at its first switch, located: the new set's branch runs in
  // lambda, on the side where it holds (enter).
  if (on_straight_branch_) return std::nullopt;
  across_followers_.clear();
  const bool counted = stability_measure() == StabilityMeasure::count;
  const int negative = counted ? negative_eigenvalues(set_, from.x, from.lambda) : 0;
  const double ds = to.arclength - from.arclength;
  // At the range's end (landed on exactly) the new set's state at that lambda, else on the step's
  // hyperplane.
  const ArcLengthOptions& o = follower.options();
  const bool range_end = to.lambda == o.lambda_max || to.lambda == o.lambda_min || o.control == PathControl::load;
  // Whether a state solved across is the path's, as far as the step's ends tell (node naming: the
  // pieces kept, an event being located, not stepped over).
  const int first = points_.begin_supported ? 1 : 0;
  const int last = d_.reactions() - 1 - (points_.end_supported ? 1 : 0);
  const auto holds = [&](const Across& a) {
    const PathPoint& p = a.point;
    const bool fold = o.control == PathControl::arc_length && (from.tangent_lambda > 0) != (p.tangent_lambda > 0);
    // (The amplitude bound and the loads asked for are located by the engine on one set: a state
    // past one is not taken here.)
    if (fold || (options_.max_amplitude && amplitude(p) >= *options_.max_amplitude)) return false;
    for (double target : options_.report_at)
      if ((from.lambda - target) * (p.lambda - target) <= 0.0 && from.lambda != target) return false;
    if (!cubics_ && !same_pieces(set_.in_contact, a.in_contact, first, last)) return false;
    return !counted || negative_eigenvalues(contact::select_contact_set(d_, a.in_contact), p.x, p.lambda) == negative;
  };
  // Every set tried on the way must keep the start's count of negative eigenvalues at its state
  // across (beyond the part of the path where it holds, so past a change of its stability there),
  // not only the set at the end. A change and its reversal on one set within one step are seen by
  // neither, here as on a step on one set: the steps' length is the resolution (the perfect
  // pipeline's descending branch has pairs 0.4 apart in lambda).
  if (negative < 0) return std::nullopt;
  const int count = counted ? negative : -1;
  std::optional<Across> end = solved_across(from, ds, failing, follower,
                                            range_end ? std::optional<double>(to.lambda) : std::nullopt, true, count);
  if (!end || !holds(*end)) end = furthest_across(from, ds, follower, holds, count);
  if (!end) return std::nullopt;
  const PathPoint& p = end->point;
  Crossing c;
  c.point_after = true;
  const ContactTopology start = topology_at_start(from);
  ContactTopology at_end = cubics_ ? topology_of(p.x) : ContactTopology{};
  if (cubics_ && !at_end.same_as(start)) {
    // The first change of topology: bisection on sigma to event_tolerance in lambda, on the
    // step's hyperplanes. (A step landed on the range's end by a fixed-lambda solve is not on its
    // hyperplane: its state across is taken on the hyperplane instead, else the footing's column
    // event at 10 elements was reported at lambda_max, 0.1 past where it lies.)
    if (range_end) {
      end = solved_across(from, ds, failing, follower, std::nullopt, true, count);
      if (!end || !holds(*end)) return std::nullopt;
      at_end = topology_of(end->point.x);
      if (at_end.same_as(start)) return std::nullopt;
    }
    double lo = 0.0, hi = ds;
    double lambda_lo = from.lambda;
    ContactTopology before = start;
    for (int i = 0; i < 200 && std::abs(end->point.lambda - lambda_lo) > options_.event_tolerance; ++i) {
      const double mid = 0.5 * (lo + hi);
      if (!(mid > lo && mid < hi)) break;
      std::vector<int> failing_mid;
      // (States only, their tangents stand-ins: the one taken is given its own below.)
      std::optional<PathPoint> plain = follower.step(from, mid, false).point;
      if (!plain) return std::nullopt;
      const VectorXd values = sign_values(set_, plain->x);
      for (int k = 0; k < d_.reactions(); ++k)
        if (values[k] < -tie_tolerance) failing_mid.push_back(k);
      std::optional<Across> at_mid = failing_mid.empty()
                                         ? std::optional<Across>(Across{*plain, set_.in_contact})
                                         : solved_across(from, mid, failing_mid, follower, std::nullopt, false, count);
      if (!at_mid) return std::nullopt;
      ContactTopology topology = topology_of(at_mid->point.x);
      if (topology.same_as(start)) {
        lo = mid, lambda_lo = at_mid->point.lambda, before = std::move(topology);
      } else {
        hi = mid, end = std::move(at_mid), at_end = std::move(topology);
      }
    }
    c.events = classify_events(member_, points_, before, at_end, end->point.lambda);
    // The tangent of the state taken, on its set, in the sense of the step.
    const ContactSet taken = contact::select_contact_set(d_, end->in_contact);
    const PathFollower on_taken(problem_on(taken), follower.options());
    const PathPoint sense = carry(from, set_, taken, n_);
    const auto tangent = on_taken.tangent(end->point.x, end->point.lambda, &sense);
    if (!tangent) return std::nullopt;
    end->point.tangent_x = tangent->first;
    end->point.tangent_lambda = tangent->second;
  }
  if (cubics_) known_topologies_ = {{end->point.lambda, at_end}};
  c.point = std::move(end->point);
  c.transition = std::move(end->in_contact);
  return c;
}

// The crossing at the lift-off load of a member only the foundation holds (kinematics'
// lift_off_load): where the step reaches it, the path's state there (a crossing the model enters
// to end the path: no equilibrium beyond). Node crossings located well before it come first; near
// it the last reactions vanish together, which round-off would split into node switches that
// leave the member floating.
std::optional<Crossing> FeMemberPath::lift_off_crossing(const PathPoint& from, const PathPoint& to,
                                                        const PathFollower& follower) {
  if (!lift_off_) return std::nullopt;
  const double load = *lift_off_;
  if (!((to.lambda - load) * (from.lambda - load) <= 0.0) || from.lambda == load) return std::nullopt;
  std::optional<PathPoint> at = follower.locate(
      from, to, [load](const PathPoint& p) { return p.lambda - load; }, options_.event_tolerance);
  if (!at) return std::nullopt;
  if (at->lambda != load)
    if (StepOutcome landed = follower.step_to_lambda(*at, load); landed.point) at = std::move(landed.point);
  Crossing c;
  c.point = polished(set_, *at, true);
  c.transition = LiftOff{};
  return c;
}

CrossingSearch FeMemberPath::crossing(const PathPoint& from, const PathPoint& to, const PathFollower& follower,
                                      bool may_take) {
  CrossingSearch search;
  if (!d_.tensionless || d_.reactions() == 0) return search;
  VectorXd start_values = sign_values(set_, from.x);
  const VectorXd end_values = sign_values(set_, to.x);
  // Nodes at zero at the step's start (just switched, or grazing: a pinned end's node, whose value
  // is w' there times h^2) failing at once switch back at the start itself, an event there; twice
  // in a row at one point means no set holds there. Second order, a node's value is rational in
  // lambda: failing at the step's end is not failing at once (the perfect pipeline's node switched
  // into contact at its descending branch's breakpoint holds on for 6e-3 in lambda, its reaction
  // negative 0.2 further on); such a node is failing at once where it fails a short way ahead (as
  // in holds_ahead), else its crossing is looked for as the others'.
  std::optional<PathPoint> ahead;  // (the search for crossings then starts there)
  if (!kin_->linear_in_state()) {
    VectorXd ahead_values;
    for (int i = 0; i < d_.reactions(); ++i) {
      if (start_values[i] > tie_tolerance || !(end_values[i] < -tie_tolerance)) continue;
      if (ahead_values.size() == 0) {
        const double span = std::abs(options_.arc_length.lambda_max - options_.arc_length.lambda_min);
        StepOutcome probe = follower.step(from, std::max(1e-6 * span, 100.0 * options_.event_tolerance), false);
        if (!probe.point) break;
        ahead = std::move(probe.point);
        ahead_values = sign_values(set_, ahead->x);
      }
      if (ahead_values[i] > tie_tolerance) start_values[i] = ahead_values[i];
    }
  }
  std::vector<bool> in_contact = set_.in_contact;
  std::vector<int> flipped;
  for (int i = 0; i < d_.reactions(); ++i)
    if (!(start_values[i] > tie_tolerance) && end_values[i] < -tie_tolerance)
      in_contact[i] = !in_contact[i], flipped.push_back(i);
  if (!flipped.empty()) {
    if (immediate_switches_ >= 2) {
      search.fail = fmt::format(
          "no contact set holds at lambda = {:.10g}: the node at {:.6g} fails its sign at once on every set tried",
          from.lambda, user_position(flipped[0]));
      return search;
    }
    ++immediate_switches_;
    Crossing c;
    c.point = from;
    c.at_start = true;
    c.events = set_events(set_.in_contact, flipped, from.lambda);
    c.transition = std::move(in_contact);
    search.crossings.push_back(std::move(c));
    return search;
  }
  immediate_switches_ = 0;
  if (std::optional<Crossing> c = unloaded_crossing(from, to, follower)) {
    search.crossings.push_back(std::move(*c));
    return search;
  }
  std::optional<Crossing> lift_off = lift_off_crossing(from, to, follower);
  const PathPoint& until = lift_off ? lift_off->point : to;
  if (may_take && !lift_off) {
    std::vector<int> failing;
    for (int i = 0; i < d_.reactions(); ++i)
      if (start_values[i] > tie_tolerance && end_values[i] < -options_.event_tolerance) failing.push_back(i);
    if (!failing.empty())
      if (std::optional<Crossing> c = taken_at_end(from, to, std::move(failing), follower)) {
        search.crossings.push_back(std::move(*c));
        return search;
      }
  }
  std::string failure;
  std::optional<Crossing> node = contact_event(ahead && start_values.minCoeff() > tie_tolerance ? *ahead : from, until,
                                               start_values, follower, failure);
  if (!node && !failure.empty()) {
    search.fail = std::move(failure);
    return search;
  }
  if (lift_off && node &&
      std::abs(node->point.lambda - lift_off->point.lambda) <=
          1e-6 * std::abs(options_.arc_length.lambda_max - options_.arc_length.lambda_min))
    node.reset();  // the last reactions vanishing together at the lift-off load
  std::optional<Crossing> switching = node ? std::move(node) : std::move(lift_off);
  if (cubics_) search.crossings = topology_events(from, switching ? switching->point : until, follower);
  if (switching) search.crossings.push_back(std::move(*switching));
  return search;
}

std::optional<Crossing> FeMemberPath::unloaded_crossing(const PathPoint& from, const PathPoint& to,
                                                        const PathFollower& follower) {
  if (!kin_->linear_in_state() || d_.has_ground_gap() || d_.prescribed.lpNorm<Eigen::Infinity>() > 0.0)
    return std::nullopt;
  // F(lambda) = F_dead + lambda F_live vanishes at lambda0 only if F_dead is -lambda0 F_live.
  const VectorXd dead = d_.load(0.0), live = d_.load(1.0) - dead;
  if (!(live.squaredNorm() > 0.0)) return std::nullopt;
  const double lambda0 = -dead.dot(live) / live.squaredNorm();
  const double size = std::max(dead.lpNorm<Eigen::Infinity>(), std::abs(lambda0) * live.lpNorm<Eigen::Infinity>());
  if ((dead + lambda0 * live).lpNorm<Eigen::Infinity>() > 64 * std::numeric_limits<double>::epsilon() * size)
    return std::nullopt;
  // Strictly past the step's start (a path that starts there took its set from a solve beyond it).
  if (!((from.lambda - lambda0) * (to.lambda - lambda0) < 0.0 || to.lambda == lambda0)) return std::nullopt;
  const KinematicsStart beyond = kin_->solve(0.5 * (lambda0 + to.lambda), options_.contact_method);
  contact_solves_ += beyond.contact_solves;
  if (beyond.x.size() == 0) return std::nullopt;
  StepOutcome at = follower.step_to_lambda(from, lambda0);
  if (!at.point) return std::nullopt;
  Crossing c;
  c.point = *at.point;
  c.point.x.setZero();  // (the unloaded state exactly: every value of it is zero)
  if (cubics_) c.events = classify_events(member_, points_, topology_at_start(from), topology_of(beyond.x), lambda0);
  c.transition = beyond.in_contact;
  return c;
}

ContactTopology FeMemberPath::topology_at_start(const PathPoint& from) const {
  for (const auto& [lambda, topology] : known_topologies_)
    if (lambda == from.lambda) return topology;
  // Unloaded, the member touches nothing, but along the first step its deflection is that of the
  // tangent: its topology is the tangent's.
  if (displacement(from.x).lpNorm<Eigen::Infinity>() == 0.0 && from.tangent_x.size() == from.x.size())
    return contact_topology(
        member_, d_, displacement(from.tangent_lambda < 0.0 ? VectorXd(-from.tangent_x) : from.tangent_x), points_);
  return topology_of(from.x);
}

// Why events are located on w and not at node switches: contact in the reports (and in the Ritz
// model, which the events are compared with) is w > 0 of the element cubic, while a switch is a
// nodal reaction or gap reaching zero: a lift-off zone opens inside an element, a little after
// the nearest node's reaction reached zero. Located by bisection on the arclength of the segment
// (on one set) to event_tolerance in lambda, each change classified between the last topology
// found equal to the one before and the first found different, never recomputed at the segment's
// start: there it comes from the set before, and an event that falls on a switch shows in one
// set's round-off and not in the other's (a heel lifting off a free end: w(0) and the end node's
// reaction vanish together, to O(h^5); the footing trace lost it on 152 of the meshes from 50 to
// 400 elements when it was recomputed).
std::vector<Crossing> FeMemberPath::topology_events(const PathPoint& from, const PathPoint& end,
                                                    const PathFollower& follower) {
  std::vector<Crossing> out;
  ContactTopology topology_a = topology_at_start(from);
  const ContactTopology topology_b = topology_of(end.x);
  const double length = end.arclength - from.arclength;
  const auto point_at = [&](double sigma) -> std::optional<PathPoint> {
    if (sigma >= length) return end;
    StepOutcome outcome = follower.step(from, sigma);
    if (!outcome.point) return std::nullopt;
    return polished(set_, *outcome.point, false);
  };
  double a = 0.0;
  ContactTopology last = topology_a;
  for (int guard = 0; guard < 64 && !topology_a.same_as(topology_b); ++guard) {
    double lo = a, hi = length;
    PathPoint lo_point = from, hi_point = end;
    ContactTopology before = topology_a;
    for (int i = 0; i < 200 && std::abs(hi_point.lambda - lo_point.lambda) > options_.event_tolerance; ++i) {
      const double mid = 0.5 * (lo + hi);
      if (!(mid > lo && mid < hi)) break;
      std::optional<PathPoint> p = point_at(mid);
      if (!p) break;
      ContactTopology at_mid = topology_of(p->x);
      if (at_mid.same_as(topology_a)) {
        lo = mid, lo_point = std::move(*p), before = std::move(at_mid);
      } else {
        hi = mid, hi_point = std::move(*p);
      }
    }
    const ContactTopology after = topology_of(hi_point.x);
    std::vector<TraceEvent> events = classify_events(member_, points_, before, after, hi_point.lambda);
    if (!events.empty() && hi < length) {
      Crossing c;
      c.point = hi_point;
      c.events = std::move(events);
      c.switches = false;
      out.push_back(std::move(c));
    } else if (!events.empty()) {  // at the segment's end: recorded with it
      Crossing c;
      c.point = end;
      c.events = std::move(events);
      c.switches = false;
      out.push_back(std::move(c));
    }
    a = hi;
    topology_a = after;
    last = after;
  }
  known_topologies_ = {{end.lambda, topology_a.same_as(topology_b) ? last : topology_b}};
  return out;
}

// The fold where the path turns back at a change of set: a limit point at the crossing.
TraceEvent FeMemberPath::fold_at_switch(const Crossing& crossing, const ContactSet& next,
                                        double new_tangent_lambda) const {
  int node = 0;
  for (int i = 0; i < d_.reactions(); ++i)
    if (next.in_contact[i] != set_.in_contact[i]) {
      node = i;
      break;
    }
  const double at = user_position(node);
  return {crossing.point.lambda, EventKind::limit_point, at,
          fmt::format("limit point: lambda reaches a {} {:.10g} ({}) as the node at {:.6g} {}; the path turns back",
                      new_tangent_lambda < 0.0 ? "maximum" : "minimum", crossing.point.lambda,
                      describe_state(crossing.point), at, set_.in_contact[node] ? "lifts off" : "touches down")};
}

PathModel::Entry FeMemberPath::enter(const Crossing& crossing, const ArcLengthOptions& options) {
  Entry entry;
  if (crossing.transition.type() == typeid(LiftOff)) {
    entry.failure = TraceTermination::no_equilibrium;
    entry.why = fmt::format(
        "no equilibrium beyond lambda = {:.10g}: the live loads lift the member off the foundation (compressive "
        "reactions can no longer balance the loads on its free rigid motions, {}), and no support holds it",
        crossing.point.lambda, d_.stability_note);
    return entry;
  }
  ContactSet next = contact::select_contact_set(d_, std::any_cast<std::vector<bool>>(crossing.transition));
  const bool from_straight = on_straight_branch_;  // (no fold: lambda was constant on it)
  on_straight_branch_ = false;  // (a straight branch ends at its first switch: the new set's runs in lambda)
  if (crossing.point_after) {   // solved there already
    set_ = std::move(next);
    entry.point = crossing.point;
    return entry;
  }
  const PathPoint carried = carry(crossing.point, set_, next, n_);
  // Continue from the crossing on the new set, on the side where it holds: the switched nodes'
  // values (a leaving node's gap, a joining node's reaction) grow along the tangent; else as before.
  const PathFollower follower(problem_on(next), options);
  nonlinear::NewtonSummary summary;
  entry.point = follower.start(carried.x, carried.lambda, &summary, carried);
  // At a fixed lambda the set's equations are singular at a fold: a crossing located next to the
  // shallow arch's limit point stalled there (residual 1e-10 for 1e-11); bordered by the crossing's
  // tangent (its own hyperplane, sigma = 0) they are not.
  if (!entry.point && carried.tangent_x.size() == carried.x.size())
    if (StepOutcome bordered = follower.step(carried, 0.0); bordered.point) entry.point = std::move(bordered.point);
  if (!entry.point) {
    entry.why =
        fmt::format("no equilibrium on the new contact set at lambda = {:.10g}: {}", carried.lambda, summary.message);
    set_ = std::move(next);
    return entry;
  }
  // (Cubic naming, the small-displacement members, whose folds are all at set changes; a von
  // Karman member's branch is oriented as before, its folds smooth and located by the engine.)
  if (cubics_ && !holds_ahead(next, *entry.point, follower)) {
    entry.point->tangent_x = -entry.point->tangent_x;
    entry.point->tangent_lambda = -entry.point->tangent_lambda;
  }
  // A straight branch goes on across a switch where the new set is singular at its lambda too.
  if (from_straight && std::abs(entry.point->tangent_lambda) <= 1e-8) {
    on_straight_branch_ = true;
    entry.point->tangent_lambda = 0.0;
  }
  if (options.control == PathControl::arc_length && !from_straight && crossing.point.tangent_lambda != 0.0 &&
      (crossing.point.tangent_lambda > 0.0) != (entry.point->tangent_lambda > 0.0))
    entry.events.push_back(fold_at_switch(crossing, next, entry.point->tangent_lambda));
  set_ = std::move(next);
  return entry;
}

// Whether the path on `next` holds ahead of `point` along its tangent. Linear kinematics: the
// switched nodes' values grow along it (affine in lambda on a set, their rates decide). Second
// order: the rates are first-order only, and on the perfect pipeline's descending branch, where
// every set is near its critical load, they pointed back where the set held ahead (the old exact
// path's test, kept): the state a short arclength ahead, 1e-6 of the load range and then 100 and
// 10^4 times closer, has every node's value nonnegative.
bool FeMemberPath::holds_ahead(const ContactSet& next, const PathPoint& point, const PathFollower& follower) const {
  if (kin_->linear_in_state()) {
    const VectorXd rates = sign_rates(next, point);
    double growing = 0.0, falling = 0.0;
    for (int i = 0; i < d_.reactions(); ++i)
      if (next.in_contact[i] != set_.in_contact[i]) (rates[i] > 0.0 ? growing : falling) += std::abs(rates[i]);
    return growing >= falling;
  }
  const double span = std::abs(options_.arc_length.lambda_max - options_.arc_length.lambda_min);
  for (double offset = std::max(1e-6 * span, 100.0 * options_.event_tolerance);
       offset >= 10.0 * options_.event_tolerance; offset *= 1e-2) {
    const StepOutcome ahead = follower.step(point, offset, false);
    if (ahead.point && sign_values(next, ahead.point->x).minCoeff() >= -tie_tolerance) return true;
  }
  return false;
}

// Second-order theory (a tangent linear in lambda): the singular point's lambda from the Rayleigh
// quotient of the critical mode phi (inverse iteration with the mixed saddle factor) on the primal
// S(lambda) = [K_t C_A^T; C_A -T_AA]: lambda_c = lambda - phi.S phi / phi.S' phi, stationary in phi,
// so second-order accurate; the state there extrapolated along the tangent. The count's bisection
// alone is early or late by the inertia's round-off (the primal pivots' eps cond(S): 1.7e-8 in
// lambda on the free-free beam at 200 elements). Not at weakly active nodes (the cone decides there).
PathPoint FeMemberPath::refine_bifurcation(const PathPoint& point) const {
  if (!kin_->straight_bifurcated_branch() || cone_at(point) || !(std::abs(point.tangent_lambda) > 0.0)) return point;
  const double span = std::abs(options_.arc_length.lambda_max - options_.arc_length.lambda_min);
  PathPoint refined = point;
  // Iterated: the mode at the refined lambda, its quotient again (the mode of the mixed factor is
  // S's null vector only at the singular point: one quotient left 7e-9 in lambda).
  for (int iteration = 0; iteration < 4; ++iteration) {
    const VectorXd mode = nearest_eigenpair(refined.x, refined.lambda).vector;
    const VectorXd u = mode.head(d_.equations), r = mode.tail(set_.size());
    const auto quadratic = [&](double lambda) {
      const SparseMatrix k = kin_->stiffness(refined.x.head(n_), lambda);
      return u.dot(k * u) + 2.0 * r.dot(set_.coupling * u) - r.dot(set_.flexibility * r);
    };
    const double at = quadratic(refined.lambda), slope = quadratic(refined.lambda + span) - at;  // linear
    if (!(std::abs(slope) > 0.0)) return point;
    const double lambda = refined.lambda - span * at / slope;
    // Trusted near the located point only (else the iteration found another mode).
    if (!(std::abs(lambda - point.lambda) <= 1e-2 * std::max(std::abs(point.lambda), 1e-3 * span))) return point;
    const double change = lambda - refined.lambda;
    refined.x = point.x + (lambda - point.lambda) / point.tangent_lambda * point.tangent_x;
    refined.lambda = lambda;
    if (std::abs(change) <= 1e-3 * options_.event_tolerance) break;
  }
  return refined;
}

StabilityState FeMemberPath::stability(const PathPoint& point) const {
  // A straight bifurcated branch is neutral (its tangent singular all along): reported unstable,
  // its count kept from the switch, so that round-off in the singular pivot reads as no change.
  if (on_straight_branch_) return {straight_branch_count_, std::numeric_limits<double>::quiet_NaN()};
  int count = negative_eigenvalues(set_, point.x, point.lambda);
  if (const std::optional<ConeVerdict> cone = cone_at(point); cone && cone->known)
    count = cone->stable ? 0 : std::max(count, 1);
  return {count, std::numeric_limits<double>::quiet_NaN()};
}

// Cubic naming (the small-displacement members): a state recorded where the set changes reports the
// stability on the set after it, the one its record carries on with (the upheaval buckle's limit
// point: the new set is beyond its critical load there, the old one not).
StabilityState FeMemberPath::stability_at_crossing(const PathPoint& point, const Crossing& crossing) const {
  if (!cubics_ || on_straight_branch_ || !crossing.switches || crossing.transition.type() != typeid(std::vector<bool>))
    return stability(point);
  const ContactSet next = contact::select_contact_set(d_, std::any_cast<std::vector<bool>>(crossing.transition));
  const PathPoint carried = carry(point, set_, next, n_);
  return {negative_eigenvalues(next, carried.x, carried.lambda), std::numeric_limits<double>::quiet_NaN()};
}

// Weakly active along the path: at zero (reaction and gap) here and not moving off zero along the
// tangent (a node passing zero here, at a switch, is no weak node: the set's count holds beyond).
std::optional<ConeVerdict> FeMemberPath::cone_at(const PathPoint& point) const {
  if (!d_.tensionless || d_.reactions() == 0) return std::nullopt;
  const VectorXd r = reactions(set_, point.x), g = d_.gap_of(r, point.x.head(d_.equations));
  std::vector<stability::NodeContact> contact = stability::classify_contact(r, g);
  if (point.tangent_x.size() == point.x.size()) {
    const VectorXd rates = sign_rates(set_, point);
    for (int i = 0; i < d_.reactions(); ++i)
      if (contact[i] == stability::NodeContact::weakly_active && std::abs(rates[i]) > tie_tolerance)
        contact[i] = set_.in_contact[i] ? stability::NodeContact::in_contact : stability::NodeContact::lifted;
  }
  return kin_->cone(contact, point.lambda);
}

BranchSwitch FeMemberPath::switch_branch(const PathPoint& bifurcation, const PathFollower& path_follower) {
  BranchSwitch out;
  // Weakly active nodes: the cone's spring set is the set whose tangent turned singular (the
  // path's state is on it too: those nodes carry nothing); the branch leaves on it.
  PathPoint at = bifurcation;
  std::optional<PathFollower> on_springs;
  if (const std::optional<ConeVerdict> cone = cone_at(bifurcation);
      cone && cone->springs.size() == set_.in_contact.size()) {
    ContactSet springs = contact::select_contact_set(d_, cone->springs);
    at = carry(bifurcation, set_, springs, n_);
    set_ = std::move(springs);
    on_springs.emplace(problem(), path_follower.options());
  }
  const PathFollower& follower = on_springs ? *on_springs : path_follower;
  on_straight_branch_ = kin_->straight_bifurcated_branch();  // (its states are not corrected at lambda)
  // A pseudo-arc-length step along the null vector from the bifurcation point.
  VectorXd direction = nearest_eigenpair(at.x, at.lambda).vector;
  branch_origin_ = at.x.head(n_);
  const VectorXd& scale = follower.problem().unknown_scale;
  direction /= std::sqrt((direction.array() * scale.array()).square().sum());
  // A short first step (a tenth of initial_step: the path's steps grow from there by its own
  // control), and the first point holds the set's contact conditions (else a contact event would lie
  // between it and the bifurcation point, stepped over): the step is halved until it does, in the
  // sense making the mode's largest component positive, else in the other (the conditions admit
  // one sense only where the mode pushes a node at zero through it).
  std::optional<PathPoint> branch;
  for (double sense : {1.0, -1.0})
    for (double ds = 0.1 * options_.arc_length.initial_step; !branch && ds >= options_.arc_length.min_step; ds *= 0.5) {
      PathPoint b = at;
      b.tangent_x = sense * direction;
      b.tangent_lambda = 0.0;
      StepOutcome outcome = follower.step(b, ds);
      if (!outcome.point) continue;
      const VectorXd values = sign_values(set_, polished(set_, *outcome.point, false).x);
      if (d_.tensionless && (values.array() < -tie_tolerance).any()) continue;
      branch = std::move(outcome.point);
      branch_mode_ = sense * direction.head(n_);
      branch_mode_ /= branch_mode_.norm();
    }
  if (!branch) {
    on_straight_branch_ = false;
    out.why_not = fmt::format("no point found on the bifurcated branch at lambda = {:.10g}", at.lambda);
    return out;
  }
  BranchStart start;
  start.point = polished(set_, *branch, false);
  start.amplitude = [this](const PathPoint& p) { return branch_mode_.dot(p.x.head(n_) - branch_origin_); };
  start.return_accuracy = branch_accuracy;
  start.return_tolerance = options_.event_tolerance;
  start.description = "along the critical mode";
  if (on_straight_branch_) {
    straight_branch_count_ = std::max(1, negative_eigenvalues(set_, start.point.x, start.point.lambda));
    start.point.tangent_lambda = 0.0;
    start.description += ", straight at fixed lambda";
  }
  out.branch = std::move(start);
  return out;
}

// The crossing of the switched branch with the path it left, from `near`: a secant in lambda on the
// eigenvalue of S nearest zero, each point solved at fixed lambda from `near` less its mode
// component and polished there bordered by its critical mode (the solve's tolerance alone left
// 2.5e-7 in the crossing's lambda at 32 elements, kappa = 8, and broke the load's order 4 at 64
// elements), to event_tolerance in lambda, as the Ritz path does. That eigenvalue is zero at the
// crossing and linear in lambda beside it: on the symmetric path S commutes with the mirror, so its
// antisymmetric block's lowest eigenvalue is simple and smooth in lambda, and it vanishes where the
// thrust reaches the antisymmetric mode's critical value, a simple root since the thrust changes at
// a rate away from a limit point. Near the crossing it is the eigenvalue nearest zero (S is regular
// on the symmetric modes off a limit point). nullopt if a solve fails, lands off that path (its
// amplitude along the mode above 1e-3 of the branch's peak) or the secant does not converge in 30
// iterations: the engine keeps `near` and says so.
std::optional<PathPoint> FeMemberPath::refine_return(const PathPoint& near, double peak, const PathFollower& follower) {
  // Near the crossing the solves amplify round-off along the mode by 1 / that eigenvalue (seen:
  // 1e-6 of the branch's peak); a point 1e-3 of it off the path would be on the branch.
  const double off_path = 1e-3 * peak;
  PathPoint guess = near;
  guess.x.head(n_) -= branch_mode_.dot(near.x.head(n_) - branch_origin_) * branch_mode_;
  const auto solved = [&](double lambda) -> std::optional<PathPoint> {
    std::optional<PathPoint> p = follower.step_to_lambda(guess, lambda, &guess.x).point;
    if (!p) return p;
    const VectorXd mode = nearest_eigenpair(p->x, p->lambda).vector;
    p = polished(set_, *p, true, &mode);
    if (!(std::abs(branch_mode_.dot(p->x.head(n_) - branch_origin_)) <= off_path)) return std::nullopt;
    return p;
  };
  std::optional<PathPoint> a = solved(near.lambda);
  if (!a) return std::nullopt;
  double margin_a = nearest_eigenpair(a->x, a->lambda).value;
  std::optional<PathPoint> b = solved(near.lambda + 1e-6 * std::max(1.0, std::abs(near.lambda)));
  for (int iteration = 0; b && iteration < 30; ++iteration) {
    // Converged: the last secant step within event_tolerance, or the eigenvalue zero within its
    // round-off (at 64 elements ~5e-11 against a slope ~0.1: 1e-9 in lambda, above the tolerance).
    const Eigenpair margin = nearest_eigenpair(b->x, b->lambda);
    if (std::abs(b->lambda - a->lambda) <= options_.event_tolerance || std::abs(margin.value) <= margin.round_off)
      return polished(set_, *b, true, &margin.vector);
    if (!std::isfinite(margin.value) || margin.value == margin_a) break;
    const double lambda = b->lambda - margin.value * (b->lambda - a->lambda) / (margin.value - margin_a);
    a = std::move(b);
    margin_a = margin.value;
    b = solved(lambda);
  }
  return std::nullopt;
}

}  // namespace

TraceResult trace_fe_von_karman(const model::MemberModel& member, const TraceOptions& options, const TraceSink& sink,
                                const VonKarmanLiveLoad& live_load, const VonKarmanStateSeam& seam) {
  options.validate(member.user_from_s(member.s_begin), member.user_from_s(member.s_end));
  FeMemberPath model(make_kinematics(member, options.elements, live_load), options, seam);
  return follow_path(model, options, sink);
}

TraceResult trace_fe(const model::MemberModel& member, const TraceOptions& options, const TraceSink& sink) {
  options.validate(member.user_from_s(member.s_begin), member.user_from_s(member.s_end));
  FeMemberPath model(make_kinematics(member, options.elements), options, {});
  return follow_path(model, options, sink);
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
