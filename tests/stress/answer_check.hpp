#pragma once
// Checking an answer's physics from the discretisation alone, for the stress tests.
//
// The solver's own residual is not trusted: equilibrium K u + C^T r - F, the gap T r - C u, the
// signs of r and gap and the complementarity r.gap are recomputed here from the assembled
// matrices and the returned u and r. Each is measured against the round-off floor a
// backward-stable computation of that answer could reach (the componentwise magnitudes
// |K||u| + |C^T||r| + |F| and |T||r| + |C||u|), so a tolerance is a multiple of eps that comes
// from the problem, not a number chosen to pass. Condition estimates (dense, for the small
// meshes of the quick set) say why accuracy is lost where it is.

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "contact/contact_solver.hpp"
#include "fe/discretisation.hpp"
#include "scene/scene.hpp"

namespace liftoff::test {

constexpr double eps = std::numeric_limits<double>::epsilon();

// The FE + LCP methods there are: dual and primal, plus the fast contact solver where this build
// has it (from_string<contact::Method>("fast")). The fast solver is developed on another branch; until it
// is merged the stress tests say so and run without it.
inline std::vector<contact::Method> fe_methods(bool stable_structure = true) {
  std::vector<contact::Method> methods;
  if (stable_structure) methods.push_back(contact::Method::dual);
  methods.push_back(contact::Method::primal);
  if (const auto fast = from_string<contact::Method>("fast")) methods.push_back(*fast);
  return methods;
}

inline bool fast_method_present() { return from_string<contact::Method>("fast").has_value(); }

struct AnswerCheck {
  // Worst ratio of each violation to its round-off floor (componentwise, see above). For
  // equilibrium this is a backward-error statement and must be <= 1 for a stable method; the
  // sign and complementarity floors ignore the conditioning of the LCP basis (a forward error),
  // so their ratios are reported, and the relative values are held to the solver's contract.
  double equilibrium_ratio = 0.0;
  double negative_reaction_ratio = 0.0;
  double negative_gap_ratio = 0.0;
  double complementarity_ratio = 0.0;
  // The same violations relative to the magnitudes involved (the solver's contract: <= 1e-6).
  double equilibrium = 0.0;
  double negative_reaction = 0.0;
  double negative_gap = 0.0;
  double complementarity = 0.0;
  double worst_relative() const { return std::max({equilibrium, negative_reaction, negative_gap, complementarity}); }
  // The solvers' contract (contact_solver.hpp): the equilibrium residual as a backward error,
  // |K u + C^T r - F| / max_i (|K||u| + |C^T||r| + |F|)_i, and the sign and complementarity
  // violations relative to their magnitudes, each <= the contract. The norm-wise `equilibrium`
  // above exceeds it on fine meshes, where |K||u| >> |F| (cond(K) ~ N^4).
  double backward_equilibrium = 0.0;
  bool within_contract(double contract) const {
    return std::max({backward_equilibrium, negative_reaction, negative_gap, complementarity}) <= contract;
  }
  // The relative equilibrium residual that round-off alone allows this answer: gamma times
  // max_i (|K||u| + |C^T||r| + |F|)_i / |F|. It grows where u is large against what K u is (a
  // soft foundation under a floating beam: |K||u| ~ |F| / k): that explains a loss of accuracy.
  double equilibrium_floor = 0.0;
  std::string report() const {
    return fmt::format("equilibrium {:.1e} (floor {:.1e}, {:.2f} of it), r<0 {:.1e}, gap<0 {:.1e}, r.gap {:.1e}",
                       equilibrium, equilibrium_floor, equilibrium_ratio, negative_reaction, negative_gap,
                       complementarity);
  }
};

// u on the equations from u on every dof.
inline Eigen::VectorXd on_equations(const fe::Discretisation& d, const Eigen::VectorXd& displacement) {
  Eigen::VectorXd u = Eigen::VectorXd::Zero(d.equations);
  for (int dof = 0; dof < d.dofs(); ++dof)
    if (d.equation_of_dof[dof] >= 0) u[d.equation_of_dof[dof]] = displacement[dof];
  return u;
}

inline fe::SparseMatrix absolute(const fe::SparseMatrix& a) { return a.cwiseAbs(); }

// `amplification`: how much larger than u the intermediate quantities of the method were (the
// dual form computes u = K^-1 F - K^-1 C^T r, which cancels when the foundation is stiff), so
// the floor grows with it. `terms`: the length of the longest inner product behind the answer
// (gamma_n = n eps in the classical bound).
inline AnswerCheck check_answer(const fe::Discretisation& d, const contact::ContactSolution& s, double load_factor,
                                double amplification = 1.0, double terms = 0.0) {
  AnswerCheck c;
  const Eigen::VectorXd u = on_equations(d, s.displacement);
  const Eigen::VectorXd& r = s.reaction;
  const Eigen::VectorXd f = d.load(load_factor);
  if (terms <= 0.0) {
    // A dense LCP's answer comes from inner products as long as the LCP; a sparse solve's from
    // a row of [K C^T] (a handful of entries).
    Eigen::Index row_length = 0;
    const fe::SparseMatrix rows = d.stiffness;  // symmetric: columns are rows
    for (Eigen::Index j = 0; j < rows.outerSize(); ++j) row_length = std::max(row_length, rows.col(j).nonZeros());
    terms = s.summary.lcp_size > 0 ? s.summary.lcp_size : static_cast<double>(row_length + 4);
  }
  const double gamma = terms * eps * std::max(1.0, amplification);
  auto ratio = [](double value, double floor) { return floor > 0.0 ? value / floor : (value > 0.0 ? INFINITY : 0.0); };

  const Eigen::VectorXd ku = d.stiffness * u, ctr = d.coupling.transpose() * r;
  const Eigen::VectorXd eq = ku + ctr - f;
  const Eigen::VectorXd eq_magnitude =
      absolute(d.stiffness) * u.cwiseAbs() + absolute(d.coupling).transpose() * r.cwiseAbs() + f.cwiseAbs();
  const double force_scale = std::max({f.lpNorm<Eigen::Infinity>(), ku.lpNorm<Eigen::Infinity>(),
                                       ctr.lpNorm<Eigen::Infinity>(), std::numeric_limits<double>::min()});
  c.equilibrium = eq.lpNorm<Eigen::Infinity>() / force_scale;
  // A row where every magnitude is (nearly) zero would have no floor at all: it gets a thousandth
  // of the largest row's, so that exact zeros are not divided by zero.
  const double eq_floor_scale = gamma * eq_magnitude.lpNorm<Eigen::Infinity>();
  c.equilibrium_floor = eq_floor_scale / force_scale;
  c.backward_equilibrium = eq.lpNorm<Eigen::Infinity>() /
                           std::max(eq_magnitude.lpNorm<Eigen::Infinity>(), std::numeric_limits<double>::min());
  for (int i = 0; i < eq.size(); ++i)
    c.equilibrium_ratio =
        std::max(c.equilibrium_ratio, ratio(std::abs(eq[i]), gamma * eq_magnitude[i] + 1e-3 * eq_floor_scale));
  if (d.reactions() == 0) return c;

  const Eigen::VectorXd tr = d.flexibility * r, cu = d.coupling * u;
  const Eigen::VectorXd gap = tr - cu;
  const Eigen::VectorXd gap_magnitude = absolute(d.flexibility) * r.cwiseAbs() + absolute(d.coupling) * u.cwiseAbs();
  const double gap_scale =
      std::max({tr.lpNorm<Eigen::Infinity>(), cu.lpNorm<Eigen::Infinity>(), std::numeric_limits<double>::min()});
  const double reaction_scale = std::max(r.lpNorm<Eigen::Infinity>(), std::numeric_limits<double>::min());
  if (!d.tensionless) {
    c.negative_gap = gap.lpNorm<Eigen::Infinity>() / gap_scale;
    for (int i = 0; i < gap.size(); ++i)
      c.negative_gap_ratio = std::max(c.negative_gap_ratio, ratio(std::abs(gap[i]), gamma * gap_magnitude[i]));
    return c;
  }
  // r >= 0: a reaction is computed from the contact nodes' system, so its floor is gamma |r|.
  c.negative_reaction = std::max(0.0, -r.minCoeff()) / reaction_scale;
  c.negative_reaction_ratio = ratio(std::max(0.0, -r.minCoeff()), gamma * reaction_scale);
  for (int i = 0; i < gap.size(); ++i) {
    const double floor = gamma * gap_magnitude[i] + 1e-3 * gamma * gap_magnitude.lpNorm<Eigen::Infinity>();
    c.negative_gap = std::max(c.negative_gap, std::max(0.0, -gap[i]) / gap_scale);
    c.negative_gap_ratio = std::max(c.negative_gap_ratio, ratio(std::max(0.0, -gap[i]), floor));
    // r_i gap_i = 0: where r_i > 0 the gap must vanish to its floor (and vice versa).
    const double product = std::abs(r[i] * gap[i]);
    c.complementarity = std::max(c.complementarity, product / (reaction_scale * gap_scale));
    c.complementarity_ratio = std::max(
        c.complementarity_ratio, ratio(product, std::abs(r[i]) * floor + std::abs(gap[i]) * gamma * reaction_scale));
  }
  return c;
}

// |K^-1 F| / |u|: how much the dual form's u = K^-1 F - K^-1 C^T r cancels (1 when the
// foundation carries little, about k h^4 / ... when it is stiff). 1 for a singular K.
inline double dual_cancellation(const fe::Discretisation& d, const contact::ContactSolution& s, double load_factor) {
  if (!d.structure_is_stable()) return 1.0;
  Eigen::SimplicialLDLT<fe::SparseMatrix> k(d.stiffness);
  if (k.info() != Eigen::Success) return 1.0;
  const Eigen::VectorXd free_displacement = k.solve(d.load(load_factor));
  const double u = on_equations(d, s.displacement).lpNorm<Eigen::Infinity>();
  return u > 0.0 ? std::max(1.0, free_displacement.lpNorm<Eigen::Infinity>() / u) : 1.0;
}

// 2-norm condition number of a symmetric matrix (dense eigenvalues: small meshes only).
inline double symmetric_condition(const Eigen::MatrixXd& a) {
  const Eigen::VectorXd ev =
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(a, Eigen::EigenvaluesOnly).eigenvalues().cwiseAbs();
  return ev.minCoeff() > 0.0 ? ev.maxCoeff() / ev.minCoeff() : INFINITY;
}

// The dual LCP matrix P = C K^-1 C^T + T (dense; small meshes only).
inline Eigen::MatrixXd dual_matrix(const fe::Discretisation& d) {
  Eigen::SimplicialLDLT<fe::SparseMatrix> k(d.stiffness);
  const Eigen::MatrixXd kc = k.solve(Eigen::MatrixXd(d.coupling.transpose()));
  return d.coupling * kc + Eigen::MatrixXd(d.flexibility);
}

}  // namespace liftoff::test
