#pragma once
// The contact problem with its contact set fixed, as one sparse system.
//
// With the set A of reaction nodes in contact (gap 0, reaction free) and the rest lifted off
// (reaction 0, gap free), the conditions K u + C^T r = F, (T r - C u)_A = 0, r_I = 0 are
//   [ K     C_A^T ] [ u   ]   [ F ]
//   [ C_A  -T_AA  ] [ r_A ] = [ 0 ],   gap_I = T_IA r_A - C_I u.
// This is the kernel shared by the sparse active-set solver and the parametric FE path.
//
// It is solved in the mixed (Hellinger-Reissner) form of the same equations: with the element
// stress resultants m = H^-1 G u as unknowns (K = G^T H^-1 G exactly, fe/discretisation.hpp)
//   [ 0     G^T   C_A^T ] [ u   ]   [ F ]
//   [ G    -H     0     ] [ m   ] = [ 0 ]
//   [ C_A   0    -T_AA  ] [ r_A ]   [ 0 ].
// Under an axial force N (fe/discretisation.hpp) the first block's 0 is -N K_g: K(N) = G^T H^-1 G
// - N K_g, indefinite or not, which the pivoting LU below takes as it comes.
// Why: K's condition grows like N^4 (1e16 at 1e4 elements), so no double-precision factorisation
// of K can be refined to an answer beyond ~1e4 elements; the mixed matrix's grows like N^2, and
// its entries (integers and +-2/h for beams, identical in every element of a segment) are exact
// data of a nearby mesh. The bilateral seed beam's nodal error against the closed form, with the
// K form and with this one: 2.7e-9 and 1.2e-15 at 1e4 elements, 0.75 and 1.2e-15 at 1e5, and
// 1.2e-15 still at 1e6 (verification/bench/accuracy_bench.cpp roundoff; arches:
// src/README.md, "Mesh size and round-off").
//
// The mixed matrix is indefinite with a zero block, so it is factorised by LU with partial
// pivoting (linalg/banded_lu.hpp) after symmetric equilibration, with the unknowns numbered
// along the member: banded, O(n) to factorise (kl = ku = 7 for beams) and O(n) per solve, so a
// contact set that does not change is never refactorised and every load (dead, live, a
// correction) is one more solve with the same factors. Each solve is refined with defects
// computed in extended precision against the matrix as assembled.
//
// Set up once, factorise per set: one fixed pattern over every reaction node; a node lifted off
// keeps only its diagonal (r_i = 0) with its coupling entries zeroed. Nothing allocates after the
// first factorise() but the returned states.
//
// A contact set that leaves a rigid motion free (the motions the supports leave free that the
// contact nodes do not see: ker K and ker C_A meet) makes the system singular; factorise() tests
// this exactly (the rank of C_A times those motions) and returns false.
//
// Not thread-safe: solve() uses workspace held by the object.

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <vector>

#include "fe/discretisation.hpp"
#include "linalg/banded_lu.hpp"

namespace liftoff::contact {

struct ContactState {
  Eigen::VectorXd displacement;  // on the equations
  Eigen::VectorXd reaction;      // every reaction node (0 where lifted off)
  Eigen::VectorXd gap;           // T r - C u, every reaction node (0 in contact, to round-off)
  double residual = -1.0;        // relative residual of the linear system after refinement
  // Relative error of (u, r) left after iterative refinement, estimated from the size of its
  // last correction (the solver's share; data_error() below gives the data's).
  double error_estimate = -1.0;
  int refinement_steps = -1;
};

// How far solve() refines: until the estimated relative error of (u, r) is at most
// target_error (0: until refinement stops gaining, at round-off), and at most max_steps steps.
// residual: also compute ContactState::residual (one more defect; -1 otherwise).
struct RefinementOptions {
  double target_error = 0.0;
  int max_steps = 6;
  bool residual = true;
};

class ActiveSetSystem {
 public:
  explicit ActiveSetSystem(const fe::Discretisation& discretisation);

  // The discretisation given to the constructor has changed (the same object, discretised again,
  // e.g. on moved nodes): assembles it again, reusing this object's storage (a limit-fitted
  // Newton step allocates nothing here when the sizes hold). Forgets the factorisation.
  void reassemble();

  // Factorises for this contact set (one flag per reaction node). Returns false when the
  // system is singular: the contact set leaves a rigid motion free.
  // The set already factorised is not factorised again.
  bool factorise(const std::vector<bool>& in_contact);

  // Solves for a load on the equations (nondimensional), refined to round-off. Requires a
  // successful factorise(). The gap offset c (one per reaction node, Discretisation::ground_gap
  // scaled as the load is) makes the contact rows C_A u - T_AA r_A = c_A and the gaps
  // T r - C u + c; the forms without it take c = 0 (a load alone, or a homogeneous response).
  ContactState solve(const Eigen::VectorXd& load) const;
  ContactState solve(const Eigen::VectorXd& load, const RefinementOptions& refinement) const;
  ContactState solve(const Eigen::VectorXd& load, const Eigen::VectorXd& gap_offset,
                     const RefinementOptions& refinement = {}) const;

  // Refines the last solve's answer further (the same set and load), e.g. to round-off after a
  // solve that stopped at a coarser target_error: no new first solve. Requires a solve().
  ContactState refine_last_solve(const RefinementOptions& refinement = {}) const;

  // The relative residual (ContactState::residual) of the last solve's answer, for a solve that
  // skipped it (RefinementOptions::residual = false): one defect, no solve.
  double residual_of_last_solve() const;

  // Relative error of u and of r (the larger) that the rounding of the system's own data can
  // cause: eps times Skeel's condition number || |A^-1| (|A| |x| + |b|) || / ||x||, per block,
  // of the mixed system, estimated by Hager's method (up to 12 solves with the current factors,
  // O(n) each). A worst-case bound for random relative perturbations of every entry; the actual
  // data of a mesh with uniform segments is perturbed systematically and does far less. Only
  // on request: nothing in the solvers calls it.
  double data_error(const ContactState& state, const Eigen::VectorXd& load) const;

  const std::vector<bool>& in_contact() const { return in_contact_; }
  // Numeric factorisations so far.
  int factorisations() const { return factorisations_; }
  // Unknowns of the fixed-pattern system: equations + stresses + every reaction node.
  int size() const { return static_cast<int>(full_.rows()); }
  // Half bandwidth of the factorised matrix (its unknowns numbered along the member).
  int bandwidth() const { return lu_.lower(); }

 private:
  void assemble();                 // everything that depends on d_ alone
  bool in_system(int slot) const;  // a displacement, a stress, or the reaction of a node in contact
  bool holds_rigid_motions(const std::vector<bool>& in_contact) const;
  void solve_in_place(Eigen::VectorXd& b) const;  // b <- A^-1 b, by S (S A S)^-1 S
  // defect = rhs - A x (extended precision), magnitude = |rhs| + |A| |x|, over the current set.
  void compute_defect(const Eigen::VectorXd& rhs, const Eigen::VectorXd& x) const;
  double relative_defect() const;
  ContactState refine(const RefinementOptions& refinement) const;  // from x_ for rhs_

  const fe::Discretisation& d_;
  std::vector<bool> in_contact_;
  // Unknowns are numbered along the member ("slots"): equation e at slot_[e], stress k at
  // slot_[n + k], reaction i at slot_[n + ns + i]; reaction_of_slot_ gives the reaction node
  // of a slot, or -1.
  std::vector<int> slot_;
  std::vector<int> reaction_of_slot_;
  std::vector<int> block_of_slot_;   // 0 displacement, 1 stress, 2 reaction
  fe::SparseMatrix full_;            // the mixed matrix as assembled, every node in contact, in slots
  std::vector<double> masked_;       // its values for the current set (lifted-off couplings zeroed)
  bool symmetric_ = false;           // full_ equals its transpose exactly (by construction it does)
  Eigen::VectorXd scaling_;          // S: S A S has entries of at most 1 in every row
  Eigen::MatrixXd coupled_motions_;  // C Q: the free rigid motions Q seen by every reaction node
  linalg::BandedLu lu_;
  bool factorised_ = false;
  mutable bool solved_ = false;  // x_ holds a solve for the current factors
  int factorisations_ = 0;
  // Workspace of solve().
  mutable Eigen::VectorXd rhs_, x_, correction_, defect_, magnitude_;
  mutable Eigen::VectorXd offset_;  // the last solve's gap offset (reactions)
  mutable std::vector<long double> accumulator_;
};

}  // namespace liftoff::contact
