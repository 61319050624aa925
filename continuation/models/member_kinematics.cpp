#include "continuation/models/member_kinematics.hpp"

// Why things are done the way they are:
//  - The second-order tangent is K(N(lambda)) = K(N(1)) - (N(lambda) - N(1)) K_g from the
//    assembled K_g (no second element loop), as the beam-column path always formed it.
//  - The lift-off load of a member only the foundation holds is decided on the exact rigid motions
//    (discretise's, not K's kernel): near that load the loads' work on those motions is a tiny
//    residue of large, nearly balancing terms, which a kernel computed to eps cond(K) would drown.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "contact/contact_solver.hpp"
#include "contact/von_karman_solve.hpp"
#include "continuation/models/fe_states.hpp"
#include "continuation/step_state.hpp"
#include "lcp/lemke.hpp"
#include "stability/critical_load.hpp"

namespace liftoff::continuation {

using Eigen::VectorXd;
using SparseMatrix = Eigen::SparseMatrix<double>;

MemberKinematics::MemberKinematics(const model::MemberModel& member, int elements)
    : member_(member), d_(fe::discretise(member, elements)) {}

namespace {

// The contact set of a contact solve at lambda on `d` (method: dual or primal as asked, else fast).
KinematicsStart contact_start(const fe::Discretisation& d, double lambda, contact::Method asked) {
  KinematicsStart out;
  const contact::ContactSolution solution = fe_states::contact_solve(d, asked, lambda);
  out.contact_solves = 1;
  out.method = solution.summary.method;
  if (!solution.summary.is_usable()) {
    out.no_equilibrium = solution.summary.termination == contact::ContactTermination::no_equilibrium;
    out.why = fmt::format("the contact solver at lambda = {:.10g}: {}", lambda, solution.summary.message);
    return out;
  }
  // A bilateral foundation holds every node, whatever the reaction's sign.
  out.in_contact = d.tensionless ? fe_states::contact_set_of(d, solution) : std::vector<bool>(d.reactions(), true);
  out.x = d.on_equations(solution.displacement);
  out.reaction = solution.reaction;
  return out;
}

// The typical size of each displacement unknown for deflections of w_ref: w_ref for w and u, and
// w_ref / h for a slope (a slope is a deflection over the element; measured as w' itself it would
// weigh a localised buckle's shape by 1 / h and its steps would shrink with the mesh).
VectorXd displacement_sizes(const fe::Discretisation& d, double w_ref) {
  VectorXd sizes = VectorXd::Constant(d.equations, w_ref);
  double h = std::numeric_limits<double>::infinity();
  for (int e = 0; e < d.mesh.elements(); ++e) h = std::min(h, d.mesh.element_size(e));
  for (int dof = 0; dof < d.dofs(); ++dof)
    if (const int eq = d.equation_of_dof[dof]; eq >= 0 && d.role_of_dof(dof) == fe::DofRole::slope)
      sizes[eq] = w_ref / h;
  return sizes;
}

// A start on the mixed form's unknowns: the stresses m = H^-1 G u of its displacement.
KinematicsStart complete(KinematicsStart start, const fe::Discretisation& d) {
  if (start.x.size() == d.equations) {
    VectorXd x(d.equations + d.stresses());
    x.head(d.equations) = start.x;
    x.tail(d.stresses()) = (d.stress_coupling * start.x).cwiseQuotient(d.compliance);
    start.x = std::move(x);
  }
  return start;
}

// The linear and the second-order member (N = 0 for the linear one) in the mixed form of the
// contact system (contact/active_set_system.hpp): x = (u, m), the element stress resultants
// m = H^-1 G u beside the displacement, so that the saddle matrix
//   [ -N(lambda) K_g   G^T   C_A^T ]
//   [  G              -H     0     ]
//   [  C_A             0    -T_AA  ]
// has a condition growing like N^2 where the primal [K C_A^T; C_A -T_AA]'s grows like N^4 (the
// footing trace at 200 elements: 3.8e-6 relative in the final deflection with the primal form,
// against the exact path's round-off).
class SmallDisplacementKinematics : public MemberKinematics {
 public:
  SmallDisplacementKinematics(const model::MemberModel& member, int elements)
      : MemberKinematics(member, elements),
        axial_(member.kind == model::StructureKind::beam && member.has_axial_force()),
        at_(d_) {}
  int unknowns() const override { return d_.equations + d_.stresses(); }
  SparseMatrix stiffness(const VectorXd&, double lambda) const override {
    return axial_ ? SparseMatrix(d_.stiffness - (member_.axial_force(lambda) - d_.axial_force) * d_.geometric_stiffness)
                  : d_.stiffness;
  }
  bool convex() const override { return !axial_; }
  bool linear_in_state() const override { return !axial_; }
  bool measured_by_certificate() const override { return false; }
  bool straight_bifurcated_branch() const override { return axial_; }
  bool force(const VectorXd& x, double lambda, VectorXd& f) const override {
    const int n = d_.equations;
    const auto u = x.head(n), m = x.tail(d_.stresses());
    f.resize(x.size());
    f.head(n) = d_.stress_coupling.transpose() * m - d_.load(lambda);
    if (axial_) f.head(n) -= member_.axial_force(lambda) * (d_.geometric_stiffness * u);
    f.tail(d_.stresses()) = d_.stress_coupling * u - d_.compliance.cwiseProduct(m);
    return f.allFinite();
  }
  SparseMatrix tangent(const VectorXd&, double lambda) const override;
  VectorXd lambda_derivative(const VectorXd& x, double) const override {
    VectorXd g = VectorXd::Zero(x.size());
    g.head(d_.equations) = -d_.live_load;
    if (axial_) g.head(d_.equations) -= member_.axial_live * (d_.geometric_stiffness * x.head(d_.equations));
    return g;
  }
  VectorXd load(double lambda) const override {
    VectorXd f = VectorXd::Zero(unknowns());
    f.head(d_.equations) = d_.load(lambda);
    return f;
  }
  VectorXd typical(double w_ref) const override {
    VectorXd t(unknowns());
    t.head(d_.equations) = displacement_sizes(d_, w_ref);
    // m = H^-1 G u: its size for |u| ~ those.
    const VectorXd g = SparseMatrix(d_.stress_coupling.cwiseAbs()) * t.head(d_.equations);
    t.tail(d_.stresses()) = g.cwiseQuotient(d_.compliance).cwiseMax(std::numeric_limits<double>::min());
    return t;
  }
  VectorXd metric(double w_ref) const override {
    // The displacement's root mean square over its typical size; the stresses (which follow from
    // it) 1e-3 less.
    const VectorXd t = typical(w_ref);
    VectorXd scale(unknowns());
    const double rms_u = 1.0 / std::sqrt(static_cast<double>(d_.equations));
    const double rms_m = 1.0 / std::sqrt(static_cast<double>(std::max(d_.stresses(), 1)));
    scale.head(d_.equations) = rms_u * t.head(d_.equations).cwiseInverse();
    scale.tail(d_.stresses()) = 1e-3 * rms_m * t.tail(d_.stresses()).cwiseInverse();
    return scale;
  }
  double axial_force(const VectorXd&, double lambda) const override {
    return axial_ ? member_.axial_force(lambda) * member_.scales.force() : 0.0;
  }
  certify::Certificate certificate(const VectorXd& x, const VectorXd& reaction, double lambda,
                                   double sign_floor) const override {
    return fe_states::certificate_of(member_, at(lambda), lambda, d_.expand_displacement(x.head(d_.equations)),
                                     reaction, sign_floor);
  }
  void record_state(TraceStep& step, const VectorXd& x, const VectorXd& reaction, double lambda,
                    const certify::Certificate* certificate) const override {
    const VectorXd displacement = d_.expand_displacement(x.head(d_.equations));
    record_fe_state(step, member_, at(lambda), lambda, displacement, reaction,
                    certificate ? *certificate : this->certificate(x, reaction, lambda, 0.0));
  }
  KinematicsStart solve(double lambda, contact::Method method) const override;
  std::optional<ConeVerdict> cone(const std::vector<stability::NodeContact>& contact, double lambda) const override;
  std::optional<double> lift_off_load(double from, double to, double tolerance) const override;

 private:
  // Can compressive reactions balance the loads' work on the free rigid motions at lambda?
  bool rigid_motions_balanced(double lambda) const;
  Eigen::MatrixXd free_motions() const;
  // The discretisation assembled at lambda (K(N(lambda)), N(lambda)), for the certificate and the cone.
  const fe::Discretisation& at(double lambda) const {
    if (axial_ && member_.axial_force(lambda) != at_.axial_force) {
      at_.stiffness = d_.stiffness - (member_.axial_force(lambda) - d_.axial_force) * d_.geometric_stiffness;
      at_.axial_force = member_.axial_force(lambda);
    }
    return at_;
  }
  bool axial_ = false;
  mutable fe::Discretisation at_;
};

SparseMatrix SmallDisplacementKinematics::tangent(const VectorXd&, double lambda) const {
  const int n = d_.equations, s = d_.stresses();
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(2 * d_.stress_coupling.nonZeros() + s + (axial_ ? d_.geometric_stiffness.nonZeros() : 0));
  if (axial_) {
    const double axial = member_.axial_force(lambda);
    for (int k = 0; k < d_.geometric_stiffness.outerSize(); ++k)
      for (SparseMatrix::InnerIterator it(d_.geometric_stiffness, k); it; ++it)
        t.emplace_back(it.row(), it.col(), -axial * it.value());
  }
  for (int k = 0; k < d_.stress_coupling.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(d_.stress_coupling, k); it; ++it) {
      t.emplace_back(n + it.row(), it.col(), it.value());
      t.emplace_back(it.col(), n + it.row(), it.value());
    }
  for (int i = 0; i < s; ++i) t.emplace_back(n + i, n + i, -d_.compliance[i]);
  SparseMatrix a(n + s, n + s);
  a.setFromTriplets(t.begin(), t.end());
  return a;
}

KinematicsStart SmallDisplacementKinematics::solve(double lambda, contact::Method method) const {
  if (!axial_) return complete(contact_start(d_, lambda, method), d_);
  // The contact solver on the member with N(lambda) as a dead load (the same equations at lambda).
  model::MemberModel fixed = member_;
  fixed.axial_dead = member_.axial_force(lambda);
  fixed.axial_live = 0.0;
  return complete(contact_start(fe::discretise(fixed, d_.mesh.elements()), lambda, method), d_);
}

Eigen::MatrixXd SmallDisplacementKinematics::free_motions() const {
  const int k = d_.unstable_rigid_motions, n = d_.equations;
  const Eigen::MatrixXd& z = d_.free_rigid_motions;
  const double largest = std::max(1.0, d_.stiffness.diagonal().cwiseAbs().maxCoeff());
  if (z.cols() != k || !((d_.stiffness * z).lpNorm<Eigen::Infinity>() <= 1e-8 * largest * z.lpNorm<Eigen::Infinity>()))
    return Eigen::MatrixXd(n, 0);
  return Eigen::HouseholderQR<Eigen::MatrixXd>(z).householderQ() * Eigen::MatrixXd::Identity(n, k);
}

// Is b = Z^T F in the cone of the columns a_i = Z^T C^T e_i (what a compressive reaction at node i
// does on the motions)? Both normalised. One or two motions (beams): the cone's directions decide
// exactly; three (a free arch): non-negative least squares as an LCP, its residual decides.
bool SmallDisplacementKinematics::rigid_motions_balanced(double lambda) const {
  const int k = d_.unstable_rigid_motions;
  const Eigen::MatrixXd z = free_motions();
  if (k == 0 || z.cols() != k) return true;           // undecided: the path's contact conditions say
  Eigen::MatrixXd a = (d_.coupling * z).transpose();  // k x m
  VectorXd b = z.transpose() * d_.load(lambda);
  if (b.lpNorm<Eigen::Infinity>() == 0.0) return true;
  a /= std::max(a.lpNorm<Eigen::Infinity>(), 1e-300);
  b /= b.lpNorm<Eigen::Infinity>();
  if (k == 1) return ((a.array() * b[0]) > 0.0).any();
  if (k == 2) {
    // A cone in the plane is the plane, or the sector opposite the widest gap between the
    // directions of its generators.
    std::vector<double> angles;
    for (Eigen::Index i = 0; i < a.cols(); ++i)
      if (a.col(i).lpNorm<Eigen::Infinity>() > 1e-14) angles.push_back(std::atan2(a(1, i), a(0, i)));
    if (angles.empty()) return false;
    std::sort(angles.begin(), angles.end());
    double widest = angles.front() + 2 * std::numbers::pi - angles.back();
    double sector_begin = angles.front(), sector_end = angles.back();
    for (std::size_t i = 1; i < angles.size(); ++i)
      if (angles[i] - angles[i - 1] > widest) {
        widest = angles[i] - angles[i - 1];
        sector_begin = angles[i];
        sector_end = angles[i - 1] + 2 * std::numbers::pi;
      }
    if (widest < std::numbers::pi) return true;
    double angle = std::atan2(b[1], b[0]);
    if (angle < sector_begin - 1e-10) angle += 2 * std::numbers::pi;
    return angle >= sector_begin - 1e-10 && angle <= sector_end + 1e-10;
  }
  const lcp::LemkeResult nnls = lcp::solve_lemke(a.transpose() * a, -(a.transpose() * b), {});
  if (nnls.summary.termination != lcp::LemkeTermination::solution) return true;
  return (a * nnls.z - b).lpNorm<Eigen::Infinity>() <= 1e-8;
}

// The loads' work on the free motions is affine in lambda and the reactions span a convex cone,
// so the loads are balanced on one interval of lambda: its end by bisection.
std::optional<double> SmallDisplacementKinematics::lift_off_load(double from, double to, double tolerance) const {
  if (axial_ || d_.structure_is_stable() || !d_.tensionless || rigid_motions_balanced(to)) return std::nullopt;
  double lo = from, hi = to;
  for (int i = 0; i < 200 && std::abs(hi - lo) > tolerance; ++i) {
    const double mid = 0.5 * (lo + hi);
    (rigid_motions_balanced(mid) ? lo : hi) = mid;
  }
  return lo;
}

// The set's tangent decides stability where every node of the set presses and every other one
// stands off. A node touching with neither reaction nor gap (weakly active: a weightless strut on
// its foundation) has a spring only where the perturbation pushes in: the cone's critical load on
// the present N decides, stable when its factor exceeds 1.
std::optional<ConeVerdict> SmallDisplacementKinematics::cone(const std::vector<stability::NodeContact>& contact,
                                                             double lambda) const {
  using stability::NodeContact;
  if (!axial_) return std::nullopt;
  if (std::none_of(contact.begin(), contact.end(), [](NodeContact c) { return c == NodeContact::weakly_active; }))
    return std::nullopt;
  const fe::Discretisation& d = at(lambda);
  const stability::CriticalLoadResult result = stability::critical_load(d, 0.0, d.axial_force, contact);
  ConeVerdict verdict;
  verdict.known = true;
  switch (result.termination) {
    case stability::StabilityTermination::critical_load_found:
      verdict.stable = result.critical_load_factor > 1.0;
      break;
    case stability::StabilityTermination::stable_for_all_factors:
      verdict.stable = true;
      break;
    case stability::StabilityTermination::unstable_at_zero:
      verdict.stable = false;
      break;
    case stability::StabilityTermination::not_converged:
      verdict.known = false;
      break;
  }
  if (result.is_usable()) verdict.springs = result.spring;
  return verdict;
}

class VonKarmanKinematics : public MemberKinematics {
 public:
  VonKarmanKinematics(const model::MemberModel& member, int elements, const VonKarmanLiveLoad& live_load)
      : MemberKinematics(member, elements), system_(member, d_), certified_(!live_load) {
    const int n = system_.unknowns();
    if (live_load) {
      live_ = live_load(d_, system_);
      dead_ = VectorXd::Zero(n);
      if (live_.size() != n)
        throw std::invalid_argument(
            fmt::format("trace_fe_von_karman: live_load has {} entries, expected {}", live_.size(), n));
    } else {
      dead_ = system_.load(0.0);
      live_ = system_.load(1.0) - dead_;
    }
  }
  int unknowns() const override { return system_.unknowns(); }
  bool force(const VectorXd& x, double lambda, VectorXd& f) const override {
    f = system_.internal_force(x) - dead_ - lambda * live_;
    return f.allFinite();
  }
  SparseMatrix tangent(const VectorXd& x, double) const override { return system_.tangent_stiffness(x); }
  VectorXd lambda_derivative(const VectorXd&, double) const override { return -live_; }
  VectorXd load(double lambda) const override { return dead_ + lambda * live_; }
  // The thrust -N as a compressive force: constant along a member with both ends restrained; the
  // mean otherwise.
  double axial_force(const VectorXd& x, double) const override {
    const std::vector<double> forces = system_.normal_forces(x);
    double mean = 0.0;
    for (double f : forces) mean += f;
    if (!forces.empty()) mean /= static_cast<double>(forces.size());
    return -mean * member_.scales.force();
  }
  certify::Certificate certificate(const VectorXd& x, const VectorXd& reaction, double lambda,
                                   double sign_floor) const override {
    const certify::VonKarmanAnswer answer = answer_of(x, reaction);
    certify::CertifyOptions o;
    o.load_factor = lambda;
    o.round_off = false;
    o.pointwise = false;
    o.sign_floor = sign_floor;
    return certify::certify(member_, d_, answer, o);
  }
  KinematicsStart solve(double lambda, contact::Method) const override {
    KinematicsStart out;
    const contact::VonKarmanResult r = system_.solve(dead_ + lambda * live_, contact::VonKarmanOptions{});
    if (!r.is_usable()) {
      out.why = fmt::format("no equilibrium found at lambda = {:.10g}: {}", lambda, r.message);
      return out;
    }
    out.x = r.x;
    out.reaction = r.reaction;
    out.in_contact = r.in_contact;
    return out;
  }
  EventNaming naming() const override { return EventNaming::nodes; }
  double reference_deflection() const override {
    return member_.initial_sine ? std::max(std::abs(member_.initial_sine->amplitude), 1e-6) : 1e-3;
  }
  bool resumable() const override { return false; }
  bool certified() const override { return certified_; }
  void record_state(TraceStep& step, const VectorXd& x, const VectorXd& reaction, double lambda,
                    const certify::Certificate* certificate) const override {
    record_von_karman_state(step, member_, d_, lambda, answer_of(x, reaction), certificate);
  }

 private:
  // The state as its certificate reads it: u at every node and the elements' normal forces beside
  // w and the reactions.
  certify::VonKarmanAnswer answer_of(const VectorXd& x, const VectorXd& reaction) const {
    certify::VonKarmanAnswer answer;
    answer.displacement = d_.expand_displacement(x.head(d_.equations));
    answer.reaction = reaction;
    const int nodes = d_.mesh.elements() + 1;
    answer.axial = VectorXd::Zero(nodes);
    for (int node = 0; node < nodes; ++node)  // an arch's u is a dof of the discretisation
      if (d_.kind == model::StructureKind::arch)
        answer.axial[node] = answer.displacement[d_.tangential_dof(node)];
      else if (const int k = system_.axial_unknown(node); k >= 0)
        answer.axial[node] = x[k];
    answer.normal_force = system_.normal_forces(x);
    return answer;
  }
  contact::VonKarmanSystem system_;
  bool certified_ = true;
  VectorXd dead_, live_;
};

}  // namespace

std::unique_ptr<MemberKinematics> make_kinematics(const model::MemberModel& member, int elements,
                                                  const VonKarmanLiveLoad& live_load) {
  if (member.theory == model::Theory::von_karman)
    return std::make_unique<VonKarmanKinematics>(member, elements, live_load);
  return std::make_unique<SmallDisplacementKinematics>(member, elements);
}

}  // namespace liftoff::continuation
