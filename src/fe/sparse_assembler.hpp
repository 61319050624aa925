#pragma once
// Fixed-pattern sparse assembly of a residual and its tangent from elements (element.hpp).
//
// Set up once, assemble many (as contact::ActiveSetSystem does for its saddle-point system):
// the constructor takes each element's global dofs and the dof-to-equation map, builds the
// symbolic pattern of K (every entry some element couples, in compressed column storage) and,
// per element, the position in the value array of each of its (i, j) entries. assemble() then
// zeroes the values and adds each element's K_t and f_int in place: no search, no insertion, no
// reallocation, so the matrix's arrays (and a factorisation's symbolic analysis of them) stay
// valid from one assembly to the next. Dofs mapped to -1 (supports, gauge) are dropped: their
// rows and columns are not equations; their values still enter each element's state.
//
// The assembled matrix holds structural zeros where elements couple dofs whose entries cancel,
// as Eigen's setFromTriplets does: the pattern is that of the coupling, not of the values.

#include <Eigen/Sparse>
#include <memory>
#include <vector>

#include "fe/element.hpp"

namespace liftoff::fe {

class SparseAssembler {
 public:
  using SparseMatrix = Eigen::SparseMatrix<double>;

  // element_dofs[e]: element e's global dofs, in its local order; equation_of_dof: the equation
  // of each global dof, -1 where fixed. Throws std::invalid_argument on a dof out of range.
  SparseAssembler(std::vector<std::vector<int>> element_dofs, std::vector<int> equation_of_dof);

  int elements() const { return static_cast<int>(element_dofs_.size()); }
  int equations() const { return static_cast<int>(tangent_.rows()); }

  // Evaluate every element at the displacement on every dof (u_all, the prescribed values
  // included) and load factor lambda, and assemble K_t and f_int on the equations in place.
  // elements[e] acts on element_dofs[e]; throws std::invalid_argument on mismatched sizes.
  void assemble(const std::vector<std::unique_ptr<const Element>>& elements, const Eigen::VectorXd& u_all,
                double load_factor);

  // The last assembly: K_t (equations x equations) and f_int (equations).
  const SparseMatrix& tangent() const { return tangent_; }
  const Eigen::VectorXd& internal_force() const { return internal_force_; }

 private:
  std::vector<std::vector<int>> element_dofs_;
  std::vector<int> equation_of_dof_;
  // Per element, row-major over its local (i, j): the index into tangent_'s values, -1 if dropped.
  std::vector<std::vector<int>> slots_;
  SparseMatrix tangent_;
  Eigen::VectorXd internal_force_;
  std::vector<ElementState> states_;  // scratch, by element size
  std::vector<ElementResponse> responses_;
};

}  // namespace liftoff::fe
