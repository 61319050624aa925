#include "contact/active_set_system.hpp"

#include <cmath>
#include <stdexcept>

namespace liftoff::contact {

using Eigen::VectorXd;

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
  for (int k = 0; k < full_.outerSize(); ++k)
    for (fe::SparseMatrix::InnerIterator it(full_, k); it; ++it)
      it.valueRef() *= scaling_[it.row()] * scaling_[it.col()];
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
      if (it.row() == it.col())
        values[p] = lifted_off(it.row()) ? -1.0 : full[p];
      else
        values[p] = lifted_off(it.row()) || lifted_off(it.col()) ? 0.0 : full[p];
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
  // The equilibrated system S A S y = S b, x = S y; one step of refinement on it.
  VectorXd rhs = VectorXd::Zero(scaled_.rows());
  rhs.head(n) = scaling_.head(n).cwiseProduct(load);
  VectorXd y = factors_.solve(rhs);
  VectorXd defect = rhs - scaled_ * y;
  y += factors_.solve(defect);
  defect = rhs - scaled_ * y;

  ContactState state;
  state.displacement = scaling_.head(n).cwiseProduct(y.head(n));
  state.reaction = scaling_.tail(m).cwiseProduct(y.tail(m));
  for (int i = 0; i < m; ++i)
    if (!in_contact_[i]) state.reaction[i] = 0.0;
  state.gap = d_.flexibility * state.reaction - d_.coupling * state.displacement;
  for (int i = 0; i < m; ++i)
    if (in_contact_[i]) state.gap[i] = 0.0;  // exact by construction; the defect measures it
  // Row-wise relative defect |A x - b|_i / (sum_j |A_ij x_j| + |b_i|): the same for the
  // equilibrated rows as for the original ones.
  VectorXd magnitude = rhs.cwiseAbs();
  for (int k = 0; k < scaled_.outerSize(); ++k)
    for (fe::SparseMatrix::InnerIterator it(scaled_, k); it; ++it)
      magnitude[it.row()] += std::abs(it.value() * y[it.col()]);
  double residual = 0.0;
  for (Eigen::Index i = 0; i < defect.size(); ++i)
    if (magnitude[i] > 0) residual = std::max(residual, std::abs(defect[i]) / magnitude[i]);
  state.residual = residual;
  return state;
}

}  // namespace liftoff::contact
