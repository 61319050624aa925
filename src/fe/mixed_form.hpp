#pragma once
// The member's equations without contact in mixed (Hellinger-Reissner) form, as one sparse matrix
// over z = (m, u), the element stress resultants then the equations' displacements:
//     [ H   -G ] [ m ]   [ 0 ]
//     [ G^T  0 ] [ u ] = [ f ],   so that  G^T H^-1 G u = K u = f.
// Its condition grows like N^2 where K's grows like N^4 (see contact/active_set_system.hpp, which
// adds the contact rows to the same blocks): the form in which a 1e5-element member still has
// digits. Used where a plain linear FE residual is wanted in that form: Newton over the sparse
// linear-solver seam in tests and in the benchmark.

#include <Eigen/Sparse>
#include <vector>

#include "fe/discretisation.hpp"

namespace liftoff::fe {

inline Eigen::SparseMatrix<double> mixed_matrix(const Discretisation& d) {
  const Eigen::SparseMatrix<double>& g = d.stress_coupling;
  const int m = d.stresses(), n = m + d.equations;
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<std::size_t>(m + 2 * g.nonZeros()));
  for (int i = 0; i < m; ++i) entries.emplace_back(i, i, d.compliance(i));
  for (int j = 0; j < g.outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(g, j); it; ++it) {
      entries.emplace_back(static_cast<int>(it.row()), m + static_cast<int>(it.col()), -it.value());
      entries.emplace_back(m + static_cast<int>(it.col()), static_cast<int>(it.row()), it.value());
    }
  Eigen::SparseMatrix<double> matrix(n, n);
  matrix.setFromTriplets(entries.begin(), entries.end());
  return matrix;
}

}  // namespace liftoff::fe
