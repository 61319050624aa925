#include "stability/critical_load.hpp"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include "stability/geometric_stiffness.hpp"

namespace liftoff::stability {

namespace {

constexpr EnumName<NodeContact> node_contact_names[] = {
    {NodeContact::in_contact, "in_contact"},
    {NodeContact::lifted, "lifted"},
    {NodeContact::weakly_active, "weakly_active"},
};
constexpr EnumName<EigenMethod> eigen_method_names[] = {
    {EigenMethod::automatic, "automatic"},
    {EigenMethod::dense, "dense"},
    {EigenMethod::sparse, "sparse"},
};
constexpr EnumName<StabilityTermination> termination_names[] = {
    {StabilityTermination::critical_load_found, "critical_load_found"},
    {StabilityTermination::stable_for_all_factors, "stable_for_all_factors"},
    {StabilityTermination::unstable_at_zero, "unstable_at_zero"},
    {StabilityTermination::not_converged, "not_converged"},
};

using Sparse = Eigen::SparseMatrix<double>;
using SpringSet = std::vector<bool>;  // per reaction node

// The rows of the reactions in `set`, as a selection matrix (|S| x reactions).
Sparse selection(const SpringSet& set) {
  std::vector<Eigen::Triplet<double>> entries;
  int row = 0;
  for (int i = 0; i < static_cast<int>(set.size()); ++i)
    if (set[i]) entries.emplace_back(row++, i, 1.0);
  Sparse p(row, static_cast<Eigen::Index>(set.size()));
  p.setFromTriplets(entries.begin(), entries.end());
  return p;
}

enum class PairStatus { ok, not_positive_definite, no_positive_eigenvalue, not_converged };

// The smallest positive eigenpair of (K + K_S) phi = N K_g phi on one spring set (lambda holds N).
struct EigenPair {
  PairStatus status = PairStatus::not_converged;
  std::string reason;
  double lambda = std::numeric_limits<double>::quiet_NaN();
  Eigen::VectorXd phi;
  double residual = -1.0;
};

// What one spring set's problem needs, built once per solve: B = K, G = K_g. Its eigenvalues are
// the critical axial forces N of the set, (K + K_S) phi = N K_g phi: K + K_S is positive
// semidefinite whatever the loads, and N = N_dead + lambda N_live turns them into load factors.
struct Problem {
  const fe::Discretisation& d;
  Sparse b, g;  // K and K_g: the set's eigenvalues are axial forces N
  const CriticalLoadOptions& options;
  EigenMethod method;
  int iterations = 0, factorisations = 0;

  EigenPair solve(const SpringSet& set) { return method == EigenMethod::dense ? solve_dense(set) : solve_sparse(set); }

  EigenPair solve_dense(const SpringSet& set) {
    EigenPair pair;
    const Sparse p = selection(set);
    Eigen::MatrixXd b_s = Eigen::MatrixXd(b);
    if (p.rows() > 0) {
      const Sparse t_ss = p * d.flexibility * p.transpose();
      const Eigen::MatrixXd c_s = Eigen::MatrixXd(p * d.coupling);
      const Eigen::LLT<Eigen::MatrixXd> t_factor{Eigen::MatrixXd(t_ss)};
      b_s += c_s.transpose() * t_factor.solve(c_s);
    }
    b_s = 0.5 * (b_s + b_s.transpose()).eval();
    ++factorisations;
    if (Eigen::LLT<Eigen::MatrixXd>(b_s).info() != Eigen::Success) {
      pair.status = PairStatus::not_positive_definite;
      return pair;
    }
    const Eigen::MatrixXd g_dense = Eigen::MatrixXd(g);
    // mu = 1 / N of K_g phi = mu B_S phi, B_S = K + K_S: B_S definite, K_g only semidefinite.
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(g_dense, b_s);
    if (solver.info() != Eigen::Success) {
      pair.reason = "the dense generalized eigensolver failed";
      return pair;
    }
    const Eigen::Index last = solver.eigenvalues().size() - 1;
    const double mu = solver.eigenvalues()(last);
    // mu is positive beyond round-off when G has a positive direction: its size relative to the
    // eigenvalues' spread (|mu| ~ eps max|mu| is G's null space).
    if (!(mu > 64 * std::numeric_limits<double>::epsilon() * solver.eigenvalues().cwiseAbs().maxCoeff()) || mu <= 0) {
      pair.status = PairStatus::no_positive_eigenvalue;
      return pair;
    }
    pair.status = PairStatus::ok;
    pair.lambda = 1.0 / mu;
    pair.phi = solver.eigenvectors().col(last);
    const Eigen::VectorXd b_phi = b_s * pair.phi;
    pair.residual = (b_phi - pair.lambda * (g_dense * pair.phi)).norm() / b_phi.norm();
    return pair;
  }

  // The saddle-point matrix of the set in the discretisation's mixed form (K = G_s^T H^-1 G_s,
  // fe/discretisation.hpp), unknowns (stresses, u, reactions):
  //   [ -H     G_s         0     ]
  //   [ G_s^T  -sigma K_g  C_S^T ]
  //   [ 0      C_S         -T_SS ]
  // whose Schur complement on u is K + K_S - sigma K_g. The stiffness form [K - sigma K_g, C_S^T;
  // C_S, -T_SS] (LDL^T) left the eigenvalue 8e-8 off at 2000 elements and 3e-5 at 4000, and lost
  // the foundation at 1e4 (k h beside 12/h^3: it found 9.92 for 64.81); this form's condition
  // grows like N^2, and its answer at 1e4 elements agrees with 500's to 1e-10.
  Sparse mixed_saddle(const Sparse& c_s, const Sparse& t_ss, double sigma) const {
    const Eigen::Index ns = d.stresses(), n = b.rows(), s = c_s.rows();
    const Sparse& g_s = d.stress_coupling;
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(
        static_cast<std::size_t>(ns + 2 * g_s.nonZeros() + g.nonZeros() + 2 * c_s.nonZeros() + t_ss.nonZeros()));
    for (Eigen::Index i = 0; i < ns; ++i) entries.emplace_back(i, i, -d.compliance[i]);
    for (Eigen::Index k = 0; k < g_s.outerSize(); ++k)
      for (Sparse::InnerIterator it(g_s, k); it; ++it) {
        entries.emplace_back(it.row(), ns + it.col(), it.value());
        entries.emplace_back(ns + it.col(), it.row(), it.value());
      }
    const Sparse axial = -sigma * g;
    for (Eigen::Index k = 0; k < axial.outerSize(); ++k)
      for (Sparse::InnerIterator it(axial, k); it; ++it) entries.emplace_back(ns + it.row(), ns + it.col(), it.value());
    for (Eigen::Index k = 0; k < c_s.outerSize(); ++k)
      for (Sparse::InnerIterator it(c_s, k); it; ++it) {
        entries.emplace_back(ns + n + it.row(), ns + it.col(), it.value());
        entries.emplace_back(ns + it.col(), ns + n + it.row(), it.value());
      }
    for (Eigen::Index k = 0; k < t_ss.outerSize(); ++k)
      for (Sparse::InnerIterator it(t_ss, k); it; ++it)
        entries.emplace_back(ns + n + it.row(), ns + n + it.col(), -it.value());
    Sparse m(ns + n + s, ns + n + s);
    m.setFromTriplets(entries.begin(), entries.end());
    return m;
  }

  // The mixed form's sparse LU (COLAMD, partial pivoting: the matrix is indefinite). Its
  // determinant's sign is (-1)^(stresses + |S|) times that of K + K_S - sigma K_g, whose sign is the
  // parity of the number of eigenvalues below sigma (a Sturm count, modulo 2; Eigen has no
  // sparse symmetric-indefinite factorisation with pivoting that would give the count itself).
  using Lu = Eigen::SparseLU<Sparse, Eigen::COLAMDOrdering<int>>;
  // Factorises at sigma; the parity (0, 1) of the eigenvalues below sigma, -1 on failure.
  int factorise(Lu& lu, const Sparse& c_s, const Sparse& t_ss, double sigma) {
    ++factorisations;
    lu.factorize(mixed_saddle(c_s, t_ss, sigma));
    if (lu.info() != Eigen::Success) return -1;
    const double sign = lu.signDeterminant();
    if (sign == 0.0) return -1;
    const bool flipped = ((d.stresses() + c_s.rows()) % 2) != 0;
    return (sign < 0.0) != flipped ? 1 : 0;
  }

  EigenPair solve_sparse(const SpringSet& set) {
    EigenPair pair;
    const Sparse p = selection(set);
    const Sparse c_s = p * d.coupling;
    const Sparse t_ss = p * d.flexibility * p.transpose();
    const Eigen::Index n = b.rows();
    Lu lu;
    lu.analyzePattern(mixed_saddle(c_s, t_ss, 0.0));
    double sigma = 0.0;
    // K + K_S is semidefinite: a failed factorisation at sigma = 0 is a singular one, a rigid
    // motion the springs leave free.
    if (factorise(lu, c_s, t_ss, sigma) != 0) {
      pair.status = PairStatus::not_positive_definite;
      return pair;
    }
    const Eigen::Index m = std::min<Eigen::Index>(options.block_size, n);
    std::mt19937 generator(15);  // a fixed start: the same answer on every run
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    Eigen::MatrixXd x(n, m);
    for (Eigen::Index j = 0; j < m; ++j)
      for (Eigen::Index i = 0; i < n; ++i) x(i, j) = uniform(generator);
    const Eigen::Index ns = d.stresses();
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(ns + n + c_s.rows(), m);
    double previous = std::numeric_limits<double>::infinity();
    int stalled = 0;  // iterations in a row that did not lower the residual by a tenth
    for (int iteration = 1; iteration <= options.max_iterations; ++iteration) {
      ++iterations;
      const Eigen::MatrixXd gx = g * x;
      rhs.middleRows(ns, n) = gx;
      const Eigen::MatrixXd y = lu.solve(rhs).middleRows(ns, n);  // (K + K_S - sigma K_g) y = K_g x
      Eigen::MatrixXd a_p = y.transpose() * gx, g_p = y.transpose() * (g * y);
      a_p = 0.5 * (a_p + a_p.transpose()).eval();
      g_p = 0.5 * (g_p + g_p.transpose()).eval();
      // nu = 1 / (N - sigma), the largest first: the smallest N above sigma.
      const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ritz(g_p, a_p);
      if (ritz.info() != Eigen::Success) {
        pair.reason = "the Rayleigh-Ritz projection lost rank";
        return pair;
      }
      const double nu = ritz.eigenvalues()(m - 1);
      if (!(nu > 0.0)) {
        pair.status = PairStatus::no_positive_eigenvalue;
        return pair;
      }
      const Eigen::MatrixXd c = ritz.eigenvectors().rowwise().reverse();
      const double lambda = sigma + 1.0 / nu;
      // (K + K_S - sigma K_g) y c1 = K_g x c1, so the residual needs no K_S.
      const Eigen::VectorXd phi = y * c.col(0), g_phi = g * phi;
      const Eigen::VectorXd b_phi = gx * c.col(0) + sigma * g_phi;
      const double residual = (b_phi - lambda * g_phi).norm() / b_phi.norm();
      x = y * c;
      stalled = residual < 0.9 * previous ? 0 : stalled + 1;
      previous = residual;
      // The residual stalls at round-off; below sqrt(tolerance) that is the answer, reported
      // with its residual.
      const bool at_round_off = stalled >= 5 && residual <= std::sqrt(options.tolerance);
      if (residual <= options.tolerance || at_round_off) {
        // Sturm check: no eigenvalue of the set below lambda (1 - margin).
        const double below = lambda * (1.0 - options.sturm_margin);
        if (below > sigma && factorise(lu, c_s, t_ss, below) != 0) {
          pair.reason = fmt::format("an eigenvalue below the converged {:.10g} was missed (Sturm parity)", lambda);
          return pair;
        }
        pair.status = PairStatus::ok;
        pair.lambda = lambda;
        pair.phi = phi;
        pair.residual = residual;
        return pair;
      }
      // Shift towards lambda once the mode is close; the Sturm parity keeps sigma below the
      // smallest eigenvalue (a Ritz value is an upper bound, not a bracket; passing two at once
      // would need both missing from the block).
      if (residual < 1e-3 && stalled == 0) {
        double step = 0.9 * (lambda - sigma);
        int count = -1;
        for (int attempt = 0; attempt < 3 && count != 0; ++attempt, step *= 0.5)
          count = factorise(lu, c_s, t_ss, sigma + step);
        if (count == 0)
          sigma += 2.0 * step;  // the last halving was one too many
        else if (factorise(lu, c_s, t_ss, sigma) != 0) {
          pair.reason = "the sparse LU failed at a shift already accepted";
          return pair;
        }
      }
    }
    pair.reason = fmt::format("the subspace iteration did not converge in {} iterations", options.max_iterations);
    return pair;
  }
};

// The cone's conditions on a mode of the set: which weakly active nodes break them, in the
// orientation breaking fewer (ties: the smaller worst breach).
struct ConeCheck {
  double sign = 1.0;
  std::vector<int> violations;  // weakly active reaction nodes whose spring must flip
};

ConeCheck check_cone(const fe::Discretisation& d, const std::vector<NodeContact>& contact, const SpringSet& set,
                     const Eigen::VectorXd& phi, double tolerance) {
  const Eigen::VectorXd c_phi = d.coupling * phi;
  const Sparse p = selection(set);
  Eigen::VectorXd reaction = Eigen::VectorXd::Zero(d.reactions());
  if (p.rows() > 0) {
    const Sparse t_ss = p * d.flexibility * p.transpose();
    const Eigen::SimplicialLLT<Sparse> t_factor(t_ss);
    reaction = p.transpose() * t_factor.solve(Eigen::VectorXd(p * c_phi));
  }
  const Eigen::VectorXd gap = d.flexibility * reaction - c_phi;
  const double reaction_scale = std::max(reaction.lpNorm<Eigen::Infinity>(), std::numeric_limits<double>::min());
  const double gap_scale = std::max(c_phi.lpNorm<Eigen::Infinity>(), std::numeric_limits<double>::min());
  ConeCheck best;
  double best_worst = std::numeric_limits<double>::infinity();
  for (double sign : {1.0, -1.0}) {
    ConeCheck check{sign, {}};
    double worst = 0.0;
    for (int i = 0; i < d.reactions(); ++i) {
      if (contact[i] != NodeContact::weakly_active) continue;
      const double breach = set[i] ? -sign * reaction[i] / reaction_scale : -sign * gap[i] / gap_scale;
      if (breach > tolerance) check.violations.push_back(i), worst = std::max(worst, breach);
    }
    if (sign > 0 || check.violations.size() < best.violations.size() ||
        (check.violations.size() == best.violations.size() && worst < best_worst))
      best = check, best_worst = worst;
  }
  return best;
}

}  // namespace

std::string_view to_string(NodeContact v) { return name_in<NodeContact>(node_contact_names, v); }
std::string_view to_string(EigenMethod v) { return name_in<EigenMethod>(eigen_method_names, v); }
std::string_view to_string(StabilityTermination v) { return name_in<StabilityTermination>(termination_names, v); }

std::vector<NodeContact> classify_contact(const Eigen::VectorXd& reaction, const Eigen::VectorXd& gap,
                                          double tolerance) {
  if (reaction.size() != gap.size())
    throw std::invalid_argument(fmt::format("classify_contact: {} reactions but {} gaps", reaction.size(), gap.size()));
  if (!(tolerance >= 0.0 && tolerance < 1.0))
    throw std::invalid_argument("classify_contact: tolerance must lie in [0, 1)");
  if (!reaction.allFinite() || !gap.allFinite())
    throw std::invalid_argument("classify_contact: reactions and gaps must be finite");
  const double reaction_scale = tolerance * reaction.lpNorm<Eigen::Infinity>();
  const double gap_scale = tolerance * gap.lpNorm<Eigen::Infinity>();
  std::vector<NodeContact> contact(static_cast<std::size_t>(reaction.size()));
  for (Eigen::Index i = 0; i < reaction.size(); ++i)
    contact[i] = reaction[i] > reaction_scale ? NodeContact::in_contact
                 : gap[i] > gap_scale         ? NodeContact::lifted
                                              : NodeContact::weakly_active;
  return contact;
}

void CriticalLoadOptions::validate() const {
  auto fail = [](const char* what) { throw std::invalid_argument(std::string("CriticalLoadOptions: ") + what); };
  if (dense_limit < 0) fail("dense_limit must be >= 0");
  if (block_size < 1) fail("block_size must be >= 1");
  if (max_iterations < 1) fail("max_iterations must be >= 1");
  if (!(tolerance > 0.0 && tolerance < 1.0)) fail("tolerance must lie in (0, 1)");
  if (!(sturm_margin > 0.0 && sturm_margin < 1.0)) fail("sturm_margin must lie in (0, 1)");
  if (!(sign_tolerance >= 0.0 && sign_tolerance < 1.0)) fail("sign_tolerance must lie in [0, 1)");
  if (max_set_iterations < 1) fail("max_set_iterations must be >= 1");
  if (enumeration_limit < 0 || enumeration_limit > 20) fail("enumeration_limit must lie in [0, 20]");
}

double CriticalLoadResult::critical_axial_force() const {
  return dead_axial_force + critical_load_factor * live_axial_force;
}

std::string CriticalLoadResult::brief_report() const {
  return fmt::format("stability: {} (lambda_cr {:.10g}, bounds [{:.10g}, {:.10g}], {} sets, {} iterations, {}): {}",
                     to_string(termination), critical_load_factor, lower_bound, upper_bound, set_iterations,
                     eigen_iterations, to_string(method), message);
}

CriticalLoadResult critical_load(const fe::Discretisation& d, double dead_axial_force, double live_axial_force,
                                 const std::vector<NodeContact>& contact, const CriticalLoadOptions& options) {
  return critical_load(d, geometric_stiffness(d), dead_axial_force, live_axial_force, contact, options);
}

CriticalLoadResult critical_load(const fe::Discretisation& d, const Sparse& geometric, double dead_axial_force,
                                 double live_axial_force, const std::vector<NodeContact>& contact,
                                 const CriticalLoadOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  options.validate();
  if (d.kind != model::StructureKind::beam) throw std::invalid_argument("critical_load: beams only");
  if (geometric.rows() != d.equations || geometric.cols() != d.equations)
    throw std::invalid_argument(fmt::format("critical_load: the geometric stiffness is {} x {}, the equations {}",
                                            geometric.rows(), geometric.cols(), d.equations));
  if (static_cast<int>(contact.size()) != d.reactions())
    throw std::invalid_argument(
        fmt::format("critical_load: {} contact states for {} reaction nodes", contact.size(), d.reactions()));
  if (!std::isfinite(dead_axial_force) || !std::isfinite(live_axial_force))
    throw std::invalid_argument("critical_load: the axial forces must be finite");

  CriticalLoadResult result;
  result.contact = contact;
  result.dead_axial_force = dead_axial_force;
  result.live_axial_force = live_axial_force;
  result.method = options.method != EigenMethod::automatic ? options.method
                  : d.equations <= options.dense_limit     ? EigenMethod::dense
                                                           : EigenMethod::sparse;
  // B = K without the axial force: a discretisation under N holds K(N) = K - N K_g in `stiffness`
  // (fe/discretisation.hpp), which would count N twice here (the mixed form of the sparse path is
  // K's alone); N K_g is added back with the K_g that was subtracted.
  Sparse bare = d.stiffness;
  if (d.has_axial_force()) bare += d.axial_force * d.geometric_stiffness;
  Problem problem{d, std::move(bare), geometric, options, result.method};
  auto finish = [&](StabilityTermination termination, std::string message) {
    result.termination = termination;
    result.message = std::move(message);
    result.eigen_iterations = problem.iterations;
    result.factorisations = problem.factorisations;
    result.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
  };

  SpringSet in_contact(contact.size()), every(contact.size());
  std::vector<int> weak;
  for (int i = 0; i < d.reactions(); ++i) {
    in_contact[i] = contact[i] == NodeContact::in_contact;
    every[i] = contact[i] != NodeContact::lifted;
    if (contact[i] == NodeContact::weakly_active) weak.push_back(i);
  }
  result.set_iterations = 1;
  const EigenPair fewest = problem.solve(in_contact);
  if (fewest.status == PairStatus::not_positive_definite) {
    if (weak.empty() || problem.solve(every).status == PairStatus::not_positive_definite)
      return finish(StabilityTermination::unstable_at_zero,
                    "K + K_S is singular: a rigid motion no spring holds buckles under any compression");
    return finish(StabilityTermination::not_converged,
                  "K + K_S is singular without the weakly active springs but not with them: stability at N = 0 "
                  "depends on the cone, which this solver does not decide");
  }
  if (fewest.status == PairStatus::no_positive_eigenvalue)
    return finish(StabilityTermination::stable_for_all_factors, "K_g vanishes on the free motions");
  if (fewest.status != PairStatus::ok) return finish(StabilityTermination::not_converged, fewest.reason);
  // The sets' eigenvalues are axial forces; the bounds of the cone's critical force.
  const double force_lower = fewest.lambda;
  double force_upper = fewest.lambda;
  if (!weak.empty()) {
    const EigenPair most = problem.solve(every);
    if (most.status != PairStatus::ok) return finish(StabilityTermination::not_converged, most.reason);
    force_upper = most.lambda;
  }

  auto accept = [&](const SpringSet& set, const EigenPair& pair, double sign, std::string how) {
    result.spring = set;
    result.residual = pair.residual;
    Eigen::VectorXd mode = sign * pair.phi;
    double largest = 0.0;
    for (int dof = 0; dof < d.dofs(); ++dof)
      if (d.equation_of_dof[dof] >= 0 && d.role_of_dof(dof) == fe::DofRole::deflection)
        largest = std::max(largest, std::abs(mode[d.equation_of_dof[dof]]));
    result.mode = mode / (largest > 0.0 ? largest : mode.lpNorm<Eigen::Infinity>());
    // N_cr = N_dead + lambda N_live.
    const double force = pair.lambda;
    if (force <= dead_axial_force)
      return finish(
          StabilityTermination::unstable_at_zero,
          fmt::format("the critical axial force {:.10g} is below the dead one {:.10g}: unstable at lambda = 0 "
                      "({})",
                      force, dead_axial_force, how));
    if (live_axial_force <= 0.0)
      return finish(StabilityTermination::stable_for_all_factors,
                    fmt::format("N_live <= 0 never reaches the critical axial force {:.10g} ({})", force, how));
    result.critical_load_factor = (force - dead_axial_force) / live_axial_force;
    result.lower_bound = (force_lower - dead_axial_force) / live_axial_force;
    result.upper_bound = (force_upper - dead_axial_force) / live_axial_force;
    return finish(StabilityTermination::critical_load_found, std::move(how));
  };

  // The fixed point, from the fewest springs.
  std::vector<SpringSet> visited{in_contact};
  SpringSet set = in_contact;
  EigenPair pair = fewest;
  for (int iteration = 1; iteration <= options.max_set_iterations; ++iteration) {
    const ConeCheck check = check_cone(d, contact, set, pair.phi, options.sign_tolerance);
    if (check.violations.empty())
      return accept(set, pair, check.sign,
                    fmt::format("the mode meets the cone's conditions on spring set {} of the iteration", iteration));
    for (int i : check.violations) set[i] = !set[i];
    if (std::find(visited.begin(), visited.end(), set) != visited.end()) break;  // a cycle
    visited.push_back(set);
    ++result.set_iterations;
    pair = problem.solve(set);
    if (pair.status != PairStatus::ok)
      return finish(StabilityTermination::not_converged, "on a spring set of the iteration: " + pair.reason);
  }

  if (static_cast<int>(weak.size()) > options.enumeration_limit)
    return finish(StabilityTermination::not_converged,
                  fmt::format("the spring-set iteration did not reach a fixed point and {} weakly active nodes are "
                              "more than enumeration_limit {}",
                              weak.size(), options.enumeration_limit));
  // Enumerate: the smallest admissible eigenpair over every subset of the weak springs.
  std::optional<std::pair<SpringSet, EigenPair>> best;
  double best_sign = 1.0;
  for (unsigned long mask = 0; mask < (1ul << weak.size()); ++mask) {
    SpringSet trial = in_contact;
    for (std::size_t j = 0; j < weak.size(); ++j) trial[weak[j]] = ((mask >> j) & 1ul) != 0;
    ++result.set_iterations;
    const EigenPair candidate = problem.solve(trial);
    if (candidate.status != PairStatus::ok) continue;
    const ConeCheck check = check_cone(d, contact, trial, candidate.phi, options.sign_tolerance);
    if (check.violations.empty() && (!best || candidate.lambda < best->second.lambda))
      best.emplace(trial, candidate), best_sign = check.sign;
  }
  if (!best)
    return finish(StabilityTermination::not_converged,
                  "no spring set of the weakly active nodes has an admissible smallest mode");
  return accept(best->first, best->second, best_sign,
                fmt::format("the smallest admissible mode of {} enumerated spring sets", 1ul << weak.size()));
}

}  // namespace liftoff::stability

namespace liftoff {
template <>
std::optional<stability::NodeContact> from_string(std::string_view name) {
  return value_in<stability::NodeContact>(stability::node_contact_names, name);
}
template <>
std::optional<stability::EigenMethod> from_string(std::string_view name) {
  return value_in<stability::EigenMethod>(stability::eigen_method_names, name);
}
template <>
std::optional<stability::StabilityTermination> from_string(std::string_view name) {
  return value_in<stability::StabilityTermination>(stability::termination_names, name);
}
}  // namespace liftoff
