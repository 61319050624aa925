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
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "certify/certificate.hpp"
#include "contact/von_karman_solve.hpp"
#include "continuation/engine.hpp"
#include "continuation/events.hpp"
#include "continuation/fe_states.hpp"
#include "continuation/step_state.hpp"
#include "post/fields.hpp"

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

// The eigenvalue of S nearest zero and its eigenvector (with its reactions' response).
struct Eigenpair {
  VectorXd vector;
  double value = std::numeric_limits<double>::quiet_NaN();
  double round_off = std::numeric_limits<double>::quiet_NaN();
};

class FeMemberPath final : public PathModel {
 public:
  FeMemberPath(const model::MemberModel& member, const TraceOptions& options, const VonKarmanLiveLoad& live_load,
               VonKarmanStateSeam seam);

  PathKind kind() const override { return PathKind::fe; }
  PathProblem problem() const override { return problem_on(set_); }
  Start start(const ArcLengthOptions& options) override;
  PathPoint refine(const PathPoint& point, bool fixed_lambda) const override {
    return polished(set_, point, fixed_lambda);
  }
  CrossingSearch crossing(const PathPoint& from, const PathPoint& to, const PathFollower& follower,
                          bool alone) override;
  Entry enter(const Crossing& crossing, const ArcLengthOptions& options) override;
  StabilityMeasure stability_measure() const override { return StabilityMeasure::count; }
  StabilityState stability(const PathPoint& point) const override {
    return {negative_eigenvalues(set_, point.x), std::numeric_limits<double>::quiet_NaN()};
  }
  BranchSwitch switch_branch(const PathPoint& at, const PathFollower& follower) override;
  std::optional<PathPoint> refine_return(const PathPoint& located, double peak, const PathFollower& follower) override;
  double event_position(const PathPoint&) const override { return options_.monitor; }
  std::string describe_state(const PathPoint& point) const override;
  double amplitude(const PathPoint& point) const override;
  std::optional<std::string> certify(const PathPoint& point) const override;
  TraceStep record(const PathPoint& point, const RecordContext& context) const override;
  std::string summary_note() const override { return fmt::format("{} elements", options_.elements); }

 private:
  // The bordered equations of a set.
  PathProblem problem_on(const ContactSet& set) const;
  bool residual(const ContactSet& set, const VectorXd& y, double lambda, VectorXd& g) const;
  SparseMatrix saddle(const ContactSet& set, const VectorXd& y) const;
  VectorXd unknown_scale(const ContactSet& set) const;
  VectorXd residual_scale(const ContactSet& set) const;
  // The point with Newton corrections of the bordered system (see refine; `mode`: at fixed lambda
  // on a bifurcation point, bordered by the critical mode).
  PathPoint polished(const ContactSet& set, const PathPoint& point, bool fixed_lambda,
                     const VectorXd* mode = nullptr) const;
  VectorXd reactions(const ContactSet& set, const VectorXd& y) const;
  // Per reaction unknown: r_i / (k w_ref) on the set, gap_i / (h w_ref) off it (>= 0: the sign holds).
  VectorXd sign_values(const ContactSet& set, const VectorXd& y) const;
  int negative_eigenvalues(const ContactSet& set, const VectorXd& y) const;
  Eigenpair nearest_eigenpair(const VectorXd& y) const;
  certify::Certificate certificate(VectorXd y, double lambda) const;
  certify::Check backward_error(const ContactSet& set, const VectorXd& y, double lambda) const;
  certify::VonKarmanAnswer answer_of(const ContactSet& set, const VectorXd& y) const;
  double user_position(int reaction) const { return member_.user_from_s(d_.mesh.nodes[d_.reaction_nodes[reaction]]); }
  double axial_force(const VectorXd& y) const;
  // The events of switching `flipped` in the node set `before`, from the set's pieces.
  std::vector<TraceEvent> set_events(const std::vector<bool>& before, const std::vector<int>& flipped,
                                     double lambda) const;
  // The contact event inside the step (nodes at zero at its start left out), located.
  std::optional<Crossing> contact_event(const PathPoint& from, const PathPoint& to, const VectorXd& start_values,
                                        const PathFollower& follower, std::string& failure) const;
  // The nodes of `failing` switched at the step's end without locating where (the pieces of the
  // node set keep their number and order: a limit moves on by a node or a few), the state solved
  // there on the new set; nullopt where that state is not the path's (see crossing()).
  std::optional<Crossing> taken_at_end(const PathPoint& from, const PathPoint& to, std::vector<int> failing,
                                       const PathFollower& follower) const;

  const model::MemberModel& member_;
  const TraceOptions& options_;
  const fe::Discretisation d_;
  const contact::VonKarmanSystem system_;
  VonKarmanStateSeam seam_;
  const bool certified_;
  const SpecialPoints points_;
  int n_ = 0;
  VectorXd dead_, live_;
  double w_ref_ = 1e-3, reaction_unit_ = 1.0, gap_unit_ = 1.0;
  ContactSet set_;
  int immediate_switches_ = 0;  // switches back at a step's start, in a row
  // The certificate of the point certify() saw last: record() follows it on the same point (the
  // engine's keep), and the step's supports are that certificate's.
  mutable std::optional<certify::Certificate> last_certificate_;
  // The switched branch: its critical mode (x part) and origin.
  VectorXd branch_mode_, branch_origin_;
};

FeMemberPath::FeMemberPath(const model::MemberModel& member, const TraceOptions& options,
                           const VonKarmanLiveLoad& live_load, VonKarmanStateSeam seam)
    : member_(member),
      options_(options),
      d_(fe::discretise(member, options.elements)),
      system_(member, d_),
      seam_(std::move(seam)),
      certified_(!live_load),
      points_(special_points(member)) {
  n_ = system_.unknowns();
  if (live_load) {
    live_ = live_load(d_, system_);
    dead_ = VectorXd::Zero(n_);
    if (live_.size() != n_)
      throw std::invalid_argument(
          fmt::format("trace_fe_von_karman: live_load has {} entries, expected {}", live_.size(), n_));
  } else {
    dead_ = system_.load(0.0);
    live_ = system_.load(1.0) - dead_;
  }
  w_ref_ = member.initial_sine ? std::max(std::abs(member.initial_sine->amplitude), 1e-6) : 1e-3;
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
  p.sparse_jacobian = [this, set](const VectorXd& y, double, SparseMatrix& g_y) {
    if (!y.allFinite()) return false;
    g_y = saddle(*set, y);
    return true;
  };
  p.lambda_derivative = [this, m](const VectorXd&, double, VectorXd& g_lambda) {
    g_lambda = VectorXd::Zero(n_ + m);
    g_lambda.head(n_) = -live_;
    return true;
  };
  p.unknown_scale = unknown_scale(*set);
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
  g.head(n_) = system_.internal_force(y.head(n_)) - dead_ - lambda * live_;
  if (m > 0) {
    g.head(neq) += set.coupling.transpose() * y.tail(m);
    g.tail(m) = set.coupling * y.head(neq) - set.ground_gap - set.flexibility * y.tail(m);
  }
  return g.allFinite();
}

SparseMatrix FeMemberPath::saddle(const ContactSet& set, const VectorXd& y) const {
  const int m = set.size();
  const SparseMatrix kt = system_.tangent_stiffness(y.head(n_));
  Triplets t;
  t.reserve(kt.nonZeros() + 2 * set.coupling.nonZeros() + set.flexibility.nonZeros());
  for (int k = 0; k < kt.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(kt, k); it; ++it) t.emplace_back(it.row(), it.col(), it.value());
  for (int k = 0; k < set.coupling.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(set.coupling, k); it; ++it) {
      t.emplace_back(n_ + it.row(), it.col(), it.value());
      t.emplace_back(it.col(), n_ + it.row(), it.value());
    }
  for (int k = 0; k < set.flexibility.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(set.flexibility, k); it; ++it)
      t.emplace_back(n_ + it.row(), n_ + it.col(), -it.value());
  SparseMatrix a(n_ + m, n_ + m);
  a.setFromTriplets(t.begin(), t.end());
  return a;
}

VectorXd FeMemberPath::residual_scale(const ContactSet& set) const {
  const int m = set.size();
  VectorXd typical = VectorXd::Constant(n_ + m, w_ref_);
  if (m > 0) typical.tail(m).setConstant(reaction_unit_);
  const SparseMatrix j0 = saddle(set, VectorXd::Zero(n_ + m));
  const VectorXd size = SparseMatrix(j0.cwiseAbs()) * typical;
  return size.cwiseMax(std::numeric_limits<double>::min()).cwiseInverse();
}

// The metric's weights: the root mean square of the change of the member's unknowns over w_ref,
// times the load range (a change of the shape by w_ref weighs as a change of lambda over the whole
// range: neither dominates the step's length, which stays in units of lambda), the reactions 1e-3
// less. (Divided by sqrt(n): a plain sum over the nodes would make a step's length grow like the
// square root of the number of elements for the same change of shape, and the steps shrink with
// the mesh.)
VectorXd FeMemberPath::unknown_scale(const ContactSet& set) const {
  const double range = std::abs(options_.arc_length.lambda_max - options_.arc_length.lambda_min);
  const double rms = range / std::sqrt(static_cast<double>(n_));
  VectorXd scale = VectorXd::Constant(n_ + set.size(), rms / w_ref_);
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
  PathPoint best = point;
  VectorXd g;
  if (!residual(set, best.x, best.lambda, g)) return point;
  VectorXd weight;
  if (!certified_) {
    VectorXd terms = SparseMatrix(saddle(set, best.x).cwiseAbs()) * best.x.cwiseAbs();
    terms.head(n_) += (dead_ + best.lambda * live_).cwiseAbs();
    terms.tail(set.size()) += set.ground_gap.cwiseAbs();
    weight = terms.cwiseMax(std::numeric_limits<double>::min()).cwiseInverse();
  }
  // Certified: the backward error relative to its tolerance (<= 1 passes); else the weighted |G|.
  const auto measure = [&](const PathPoint& p, const VectorXd& g_p) {
    if (!certified_) return g_p.cwiseProduct(weight).lpNorm<Eigen::Infinity>();
    const certify::Check backward = backward_error(set, p.x, p.lambda);
    return backward.value / backward.tolerance;
  };
  double norm = measure(best, g);
  VectorXd normal = VectorXd::Zero(best.x.size());
  if (point.tangent_x.size() == best.x.size() && !fixed_lambda)
    normal = point.tangent_x.cwiseProduct(unknown_scale(set).array().square().matrix());
  VectorXd g_lambda = VectorXd::Zero(best.x.size());
  g_lambda.head(n_) = -live_;
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
  const SparseMatrix j = saddle(set, best.x);
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

int FeMemberPath::negative_eigenvalues(const ContactSet& set, const VectorXd& y) const {
  Eigen::SimplicialLDLT<SparseMatrix> ldlt(saddle(set, y));
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
Eigenpair FeMemberPath::nearest_eigenpair(const VectorXd& y) const {
  const SparseMatrix a = saddle(set_, y);
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

certify::VonKarmanAnswer FeMemberPath::answer_of(const ContactSet& set, const VectorXd& y) const {
  certify::VonKarmanAnswer answer;
  answer.displacement = d_.expand_displacement(y.head(d_.equations));
  answer.reaction = reactions(set, y);
  const int nodes = d_.mesh.elements() + 1;
  answer.axial = VectorXd::Zero(nodes);
  for (int node = 0; node < nodes; ++node)  // an arch's u is a dof of the discretisation
    if (d_.kind == model::StructureKind::arch)
      answer.axial[node] = answer.displacement[d_.tangential_dof(node)];
    else if (const int k = system_.axial_unknown(node); k >= 0)
      answer.axial[node] = y[k];
  answer.normal_force = system_.normal_forces(y.head(n_));
  return answer;
}

certify::CertifyOptions certificate_options(double lambda) {
  certify::CertifyOptions o;
  o.load_factor = lambda;
  o.round_off = false;
  o.pointwise = false;
  return o;
}

// The certificate of a path point (certify/certificate.hpp, the von Karman answer from its fields
// alone) at the path's own accuracy:
//  - backward error: the certificate's own tolerance, for y polished to round-off.
//  - signs: the path accepts a node's value r_i / (k w_ref) or gap_i / (h w_ref) down to
//    -max(tie_tolerance, event_tolerance) (below, an event is located or a node switches at
//    once); the certificate's are r_i / max r and gap_i / (h max |w|) or larger: the floor is
//    that bound in its units, max(k w_ref / max r, w_ref / max |w|) times it, at most 1e-4 (the
//    certificate takes floors below 1e-3 / 8; a larger one is a state within 1e-4 w_ref of the
//    unloaded one, whose nodes' signs the certificate then checks more finely than the path).
certify::Certificate FeMemberPath::certificate(VectorXd y, double lambda) const {
  if (seam_) seam_(lambda, y);
  const certify::VonKarmanAnswer answer = answer_of(set_, y);
  const int nodes = d_.mesh.elements() + 1;
  double w_largest = 0.0;
  for (int node = 0; node < nodes; ++node)
    w_largest = std::max(w_largest, std::abs(answer.displacement[d_.deflection_dof(node)]));
  const double r_largest = answer.reaction.size() > 0 ? answer.reaction.cwiseAbs().maxCoeff() : 0.0;
  const double tiny = std::numeric_limits<double>::min();
  const double w_ratio = std::max(1.0, w_ref_ / std::max(w_largest, tiny));
  certify::CertifyOptions o = certificate_options(lambda);
  o.sign_floor = std::min(1e-4, std::max(tie_tolerance, options_.event_tolerance) *
                                    std::max(w_ratio, r_largest > 0.0 ? reaction_unit_ / r_largest : 0.0));
  return certify::certify(member_, d_, answer, o);
}

certify::Check FeMemberPath::backward_error(const ContactSet& set, const VectorXd& y, double lambda) const {
  const certify::Certificate c = certify::certify(member_, d_, answer_of(set, y), certificate_options(lambda));
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

// The thrust -N as a compressive force (user force units): N is constant along a member with both
// ends restrained; the mean otherwise.
double FeMemberPath::axial_force(const VectorXd& y) const {
  const std::vector<double> forces = system_.normal_forces(y.head(n_));
  double mean = 0.0;
  for (double f : forces) mean += f;
  if (!forces.empty()) mean /= static_cast<double>(forces.size());
  return -mean * member_.scales.force();
}

TraceStep FeMemberPath::record(const PathPoint& point, const RecordContext&) const {
  const VectorXd displacement = d_.expand_displacement(point.x.head(d_.equations));
  TraceStep step = fe_states::step_of(member_, d_, points_, options_, point.lambda, displacement,
                                      reactions(set_, point.x), set_.in_contact);
  step.axial_force = axial_force(point.x);
  step.iterations = point.iterations;
  // The whole state, with the certificate the engine certified it with just before (certify()).
  record_von_karman_state(step, member_, d_, point.lambda, answer_of(set_, point.x),
                          certified_ && last_certificate_ ? &*last_certificate_ : nullptr);
  return step;
}

double FeMemberPath::amplitude(const PathPoint& point) const {
  return lift_measures(member_, d_, d_.expand_displacement(point.x.head(d_.equations)), points_).amplitude;
}

std::string FeMemberPath::describe_state(const PathPoint& point) const {
  const model::Scales& scales = member_.scales;
  const VectorXd displacement = d_.expand_displacement(point.x.head(d_.equations));
  const double s = std::clamp(member_.s_from_user(options_.monitor), member_.s_begin, member_.s_end);
  const int e = d_.mesh.element_containing(s);
  const double crown =
      post::evaluate(d_, displacement, e, (s - d_.mesh.nodes[e]) / d_.mesh.element_size(e)).w * scales.displacement();
  return fmt::format("crown deflection {:.6g}, thrust {:.6g}", crown, axial_force(point.x));
}

PathModel::Start FeMemberPath::start(const ArcLengthOptions& options) {
  Start out;
  if (options_.resume_from) {
    out.why =
        "TraceOptions.resume_from: refused: the FE von Karman path does not resume yet (run the trace again from "
        "the start)";
    return out;
  }
  // The contact solve at lambda_min from zero.
  const double lambda0 = options.lambda_min;
  const contact::VonKarmanResult first = system_.solve(dead_ + lambda0 * live_, contact::VonKarmanOptions{});
  if (!first.is_usable()) {
    out.why = fmt::format("no equilibrium found at lambda = {:.10g}: {}", lambda0, first.message);
    return out;
  }
  std::vector<bool> first_set = first.in_contact;
  if (d_.tensionless && first.x.lpNorm<Eigen::Infinity>() == 0.0) {
    // The unloaded state: every node is at zero reaction and zero gap, so any set holds there; the
    // one the path leaves on is that of the first loads (near zero the response is linear in lambda,
    // so the set of a small step is the set of every small step).
    const double probe = lambda0 + options.direction * options.min_step;
    const contact::VonKarmanResult near = system_.solve(dead_ + probe * live_, contact::VonKarmanOptions{});
    if (near.is_usable()) first_set = near.in_contact;
  }
  set_ = contact::select_contact_set(d_, first_set);
  VectorXd y(n_ + set_.size());
  y.head(n_) = first.x;
  for (int a = 0; a < set_.size(); ++a)
    y[n_ + a] = first.in_contact[set_.members[a]] ? first.reaction[set_.members[a]] : 0.0;
  const PathFollower follower(problem(), options);
  nonlinear::NewtonSummary summary;
  std::optional<PathPoint> point = follower.start(y, lambda0, &summary);
  if (!point) {
    out.why =
        fmt::format("the start at lambda = {:.10g} did not converge on its contact set: {}", lambda0, summary.message);
    return out;
  }
  out.point = polished(set_, *point, true);
  return out;
}

std::vector<TraceEvent> FeMemberPath::set_events(const std::vector<bool>& before, const std::vector<int>& flipped,
                                                 double lambda) const {
  std::vector<TraceEvent> events;
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
  const auto crossing_at = [&](const PathPoint& located, std::vector<int>& flipped) {
    const VectorXd at = sign_values(set_, located.x), past = sign_values(set_, to.x);
    double smallest = std::numeric_limits<double>::infinity();
    for (int i = 0; i < d_.reactions(); ++i)
      if (start_values[i] > tie_tolerance && past[i] < 0.0) smallest = std::min(smallest, at[i]);
    flipped.clear();
    for (int i = 0; i < d_.reactions(); ++i)
      if (start_values[i] > tie_tolerance && past[i] < 0.0 && at[i] <= smallest + tie_tolerance) flipped.push_back(i);
  };
  std::optional<PathPoint> located = follower.locate(from, to, least_of(false), options_.event_tolerance, false);
  std::vector<int> flipped;
  if (located) {
    *located = polished(set_, *located, false);
    crossing_at(*located, flipped);
    // Polishing moves the point along the step's hyperplane (on a bifurcated branch by 7e-7 in
    // lambda): where the node is then past zero (penetrating by 1e-7 of a gap), the certificate
    // on the set would fail: located again on polished points too.
    const bool past = sign_values(set_, located->x).minCoeff() < -tie_tolerance;
    if (!flipped.empty() && (past || !set_events(set_.in_contact, flipped, located->lambda).empty())) {
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

// Taken at the step's end: the state solved on the new set at the step's arclength (the same
// hyperplane), its sign values checked, the nodes still failing switched too, at most 8 rounds,
// the pieces kept throughout. It is the path's state there (an equilibrium of the tensionless
// problem: every reaction on its set and gap off it holds) and nothing the engine watches happened
// on the way, as far as its ends tell: lambda's tangent keeps its sign (no fold) and the count of
// negative eigenvalues is the step start's (no change of stability). Otherwise nullopt: the
// crossing is located (contact_event).
std::optional<Crossing> FeMemberPath::taken_at_end(const PathPoint& from, const PathPoint& to, std::vector<int> failing,
                                                   const PathFollower& follower) const {
  const int first = points_.begin_supported ? 1 : 0;
  const int last = d_.reactions() - 1 - (points_.end_supported ? 1 : 0);
  const double ds = to.arclength - from.arclength;
  std::vector<bool> in_contact = set_.in_contact;
  const int negative = negative_eigenvalues(set_, from.x);
  for (int round = 0; round < 8 && !failing.empty(); ++round) {
    for (int i : failing) in_contact[i] = !in_contact[i];
    if (!same_pieces(set_.in_contact, in_contact, first, last)) return std::nullopt;
    const ContactSet next = contact::select_contact_set(d_, in_contact);
    const PathFollower on_next(problem_on(next), follower.options());
    // At the range's end (landed on exactly) the new set's state at that lambda, else on the step's
    // hyperplane.
    const ArcLengthOptions& o = follower.options();
    const bool at_end = to.lambda == o.lambda_max || to.lambda == o.lambda_min || o.control == PathControl::load;
    const PathPoint start = carry(from, set_, next, n_);
    StepOutcome step = at_end ? on_next.step_to_lambda(start, to.lambda) : on_next.step(start, ds);
    if (!step.point) return std::nullopt;
    const PathPoint p = polished(next, *step.point, at_end);
    const VectorXd values = sign_values(next, p.x);
    failing.clear();
    for (int i = 0; i < d_.reactions(); ++i)
      if (values[i] < -tie_tolerance) failing.push_back(i);
    if (!failing.empty()) continue;
    const bool fold =
        follower.options().control == PathControl::arc_length && (from.tangent_lambda > 0) != (p.tangent_lambda > 0);
    if (fold || negative < 0 || negative_eigenvalues(next, p.x) != negative) return std::nullopt;
    Crossing c;
    c.point = p;
    c.point_after = true;
    c.transition = std::move(in_contact);
    return c;
  }
  return std::nullopt;
}

CrossingSearch FeMemberPath::crossing(const PathPoint& from, const PathPoint& to, const PathFollower& follower,
                                      bool alone) {
  CrossingSearch search;
  if (!d_.tensionless || d_.reactions() == 0) return search;
  const VectorXd start_values = sign_values(set_, from.x), end_values = sign_values(set_, to.x);
  // Nodes at zero at the step's start (just switched, or grazing: a pinned end's node, whose value
  // is w' there times h^2) failing at once switch back at the start itself, an event there; twice
  // in a row at one point means no set holds there.
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
  if (alone) {
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
  if (std::optional<Crossing> c = contact_event(from, to, start_values, follower, failure))
    search.crossings.push_back(std::move(*c));
  else if (!failure.empty())
    search.fail = std::move(failure);
  return search;
}

PathModel::Entry FeMemberPath::enter(const Crossing& crossing, const ArcLengthOptions& options) {
  Entry entry;
  ContactSet next = contact::select_contact_set(d_, std::any_cast<std::vector<bool>>(crossing.transition));
  if (crossing.point_after) {  // solved there already
    set_ = std::move(next);
    entry.point = crossing.point;
    return entry;
  }
  const PathPoint carried = carry(crossing.point, set_, next, n_);
  set_ = std::move(next);
  // Continue from the crossing on the new set, oriented as before.
  const PathFollower follower(problem(), options);
  nonlinear::NewtonSummary summary;
  entry.point = follower.start(carried.x, carried.lambda, &summary, carried);
  if (!entry.point)
    entry.why =
        fmt::format("no equilibrium on the new contact set at lambda = {:.10g}: {}", carried.lambda, summary.message);
  return entry;
}

BranchSwitch FeMemberPath::switch_branch(const PathPoint& at, const PathFollower& follower) {
  BranchSwitch out;
  // A pseudo-arc-length step along the null vector from the bifurcation point.
  VectorXd direction = nearest_eigenpair(at.x).vector;
  branch_mode_ = direction.head(n_);
  branch_origin_ = at.x.head(n_);
  const VectorXd& scale = follower.problem().unknown_scale;
  direction /= std::sqrt((direction.array() * scale.array()).square().sum());
  PathPoint b = at;
  b.tangent_x = direction;
  b.tangent_lambda = 0.0;
  // A short first step (a tenth of initial_step: the path's steps grow from there by its own
  // control), and the first point holds the set's contact conditions (else a contact event would lie
  // between it and the bifurcation point, stepped over): the step is halved until it does.
  std::optional<PathPoint> branch;
  for (double ds = 0.1 * options_.arc_length.initial_step; ds >= options_.arc_length.min_step; ds *= 0.5) {
    StepOutcome outcome = follower.step(b, ds);
    if (!outcome.point) continue;
    const VectorXd values = sign_values(set_, polished(set_, *outcome.point, false).x);
    if (d_.tensionless && (values.array() < -tie_tolerance).any()) continue;
    branch = std::move(outcome.point);
    break;
  }
  if (!branch) {
    out.why_not = fmt::format("no point found on the bifurcated branch at lambda = {:.10g}", at.lambda);
    return out;
  }
  BranchStart start;
  start.point = polished(set_, *branch, false);
  start.amplitude = [this](const PathPoint& p) { return branch_mode_.dot(p.x.head(n_) - branch_origin_); };
  start.return_accuracy = branch_accuracy;
  start.return_tolerance = options_.event_tolerance;
  start.description = "along the critical mode";
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
    const VectorXd mode = nearest_eigenpair(p->x).vector;
    p = polished(set_, *p, true, &mode);
    if (!(std::abs(branch_mode_.dot(p->x.head(n_) - branch_origin_)) <= off_path)) return std::nullopt;
    return p;
  };
  std::optional<PathPoint> a = solved(near.lambda);
  if (!a) return std::nullopt;
  double margin_a = nearest_eigenpair(a->x).value;
  std::optional<PathPoint> b = solved(near.lambda + 1e-6 * std::max(1.0, std::abs(near.lambda)));
  for (int iteration = 0; b && iteration < 30; ++iteration) {
    // Converged: the last secant step within event_tolerance, or the eigenvalue zero within its
    // round-off (at 64 elements ~5e-11 against a slope ~0.1: 1e-9 in lambda, above the tolerance).
    const Eigenpair margin = nearest_eigenpair(b->x);
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
  FeMemberPath model(member, options, live_load, seam);
  return follow_path(model, options, sink);
}

}  // namespace liftoff::continuation
