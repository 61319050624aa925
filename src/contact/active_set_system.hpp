#pragma once
// The contact problem with its contact set fixed, as one sparse symmetric system.
//
// With the set A of reaction nodes in contact (gap 0, reaction free) and the rest lifted off
// (reaction 0, gap free), the conditions K u + C^T r = F, (T r - C u)_A = 0, r_I = 0 are
//   [ K     C_A^T ] [ u   ]   [ F ]
//   [ C_A  -T_AA  ] [ r_A ] = [ 0 ],   gap_I = T_IA r_A - C_I u.
// This is the kernel shared by the sparse active-set solver and the parametric FE path: it
// costs O(n) to factorise for a beam or arch (banded after AMD ordering; unknowns numbered
// along the member) and O(n) per solve, so
// a contact set that does not change is never refactorised, and every load (dead, live, a
// correction) is one more solve with the same factors.
//
// Set up once, factorise per set: the matrix keeps one fixed pattern, [K C^T; C -T] over every
// reaction node, and a node lifted off keeps only its diagonal (-T_ii r_i = 0, so r_i = 0)
// with its coupling entries zeroed. The ordering and symbolic analysis are therefore done once,
// on the first factorise(); every other contact set costs one numeric factorisation, and asking
// again for the set already factorised costs nothing.
//
// The matrix is quasi-definite when K is positive definite; when K is singular (a member only
// the foundation holds) it is still nonsingular as long as the contact set holds every rigid
// motion. It is equilibrated symmetrically (unit diagonal) before an LDL^T factorisation, and
// each solve is refined with defects in extended precision (beams and arches reach cond ~ N^4,
// 1e16 at 1e4 elements).

#include <vector>

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include "fe/discretisation.hpp"

namespace liftoff::contact {

struct ContactState {
  Eigen::VectorXd displacement;  // on the equations
  Eigen::VectorXd reaction;      // every reaction node (0 where lifted off)
  Eigen::VectorXd gap;           // T r - C u, every reaction node (0 in contact, to round-off)
  double residual = -1.0;        // relative residual of the linear system after refinement
  // Relative error of (u, r) left after iterative refinement, estimated from the size of its
  // last correction (the solver's share; data_error() below gives the data's).
  double error_estimate = -1.0;
};

class ActiveSetSystem {
 public:
  explicit ActiveSetSystem(const fe::Discretisation& discretisation);

  // Factorises for this contact set (one flag per reaction node). Returns false when the
  // system is singular to working precision: the contact set leaves a rigid motion free.
  // The set already factorised is not factorised again.
  bool factorise(const std::vector<bool>& in_contact);

  // Solves for a load on the equations (nondimensional). Requires a successful factorise().
  ContactState solve(const Eigen::VectorXd& load) const;

  // Relative error of u and of r (the larger) that the rounding of the system's own data can
  // cause: eps times Skeel's condition number || |A^-1| (|A| |x| + |b|) || / ||x||, per block,
  // estimated by Hager's method (a few solves with the current factors, O(n)). Unlike the
  // refinement's estimate this sees the ill-conditioning of fine meshes (N^4), where element
  // sizes rounded to double already move the answer.
  double data_error(const ContactState& state, const Eigen::VectorXd& load) const;

  const std::vector<bool>& in_contact() const { return in_contact_; }
  // Numeric factorisations so far (the symbolic analysis is done once).
  int factorisations() const { return factorisations_; }
  // Unknowns of the fixed-pattern system: equations + every reaction node.
  int size() const { return static_cast<int>(scaled_.rows()); }

 private:
  bool in_system(int slot) const;  // a displacement, or the reaction of a node in contact
  Eigen::VectorXd unscaled_solve(const Eigen::VectorXd& b) const;  // A^-1 b, by S (S A S)^-1 S

  const fe::Discretisation& d_;
  std::vector<bool> in_contact_;
  // Unknowns are numbered along the member ("slots"): equation e at slot_[e], reaction i at
  // slot_[n + i]; reaction_of_slot_ gives the reaction node of a slot, or -1.
  std::vector<int> slot_;
  std::vector<int> reaction_of_slot_;
  fe::SparseMatrix full_;     // [K C^T; C -T] as assembled, every node in contact, in slots
  fe::SparseMatrix scaled_;   // equilibrated, for the current contact set (same pattern)
  Eigen::VectorXd scaling_;   // S: S A S has unit diagonal
  // AMD, not the band order of the slots: with the band order the pivot of a free rigid motion
  // is not at round-off level (a chain of N eliminations amplifies it), so factorise() could not
  // tell a singular set; AMD costs ~1 s per 1e6 unknowns, once.
  Eigen::SimplicialLDLT<fe::SparseMatrix, Eigen::Lower, Eigen::AMDOrdering<int>> factors_;
  bool analysed_ = false;
  bool factorised_ = false;
  int factorisations_ = 0;
};

}  // namespace liftoff::contact
