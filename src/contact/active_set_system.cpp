#include "contact/active_set_system.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace liftoff::contact {

using Eigen::VectorXd;

namespace {
constexpr int max_refinement_steps = 6;
}  // namespace

ActiveSetSystem::ActiveSetSystem(const fe::Discretisation& discretisation) : d_(discretisation) {
  const int n = d_.equations, m = d_.reactions(), size = n + m;
  // Unknowns in order along the member (a node's dofs, then its reaction): the matrix is
  // banded in this order, which keeps the matrix products cache-friendly.
  std::vector<double> position(size, 0.0);
  for (int dof = 0; dof < d_.dofs(); ++dof)
    if (d_.equation_of_dof[dof] >= 0) position[d_.equation_of_dof[dof]] = d_.position_of_dof(dof);
  for (int i = 0; i < m; ++i) position[n + i] = d_.mesh.nodes[d_.reaction_nodes[i]];
  std::vector<int> order(size);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return position[a] < position[b] || (position[a] == position[b] && (a < n) > (b < n));
  });
  slot_.resize(size);
  reaction_of_slot_.assign(size, -1);
  for (int s = 0; s < size; ++s) {
    slot_[order[s]] = s;
    if (order[s] >= n) reaction_of_slot_[s] = order[s] - n;
  }

  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(d_.stiffness.nonZeros() + 2 * d_.coupling.nonZeros() + d_.flexibility.nonZeros() + m);
  for (int k = 0; k < d_.stiffness.outerSize(); ++k)
    for (fe::SparseMatrix::InnerIterator it(d_.stiffness, k); it; ++it)
      entries.emplace_back(slot_[it.row()], slot_[it.col()], it.value());
  for (int k = 0; k < d_.coupling.outerSize(); ++k)
    for (fe::SparseMatrix::InnerIterator it(d_.coupling, k); it; ++it) {
      entries.emplace_back(slot_[n + it.row()], slot_[it.col()], it.value());
      entries.emplace_back(slot_[it.col()], slot_[n + it.row()], it.value());
    }
  for (int k = 0; k < d_.flexibility.outerSize(); ++k)
    for (fe::SparseMatrix::InnerIterator it(d_.flexibility, k); it; ++it)
      entries.emplace_back(slot_[n + it.row()], slot_[n + it.col()], -it.value());
  // Every reaction node keeps its diagonal in the pattern, whatever T holds.
  for (int i = 0; i < m; ++i) entries.emplace_back(slot_[n + i], slot_[n + i], 0.0);
  full_.resize(size, size);
  full_.setFromTriplets(entries.begin(), entries.end());
  full_.makeCompressed();

  scaling_ = full_.diagonal().cwiseAbs();
  for (Eigen::Index i = 0; i < scaling_.size(); ++i)
    scaling_[i] = scaling_[i] > 0 ? 1.0 / std::sqrt(scaling_[i]) : 1.0;
  scaled_ = full_;
}

bool ActiveSetSystem::in_system(int slot) const {
  const int node = reaction_of_slot_[slot];
  return node < 0 || in_contact_[node];
}

bool ActiveSetSystem::factorise(const std::vector<bool>& in_contact) {
  if (static_cast<int>(in_contact.size()) != d_.reactions())
    throw std::invalid_argument("ActiveSetSystem::factorise: one contact flag per reaction node expected");
  if (factorised_ && in_contact == in_contact_) return true;
  in_contact_ = in_contact;

  // A lifted-off node keeps its (unit or -1) diagonal and nothing else: r_i = 0.
  const double* full = full_.valuePtr();
  double* values = scaled_.valuePtr();
  const int* rows = scaled_.innerIndexPtr();
  const int* starts = scaled_.outerIndexPtr();
  for (int col = 0; col < scaled_.outerSize(); ++col) {
    const bool col_in = in_system(col);
    for (int p = starts[col]; p < starts[col + 1]; ++p) {
      const int row = rows[p];
      if (row == col)
        values[p] = col_in ? full[p] * scaling_[row] * scaling_[col] : -1.0;
      else
        values[p] = col_in && in_system(row) ? full[p] * scaling_[row] * scaling_[col] : 0.0;
    }
  }

  if (!analysed_) {
    factors_.analyzePattern(scaled_);
    analysed_ = true;
  }
  factors_.factorize(scaled_);
  ++factorisations_;
  factorised_ = factors_.info() == Eigen::Success;
  if (!factorised_) return false;
  // A free rigid motion shows as a pivot at round-off level of the equilibrated matrix.
  const VectorXd pivots = factors_.vectorD().cwiseAbs();
  if (pivots.size() > 0 && !(pivots.minCoeff() > 1e-13 * pivots.maxCoeff())) factorised_ = false;
  return factorised_;
}

VectorXd ActiveSetSystem::unscaled_solve(const VectorXd& b) const {
  return scaling_.cwiseProduct(factors_.solve(scaling_.cwiseProduct(b)));
}

ContactState ActiveSetSystem::solve(const VectorXd& load) const {
  if (!factorised_) throw std::logic_error("ActiveSetSystem::solve before a successful factorise()");
  const int n = d_.equations, m = d_.reactions();
  const Eigen::Index size = full_.rows();
  VectorXd rhs = VectorXd::Zero(size);
  for (int e = 0; e < n; ++e) rhs[slot_[e]] = load[e];
  // The equilibrated system S A S y = S b gives x = S y. Refinement computes the defect
  // b - A x on A as assembled (not its equilibrated, rounded copy) and in extended precision:
  // for a smooth u a row of K u cancels terms ~N^4 times larger than their sum, so a defect in
  // double precision holds no digits beyond ~1e4 elements. The size of the last correction
  // estimates the error left.
  VectorXd x = unscaled_solve(rhs);
  std::vector<long double> accumulator(size);
  VectorXd defect(size), magnitude(size);
  // defect = b - A x (extended precision), magnitude = |b| + |A| |x|, over the current set.
  auto compute_defect = [&]() {
    for (Eigen::Index i = 0; i < size; ++i) accumulator[i] = rhs[i];
    magnitude = rhs.cwiseAbs();
    const double* values = full_.valuePtr();
    const int* rows = full_.innerIndexPtr();
    const int* starts = full_.outerIndexPtr();
    for (int col = 0; col < size; ++col) {
      if (!in_system(col)) continue;
      const long double xc = x[col];
      for (int p = starts[col]; p < starts[col + 1]; ++p) {
        if (!in_system(rows[p])) continue;
        accumulator[rows[p]] -= static_cast<long double>(values[p]) * xc;
        magnitude[rows[p]] += std::abs(values[p] * x[col]);
      }
    }
    for (Eigen::Index i = 0; i < size; ++i) defect[i] = static_cast<double>(accumulator[i]);
  };
  double previous = INFINITY, estimate = 0.0;
  for (int step = 0; step < max_refinement_steps; ++step) {
    compute_defect();
    const VectorXd correction = unscaled_solve(defect);
    x += correction;
    const double change = correction.lpNorm<Eigen::Infinity>() / std::max(x.lpNorm<Eigen::Infinity>(), 1e-300);
    estimate = change;
    if (!(change > 1e-15) || change > 0.5 * previous) break;  // converged, or no longer contracting
    previous = change;
  }
  compute_defect();

  ContactState state;
  state.displacement.resize(n);
  for (int e = 0; e < n; ++e) state.displacement[e] = x[slot_[e]];
  state.reaction = VectorXd::Zero(m);
  for (int i = 0; i < m; ++i)
    if (in_contact_[i]) state.reaction[i] = x[slot_[n + i]];
  state.gap = d_.flexibility * state.reaction - d_.coupling * state.displacement;
  for (int i = 0; i < m; ++i)
    if (in_contact_[i]) state.gap[i] = 0.0;  // exact by construction; the defect measures it
  // Row-wise relative defect |A x - b|_i / (sum_j |A_ij x_j| + |b_i|).
  double residual = 0.0;
  for (Eigen::Index i = 0; i < size; ++i)
    if (magnitude[i] > 0) residual = std::max(residual, std::abs(defect[i]) / magnitude[i]);
  state.residual = residual;
  state.error_estimate = estimate;
  return state;
}

double ActiveSetSystem::data_error(const ContactState& state, const VectorXd& load) const {
  if (!factorised_) throw std::logic_error("ActiveSetSystem::data_error before a successful factorise()");
  const int n = d_.equations, m = d_.reactions();
  const Eigen::Index size = full_.rows();
  VectorXd x(size), weight = VectorXd::Zero(size);  // weight: D = |A| |x| + |b| over the set
  for (int e = 0; e < n; ++e) {
    x[slot_[e]] = state.displacement[e];
    weight[slot_[e]] = std::abs(load[e]);
  }
  for (int i = 0; i < m; ++i) x[slot_[n + i]] = state.reaction[i];
  for (int col = 0; col < size; ++col) {
    if (!in_system(col)) continue;
    for (fe::SparseMatrix::InnerIterator it(full_, col); it; ++it)
      if (in_system(static_cast<int>(it.row()))) weight[it.row()] += std::abs(it.value() * x[col]);
  }
  // Hager's estimate of || P A^-1 D ||_inf = || D A^-1 P^T ||_1 for the rows P of one block
  // (the displacements, or the reactions).
  auto block_norm = [&](bool reactions) {
    std::vector<int> rows;
    for (int s = 0; s < size; ++s)
      if ((reaction_of_slot_[s] >= 0) == reactions) rows.push_back(s);
    const Eigen::Index count = static_cast<Eigen::Index>(rows.size());
    if (count == 0) return 0.0;
    VectorXd v = VectorXd::Constant(count, 1.0 / static_cast<double>(count)), embedded(size);
    double estimate = 0.0;
    for (int iteration = 0; iteration < 3; ++iteration) {
      embedded.setZero();
      for (Eigen::Index k = 0; k < count; ++k) embedded[rows[k]] = v[k];
      const VectorXd y = weight.cwiseProduct(unscaled_solve(embedded));  // D A^-1 P^T v
      estimate = y.lpNorm<1>();
      const VectorXd signs = y.unaryExpr([](double value) { return value >= 0 ? 1.0 : -1.0; });
      const VectorXd back = unscaled_solve(weight.cwiseProduct(signs));  // A^-1 D sign(y)
      VectorXd z(count);
      for (Eigen::Index k = 0; k < count; ++k) z[k] = back[rows[k]];
      Eigen::Index j = 0;
      if (z.cwiseAbs().maxCoeff(&j) <= z.dot(v)) break;
      v.setZero();
      v[j] = 1.0;
    }
    return estimate;
  };
  constexpr double eps = std::numeric_limits<double>::epsilon();
  const double u_scale = state.displacement.lpNorm<Eigen::Infinity>();
  const double r_scale = state.reaction.lpNorm<Eigen::Infinity>();
  double error = 0.0;
  if (u_scale > 0) error = std::max(error, eps * block_norm(false) / u_scale);
  if (r_scale > 0) error = std::max(error, eps * block_norm(true) / r_scale);
  return error;
}

}  // namespace liftoff::contact
