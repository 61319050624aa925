#include "stability/geometric_stiffness.hpp"

#include <stdexcept>
#include <vector>

#include "fe/beam_element.hpp"

namespace liftoff::stability {

Eigen::SparseMatrix<double> geometric_stiffness(const fe::Discretisation& d) {
  if (d.kind != model::StructureKind::beam)
    throw std::invalid_argument("stability::geometric_stiffness: beams only (an arch has no axial-force term here)");
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(16 * static_cast<std::size_t>(d.mesh.elements()));
  for (int e = 0; e < d.mesh.elements(); ++e) {
    const Eigen::Matrix4d g = fe::beam_element::geometric_stiffness(d.mesh.element_size(e));
    const std::vector<int> dofs = d.element_dofs(e);
    for (int i = 0; i < 4; ++i) {
      const int row = d.equation_of_dof[dofs[i]];
      if (row < 0) continue;
      for (int j = 0; j < 4; ++j) {
        const int column = d.equation_of_dof[dofs[j]];
        if (column >= 0) entries.emplace_back(row, column, g(i, j));
      }
    }
  }
  Eigen::SparseMatrix<double> k_g(d.equations, d.equations);
  k_g.setFromTriplets(entries.begin(), entries.end());
  return k_g;
}

}  // namespace liftoff::stability
