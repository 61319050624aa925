#include "fe/sparse_assembler.hpp"

#include <algorithm>
#include <stdexcept>

namespace liftoff::fe {

SparseAssembler::SparseAssembler(std::vector<std::vector<int>> element_dofs, std::vector<int> equation_of_dof)
    : element_dofs_(std::move(element_dofs)), equation_of_dof_(std::move(equation_of_dof)) {
  const int dofs = static_cast<int>(equation_of_dof_.size());
  const int n =
      static_cast<int>(std::count_if(equation_of_dof_.begin(), equation_of_dof_.end(), [](int eq) { return eq >= 0; }));
  // Symbolic stage: the pattern from triplets of value 0, compressed once.
  std::vector<Eigen::Triplet<double>> pattern;
  for (const auto& dofs_of_element : element_dofs_) {
    for (int dof : dofs_of_element)
      if (dof < 0 || dof >= dofs) throw std::invalid_argument("SparseAssembler: an element dof out of range");
    for (int i : dofs_of_element)
      for (int j : dofs_of_element)
        if (equation_of_dof_[i] >= 0 && equation_of_dof_[j] >= 0)
          pattern.emplace_back(equation_of_dof_[i], equation_of_dof_[j], 0.0);
  }
  tangent_.resize(n, n);
  tangent_.setFromTriplets(pattern.begin(), pattern.end());
  tangent_.makeCompressed();
  internal_force_ = Eigen::VectorXd::Zero(n);

  // Each element entry's position in the value array, found once by binary search in its column.
  const int* outer = tangent_.outerIndexPtr();
  const int* inner = tangent_.innerIndexPtr();
  slots_.resize(element_dofs_.size());
  for (std::size_t e = 0; e < element_dofs_.size(); ++e) {
    const auto& local = element_dofs_[e];
    const int m = static_cast<int>(local.size());
    slots_[e].assign(static_cast<std::size_t>(m) * m, -1);
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < m; ++j) {
        const int row = equation_of_dof_[local[i]], col = equation_of_dof_[local[j]];
        if (row < 0 || col < 0) continue;
        const int* found = std::lower_bound(inner + outer[col], inner + outer[col + 1], row);
        slots_[e][static_cast<std::size_t>(i) * m + j] = static_cast<int>(found - inner);
      }
  }
}

void SparseAssembler::assemble(const std::vector<std::unique_ptr<const Element>>& elements,
                               const Eigen::VectorXd& u_all, double load_factor) {
  if (elements.size() != element_dofs_.size())
    throw std::invalid_argument("SparseAssembler::assemble: one element per dof list expected");
  if (u_all.size() != static_cast<Eigen::Index>(equation_of_dof_.size()))
    throw std::invalid_argument("SparseAssembler::assemble: one displacement per dof expected");
  double* values = tangent_.valuePtr();
  std::fill(values, values + tangent_.nonZeros(), 0.0);
  internal_force_.setZero();
  for (std::size_t e = 0; e < elements.size(); ++e) {
    const auto& local = element_dofs_[e];
    const int m = static_cast<int>(local.size());
    if (elements[e]->dofs() != m)
      throw std::invalid_argument("SparseAssembler::assemble: an element's dofs differ from its dof list");
    // Scratch per element size, so that a mesh mixing sizes (arch and Winkler) reallocates nothing.
    if (m >= static_cast<int>(states_.size())) {
      states_.resize(m + 1);
      responses_.resize(m + 1);
    }
    ElementState& state = states_[m];
    ElementResponse& response = responses_[m];
    state.load_factor = load_factor;
    state.displacement.resize(m);
    for (int i = 0; i < m; ++i) state.displacement[i] = u_all[local[i]];
    elements[e]->evaluate(state, response);
    const int* slot = slots_[e].data();
    for (int i = 0; i < m; ++i) {
      const int row = equation_of_dof_[local[i]];
      if (row >= 0) internal_force_[row] += response.internal_force[i];
      for (int j = 0; j < m; ++j, ++slot)
        if (*slot >= 0) values[*slot] += response.tangent(i, j);
    }
  }
}

}  // namespace liftoff::fe
