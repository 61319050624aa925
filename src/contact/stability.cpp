#include "contact/stability.hpp"

#include <fmt/format.h>

#include <Eigen/SparseCholesky>
#include <cmath>

namespace liftoff::contact {

StabilityCheck check_tangent(const fe::Discretisation& d, const std::vector<bool>& in_contact) {
  const int n = d.equations, m = d.reactions();
  std::vector<int> row_of_reaction(m, -1);
  int size = n;
  for (int i = 0; i < m; ++i)
    if (!d.tensionless || (i < static_cast<int>(in_contact.size()) && in_contact[i])) row_of_reaction[i] = size++;
  const int contact = size - n;
  std::vector<Eigen::Triplet<double>> entries;
  for (int k = 0; k < d.stiffness.outerSize(); ++k)
    for (fe::SparseMatrix::InnerIterator it(d.stiffness, k); it; ++it)
      entries.emplace_back(static_cast<int>(it.row()), static_cast<int>(it.col()), it.value());
  for (int k = 0; k < d.coupling.outerSize(); ++k)
    for (fe::SparseMatrix::InnerIterator it(d.coupling, k); it; ++it)
      if (const int row = row_of_reaction[it.row()]; row >= 0) {
        entries.emplace_back(row, static_cast<int>(it.col()), it.value());
        entries.emplace_back(static_cast<int>(it.col()), row, it.value());
      }
  for (int k = 0; k < d.flexibility.outerSize(); ++k)
    for (fe::SparseMatrix::InnerIterator it(d.flexibility, k); it; ++it)
      if (row_of_reaction[it.row()] >= 0 && row_of_reaction[it.col()] >= 0)
        entries.emplace_back(row_of_reaction[it.row()], row_of_reaction[it.col()], -it.value());
  fe::SparseMatrix saddle(size, size);
  saddle.setFromTriplets(entries.begin(), entries.end());
  // Symmetric diagonal scaling, a congruence (the inertia stays): K's entries (~1/h^3) and T's
  // (~h/k) differ by 20 orders of magnitude on a long member, so pivots are compared scaled.
  Eigen::VectorXd scaling = Eigen::VectorXd::Ones(size);
  for (int k = 0; k < saddle.outerSize(); ++k)
    for (fe::SparseMatrix::InnerIterator it(saddle, k); it; ++it)
      if (it.row() == it.col() && it.value() != 0.0) scaling[k] = 1.0 / std::sqrt(std::abs(it.value()));
  saddle = scaling.asDiagonal() * saddle * scaling.asDiagonal();

  StabilityCheck check;
  const Eigen::SimplicialLDLT<fe::SparseMatrix> ldlt(saddle);
  if (ldlt.info() != Eigen::Success) {
    check.negative_eigenvalues = -1;
    check.message = "the tangent on the contact set is singular (its LDL^T factorisation met a zero pivot)";
    return check;
  }
  const Eigen::VectorXd pivots = ldlt.vectorD();
  const double scale = pivots.cwiseAbs().maxCoeff();
  int negative = 0, zero = 0;
  for (int i = 0; i < size; ++i) {
    if (!(std::abs(pivots[i]) > 1e-14 * scale))
      ++zero;
    else if (pivots[i] < 0.0)
      ++negative;
  }
  check.negative_eigenvalues = negative - contact;
  check.positive_definite = zero == 0 && negative == contact;
  if (!check.positive_definite)
    check.message = zero > 0 ? "the tangent on the contact set is singular (a zero pivot)"
                             : fmt::format("the tangent on the contact set has {} negative eigenvalue{}",
                                           check.negative_eigenvalues, check.negative_eigenvalues == 1 ? "" : "s");
  return check;
}

bool is_positive_definite(const fe::SparseMatrix& matrix) {
  const Eigen::SimplicialLLT<fe::SparseMatrix> llt(matrix);
  return llt.info() == Eigen::Success;
}

}  // namespace liftoff::contact
