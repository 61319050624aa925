#include "contact/active_set_system.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace liftoff::contact {

using Eigen::VectorXd;

namespace {
constexpr int max_refinement_steps = 6;
}  // namespace

ActiveSetSystem::ActiveSetSystem(const fe::Discretisation& discretisation) : d_(discretisation) {
  const int n = d_.equations, m = d_.reactions();
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(d_.stiffness.nonZeros() + 2 * d_.coupling.nonZeros() + d_.flexibility.nonZeros());
  for (int k = 0; k < d_.stiffness.outerSize(); ++k)
    for (fe::SparseMatrix::InnerIterator it(d_.stiffness, k); it; ++it)
      entries.emplace_back(it.row(), it.col(), it.value());
  for (int k = 0; k < d_.coupling.outerSize(); ++k)
    for (fe::SparseMatrix::InnerIterator it(d_.coupling, k); it; ++it) {
      entries.emplace_back(n + it.row(), it.col(), it.value());
      entries.emplace_back(it.col(), n + it.row(), it.value());
    }
  for (int k = 0; k < d_.flexibility.outerSize(); ++k)
    for (fe::SparseMatrix::InnerIterator it(d_.flexibility, k); it; ++it)
      entries.emplace_back(n + it.row(), n + it.col(), -it.value());
  // Every reaction node keeps its diagonal in the pattern, whatever T holds.
  for (int i = 0; i < m; ++i) entries.emplace_back(n + i, n + i, 0.0);
  full_.resize(n + m, n + m);
  full_.setFromTriplets(entries.begin(), entries.end());
  full_.makeCompressed();

  scaling_ = full_.diagonal().cwiseAbs();
  for (Eigen::Index i = 0; i < scaling_.size(); ++i)
    scaling_[i] = scaling_[i] > 0 ? 1.0 / std::sqrt(scaling_[i]) : 1.0;
  scaled_ = full_;
}

bool ActiveSetSystem::factorise(const std::vector<bool>& in_contact) {
  const int n = d_.equations, m = d_.reactions();
  if (static_cast<int>(in_contact.size()) != m)
    throw std::invalid_argument("ActiveSetSystem::factorise: one contact flag per reaction node expected");
  if (factorised_ && in_contact == in_contact_) return true;
  in_contact_ = in_contact;

  // A lifted-off node keeps its (unit or -1) diagonal and nothing else: r_i = 0.
  auto lifted_off = [&](Eigen::Index index) { return index >= n && !in_contact[index - n]; };
  const double* full = full_.valuePtr();
  double* values = scaled_.valuePtr();
  for (int k = 0; k < scaled_.outerSize(); ++k)
    for (fe::SparseMatrix::InnerIterator it(scaled_, k); it; ++it) {
      const Eigen::Index p = &it.valueRef() - values;
      const double scaled = full[p] * scaling_[it.row()] * scaling_[it.col()];
      if (it.row() == it.col())
        values[p] = lifted_off(it.row()) ? -1.0 : scaled;
      else
        values[p] = lifted_off(it.row()) || lifted_off(it.col()) ? 0.0 : scaled;
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

ContactState ActiveSetSystem::solve(const VectorXd& load) const {
  if (!factorised_) throw std::logic_error("ActiveSetSystem::solve before a successful factorise()");
  const int n = d_.equations, m = d_.reactions();
  // The equilibrated system S A S y = S b gives x = S y. Refinement computes the defect
  // b - A x on A as assembled (not its equilibrated, rounded copy) and in extended precision:
  // for a smooth u a row of K u cancels terms ~N^4 times larger than their sum, so a defect in
  // double precision holds no digits beyond ~1e4 elements. The size of the last correction
  // estimates the error left.
  const Eigen::Index size = full_.rows();
  VectorXd scaled_rhs = VectorXd::Zero(size);
  scaled_rhs.head(n) = scaling_.head(n).cwiseProduct(load);
  VectorXd x = scaling_.cwiseProduct(factors_.solve(scaled_rhs));
  std::vector<long double> accumulator(size);
  VectorXd defect(size), magnitude(size);
  auto in_system = [&](Eigen::Index index) { return index < n || in_contact_[index - n]; };
  // defect = b - A x (extended precision), magnitude = |b| + |A| |x|, over the current set.
  auto compute_defect = [&]() {
    for (Eigen::Index i = 0; i < size; ++i) accumulator[i] = i < n ? load[i] : 0.0;
    magnitude.head(n) = load.cwiseAbs();
    magnitude.tail(m).setZero();
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
    const VectorXd correction = scaling_.cwiseProduct(factors_.solve(scaling_.cwiseProduct(defect)));
    x += correction;
    const double change = correction.lpNorm<Eigen::Infinity>() / std::max(x.lpNorm<Eigen::Infinity>(), 1e-300);
    estimate = change;
    if (!(change > 1e-15) || change > 0.5 * previous) break;  // converged, or no longer contracting
    previous = change;
  }
  compute_defect();

  ContactState state;
  state.displacement = x.head(n);
  state.reaction = x.tail(m);
  for (int i = 0; i < m; ++i)
    if (!in_contact_[i]) state.reaction[i] = 0.0;
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
  VectorXd x(size);
  x << state.displacement, state.reaction;
  // D = |A| |x| + |b| over the current set.
  VectorXd weight = VectorXd::Zero(size);
  weight.head(n) = load.cwiseAbs();
  auto in_system = [&](Eigen::Index index) { return index < n || in_contact_[index - n]; };
  for (int col = 0; col < size; ++col) {
    if (!in_system(col)) continue;
    for (fe::SparseMatrix::InnerIterator it(full_, col); it; ++it)
      if (in_system(it.row())) weight[it.row()] += std::abs(it.value() * x[col]);
  }
  auto inverse = [&](const VectorXd& v) -> VectorXd {
    return scaling_.cwiseProduct(factors_.solve(scaling_.cwiseProduct(v)));
  };
  // Hager's estimate of || P A^-1 D ||_inf = || D A^-1 P^T ||_1 for the rows P of one block.
  auto block_norm = [&](Eigen::Index first, Eigen::Index count) {
    if (count == 0) return 0.0;
    auto apply = [&](const VectorXd& v) -> VectorXd {  // D A^-1 P^T v
      VectorXd embedded = VectorXd::Zero(size);
      embedded.segment(first, count) = v;
      return weight.cwiseProduct(inverse(embedded));
    };
    auto apply_transpose = [&](const VectorXd& w) -> VectorXd {  // P A^-1 D w
      return inverse(weight.cwiseProduct(w)).segment(first, count);
    };
    VectorXd v = VectorXd::Constant(count, 1.0 / static_cast<double>(count));
    double estimate = 0.0;
    for (int iteration = 0; iteration < 4; ++iteration) {
      const VectorXd y = apply(v);
      estimate = y.lpNorm<1>();
      const VectorXd signs = y.unaryExpr([](double value) { return value >= 0 ? 1.0 : -1.0; });
      const VectorXd z = apply_transpose(signs);
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
  if (u_scale > 0) error = std::max(error, eps * block_norm(0, n) / u_scale);
  if (r_scale > 0) error = std::max(error, eps * block_norm(n, m) / r_scale);
  return error;
}

}  // namespace liftoff::contact
