#include "contact/contact_solver.hpp"

#include <chrono>
#include <cmath>
#include <stdexcept>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#include <fmt/format.h>

#include "core/error.hpp"

namespace liftoff::contact {

using Eigen::MatrixXd;
using Eigen::VectorXd;
using fe::Discretisation;

std::string_view to_string(ContactTermination t) {
  switch (t) {
    case ContactTermination::solved: return "solved";
    case ContactTermination::no_equilibrium: return "no_equilibrium";
    case ContactTermination::pivot_limit: return "pivot_limit";
    case ContactTermination::numerical_failure: return "numerical_failure";
  }
  return "unknown";
}

void ContactOptions::validate() const {
  if (!std::isfinite(load_factor)) throw std::invalid_argument("ContactOptions::load_factor must be finite");
  if (method != Method::dual && method != Method::primal && method != Method::automatic)
    throw std::invalid_argument("ContactOptions::method must be dual, primal or auto (an FE + LCP formulation)");
  lemke.validate();
}

std::string ContactSummary::brief_report() const {
  return fmt::format("{} ({}): {} pivots, residual {:.2e}, {:.3f} s", to_string(termination),
                     scene::to_string(method), pivots, residual, time_s);
}

namespace {

// An answer whose relative residual (see ContactSummary::residual) exceeds this is not returned
// as a solution: at 1e-6 the contact limits are already uncertain to a fraction of an element.
constexpr double acceptable_residual = 1e-6;

// Solution on the equations, before expansion to every dof.
struct Unknowns {
  VectorXd displacement;
  VectorXd reaction;
};

double relative_residual(const Discretisation& d, const Unknowns& x, const VectorXd& load, bool tensionless) {
  const VectorXd support = d.coupling.transpose() * x.reaction;
  const VectorXd stiffness_force = d.stiffness * x.displacement;
  const double force_scale = std::max({load.lpNorm<Eigen::Infinity>(), support.lpNorm<Eigen::Infinity>(),
                                       stiffness_force.lpNorm<Eigen::Infinity>(), 1e-300});
  double residual = (stiffness_force + support - load).lpNorm<Eigen::Infinity>() / force_scale;
  if (d.reactions() == 0) return residual;

  const VectorXd coupled = d.coupling * x.displacement;
  const VectorXd foundation = d.flexibility * x.reaction;
  const VectorXd gap = foundation - coupled;
  const double gap_scale = std::max({coupled.lpNorm<Eigen::Infinity>(), foundation.lpNorm<Eigen::Infinity>(), 1e-300});
  if (!tensionless) return std::max(residual, gap.lpNorm<Eigen::Infinity>() / gap_scale);

  const double reaction_scale = std::max(x.reaction.lpNorm<Eigen::Infinity>(), 1e-300);
  residual = std::max(residual, std::max(0.0, -x.reaction.minCoeff()) / reaction_scale);
  residual = std::max(residual, std::max(0.0, -gap.minCoeff()) / gap_scale);
  residual = std::max(residual, x.reaction.cwiseProduct(gap).cwiseAbs().maxCoeff() / (reaction_scale * gap_scale));
  return residual;
}

ContactTermination termination_of(const lcp::LemkeSummary& summary) {
  switch (summary.termination) {
    case lcp::LemkeTermination::solution: return ContactTermination::solved;
    case lcp::LemkeTermination::ray: return ContactTermination::no_equilibrium;
    case lcp::LemkeTermination::pivot_limit: return ContactTermination::pivot_limit;
    case lcp::LemkeTermination::numerical_failure: return ContactTermination::numerical_failure;
  }
  return ContactTermination::numerical_failure;
}

std::string explain(ContactTermination termination, const lcp::LemkeSummary& lemke) {
  switch (termination) {
    case ContactTermination::solved: return "equilibrium found";
    case ContactTermination::no_equilibrium:
      return "no equilibrium exists: the loads would lift the member off the foundation and the supports "
             "cannot hold it, so it is a mechanism (Lemke ray termination after " +
             std::to_string(lemke.pivots) + " pivots)";
    case ContactTermination::pivot_limit:
      return "Lemke's algorithm reached its pivot limit (" + std::to_string(lemke.pivots) + " pivots) without a solution";
    case ContactTermination::numerical_failure: return "Lemke's algorithm failed numerically: " + lemke.message;
  }
  return lemke.message;
}

struct LcpOutcome {
  Unknowns unknowns;
  lcp::LemkeSummary lemke;
  int size = 0;
};

LcpOutcome solve_dual(const Discretisation& d, const VectorXd& load, const lcp::LemkeOptions& options) {
  Eigen::SimplicialLDLT<fe::SparseMatrix> stiffness(d.stiffness);
  if (stiffness.info() != Eigen::Success)
    throw SolverFailure("the dual form could not factorise the stiffness matrix K; use method = \"primal\"");
  const MatrixXd flexibility_of_structure = stiffness.solve(MatrixXd(d.coupling.transpose()));  // K^-1 C^T
  const MatrixXd p = d.coupling * flexibility_of_structure + MatrixXd(d.flexibility);
  const VectorXd free_displacement = stiffness.solve(load);                                      // K^-1 F
  const VectorXd q = -(d.coupling * free_displacement);

  const lcp::LemkeResult result = lcp::solve_lemke(p, q, options);
  LcpOutcome outcome;
  outcome.lemke = result.summary;
  outcome.size = static_cast<int>(q.size());
  outcome.unknowns.reaction = result.z;
  outcome.unknowns.displacement = free_displacement - flexibility_of_structure * result.z;
  return outcome;
}

LcpOutcome solve_primal(const Discretisation& d, const VectorXd& load, const lcp::LemkeOptions& options) {
  const int n = d.equations, m = d.reactions();
  const MatrixXd k(d.stiffness), c(d.coupling);
  MatrixXd lcp_matrix(2 * n + m, 2 * n + m);
  lcp_matrix << k, -k, c.transpose(),  //
      -k, k, -c.transpose(),           //
      -c, c, MatrixXd(d.flexibility);
  VectorXd q(2 * n + m);
  q << -load, load, VectorXd::Zero(m);

  const lcp::LemkeResult result = lcp::solve_lemke(lcp_matrix, q, options);
  LcpOutcome outcome;
  outcome.lemke = result.summary;
  outcome.size = 2 * n + m;
  outcome.unknowns.displacement = result.z.head(n) - result.z.segment(n, n);
  outcome.unknowns.reaction = result.z.tail(m);
  return outcome;
}

// Bilateral foundation: the saddle-point system [K C^T; C -T] (u, r) = (F, 0).
bool solve_bilateral(const Discretisation& d, const VectorXd& load, Unknowns& x) {
  const int n = d.equations, m = d.reactions();
  std::vector<Eigen::Triplet<double>> entries;
  auto add = [&](const fe::SparseMatrix& block, int row0, int col0, double sign, bool transpose) {
    for (int k = 0; k < block.outerSize(); ++k)
      for (fe::SparseMatrix::InnerIterator it(block, k); it; ++it) {
        const int i = transpose ? it.col() : it.row(), j = transpose ? it.row() : it.col();
        entries.emplace_back(row0 + i, col0 + j, sign * it.value());
      }
  };
  add(d.stiffness, 0, 0, 1.0, false);
  add(d.coupling, 0, n, 1.0, true);
  add(d.coupling, n, 0, 1.0, false);
  add(d.flexibility, n, n, -1.0, false);
  fe::SparseMatrix system(n + m, n + m);
  system.setFromTriplets(entries.begin(), entries.end());
  Eigen::SparseLU<fe::SparseMatrix> lu(system);
  if (lu.info() != Eigen::Success) return false;
  VectorXd rhs = VectorXd::Zero(n + m);
  rhs.head(n) = load;
  const VectorXd solution = lu.solve(rhs);
  if (lu.info() != Eigen::Success || !solution.allFinite()) return false;
  x.displacement = solution.head(n);
  x.reaction = solution.tail(m);
  return true;
}

}  // namespace

ContactSolution solve_contact(const Discretisation& d, const ContactOptions& options) {
  options.validate();
  const auto start = std::chrono::steady_clock::now();
  ContactSolution solution;
  ContactSummary& summary = solution.summary;

  summary.method = options.method;
  if (options.method == Method::automatic) {
    summary.method = d.structure_is_stable() ? Method::dual : Method::primal;
    summary.method_reason =
        d.structure_is_stable()
            ? "dual: the structure is stable on its supports, so the LCP needs only the reaction unknowns"
            : "primal: " + d.stability_note + ", so K is singular and the dual form does not exist";
  }
  if (summary.method == Method::dual && d.tensionless && !d.structure_is_stable())
    throw SolverFailure("the dual form needs a positive definite stiffness matrix K, but " + d.stability_note +
                        "; use method = \"primal\" (or \"auto\"), which handles it");

  const VectorXd load = d.load(options.load_factor);
  const double load_scale = load.lpNorm<Eigen::Infinity>();
  Unknowns x{VectorXd::Zero(d.equations), VectorXd::Zero(d.reactions())};
  summary.termination = ContactTermination::solved;
  summary.pivots = 0;

  if (load_scale == 0.0) {
    summary.message = "no load: the member stays where it is";
  } else if (!d.tensionless) {
    summary.method_reason = "bilateral foundation: one linear solve, no LCP";
    if (!solve_bilateral(d, load / load_scale, x)) {
      summary.termination = ContactTermination::numerical_failure;
      summary.message = "the bilateral system is singular: the structure is a mechanism even on the foundation";
    } else {
      summary.message = "equilibrium found";
    }
  } else {
    LcpOutcome outcome = summary.method == Method::dual ? solve_dual(d, load / load_scale, options.lemke)
                                                        : solve_primal(d, load / load_scale, options.lemke);
    x = outcome.unknowns;
    summary.pivots = outcome.lemke.pivots;
    summary.lcp_size = outcome.size;
    summary.termination = termination_of(outcome.lemke);
    summary.message = explain(summary.termination, outcome.lemke);
  }
  x.displacement *= load_scale;
  x.reaction *= load_scale;

  solution.displacement = d.expand(x.displacement);
  solution.reaction = x.reaction;
  solution.gap = d.flexibility * x.reaction - d.coupling * x.displacement;
  summary.residual = load_scale == 0.0 ? 0.0 : relative_residual(d, x, load, d.tensionless);
  // Lemke's own checks are in its scaled units; the answer must also hold in the mechanics'.
  if (summary.termination == ContactTermination::solved && !(summary.residual <= acceptable_residual)) {
    summary.termination = ContactTermination::numerical_failure;
    summary.message = fmt::format(
        "the {} LCP ended with a relative residual of {:.1e} (equilibrium or contact conditions violated), above {:.0e}: "
        "round-off has overwhelmed this {}-unknown problem; {}",
        scene::to_string(summary.method), summary.residual, acceptable_residual, summary.lcp_size,
        d.structure_is_stable() ? "use the dual form or fewer elements"
                                : "use fewer elements, or method = \"ritz\" (the dual form needs a stable structure)");
  }
  summary.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return solution;
}

}  // namespace liftoff::contact
