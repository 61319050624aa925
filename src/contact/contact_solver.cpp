#include "contact/contact_solver.hpp"

#include <fmt/format.h>

#include <Eigen/SparseCholesky>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "contact/stability.hpp"
#include "core/error.hpp"
#include "core/require.hpp"

namespace liftoff::contact {

using Eigen::MatrixXd;
using Eigen::VectorXd;
using fe::Discretisation;

namespace {
constexpr EnumName<ContactTermination> contact_termination_names[] = {
    {ContactTermination::solved, "solved"},
    {ContactTermination::no_equilibrium, "no_equilibrium"},
    {ContactTermination::pivot_limit, "pivot_limit"},
    {ContactTermination::iteration_limit, "iteration_limit"},
    {ContactTermination::numerical_failure, "numerical_failure"},
    {ContactTermination::unstable_equilibrium, "unstable_equilibrium"},
};
}  // namespace

std::string_view to_string(ContactTermination t) { return name_in<ContactTermination>(contact_termination_names, t); }

void ContactOptions::validate() const {
  require(std::isfinite(load_factor), "ContactOptions::load_factor", "must be finite");
  require(method == Method::dual || method == Method::primal || method == Method::fast || method == Method::automatic,
          "ContactOptions::method", "must be dual, primal, fast or auto");
  lemke.validate();
  active_set.validate();
}

std::string ContactSummary::brief_report() const {
  if (iterations >= 0)
    return fmt::format("{} ({}): {} contact sets, {} factorisations, residual {:.2e}, {:.3f} s", to_string(termination),
                       to_string(method), iterations, factorisations, residual, time_s);
  return fmt::format("{} ({}): {} pivots, residual {:.2e}, {:.3f} s", to_string(termination), to_string(method), pivots,
                     residual, time_s);
}

namespace {

// An answer whose relative residual (see ContactSummary::residual) exceeds this is not returned
// as a solution: at 1e-6 the contact limits are already uncertain to a fraction of an element.
constexpr double acceptable_residual = 1e-6;
// Likewise for the relative error iterative refinement leaves in u and r (sparse solves): above
// it the factorisation no longer solves the stored system (from ~1e4 elements for a beam).
constexpr double acceptable_error = 1e-6;

// Solution on the equations, before expansion to every dof.
struct Unknowns {
  VectorXd displacement;
  VectorXd reaction;
};

// |A| |x|: the size of the terms a row of A x sums, the scale its round-off is measured on.
VectorXd absolute_product(const fe::SparseMatrix& a, const VectorXd& x) {
  VectorXd out = VectorXd::Zero(a.rows());
  for (int k = 0; k < a.outerSize(); ++k)
    for (fe::SparseMatrix::InnerIterator it(a, k); it; ++it) out[it.row()] += std::abs(it.value() * x[it.col()]);
  return out;
}

// Relative residual of an answer (ContactSummary::residual). Row by row, equilibrium is a backward
// error against |K||u|, the round-off floor of K u. That alone cannot be trusted where u carries a
// rigid motion that K annihilates (a member only the foundation holds): there |K||u| is ~1e7 times
// the loads at 200 elements, and an equilibrium error of 3.5 % of the loads read 1.5e-10 (issue 10).
// So on each free rigid motion rho equilibrium is also measured in its own terms, rho^T (F - C^T r)
// = rho^T K u = 0, against |rho|^T (|F| + |C^T||r|): the global force and moment balance, whose
// round-off floor is that of the loads and reactions, not of K.
double relative_residual(const Discretisation& d, const Unknowns& x, const VectorXd& load, bool tensionless) {
  // The gap's terms include the ground gap c (gap = T r - C u + c).
  const VectorXd equilibrium = d.stiffness * x.displacement + d.coupling.transpose() * x.reaction - load;
  const VectorXd force_terms = absolute_product(d.stiffness, x.displacement) +
                               absolute_product(d.coupling.transpose(), x.reaction) + load.cwiseAbs();
  double residual = equilibrium.lpNorm<Eigen::Infinity>() / std::max(force_terms.maxCoeff(), 1e-300);
  // The rigid motions no support holds, as fe::discretise found them (on the equations).
  // Under an axial force N, K(N) = K - N K_g does not annihilate them: rho^T K(N) u = -N (K_g rho)^T u,
  // the moment of N on the displaced member (a free-free member tilted under compression).
  const MatrixXd& motions = d.free_rigid_motions;
  if (motions.cols() > 0) {
    const VectorXd reaction_forces = d.coupling.transpose() * x.reaction;
    const VectorXd balance_terms = absolute_product(d.coupling.transpose(), x.reaction) + load.cwiseAbs();
    for (int k = 0; k < motions.cols(); ++k) {
      double unbalanced = motions.col(k).dot(load - reaction_forces);
      double terms = motions.col(k).cwiseAbs().dot(balance_terms);
      if (d.has_axial_force()) {
        const VectorXd geometric = d.geometric_stiffness * motions.col(k);
        unbalanced += d.axial_force * geometric.dot(x.displacement);
        terms += std::abs(d.axial_force) * geometric.cwiseAbs().dot(x.displacement.cwiseAbs());
      }
      residual = std::max(residual, std::abs(unbalanced) / std::max(terms, 1e-300));
    }
  }
  if (d.reactions() == 0) return residual;

  const VectorXd gap = d.gap_of(x.reaction, x.displacement);
  const VectorXd gap_terms = absolute_product(d.flexibility, x.reaction) +
                             absolute_product(d.coupling, x.displacement) + d.ground_gap.cwiseAbs();
  const double gap_scale = std::max(gap_terms.maxCoeff(), 1e-300);
  if (!tensionless) return std::max(residual, gap.lpNorm<Eigen::Infinity>() / gap_scale);

  const double reaction_scale = std::max(x.reaction.lpNorm<Eigen::Infinity>(), 1e-300);
  residual = std::max(residual, std::max(0.0, -x.reaction.minCoeff()) / reaction_scale);
  residual = std::max(residual, std::max(0.0, -gap.minCoeff()) / gap_scale);
  residual = std::max(residual, x.reaction.cwiseProduct(gap).cwiseAbs().maxCoeff() / (reaction_scale * gap_scale));
  return residual;
}

ContactTermination termination_of(const lcp::LemkeSummary& summary) {
  switch (summary.termination) {
    case lcp::LemkeTermination::solution:
      return ContactTermination::solved;
    case lcp::LemkeTermination::ray:
      return ContactTermination::no_equilibrium;
    case lcp::LemkeTermination::pivot_limit:
      return ContactTermination::pivot_limit;
    case lcp::LemkeTermination::numerical_failure:
      return ContactTermination::numerical_failure;
  }
  return ContactTermination::numerical_failure;
}

std::string explain(ContactTermination termination, const lcp::LemkeSummary& lemke) {
  switch (termination) {
    case ContactTermination::solved:
      return "equilibrium found";
    case ContactTermination::no_equilibrium:
      return "no equilibrium exists: the loads would lift the member off the foundation and the supports "
             "cannot hold it, so it is a mechanism (Lemke ray termination after " +
             std::to_string(lemke.pivots) + " pivots)";
    case ContactTermination::pivot_limit:
      return "Lemke's algorithm reached its pivot limit (" + std::to_string(lemke.pivots) +
             " pivots) without a solution";
    case ContactTermination::numerical_failure:
      return "Lemke's algorithm failed numerically: " + lemke.message;
    case ContactTermination::iteration_limit:
    case ContactTermination::unstable_equilibrium:
      break;  // not a Lemke outcome
  }
  return lemke.message;
}

struct LcpOutcome {
  Unknowns unknowns;
  lcp::LemkeSummary lemke;
  int size = 0;
  Eigen::VectorXd ray;     // Lemke's ray without z0 (ray termination only)
  double q_dot_ray = 0.0;  // q^T ray
};

// Lemke's ray, z0 dropped, with q^T dz: the certificate of no equilibrium.
void keep_ray(const lcp::LemkeResult& result, const VectorXd& q, LcpOutcome& outcome) {
  if (result.summary.termination != lcp::LemkeTermination::ray || result.ray.size() != q.size() + 1) return;
  outcome.ray = result.ray.head(q.size());
  outcome.q_dot_ray = q.dot(outcome.ray);
}

// Lemke's answer is a contact set; its numbers are taken from the sparse fixed-set system, and the
// set is an answer only if its signs hold there.
//
// Why (issue 10: primal returned contact [0.75, 3] on a footing whose answer is [0.9065, 3], with
// "residual 1.5e-10" and equilibrium off by 3.5 %). The primal LCP holds K itself: its bases reach
// cond 1e10 .. 1e12 at 200 elements on a soft foundation, so after a few thousand pivots Lemke's
// decisions rest on entries that are round-off (lemke.hpp); the path ends at a complementary basis
// that is wrong, or right in its contact set but with a u+/u- split of the wrong sign, or at a false
// ray. Lemke's own residuals, and this file's relative residual, are relative to |K||u|, which for
// a member that floats on the foundation carries its rigid motion (K annihilates it): 1e7 times the
// loads, so an equilibrium error of 3.5 % of the loads read 1.5e-10. The physics fixes both: the
// u+/u- split means nothing (u = u+ - u-), and the contact set alone determines (u, r), which the
// sparse system [K C_A^T; C_A -T_AA] (active_set_system.hpp; refined in extended precision) gives
// to round-off. The set is then the answer exactly when r_A >= 0 and gap_I >= 0 there, judged as
// the fast solver judges them. A wrong set is reported, never returned.
void settle_contact_set(const Discretisation& d, const VectorXd& load, const VectorXd& offset,
                        const std::vector<int>& contact_nodes, std::string_view form, LcpOutcome& outcome) {
  lcp::LemkeSummary& lemke = outcome.lemke;
  auto fail = [&](const std::string& why) {
    lemke.termination = lcp::LemkeTermination::numerical_failure;
    lemke.message = fmt::format(
        "the {} LCP's final contact set ({} nodes, after {} pivots) is not the answer: {}; "
        "Lemke's pivoting lost accuracy on this ill-conditioned LCP; use method = \"fast\" (the same discrete "
        "problem, solved sparsely){}",
        form, contact_nodes.size(), lemke.pivots, why,
        d.structure_is_stable() ? ", or the other LCP form" : ", fewer elements, or method = \"ritz\"");
  };
  std::vector<bool> in_contact(d.reactions(), false);
  for (int i : contact_nodes) in_contact[i] = true;
  ActiveSetSystem system(d);
  if (!system.factorise(in_contact)) {
    // A set that leaves a rigid motion free which the loads do not drive (a floating member
    // balanced on one node) has no unique answer: Lemke's own is kept, and solve_contact's
    // residual, whose global balance cannot hide an equilibrium error, judges it.
    lemke.message += "; its contact set leaves a rigid motion free (a neutral balance), so Lemke's answer is kept";
    return;
  }
  ContactState state = system.solve(load, offset);
  // As the fast solver's sign test (active_set_solver.cpp): signs are trusted beyond 1e-11 of their
  // scale or ten times the solve's own error estimate, whichever is larger.
  constexpr double max_solve_error = 1e-6;
  if (!(state.error_estimate <= max_solve_error))
    return fail(fmt::format("its fixed-set system cannot be solved to {:.0e} (relative error {:.1e})", max_solve_error,
                            state.error_estimate));
  const double tolerance = std::max(ActiveSetOptions{}.sign_tolerance, 10.0 * state.error_estimate);
  const double reaction_scale = state.reaction.lpNorm<Eigen::Infinity>();
  const double gap_scale = std::max({(d.coupling * state.displacement).lpNorm<Eigen::Infinity>(),
                                     state.gap.lpNorm<Eigen::Infinity>(), offset.lpNorm<Eigen::Infinity>()});
  int worst = -1;
  double worst_ratio = 0.0;
  for (int i = 0; i < d.reactions(); ++i) {
    const double ratio = in_contact[i] ? -state.reaction[i] / std::max(reaction_scale, 1e-300)
                                       : -state.gap[i] / std::max(gap_scale, 1e-300);
    if (ratio > tolerance && ratio > worst_ratio) {
      worst = i;
      worst_ratio = ratio;
    }
  }
  if (worst >= 0)
    return fail(fmt::format(
        "re-solved, node {} (s = {:.6g}) has {} of {:.1e} of the largest", worst, d.mesh.nodes[d.reaction_nodes[worst]],
        in_contact[worst] ? "a negative reaction (tension)" : "a negative gap (penetration)", worst_ratio));
  if (lemke.termination != lcp::LemkeTermination::solution)  // its residual test failed, the set is right
    lemke.message +=
        "; the contact set was right all the same (the residual test sees Lemke's u+/u- split, "
        "which means nothing physically)";
  lemke.termination = lcp::LemkeTermination::solution;
  lemke.message += "; contact set re-solved by the sparse fixed-set system, its signs checked";
  outcome.unknowns.displacement = std::move(state.displacement);
  outcome.unknowns.reaction = std::move(state.reaction);
}

// `offset`: the ground gap c scaled as the load is; it is q's constant part (gap = T r - C u + c).
LcpOutcome solve_dual(const Discretisation& d, const VectorXd& load, const VectorXd& offset,
                      const lcp::LemkeOptions& options) {
  Eigen::SimplicialLDLT<fe::SparseMatrix> stiffness(d.stiffness);
  if (stiffness.info() != Eigen::Success)
    throw SolverFailure("the dual form could not factorise the stiffness matrix K; use method = \"primal\"");
  const MatrixXd flexibility_of_structure = stiffness.solve(MatrixXd(d.coupling.transpose()));  // K^-1 C^T
  const MatrixXd p = d.coupling * flexibility_of_structure + MatrixXd(d.flexibility);
  const VectorXd free_displacement = stiffness.solve(load);  // K^-1 F
  const VectorXd q = offset - d.coupling * free_displacement;

  const lcp::LemkeResult result = lcp::solve_lemke(p, q, options);
  LcpOutcome outcome;
  outcome.lemke = result.summary;
  outcome.size = static_cast<int>(q.size());
  outcome.unknowns.reaction = result.z;
  // u from one more solve with the final reactions, not as K^-1 F - (K^-1 C^T) z: the difference
  // of two large vectors carries eps times their size, so its equilibrium residual was up to
  // 1e-12 of the row terms where a backward-stable solve leaves a few eps.
  outcome.unknowns.displacement = stiffness.solve(load - d.coupling.transpose() * result.z);
  keep_ray(result, q, outcome);
  if (result.complementary) settle_contact_set(d, load, offset, result.basic_z, "dual", outcome);
  return outcome;
}

LcpOutcome solve_primal(const Discretisation& d, const VectorXd& load, const VectorXd& offset,
                        const lcp::LemkeOptions& options) {
  const int n = d.equations, m = d.reactions();
  const MatrixXd k(d.stiffness), c(d.coupling);
  MatrixXd lcp_matrix(2 * n + m, 2 * n + m);
  lcp_matrix << k, -k, c.transpose(),  //
      -k, k, -c.transpose(),           //
      -c, c, MatrixXd(d.flexibility);
  VectorXd q(2 * n + m);
  q << -load, load, offset;

  const lcp::LemkeResult result = lcp::solve_lemke(lcp_matrix, q, options);
  LcpOutcome outcome;
  outcome.lemke = result.summary;
  outcome.size = 2 * n + m;
  outcome.unknowns.displacement = result.z.head(n) - result.z.segment(n, n);
  outcome.unknowns.reaction = result.z.tail(m);
  keep_ray(result, q, outcome);
  if (result.complementary) {
    std::vector<int> contact_nodes;  // the reactions among the basic z: (u+, u-, r)
    for (int i : result.basic_z)
      if (i >= 2 * n) contact_nodes.push_back(i - 2 * n);
    settle_contact_set(d, load, offset, contact_nodes, "primal", outcome);
  }
  return outcome;
}

// Bilateral foundation: the saddle-point system [K C^T; C -T] (u, r) = (F, 0), which is the
// fixed-contact-set system with every node in contact.
// Its round-off bound (Hager's estimate, up to 12 more solves) only on request, as for fast.
bool solve_bilateral(const Discretisation& d, const VectorXd& load, const VectorXd& offset, bool estimate_round_off,
                     Unknowns& x, ContactSummary& summary) {
  ActiveSetSystem system(d);
  const bool factorised = system.factorise(std::vector<bool>(d.reactions(), true));
  summary.factorisations = system.factorisations();
  if (!factorised) return false;
  ContactState state = system.solve(load, offset);
  summary.error_estimate = state.error_estimate;
  if (estimate_round_off && state.error_estimate <= acceptable_error)
    summary.round_off_bound = system.data_error(state, load);
  if (!state.displacement.allFinite() || !state.reaction.allFinite()) return false;
  x.displacement = std::move(state.displacement);
  x.reaction = std::move(state.reaction);
  return true;
}

// The dense LCP of a Lemke formulation: its size, refused above max_dense_lcp.
int lcp_size_of(const Discretisation& d, Method method) {
  return method == Method::dual ? d.reactions() : 2 * d.equations + d.reactions();
}

void check_dense_size(const Discretisation& d, Method method) {
  const int size = lcp_size_of(d, method);
  if (size > max_dense_lcp)
    throw SolverFailure(
        fmt::format("the {} LCP would have {} unknowns, a dense matrix of {:.1f} GB for Lemke (limit {} "
                    "unknowns); use method = \"fast\" (or \"auto\"), which is O(n)",
                    to_string(method), size, 8.0 * size * size / 1e9, max_dense_lcp));
}

}  // namespace

MethodChoice choose_fe_method(const Discretisation& d) {
  if (!d.tensionless) return {Method::fast, "bilateral foundation: one sparse solve, no LCP"};
  return {Method::fast,
          "fast: the sparse active-set solver, O(n), for every FE scene; dense Lemke (dual, primal) "
          "only when asked for by name"};
}

ContactSolution solve_contact(const Discretisation& d, const ContactOptions& options) {
  options.validate();
  const auto start = std::chrono::steady_clock::now();
  ContactSolution solution;
  ContactSummary& summary = solution.summary;

  summary.method = options.method;
  if (options.method == Method::automatic) {
    const MethodChoice choice = choose_fe_method(d);
    summary.method = choice.method;
    summary.method_reason = choice.reason;
  }
  if (summary.method == Method::dual && d.tensionless && !d.structure_is_stable())
    throw SolverFailure("the dual form needs a positive definite stiffness matrix K, but " + d.stability_note +
                        "; use method = \"auto\" or \"fast\" (the sparse solver, which handles it; or \"primal\")");
  // Lemke's dual form inverts K(N): below the member's own critical load only.
  const bool dual_admissible = d.structure_is_stable() && (!d.has_axial_force() || is_positive_definite(d.stiffness));
  if (summary.method == Method::dual && d.tensionless && !dual_admissible)
    throw SolverFailure(
        "the dual form needs a positive definite K(N) = K - N K_g, but the axial force exceeds the critical load "
        "of the member without its foundation; use method = \"fast\" or \"primal\"");
  if (d.tensionless && (summary.method == Method::dual || summary.method == Method::primal))
    check_dense_size(d, summary.method);

  const VectorXd load = d.load(options.load_factor);
  // The problem is linear in (F, c) together: both are scaled by one number, the larger of them.
  const VectorXd ground_gap = d.ground_gap.size() == d.reactions() ? d.ground_gap : VectorXd::Zero(d.reactions());
  const double load_scale = std::max(load.lpNorm<Eigen::Infinity>(), ground_gap.lpNorm<Eigen::Infinity>());
  const VectorXd offset = load_scale > 0.0 ? VectorXd(ground_gap / load_scale) : ground_gap;
  Unknowns x{VectorXd::Zero(d.equations), VectorXd::Zero(d.reactions())};
  summary.termination = ContactTermination::solved;
  summary.pivots = 0;

  auto solve_by_lemke = [&](Method method) {
    LcpOutcome outcome = method == Method::dual ? solve_dual(d, load / load_scale, offset, options.lemke)
                                                : solve_primal(d, load / load_scale, offset, options.lemke);
    x = outcome.unknowns;
    summary.pivots = outcome.lemke.pivots;
    summary.lcp_size = outcome.size;
    summary.termination = termination_of(outcome.lemke);
    summary.message = explain(summary.termination, outcome.lemke);
    if (summary.termination == ContactTermination::no_equilibrium && outcome.ray.size() > 0)
      solution.no_equilibrium_certificate = NoEquilibriumCertificate{method, outcome.ray, outcome.q_dot_ray};
    else
      solution.no_equilibrium_certificate.reset();
  };

  if (load_scale == 0.0) {
    summary.message = "no load and no ground gap: the member stays where it is";
  } else if (!d.tensionless) {
    summary.method_reason = "bilateral foundation: one sparse solve, no LCP";
    summary.pivots = -1;
    if (!solve_bilateral(d, load / load_scale, offset, options.active_set.estimate_round_off, x, summary)) {
      summary.termination = ContactTermination::numerical_failure;
      summary.message = "the bilateral system is singular: the structure is a mechanism even on the foundation";
    } else {
      summary.message = "equilibrium found";
    }
  } else if (summary.method == Method::fast) {
    summary.pivots = -1;
    // On a large uniform mesh the first set comes from a coarser mesh's answer: the limits then
    // start within a coarse element of their place (2-3 sets here instead of 10 or more).
    CoarseStart start;
    if (!options.initial_contact.empty()) {
      if (static_cast<int>(options.initial_contact.size()) != d.reactions())
        throw std::invalid_argument(
            fmt::format("ContactOptions::initial_contact: expected {} flags (one per reaction node), got {}",
                        d.reactions(), options.initial_contact.size()));
      start.initial = options.initial_contact;
    } else if (d.uniform_member) {
      start = coarse_start(*d.uniform_member, d, options.load_factor, options.active_set);
    }
    ActiveSetOptions fast_options = options.active_set;
    if (start.levels > 1 && !start.initial.empty()) fast_options.unrefined_first_set = true;  // rarely the answer
    ActiveSetResult fast = solve_active_set(d, load / load_scale, fast_options, std::move(start.initial), offset);
    if (start.levels > 1 && fast.summary.is_usable())
      fast.summary.message += fmt::format(", started from a coarser mesh's set ({} sets on {} coarser meshes)",
                                          start.coarse_sets, start.levels - 1);
    summary.iterations = fast.summary.iterations;
    summary.factorisations = fast.summary.factorisations;
    summary.error_estimate = fast.state.error_estimate;
    summary.round_off_bound = fast.round_off_bound;
    if (fast.summary.is_usable()) {
      x.displacement = std::move(fast.state.displacement);
      x.reaction = std::move(fast.state.reaction);
      summary.message = "equilibrium found: " + fast.summary.message;
    } else {
      // Lemke takes over: dual where the structure is stable, else primal, if its dense LCP fits.
      const Method fallback = dual_admissible ? Method::dual : Method::primal;
      const std::string why =
          fmt::format("the fast solver stopped ({}: {})", to_string(fast.summary.termination), fast.summary.message);
      if (lcp_size_of(d, fallback) > max_fallback_lcp) {
        summary.termination = fast.summary.termination == ActiveSetTermination::singular_system
                                  ? ContactTermination::numerical_failure
                                  : ContactTermination::iteration_limit;
        summary.message = fmt::format("{}, and the {} LCP ({} unknowns) is too large for the Lemke fallback (limit {})",
                                      why, to_string(fallback), lcp_size_of(d, fallback), max_fallback_lcp);
      } else {
        solve_by_lemke(fallback);
        summary.method = fallback;
        summary.method_reason =
            fmt::format("{}fell back to {} Lemke: {}",
                        summary.method_reason.empty() ? "" : summary.method_reason + "; ", to_string(fallback), why);
        summary.message += fmt::format(" (after falling back to {} Lemke: {})", to_string(fallback), why);
      }
    }
  } else {
    solve_by_lemke(summary.method);
  }
  x.displacement *= load_scale;
  x.reaction *= load_scale;

  solution.displacement = d.expand_displacement(x.displacement);
  solution.reaction = x.reaction;
  solution.gap = d.gap_of(x.reaction, x.displacement);
  summary.residual = load_scale == 0.0 ? 0.0 : relative_residual(d, x, load, d.tensionless);
  // Lemke's own checks are in its scaled units; the answer must also hold in the mechanics'.
  if (summary.termination == ContactTermination::solved && !(summary.residual <= acceptable_residual)) {
    summary.termination = ContactTermination::numerical_failure;
    if (summary.lcp_size < 0)  // a sparse solve: fast, or the bilateral system
      summary.message = fmt::format(
          "the {} solve ended with a relative residual of {:.1e} (equilibrium or contact conditions violated), above "
          "{:.0e}: round-off has overwhelmed this {}-equation system; use fewer elements",
          d.tensionless ? to_string(summary.method) : "bilateral", summary.residual, acceptable_residual,
          d.equations + d.reactions());
    else
      summary.message = fmt::format(
          "the {} LCP ended with a relative residual of {:.1e} (equilibrium or contact conditions violated), above "
          "{:.0e}: round-off has overwhelmed this {}-unknown problem; {}",
          to_string(summary.method), summary.residual, acceptable_residual, summary.lcp_size,
          d.structure_is_stable() ? "use method = \"fast\", the dual form or fewer elements"
                                  : "use method = \"fast\", fewer elements, or method = \"ritz\"");
  }
  if (summary.termination == ContactTermination::solved && summary.error_estimate > acceptable_error) {
    summary.termination = ContactTermination::numerical_failure;
    summary.message = fmt::format(
        "round-off owns this mesh: the FE system's condition grows like N^4 ({} elements), and iterative refinement "
        "in extended precision leaves a relative error of {:.1e} in u and r, above {:.0e}; use fewer elements",
        d.mesh.elements(), summary.error_estimate, acceptable_error);
  }
  // Beyond the critical load of the member lifted off (K(N) indefinite) a failed search is
  // explained by it: the member may buckle away from the foundation, which then cannot help.
  if (summary.termination != ContactTermination::solved && d.has_axial_force() && !dual_admissible &&
      d.structure_is_stable()) {
    // A proof of no equilibrium at all (Lemke's ray) stays what it is, with the reason added.
    if (summary.termination != ContactTermination::no_equilibrium)
      summary.termination = ContactTermination::unstable_equilibrium;
    summary.message = fmt::format(
        "the axial force exceeds the critical load of the current configuration: no stable equilibrium was found, "
        "and the axial force exceeds the critical load of the member without its foundation (K - N K_g is not "
        "positive definite), so it may buckle away from the foundation, which cannot hold it ({})",
        summary.message);
  }
  if (summary.termination == ContactTermination::solved && d.has_axial_force()) {
    std::vector<bool> in_contact(d.reactions(), true);
    // A node touching with no reaction may lift freely: no spring (the conservative side).
    for (int i = 0; i < d.reactions(); ++i) in_contact[i] = x.reaction[i] > 0.0;
    const StabilityCheck stability = check_tangent(d, in_contact);
    if (!stability.positive_definite) {
      summary.termination = ContactTermination::unstable_equilibrium;
      summary.message = fmt::format(
          "the axial force exceeds the critical load of the current configuration: the equilibrium found is "
          "unstable ({})",
          stability.message);
    }
  }
  summary.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return solution;
}

}  // namespace liftoff::contact

namespace liftoff {
template <>
std::optional<contact::ContactTermination> from_string(std::string_view name) {
  return value_in<contact::ContactTermination>(contact::contact_termination_names, name);
}
}  // namespace liftoff
