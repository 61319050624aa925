#include "continuation/fe_von_karman_path.hpp"

#include <fmt/format.h>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "certify/certificate.hpp"
#include "contact/von_karman_solve.hpp"
#include "continuation/arclength.hpp"
#include "continuation/events.hpp"
#include "continuation/fe_states.hpp"
#include "continuation/step_state.hpp"

namespace liftoff::continuation {

namespace {

using Eigen::VectorXd;
using SparseMatrix = Eigen::SparseMatrix<double>;
using Triplets = std::vector<Eigen::Triplet<double>>;

// Nodes whose normalised sign value is within this of zero at a located contact event switch
// together (mirror nodes of a symmetric member reach zero at one lambda up to round-off).
constexpr double tie_tolerance = 1e-8;

using ContactSet = contact::ContactSelection;
constexpr auto make_set = contact::select_contact_set;

class Tracer {
 public:
  Tracer(const model::MemberModel& model, const fe::Discretisation& d, const contact::VonKarmanSystem& system,
         VectorXd dead, VectorXd live, double w_ref, VonKarmanStateSeam seam, bool certified)
      : model_(model),
        d_(d),
        system_(system),
        dead_(std::move(dead)),
        live_(std::move(live)),
        w_ref_(w_ref),
        seam_(std::move(seam)),
        certified_(certified) {
    n_ = system.unknowns();
    double h = std::numeric_limits<double>::infinity();
    for (int e = 0; e < d.mesh.elements(); ++e) h = std::min(h, d.mesh.element_size(e));
    reaction_unit_ = std::max(d.k, 1e-300) * w_ref;
    gap_unit_ = h * w_ref;
  }

  int n() const { return n_; }

  // The bordered equations of the set.
  PathProblem problem(const ContactSet& set) const {
    const int m = set.size();
    PathProblem p;
    p.unknowns = n_ + m;
    p.residual = [this, &set](const VectorXd& y, double lambda, VectorXd& g) { return residual(set, y, lambda, g); };
    p.sparse_jacobian = [this, &set](const VectorXd& y, double, SparseMatrix& g_y) {
      if (!y.allFinite()) return false;
      g_y = saddle(set, y);
      return true;
    };
    p.lambda_derivative = [this, m](const VectorXd&, double, VectorXd& g_lambda) {
      g_lambda = VectorXd::Zero(n_ + m);
      g_lambda.head(n_) = -live_;
      return true;
    };
    p.unknown_scale = unknown_scale(set);
    // The corrector's test relative to each equation's size: |G_i| against sum_j |dG_i/dy_j| y_ref_j
    // at the unloaded state (the membrane terms of EA and the h^-3 of bending included), so that its
    // tolerance means the same on every mesh.
    p.residual_scale = residual_scale(set);
    return p;
  }

  bool residual(const ContactSet& set, const VectorXd& y, double lambda, VectorXd& g) const {
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

  VectorXd residual_scale(const ContactSet& set) const {
    const int m = set.size();
    VectorXd typical = VectorXd::Constant(n_ + m, w_ref_);
    if (m > 0) typical.tail(m).setConstant(reaction_unit_);
    const SparseMatrix j0 = saddle(set, VectorXd::Zero(n_ + m));
    const VectorXd size = SparseMatrix(j0.cwiseAbs()) * typical;
    return size.cwiseMax(std::numeric_limits<double>::min()).cwiseInverse();
  }

  VectorXd unknown_scale(const ContactSet& set) const {
    VectorXd scale = VectorXd::Constant(n_ + set.size(), 1.0 / w_ref_);
    scale.tail(set.size()).setConstant(1e-3 / reaction_unit_);
    return scale;
  }

  // The point the path decides on and records: the corrector's point, with Newton corrections of
  // the bordered system (G = 0 and the hyperplane through the point normal to its tangent in the
  // path's metric; fixed_lambda: at its lambda) while its backward error is above the
  // certificate's tolerance and they reduce it, at most 6. The backward error is the
  // certificate's own (certify/certificate.hpp: each row against the terms summed into it, the
  // membrane force's included), so a polished state that stops short of it has stagnated at its
  // round-off, and the certificate's message says so; where the states are not certified (a
  // live_load), |G| against |J| |y| and the loads, at most 6 corrections while they reduce it. The
  // corrector stops at 1e-11 of each equation's size at the unloaded state, which near a limit
  // point leaves the state off by ~1e-7 of w_ref (more than the signs the events decide). A
  // state that passes already is not corrected (most are: the corrector's last Newton step
  // usually takes it to round-off). Not at fixed lambda on an arc-length path: near a limit
  // point G_y is nearly singular and such a correction would move the state along its null
  // vector; the bordered matrix is regular there. With `mode` (at fixed lambda on a bifurcation
  // point, where G_y is singular along the critical mode phi: the switched branch's return), the
  // border is phi instead, [G_y phi; phi^T 0] (dy, mu) = (-G, 0): regular there (phi spans G_y's
  // null space, so it is not in its range), the state's component along phi held, lambda fixed.
  PathPoint polished(const ContactSet& set, const PathPoint& point, bool fixed_lambda,
                     const VectorXd* mode = nullptr) const {
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

  SparseMatrix saddle(const ContactSet& set, const VectorXd& y) const {
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

  // Reactions on every reaction unknown (0 off the set) and the gaps.
  VectorXd reactions(const ContactSet& set, const VectorXd& y) const {
    VectorXd r = VectorXd::Zero(d_.reactions());
    for (int a = 0; a < set.size(); ++a) r[set.members[a]] = y[n_ + a];
    return r;
  }
  VectorXd gaps(const ContactSet& set, const VectorXd& y) const {
    return d_.gap_of(reactions(set, y), y.head(d_.equations));
  }
  // Per reaction unknown: r_i / (k w_ref) on the set, gap_i / (h w_ref) off it (>= 0: the sign holds).
  VectorXd sign_values(const ContactSet& set, const VectorXd& y) const {
    const VectorXd r = reactions(set, y), g = gaps(set, y);
    VectorXd v(d_.reactions());
    for (int i = 0; i < d_.reactions(); ++i) v[i] = set.in_contact[i] ? r[i] / reaction_unit_ : g[i] / gap_unit_;
    return v;
  }
  // Negative eigenvalues of S (negative pivots of the saddle factor less |A|); -1 if the factor fails.
  int negative_eigenvalues(const ContactSet& set, const VectorXd& y) const {
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
  // matrix that close to A; the secant below saw 0.02 to 0.1 of it, at 16 to 64 elements).
  struct Eigenpair {
    VectorXd vector;
    double value = std::numeric_limits<double>::quiet_NaN();
    double round_off = std::numeric_limits<double>::quiet_NaN();
  };
  Eigenpair nearest_eigenpair(const ContactSet& set, const VectorXd& y) const {
    const SparseMatrix a = saddle(set, y);
    Eigen::SparseLU<SparseMatrix> lu(a);
    Eigenpair pair;
    VectorXd& full = pair.vector;
    full = VectorXd::Zero(a.rows());
    if (lu.info() != Eigen::Success) return pair;
    pair.round_off =
        std::numeric_limits<double>::epsilon() * (SparseMatrix(a.cwiseAbs()) * VectorXd::Ones(a.cols())).maxCoeff();
    VectorXd v = VectorXd::LinSpaced(n_, 1.0, 2.0);  // deterministic, not orthogonal to a mode
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
  // Its eigenvector alone: the critical mode at a bifurcation point.
  VectorXd null_vector(const ContactSet& set, const VectorXd& y) const { return nearest_eigenpair(set, y).vector; }

  // The step of a point on the set (user units).
  TraceStep step_of(const ContactSet& set, const PathPoint& p, const SpecialPoints& points,
                    const TraceOptions& options) const {
    const VectorXd displacement = d_.expand_displacement(p.x.head(d_.equations));
    TraceStep step =
        fe_states::step_of(model_, d_, points, options, p.lambda, displacement, reactions(set, p.x), set.in_contact);
    const std::vector<double> forces = system_.normal_forces(p.x.head(n_));
    double mean = 0.0;
    for (double f : forces) mean += f;
    if (!forces.empty()) mean /= static_cast<double>(forces.size());
    step.axial_force = -mean * model_.scales.force();
    const int negative = negative_eigenvalues(set, p.x);
    step.stability = negative == 0  ? continuation::Stability::stable
                     : negative > 0 ? continuation::Stability::unstable
                                    : continuation::Stability::unknown;
    step.iterations = p.iterations;
    return step;
  }

  // The step's whole state (step_state.hpp), certified by `certificate` (null: not certified).
  void record_state(TraceStep& step, const ContactSet& set, const PathPoint& p,
                    const certify::Certificate* certificate) const {
    record_von_karman_state(step, model_, d_, p.lambda, answer_of(set, p.x), certificate);
  }

  // The certificate of a path point (certify/certificate.hpp, the von Karman answer from its fields
  // alone) at the path's own accuracy:
  //  - backward error: the certificate's own tolerance, for y polished() to round-off.
  //  - signs: the path accepts a node's value r_i / (k w_ref) or gap_i / (h w_ref) down to
  //    -max(tie_tolerance, event_tolerance) (below, an event is located or a node switches at
  //    once); the certificate's are r_i / max r and gap_i / (h max |w|) or larger: the floor is
  //    that bound in its units, max(k w_ref / max r, w_ref / max |w|) times it, at most 1e-4 (the
  //    certificate takes floors below 1e-3 / 8; a larger one is a state within 1e-4 w_ref of the
  //    unloaded one, whose nodes' signs the certificate then checks more finely than the path).
  certify::Certificate certificate(const ContactSet& set, VectorXd y, double lambda,
                                   const TraceOptions& options) const {
    if (seam_) seam_(lambda, y);
    const certify::VonKarmanAnswer answer = answer_of(set, y);
    const int nodes = d_.mesh.elements() + 1;
    double w_largest = 0.0;
    for (int node = 0; node < nodes; ++node)
      w_largest = std::max(w_largest, std::abs(answer.displacement[d_.deflection_dof(node)]));
    const double r_largest = answer.reaction.size() > 0 ? answer.reaction.cwiseAbs().maxCoeff() : 0.0;
    const double tiny = std::numeric_limits<double>::min();
    const double w_ratio = std::max(1.0, w_ref_ / std::max(w_largest, tiny));
    certify::CertifyOptions o = certificate_options(lambda);
    o.sign_floor = std::min(1e-4, std::max(tie_tolerance, options.event_tolerance) *
                                      std::max(w_ratio, r_largest > 0.0 ? reaction_unit_ / r_largest : 0.0));
    return certify::certify(model_, d_, answer, o);
  }

  // The certificate's backward error of a state (its other checks not looked at).
  certify::Check backward_error(const ContactSet& set, const VectorXd& y, double lambda) const {
    const certify::Certificate c = certify::certify(model_, d_, answer_of(set, y), certificate_options(lambda));
    const certify::Check* check = c.find(certify::check_name::backward_error);
    if (check) return *check;
    certify::Check none;  // no answer to certify (not finite): infinitely far
    none.value = std::numeric_limits<double>::infinity(), none.tolerance = 1.0;
    return none;
  }

  static certify::CertifyOptions certificate_options(double lambda) {
    certify::CertifyOptions o;
    o.load_factor = lambda;
    o.round_off = false;
    o.pointwise = false;
    return o;
  }

  // The von Karman answer of a state, from its fields alone.
  certify::VonKarmanAnswer answer_of(const ContactSet& set, const VectorXd& y) const {
    certify::VonKarmanAnswer answer;
    answer.displacement = d_.expand_displacement(y.head(d_.equations));
    answer.reaction = reactions(set, y);
    const int nodes = d_.mesh.elements() + 1;
    answer.axial = VectorXd::Zero(nodes);
    for (int node = 0; node < nodes; ++node)
      if (const int k = system_.axial_unknown(node); k >= 0) answer.axial[node] = y[k];
    answer.normal_force = system_.normal_forces(y.head(n_));
    return answer;
  }

  ContactTopology topology(const VectorXd& y, const SpecialPoints& points) const {
    return contact_topology(model_, d_, d_.expand_displacement(y.head(d_.equations)), points);
  }

  double user_position(int reaction) const { return model_.user_from_s(d_.mesh.nodes[d_.reaction_nodes[reaction]]); }

 private:
  const model::MemberModel& model_;
  const fe::Discretisation& d_;
  const contact::VonKarmanSystem& system_;
  VectorXd dead_, live_;
  double w_ref_;
  VonKarmanStateSeam seam_;
  bool certified_ = true;
  int n_ = 0;
  double reaction_unit_ = 1.0, gap_unit_ = 1.0;
};

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

}  // namespace

TraceResult trace_fe_von_karman(const model::MemberModel& member, const TraceOptions& options, const TraceSink& sink,
                                const VonKarmanLiveLoad& live_load, const VonKarmanStateSeam& seam) {
  const auto started = std::chrono::steady_clock::now();
  options.validate(member.user_from_s(member.s_begin), member.user_from_s(member.s_end));
  TraceResult result;
  result.summary.path = PathKind::fe;
  const auto finish = [&](TraceTermination termination, std::string message) {
    result.summary.termination = termination;
    result.summary.message = std::move(message);
    result.summary.steps = static_cast<int>(result.steps.size());
    result.summary.final_load_factor =
        result.steps.empty() ? options.arc_length.lambda_min : result.steps.back().load_factor;
    result.summary.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    return result;
  };
  if (options.resume_from)
    return finish(TraceTermination::solver_failure,
                  "TraceOptions.resume_from: refused: the FE von Karman path does not resume yet (run the trace "
                  "again from the start)");

  const fe::Discretisation d = fe::discretise(member, options.elements);
  const contact::VonKarmanSystem system(member, d);
  const int n = system.unknowns();
  VectorXd dead, live;
  if (live_load) {
    live = live_load(d, system);
    dead = VectorXd::Zero(n);
    if (live.size() != n)
      throw std::invalid_argument(
          fmt::format("trace_fe_von_karman: live_load has {} entries, expected {}", live.size(), n));
  } else {
    dead = system.load(0.0);
    live = system.load(1.0) - dead;
  }
  const double w_ref = member.initial_sine ? std::max(std::abs(member.initial_sine->amplitude), 1e-6) : 1e-3;
  const Tracer tracer(member, d, system, dead, live, w_ref, seam, !live_load);
  const SpecialPoints points = special_points(member);

  // The start: the contact solve at lambda_min from zero.
  const double lambda0 = options.arc_length.lambda_min;
  const contact::VonKarmanResult first = system.solve(dead + lambda0 * live, contact::VonKarmanOptions{});
  if (!first.is_usable())
    return finish(TraceTermination::solver_failure,
                  fmt::format("no equilibrium found at lambda = {:.10g}: {}", lambda0, first.message));
  std::vector<bool> first_set = first.in_contact;
  if (d.tensionless && first.x.lpNorm<Eigen::Infinity>() == 0.0) {
    // The unloaded state: every node is at zero reaction and zero gap, so any set holds there; the
    // one the path leaves on is that of the first loads (near zero the response is linear in lambda,
    // so the set of a small step is the set of every small step).
    const double probe = lambda0 + options.arc_length.direction * options.arc_length.min_step;
    const contact::VonKarmanResult near = system.solve(dead + probe * live, contact::VonKarmanOptions{});
    if (near.is_usable()) first_set = near.in_contact;
  }
  ContactSet set = make_set(d, first_set);
  std::optional<PathPoint> point;
  {
    VectorXd y(n + set.size());
    y.head(n) = first.x;
    for (int a = 0; a < set.size(); ++a)
      y[n + a] = first.in_contact[set.members[a]] ? first.reaction[set.members[a]] : 0.0;
    const PathFollower follower(tracer.problem(set), options.arc_length);
    nonlinear::NewtonSummary summary;
    point = follower.start(y, lambda0, &summary);
    if (!point)
      return finish(TraceTermination::solver_failure,
                    fmt::format("the start at lambda = {:.10g} did not converge on its contact set: {}", lambda0,
                                summary.message));
  }
  // Every state is certified from its own fields (Tracer::certificate) before it is reported: one
  // that fails is not recorded and ends the path (solver_failure), the steps before it valid. A
  // step reaching max_amplitude ends it too (completed). Under a live_load (a load the member model
  // does not describe, so the certificate cannot balance it) the states are not certified.
  std::string not_certified;
  // Polished at its lambda under load control and at the range's ends (landed on exactly).
  const auto polish = [&](const ContactSet& on, const PathPoint& p) {
    const bool fixed_lambda = options.arc_length.control == PathControl::load ||
                              p.lambda == options.arc_length.lambda_max || p.lambda == options.arc_length.lambda_min;
    return tracer.polished(on, p, fixed_lambda);
  };
  bool amplitude_reached = false;
  // `p` as polish() (or Tracer::polished at fixed lambda) left it: the observer decides on the
  // polished point, and a second polish would cost a factorisation and two certificates a step.
  const auto record_point = [&](const ContactSet& on, const PathPoint& p) {
    const certify::Certificate certificate =
        live_load ? certify::Certificate{} : tracer.certificate(on, p.x, p.lambda, options);
    if (!live_load && !certificate.passed) {
      const certify::Check* backward = certificate.find(certify::check_name::backward_error);
      not_certified = fmt::format(
          "the state at lambda = {:.10g} failed its certificate: {}{}", p.lambda, certificate.message,
          backward && !backward->passed ? " (the Newton corrections of the state stagnated above its tolerance)" : "");
      return false;
    }
    result.steps.push_back(tracer.step_of(on, p, points, options));
    tracer.record_state(result.steps.back(), on, p, live_load ? nullptr : &certificate);
    if (sink.on_step) sink.on_step(result.steps.back());
    if (options.max_amplitude && result.steps.back().amplitude >= *options.max_amplitude) amplitude_reached = true;
    return true;
  };
  const auto record_event = [&](TraceEvent event) {
    result.events.push_back(std::move(event));
    if (sink.on_event) sink.on_event(result.events.back());
  };
  const auto crown = [&](const PathPoint& p) { return tracer.step_of(set, p, points, options).monitor_deflection; };
  if (!record_point(set, polish(set, *point))) return finish(TraceTermination::solver_failure, not_certified);

  // The events of switching `flipped` in the node set `before` (at lambda), from the node set's
  // pieces: a node leaving inside a piece opens a lift-off zone, the last node of a piece leaving
  // ends it; a node joining inside a zone opens a contact region, the last node of a zone joining
  // closes it; a node at the foundation's end switching moves a limit onto or off it (at a support:
  // limit_at_support). Otherwise a limit moves on by a node: no event. (The cubics' signs,
  // events.hpp, see lift-off zones shorter than an element that the nodes do not: near a pinned end
  // they open and close with every node the limit passes, so the path counts on its nodes.)
  const auto set_events = [&](const std::vector<bool>& before, const std::vector<int>& flipped, double lambda) {
    std::vector<TraceEvent> events;
    // A supported end's node has w = 0: its sign is that of w' there (times h^2), no piece of its
    // own; the pieces are counted on the nodes inside, the end's limit at its neighbour.
    const int first = points.begin_supported ? 1 : 0;
    const int last = d.reactions() - 1 - (points.end_supported ? 1 : 0);
    for (int i : flipped) {
      if (i < first || i > last) continue;
      const bool leaving = before[i];
      const double at = tracer.user_position(i);
      const bool left_same = i > first && before[i - 1] == before[i];
      const bool right_same = i < last && before[i + 1] == before[i];
      EventKind kind;
      std::string what;
      if (i == first || i == last) {
        const bool supported = i == first ? points.begin_supported : points.end_supported;
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
  };
  int folds = 0, bifurcations = 0, contact_events = 0;
  int immediate_switches = 0;  // switches back at a step's start, in a row
  bool switched = false;
  // The switched branch's critical mode (x part) and its origin: its amplitude along the mode
  // changing sign is the branch meeting the path it left (or its mirror image) again. On that path
  // the amplitude is zero but for the state's error, whose sign is chance: the corrector can land
  // a step on the path itself (seen at 32 elements, kappa = 8: 4e-9 from the corrector, 1e-10 of
  // either sign once polished, against a branch reaching 0.8). So the branch has met the path once
  // its amplitude is within the corrector's relative accuracy (1e-7, as of w_ref: header) of the
  // largest it reached: closer, the two are not told apart at that accuracy.
  VectorXd branch_mode, branch_origin;
  double branch_peak = 0.0;
  constexpr double branch_accuracy = 1e-7;
  // The crossing of the switched branch with the path it left, from `near` (the return located on
  // the amplitude along the mode, which vanishes all along the path it rejoins, so that the locate
  // lands on that path but not at the crossing: 16 / 32 elements, kappa = 2: 13.4290 / 13.4329,
  // kappa = 8: 88.6184 / 89.3594, against 13.46827 / 88.61662): a secant in lambda on the
  // eigenvalue of S nearest zero (Tracer::nearest_eigenpair), each point solved at fixed lambda
  // from `near` less its mode component and polished there bordered by its critical mode (the
  // solve's tolerance alone left 2.5e-7 in the crossing's lambda at 32 elements, kappa = 8, and
  // broke the load's order 4 at 64 elements), to event_tolerance in lambda, as the Ritz path does
  // (ritz_path.cpp, RitzTracer::refined_crossing). That eigenvalue is zero at the crossing and
  // linear in lambda beside it: on the symmetric path S commutes with the mirror, so its
  // antisymmetric block's lowest eigenvalue is simple and smooth in lambda, and it vanishes where
  // the thrust reaches the antisymmetric mode's critical value, a simple root since the thrust
  // changes at a rate away from a limit point (the closed form's two bifurcation loads are the
  // distinct roots of a quadratic). Near the crossing it is the eigenvalue nearest zero (S is
  // regular on the symmetric modes off a limit point). nullopt if a solve fails, lands off that
  // path (its amplitude along the mode above 1e-3 of the branch's peak) or the secant does not
  // converge in 30 iterations: the caller keeps `near` and says so.
  struct Crossing {
    PathPoint point;
    VectorXd mode;  // the saddle matrix's null vector there (Tracer::nearest_eigenpair)
  };
  const auto refined_crossing = [&](const PathFollower& follower, const ContactSet& on,
                                    const PathPoint& near) -> std::optional<Crossing> {
    // Near the crossing the solves amplify round-off along the mode by 1 / that eigenvalue (seen:
    // 1e-6 of the branch's peak); a point 1e-3 of it off the path would be on the branch.
    const double off_path = 1e-3 * branch_peak;
    PathPoint guess = near;
    guess.x.head(n) -= branch_mode.dot(near.x.head(n) - branch_origin) * branch_mode;
    const auto solved = [&](double lambda) -> std::optional<PathPoint> {
      std::optional<PathPoint> p = follower.step_to_lambda(guess, lambda, &guess.x).point;
      if (!p) return p;
      const VectorXd mode = tracer.nearest_eigenpair(on, p->x).vector;
      p = tracer.polished(on, *p, true, &mode);
      if (p && !(std::abs(branch_mode.dot(p->x.head(n) - branch_origin)) <= off_path)) return std::nullopt;
      return p;
    };
    std::optional<PathPoint> a = solved(near.lambda);
    if (!a) return std::nullopt;
    double margin_a = tracer.nearest_eigenpair(on, a->x).value;
    std::optional<PathPoint> b = solved(near.lambda + 1e-6 * std::max(1.0, std::abs(near.lambda)));
    for (int iteration = 0; b && iteration < 30; ++iteration) {
      // Converged: the last secant step within event_tolerance, or the eigenvalue zero within its
      // round-off (at 64 elements ~5e-11 against a slope ~0.1: 1e-9 in lambda, above the tolerance).
      const Tracer::Eigenpair margin = tracer.nearest_eigenpair(on, b->x);
      if (std::abs(b->lambda - a->lambda) <= options.event_tolerance || std::abs(margin.value) <= margin.round_off)
        return Crossing{std::move(*b), margin.vector};
      if (!std::isfinite(margin.value) || margin.value == margin_a) break;
      const double lambda = b->lambda - margin.value * (b->lambda - a->lambda) / (margin.value - margin_a);
      a = std::move(b);
      margin_a = margin.value;
      b = solved(lambda);
    }
    return std::nullopt;
  };
  std::optional<double> first_step;
  const auto amplitude_message = [&] {
    return fmt::format("max_amplitude = {:.6g} reached at lambda = {:.10g} (amplitude {:.6g})", *options.max_amplitude,
                       result.steps.back().load_factor, result.steps.back().amplitude);
  };
  if (amplitude_reached) return finish(TraceTermination::completed, amplitude_message());
  for (;;) {
    const PathFollower follower(tracer.problem(set), [&] {
      ArcLengthOptions o = options.arc_length;
      o.locate_folds = false;  // located here, in order with the other events
      o.fold_tolerance = options.event_tolerance;
      o.max_steps = std::max(1, options.arc_length.max_steps - static_cast<int>(result.steps.size()) + 1);
      return o;
    }());
    // What the observer found that ends this run.
    std::optional<ContactSet> next_set;
    std::optional<VectorXd> switch_direction;
    bool rejoined = false;
    std::string failure;
    std::vector<TraceEvent> pending_events;  // the contact events of the step being recorded
    const StepObserver observer = [&](const PathPoint& previous, PathPoint& accepted) {
      // Every decision below on the polished point (Tracer::polished): the corrector's tolerance
      // leaves the state off by ~1e-7 of w_ref near a limit point, more than the signs it decides.
      accepted = polish(set, accepted);
      // 1. Contact events, the first along the step.
      // 0. A step holding a limit point and a change of stability beyond it, or two changes, is
      // retried shorter (they are told apart by their own sides), down to 100 min_step.
      {
        const bool fold =
            previous.tangent_lambda != 0.0 && (previous.tangent_lambda > 0) != (accepted.tangent_lambda > 0);
        const int before = tracer.negative_eigenvalues(set, previous.x),
                  after = tracer.negative_eigenvalues(set, accepted.x);
        const int changes = std::abs(after - before) - (fold ? 1 : 0);
        if (before >= 0 && after >= 0 && changes >= 1 + (fold ? 0 : 1) &&
            accepted.arclength - previous.arclength > 100 * options.arc_length.min_step)
          return ObserverVerdict::reject;
      }
      // The switched branch back on the path it left: located, recorded, the trace ends there.
      if (branch_mode.size() > 0) {
        branch_peak = std::max(branch_peak, branch_mode.dot(previous.x.head(n) - branch_origin));
        const double zero = branch_accuracy * branch_peak;
        const auto amplitude = [&](const PathPoint& p) { return branch_mode.dot(p.x.head(n) - branch_origin) - zero; };
        if (amplitude(accepted) <= 0.0 && amplitude(previous) > 0.0) {
          std::optional<PathPoint> located = follower.locate(previous, accepted, amplitude, options.event_tolerance);
          const std::optional<Crossing> crossing = refined_crossing(follower, set, located ? *located : accepted);
          if (crossing)  // polished at the crossing's lambda, bordered by its critical mode
            accepted = tracer.polished(set, crossing->point, true, &crossing->mode);
          else if (located)
            accepted = polish(set, *located);
          if (!record_point(set, accepted)) {
            failure = not_certified;
            return ObserverVerdict::stop;
          }
          record_event({accepted.lambda, EventKind::bifurcation, options.monitor,
                        fmt::format("the bifurcated branch meets the path it left at lambda = {:.10g} (crown "
                                    "deflection {:.6g}){}: the trace ends here",
                                    accepted.lambda, crown(accepted),
                                    crossing ? ""
                                             : "; not located on the crossing (the secant on the tangent's eigenvalue "
                                               "nearest zero did not converge): the point where the branch's amplitude "
                                               "vanished")});
          ++bifurcations;
          rejoined = true;
          return ObserverVerdict::stop;
        }
      }
      const VectorXd start_values = tracer.sign_values(set, previous.x),
                     end_values = tracer.sign_values(set, accepted.x);
      // Nodes at zero at the step's start (just switched, or grazing: a pinned end's node, whose
      // value is w' there times h^2) failing at once switch back at the start itself, an event
      // there; twice in a row at one point means no set holds there (solver_failure).
      {
        std::vector<bool> in_contact = set.in_contact;
        std::vector<int> flipped;
        for (int i = 0; i < d.reactions() && d.tensionless; ++i)
          if (!(start_values[i] > tie_tolerance) && end_values[i] < -tie_tolerance)
            in_contact[i] = !in_contact[i], flipped.push_back(i);
        if (!flipped.empty()) {
          if (immediate_switches >= 2) {
            failure = fmt::format(
                "no contact set holds at lambda = {:.10g}: the node at {:.6g} fails its sign at once on every set "
                "tried",
                previous.lambda, tracer.user_position(flipped[0]));
            return ObserverVerdict::stop;
          }
          ++immediate_switches;
          for (TraceEvent& e : set_events(set.in_contact, flipped, previous.lambda))
            record_event(std::move(e)), ++contact_events;
          accepted = previous;
          next_set = make_set(d, std::move(in_contact));
          return ObserverVerdict::stop;
        }
      }
      immediate_switches = 0;
      const auto event = [&](const PathPoint& p) {
        const VectorXd v = tracer.sign_values(set, polish(set, p).x);
        double least = 1.0;
        for (int i = 0; i < d.reactions(); ++i)
          if (start_values[i] > tie_tolerance) least = std::min(least, v[i]);
        return least;
      };
      if (d.tensionless && d.reactions() > 0 && event(accepted) < -options.event_tolerance) {
        std::optional<PathPoint> located = follower.locate(previous, accepted, event, options.event_tolerance);
        if (!located) {
          failure = fmt::format("a contact event between lambda = {:.10g} and {:.10g} could not be located",
                                previous.lambda, accepted.lambda);
          return ObserverVerdict::stop;
        }
        *located = polish(set, *located);
        const VectorXd at = tracer.sign_values(set, located->x), past = tracer.sign_values(set, accepted.x);
        std::vector<bool> in_contact = set.in_contact;
        std::vector<int> flipped;
        // The node(s) crossing with the least value at the located point (within the tie).
        double least = std::numeric_limits<double>::infinity();
        for (int i = 0; i < d.reactions(); ++i)
          if (start_values[i] > tie_tolerance && past[i] < 0.0) least = std::min(least, at[i]);
        for (int i = 0; i < d.reactions(); ++i)
          if (start_values[i] > tie_tolerance && past[i] < 0.0 && at[i] <= least + tie_tolerance)
            in_contact[i] = !in_contact[i], flipped.push_back(i);
        if (flipped.empty()) {
          failure = fmt::format("a contact event located at lambda = {:.10g} names no node", located->lambda);
          return ObserverVerdict::stop;
        }
        std::vector<TraceEvent> events = set_events(set.in_contact, flipped, located->lambda);
        for (TraceEvent& e : events) e.load_factor = located->lambda;
        accepted = std::move(*located);
        pending_events = std::move(events);
        next_set = make_set(d, std::move(in_contact));
      }
      // 2. A limit point in the (possibly shortened) step.
      const bool fold =
          previous.tangent_lambda != 0.0 && (previous.tangent_lambda > 0) != (accepted.tangent_lambda > 0);
      if (fold) {
        const auto t_lambda = [](const PathPoint& p) { return p.tangent_lambda; };
        if (auto located = follower.locate(previous, accepted, t_lambda, options.event_tolerance)) {
          // Recorded as a step of its own: the curve passes through its extremum, and the event's
          // step is the limit point itself (the pictures draw it there).
          if (!record_point(set, polish(set, *located))) {
            failure = not_certified;
            return ObserverVerdict::stop;
          }
          // As recorded (polished: its lambda within the corrector's accuracy of the located one).
          const TraceStep& limit = result.steps.back();
          const bool maximum = previous.tangent_lambda > 0;
          record_event({limit.load_factor, EventKind::limit_point, options.monitor,
                        fmt::format("limit point: lambda reaches a {} {:.10g} (crown deflection {:.6g}, thrust {:.6g})",
                                    maximum ? "maximum" : "minimum", limit.load_factor, limit.monitor_deflection,
                                    limit.axial_force)});
          ++folds;
        }
      }
      // 3. A bifurcation: the count of negative eigenvalues changes without a fold.
      const int before = tracer.negative_eigenvalues(set, previous.x),
                after = tracer.negative_eigenvalues(set, accepted.x);
      if (!fold && before >= 0 && after >= 0 && before != after) {
        double lo = 0.0, hi = accepted.arclength - previous.arclength;
        PathPoint lo_point = previous, hi_point = accepted;
        for (int it = 0; it < 200 && std::abs(hi_point.lambda - lo_point.lambda) > options.event_tolerance; ++it) {
          const double mid = 0.5 * (lo + hi);
          if (!(mid > lo && mid < hi)) break;
          StepOutcome outcome = follower.step(previous, mid);
          if (!outcome.point) break;
          const int count = tracer.negative_eigenvalues(set, outcome.point->x);
          if (count == before)
            lo = mid, lo_point = std::move(*outcome.point);
          else
            hi = mid, hi_point = std::move(*outcome.point);
        }
        PathPoint at = lo_point;  // the last point with the count of before
        const double lambda_b = 0.5 * (lo_point.lambda + hi_point.lambda);
        const bool loses = before == 0 && after > 0;
        const bool switching = loses && options.switch_branch && !switched && !next_set;
        record_event({lambda_b, EventKind::bifurcation, options.monitor,
                      fmt::format("bifurcation at lambda = {:.10g} (crown deflection {:.6g}): negative eigenvalues of "
                                  "the tangent {} -> {}{}",
                                  lambda_b, crown(at), before, after,
                                  switching ? "; the path switches to the bifurcated branch" : "")});
        ++bifurcations;
        if (switching) {
          switch_direction = tracer.null_vector(set, at.x);
          accepted = std::move(at);
          return ObserverVerdict::stop;
        }
      }
      if (!record_point(set, accepted)) {
        failure = not_certified;
        return ObserverVerdict::stop;
      }
      for (TraceEvent& e : pending_events) record_event(std::move(e)), ++contact_events;
      pending_events.clear();
      if (next_set || amplitude_reached) return ObserverVerdict::stop;
      return ObserverVerdict::proceed;
    };
    const ArcLengthResult run = follower.follow(*point, observer, first_step);
    result.summary.rejected_steps += run.rejected_steps;
    result.summary.corrector_iterations += run.corrector_iterations;
    const auto counts = [&] {
      return fmt::format(
          "{} steps ({} rejected), {} contact event(s), {} limit point(s), {} bifurcation(s), {} elements",
          result.steps.size(), result.summary.rejected_steps, contact_events, folds, bifurcations, options.elements);
    };
    if (!failure.empty()) return finish(TraceTermination::solver_failure, failure + ": " + counts());
    if (amplitude_reached) return finish(TraceTermination::completed, amplitude_message() + ": " + counts());
    if (run.termination == ArcLengthTermination::completed)
      return finish(TraceTermination::completed,
                    fmt::format("lambda = {:.10g} reached: {}", result.steps.back().load_factor, counts()));
    if (run.termination == ArcLengthTermination::step_limit)
      return finish(TraceTermination::step_limit, fmt::format("max_steps reached: {}", counts()));
    if (run.termination == ArcLengthTermination::step_too_small)
      return finish(TraceTermination::step_too_small, run.message + ": " + counts());
    if (run.termination != ArcLengthTermination::stopped_by_observer || run.points.empty())
      return finish(TraceTermination::solver_failure, run.message + ": " + counts());
    if (static_cast<int>(result.steps.size()) >= options.arc_length.max_steps)
      return finish(TraceTermination::step_limit, fmt::format("max_steps reached: {}", counts()));
    const PathPoint& last = run.points.back();
    first_step = options.arc_length.initial_step;
    if (rejoined)
      return finish(TraceTermination::completed,
                    fmt::format("the bifurcated branch met the path it left again at lambda = {:.10g}: {}",
                                result.steps.back().load_factor, counts()));
    if (next_set) {
      // Continue from the event on the new set, oriented as before.
      const ContactSet old = std::move(set);
      set = std::move(*next_set);
      const PathPoint carried = carry(last, old, set, n);
      const PathFollower next(tracer.problem(set), options.arc_length);
      nonlinear::NewtonSummary summary;
      point = next.start(carried.x, carried.lambda, &summary, carried);
      if (!point)
        return finish(TraceTermination::solver_failure,
                      fmt::format("no equilibrium on the new contact set at lambda = {:.10g}: {}: {}", carried.lambda,
                                  summary.message, counts()));
      continue;
    }
    if (switch_direction) {
      // A pseudo-arc-length step along the null vector from the bifurcation point.
      switched = true;
      branch_mode = switch_direction->head(n);
      branch_origin = last.x.head(n);
      branch_peak = 0.0;
      PathPoint b = last;
      VectorXd direction = *switch_direction;
      const VectorXd& scale = follower.problem().unknown_scale;
      direction /= std::sqrt((direction.array() * scale.array()).square().sum());
      b.tangent_x = direction;
      b.tangent_lambda = 0.0;
      std::optional<PathPoint> branch;
      for (double ds = *first_step; ds >= options.arc_length.min_step; ds *= 0.5) {
        StepOutcome outcome = follower.step(b, ds);
        if (outcome.point) {
          branch = std::move(outcome.point);
          break;
        }
      }
      if (!branch)
        return finish(
            TraceTermination::solver_failure,
            fmt::format("no point found on the bifurcated branch at lambda = {:.10g}: {}", b.lambda, counts()));
      if (!record_point(set, polish(set, *branch)))
        return finish(TraceTermination::solver_failure, not_certified + ": " + counts());
      point = std::move(branch);
      if (amplitude_reached) return finish(TraceTermination::completed, amplitude_message());
      continue;
    }
    return finish(TraceTermination::solver_failure, run.message + ": " + counts());
  }
}

}  // namespace liftoff::continuation
