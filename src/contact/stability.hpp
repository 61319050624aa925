#pragma once
// Whether an equilibrium under a compressive axial force is stable (second-order theory).
//
// Under an axial force N the stiffness K(N) = K - N K_g (fe/discretisation.hpp) may be indefinite,
// and a contact solve may still return a state that satisfies every equilibrium and contact
// condition: an unstable equilibrium, which the member never rests in. What decides is the tangent
// on the contact set found: K(N) plus the foundation's stiffness on the nodes in contact, none on
// the nodes lifted off, on the free dofs,
//   K_A(N) = K(N) + C_A^T T_AA^-1 C_A,
// which must be positive definite. It is read from the inertia of the saddle-point matrix
//   S = [ K(N)  C_A^T ]
//       [ C_A  -T_AA  ]:
// T_AA is positive definite, so by Sylvester's law (Haynsworth's inertia additivity) S has exactly
// |A| negative eigenvalues, and no zero one, if and only if K_A(N) is positive definite. The
// inertia is that of D in a sparse LDL^T factorisation of S symmetrically scaled (congruences);
// a factorisation that breaks down, or a pivot below 1e-14 of the largest, counts as not positive
// definite (a singular tangent: at the critical load).
//
// This is the check on the contact set in hand (nodes in contact keep their springs), not the
// eigenvalue complementarity problem on the cone of admissible perturbations: a state it passes
// is stable against every perturbation that keeps the contact set; one it refuses is unstable.

#include <string>
#include <vector>

#include "fe/discretisation.hpp"

namespace liftoff::contact {

struct StabilityCheck {
  bool positive_definite = false;
  int negative_eigenvalues = 0;  // of K_A(N) (-1 when the factorisation broke down)
  std::string message;           // in words
};

// The tangent on the contact set (one flag per reaction node; a bilateral foundation: every node).
StabilityCheck check_tangent(const fe::Discretisation& discretisation, const std::vector<bool>& in_contact);

// Whether a symmetric sparse matrix is positive definite (a sparse Cholesky that succeeds): the
// dual LCP's K(N) must be.
bool is_positive_definite(const fe::SparseMatrix& matrix);

}  // namespace liftoff::contact
