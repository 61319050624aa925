#include "contact/active_set_system.hpp"

#include <cmath>
#include <stdexcept>

namespace liftoff::contact {

using Eigen::VectorXd;

ActiveSetSystem::ActiveSetSystem(const fe::Discretisation& discretisation) : d_(discretisation) {}

bool ActiveSetSystem::factorise(const std::vector<bool>& in_contact) {
  const int n = d_.equations, m = d_.reactions();
  if (static_cast<int>(in_contact.size()) != m)
    throw std::invalid_argument("ActiveSetSystem::factorise: one contact flag per reaction node expected");
  in_contact_ = in_contact;
  contact_index_.assign(m, -1);
  int active = 0;
  for (int i = 0; i < m; ++i)
    if (in_contact[i]) contact_index_[i] = active++;

  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(d_.stiffness.nonZeros() + 2 * d_.coupling.nonZeros() + d_.flexibility.nonZeros());
  for (int k = 0; k < d_.stiffness.outerSize(); ++k)
    for (fe::SparseMatrix::InnerIterator it(d_.stiffness, k); it; ++it)
      entries.emplace_back(it.row(), it.col(), it.value());
  for (int k = 0; k < d_.coupling.outerSize(); ++k)
    for (fe::SparseMatrix::InnerIterator it(d_.coupling, k); it; ++it) {
      const int a = contact_index_[it.row()];
      if (a < 0) continue;
      entries.emplace_back(n + a, it.col(), it.value());
      entries.emplace_back(it.col(), n + a, it.value());
    }
  for (int k = 0; k < d_.flexibility.outerSize(); ++k)
    for (fe::SparseMatrix::InnerIterator it(d_.flexibility, k); it; ++it) {
      const int a = contact_index_[it.row()], b = contact_index_[it.col()];
      if (a >= 0 && b >= 0) entries.emplace_back(n + a, n + b, -it.value());
    }
  matrix_.resize(n + active, n + active);
  matrix_.setFromTriplets(entries.begin(), entries.end());

  scaling_ = matrix_.diagonal().cwiseAbs();
  for (Eigen::Index i = 0; i < scaling_.size(); ++i)
    scaling_[i] = scaling_[i] > 0 ? 1.0 / std::sqrt(scaling_[i]) : 1.0;
  const fe::SparseMatrix scaled = scaling_.asDiagonal() * matrix_ * scaling_.asDiagonal();
  factors_.compute(scaled);
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
  VectorXd rhs = VectorXd::Zero(matrix_.rows());
  rhs.head(n) = load;
  auto scaled_solve = [&](const VectorXd& b) -> VectorXd {
    return scaling_.asDiagonal() * factors_.solve(scaling_.asDiagonal() * b);
  };
  VectorXd x = scaled_solve(rhs);
  VectorXd defect = rhs - matrix_ * x;
  x += scaled_solve(defect);
  defect = rhs - matrix_ * x;

  ContactState state;
  state.displacement = x.head(n);
  state.reaction = VectorXd::Zero(m);
  for (int i = 0; i < m; ++i)
    if (contact_index_[i] >= 0) state.reaction[i] = x[n + contact_index_[i]];
  state.gap = d_.flexibility * state.reaction - d_.coupling * state.displacement;
  for (int i = 0; i < m; ++i)
    if (contact_index_[i] >= 0) state.gap[i] = 0.0;  // exact by construction; the defect measures it
  // Row-wise relative defect: |A x - b|_i / (sum_j |A_ij x_j| + |b_i|).
  VectorXd magnitude = rhs.cwiseAbs();
  for (int k = 0; k < matrix_.outerSize(); ++k)
    for (fe::SparseMatrix::InnerIterator it(matrix_, k); it; ++it)
      magnitude[it.row()] += std::abs(it.value() * x[it.col()]);
  double residual = 0.0;
  for (Eigen::Index i = 0; i < defect.size(); ++i)
    if (magnitude[i] > 0) residual = std::max(residual, std::abs(defect[i]) / magnitude[i]);
  state.residual = residual;
  return state;
}

}  // namespace liftoff::contact
