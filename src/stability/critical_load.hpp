#pragma once
// The critical load factor of a solved state of a beam on a tensionless foundation, under a
// constant compressive axial force N = N_dead + lambda N_live (positive compresses, nondimensional
// N L^2 / EI).
//
// The second variation. At an equilibrium the reaction nodes are in contact (positive reaction:
// they stay in contact under a small perturbation phi, a bilateral spring), lifted (positive gap:
// no spring) or weakly active (zero reaction and zero gap: a spring only where phi pushes into
// the foundation). In the discretisation's mixed form (fe/discretisation.hpp: gap = T r - C u),
// a spring set S of reaction nodes stiffens the member by K_S = C_S^T T_SS^-1 C_S (the reactions
// dr_S = T_SS^-1 C_S phi eliminated from dgap_S = 0; with a lumped T this is sum k_i phi_i^2), and
// a weakly active node i belongs to S exactly when the perturbation keeps the discrete contact
// conditions: dr_i >= 0 for i in S, dgap_i = (T dr - C phi)_i >= 0 for i not in S. The critical
// factor is the smallest lambda > 0 at which
//   phi^T (K + K_S(phi) - N_dead K_g - lambda N_live K_g) phi
// stops being positive on some phi != 0: an eigenvalue complementarity problem on the cone of
// admissible perturbations (phi and -phi are different perturbations there).
//
// Algorithm. On a fixed set S the problem is the generalized symmetric eigenproblem in the axial
// force, (K + K_S) phi = N K_g phi, with K + K_S positive definite whatever the loads (else a
// rigid motion no spring holds) and K_g only semidefinite: it is solved as the largest
// mu = 1 / N of K_g phi = mu (K + K_S) phi, and N_cr = N_dead + lambda_cr N_live gives the factor
// (N_cr <= N_dead: unstable at lambda = 0).
//  - dense (few equations): Eigen's GeneralizedSelfAdjointEigenSolver on K + K_S (K_S formed).
//  - sparse: subspace iteration with Rayleigh-Ritz (Bathe's) on the mixed saddle-point system
//    (the discretisation's stresses, fe/discretisation.hpp, K = G^T H^-1 G) with the reactions
//    of S: [-H, G, 0; G^T, -sigma K_g, C_S^T; 0, C_S, -T_SS], factorised by a sparse LU, so
//    K_S (dense where T is not diagonal) is never formed and the condition grows like N^2, not
//    N^4 (in the stiffness form the foundation's springs, k h against EI/h^3, were lost to
//    round-off at 1e4 elements). The shift sigma moves up towards the smallest eigenvalue. The
//    LU's determinant sign is the parity of the number of eigenvalues below sigma (a Sturm count
//    modulo 2): it keeps each shift below the smallest eigenvalue and checks the answer (no odd
//    number of eigenvalues below N_cr (1 - sturm_margin)); a missed pair would pass (no sparse
//    symmetric-indefinite factorisation with pivoting, which would give the count, is in the
//    build).
// The spring set is iterated from S = the nodes in contact (no weak springs, whose eigenvalue is a
// lower bound of the cone's): the mode (of either sign, the one breaking fewer conditions) decides
// the weakly active nodes' springs, until the set is a fixed point whose mode meets every
// condition. A cycle is resolved by enumerating the weakly active nodes' subsets (at most
// enumeration_limit of them), else not_converged.
//
// Limitations. The fixed point's mode is an admissible eigenpair of the cone problem, so its
// factor bounds the cone's critical factor from above, and the factor of S = the nodes in contact
// bounds it from below (both reported); when they differ the answer is the smallest admissible
// eigenpair found by the iteration (or the enumeration), not a proof of the global minimum, which
// an EiCP solver would need. Only the smallest eigenvalue of each set is tried. A state whose
// K + K_S is singular without the weak springs but not with them is reported not_converged. The
// sparse path's Sturm check is a parity (above). Beams only, N constant along the member.

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/enum_names.hpp"
#include "fe/discretisation.hpp"

namespace liftoff::stability {

// A reaction node's state at the equilibrium.
enum class NodeContact {
  in_contact,     // positive reaction: a bilateral spring under small perturbations
  lifted,         // positive gap: no spring
  weakly_active,  // zero reaction and zero gap: a spring only where phi pushes in
};
std::string_view to_string(NodeContact);

// The state of every reaction node from a solved state's reactions and gaps (ContactSolution's
// reaction, gap): in contact where r_i > tolerance max|r|, lifted where gap_i > tolerance max|gap|,
// weakly active otherwise (both zero to the tolerance). Throws std::invalid_argument for
// different sizes or a tolerance outside [0, 1).
std::vector<NodeContact> classify_contact(const Eigen::VectorXd& reaction, const Eigen::VectorXd& gap,
                                          double tolerance = 1e-8);

enum class EigenMethod { automatic, dense, sparse };
std::string_view to_string(EigenMethod);

struct CriticalLoadOptions {
  EigenMethod method = EigenMethod::automatic;
  int dense_limit = 400;         // automatic: dense up to this many equations, else sparse
  int block_size = 8;            // sparse: vectors of the subspace iteration
  int max_iterations = 500;      // sparse: subspace iterations per spring set
  double tolerance = 1e-10;      // sparse: the mode's residual (a stalled one is accepted under its sqrt)
  double sturm_margin = 1e-7;    // sparse: no eigenvalue below lambda (1 - sturm_margin) (checked)
  double sign_tolerance = 1e-9;  // cone conditions: violated below -sign_tolerance times their scale
  int max_set_iterations = 50;   // spring-set fixed-point iterations
  int enumeration_limit = 10;    // a cycle enumerates the subsets of at most this many weak nodes
  void validate() const;         // throws std::invalid_argument naming the field
};

enum class StabilityTermination {
  critical_load_found,     // critical_load_factor and its mode, which meets the cone's conditions
  stable_for_all_factors,  // N_cr > N_dead and N_live <= 0 (or K_g vanishes): no lambda > 0 buckles
  unstable_at_zero,        // N_cr <= N_dead (the mode is reported), or K + K_S is singular even
                           // with every weak spring: unstable under the dead axial force alone
  not_converged,           // the set iteration cycled past enumeration, the subspace iteration hit
                           // its limit, or the cone decides stability at lambda = 0 (see message)
};
std::string_view to_string(StabilityTermination);

struct CriticalLoadResult {
  StabilityTermination termination = StabilityTermination::not_converged;
  std::string message;                      // in words
  EigenMethod method = EigenMethod::dense;  // the one used
  // NaN unless critical_load_found: the factor, and the bounds of the cone's factor from the
  // fewest springs (the nodes in contact only) and the most (every weakly active node too).
  double critical_load_factor = std::numeric_limits<double>::quiet_NaN();
  double lower_bound = std::numeric_limits<double>::quiet_NaN();
  double upper_bound = std::numeric_limits<double>::quiet_NaN();
  double critical_axial_force() const;  // N_dead + lambda_cr N_live
  Eigen::VectorXd mode;                 // on the equations, oriented as admissible, max |w| = 1
  std::vector<bool> spring;             // per reaction node: a spring in the mode
  std::vector<NodeContact> contact;     // the state the answer is for
  int set_iterations = -1;              // spring sets tried (enumeration included)
  int eigen_iterations = -1;            // sparse: subspace iterations over all sets (dense: 0)
  int factorisations = -1;              // sparse LU factorisations (dense: LLT of K + K_S)
  double residual = -1.0;               // |(K + K_S - N_cr K_g) phi| / |(K + K_S) phi| of the mode
  double time_s = -1.0;
  double dead_axial_force = 0.0, live_axial_force = 0.0;
  bool is_usable() const { return termination == StabilityTermination::critical_load_found; }
  std::string brief_report() const;
};

// The critical load factor of `discretisation`'s beam in the state `contact` (one per reaction
// node) under N = dead + lambda live, with the geometric stiffness `geometric` on the equations
// (stability/geometric_stiffness.hpp). A discretisation assembled under an axial force holds
// K(N) = K - N K_g in `stiffness`: its N K_g is added back, so the answer is the same whatever N
// the discretisation was made under (dead and live here are the only axial forces counted). Misuse (sizes, an arch,
// non-finite input, bad options) throws std::invalid_argument; every outcome is in the result.
CriticalLoadResult critical_load(const fe::Discretisation& discretisation, const Eigen::SparseMatrix<double>& geometric,
                                 double dead_axial_force, double live_axial_force,
                                 const std::vector<NodeContact>& contact, const CriticalLoadOptions& options = {});
// The same with geometric_stiffness(discretisation).
CriticalLoadResult critical_load(const fe::Discretisation& discretisation, double dead_axial_force,
                                 double live_axial_force, const std::vector<NodeContact>& contact,
                                 const CriticalLoadOptions& options = {});

}  // namespace liftoff::stability

namespace liftoff {
template <>
std::optional<stability::NodeContact> from_string(std::string_view);
template <>
std::optional<stability::EigenMethod> from_string(std::string_view);
template <>
std::optional<stability::StabilityTermination> from_string(std::string_view);
}  // namespace liftoff
