#pragma once
// The tensionless (or bilateral) contact problem of a discretised member, solved exactly.
//
// Formulations (seed, section 3):
//  - primal (3.14): the LCP in (u+, u-, r) with M = [K -K C^T; -K K -C^T; -C C T],
//    q = (-F, F, 0). Works for every structure, stable or not; 2n + m unknowns.
//  - dual (3.18): the LCP in r alone, M = P = C K^-1 C^T + T, q = -C K^-1 F, then
//    u = K^-1 (F - C^T r). Needs K positive definite: refused for structures that only the
//    foundation holds in place, and under an axial force N beyond the critical load of the
//    member without foundation (K(N) = K - N K_g not positive definite; SolverFailure pointing to
//    fast and primal).
// Under an axial force every answer's tangent on its contact set is checked (stability.hpp): an
// unstable equilibrium is answered unstable_equilibrium, never returned as solved.
//  - fast: the sparse active-set solver (active_set_solver.hpp) on [K C_A^T; C_A -T_AA], O(n);
//    when it ends without an answer, Lemke (dual where the structure is stable, else primal)
//    takes over and the message says so.
//  - a bilateral foundation needs no LCP: the saddle-point system [K C^T; C -T] is solved once
//    (active_set_system.hpp with every node in contact), whatever the method.
// Both LCPs are solved by Lemke (lcp/lemke.hpp) on loads scaled to unit size: the problem is
// positively homogeneous in F, so the scale is undone exactly afterwards. Lemke's LCPs are
// dense: one larger than max_dense_lcp unknowns is refused (SolverFailure pointing to fast).

#include <Eigen/Dense>
#include <optional>
#include <string>
#include <vector>

#include "contact/active_set_solver.hpp"
#include "contact/method.hpp"
#include "core/enum_names.hpp"
#include "fe/discretisation.hpp"
#include "lcp/lemke.hpp"

namespace liftoff::contact {

struct ContactOptions {
  Method method = Method::dual;
  double load_factor = 1.0;  // lambda: F = F_dead + lambda F_live
  lcp::LemkeOptions lemke;
  ActiveSetOptions active_set;  // method = fast
  // method = fast (or auto) on a tensionless foundation: the first contact set, one flag per
  // reaction node of the discretisation solved (a warm start: a nearby problem's answer, as
  // `liftoff envelope` carries from one load position to the next); empty: the default start (a
  // coarser mesh's set on large uniform meshes, else every node in contact). Any set is a valid
  // start: it changes the work, never the answer. A wrong size is refused (std::invalid_argument).
  std::vector<bool> initial_contact;
  void validate() const;  // throws std::invalid_argument naming the field
};

enum class ContactTermination {
  solved,                // u and r satisfy equilibrium and the contact conditions (see residual)
  no_equilibrium,        // Lemke ray: the LCP has no solution; the loads lift the member off and
                         // the supports cannot hold it (a mechanism)
  pivot_limit,           // Lemke stopped at its pivot limit; no answer
  iteration_limit,       // fast only: no contact set found within its limits, and the LCP is too large
                         // for the Lemke fallback; no answer
  numerical_failure,     // a singular basis or factorisation, or an answer whose residual exceeds
                         // 1e-6 (round-off overwhelmed the LCP); no answer
  unstable_equilibrium,  // under an axial force: the state found satisfies every condition but its
                         // tangent on the contact set is not positive definite (stability.hpp):
                         // the axial force exceeds the critical load of the current configuration
};
std::string_view to_string(ContactTermination);

struct ContactSummary {
  ContactTermination termination = ContactTermination::numerical_failure;
  Method method = Method::dual;  // the formulation actually used
  std::string method_reason;     // why (for method = auto, or the bilateral shortcut)
  std::string message;           // in words
  int pivots = -1;               // Lemke
  int lcp_size = -1;
  int iterations = -1;      // fast: contact sets tried
  int factorisations = -1;  // fast and bilateral: numeric sparse factorisations
  // fast and bilateral (-1 for Lemke): the relative error in u and r that iterative refinement
  // leaves (above 1e-6 the answer is a numerical_failure), and a worst-case bound on what the
  // rounding of the system's data can do (Skeel's condition, pessimistic by 1e2-1e4; the answer
  // certificate, certify/certificate.hpp, measures the round-off instead); the bound only with
  // ContactOptions::active_set.estimate_round_off, else -1.
  double error_estimate = -1.0;
  double round_off_bound = -1.0;
  // max of the relative equilibrium residual |K u + C^T r - F| / | |K||u| + |C^T||r| + |F| |, the
  // relative gap defect (bilateral) or the feasibility violations (negative r, negative gap)
  // and the complementarity r.gap (tensionless), each relative to the magnitudes involved:
  // the round-off of an exact answer rounded to double is ~1e-16 at any mesh. -1 until computed.
  double residual = -1.0;
  double time_s = -1.0;
  bool is_usable() const { return termination == ContactTermination::solved; }
  std::string brief_report() const;
};

// The evidence of no_equilibrium when a Lemke ray ended the solve (lcp/lemke.hpp): the ray dz
// of the LCP solved (artificial z0 dropped, |dz|_inf = 1), which Lemke checked as a proof that
// the LCP has no solution (dz >= 0, M^T dz <= 0, q^T dz < 0: dz^T (q + M z) < 0 for every
// z >= 0). Dual: dz = dr, one per reaction node. Primal: dz = (du+, du-, dr) over the equations;
// du = du+ - du- is a motion of the member along which the loads do work that no compressive
// foundation reaction resists (the member lifts off).
struct NoEquilibriumCertificate {
  Method formulation = Method::primal;  // the LCP whose ray it is: dual or primal
  Eigen::VectorXd ray;                  // dz in the LCP's unknowns
  double q_dot_ray = 0.0;               // q^T dz < 0, q with the loads scaled to unit size as solved
};

struct ContactSolution {
  Eigen::VectorXd displacement;  // nondimensional, on every dof (fixed dofs 0)
  Eigen::VectorXd reaction;      // nondimensional nodal reactions, one per reaction node
  Eigen::VectorXd gap;           // T r - C u + c, the weighted gap at the reaction nodes
  ContactSummary summary;
  // Set exactly when summary.termination is no_equilibrium from Lemke's ray.
  std::optional<NoEquilibriumCertificate> no_equilibrium_certificate;
};

// Unknowns of the largest LCP handed to (dense) Lemke: 8000^2 doubles are 512 MB.
inline constexpr int max_dense_lcp = 8000;
// ... and of one it is handed automatically, as a fallback the user did not ask for: dense
// Lemke's time grows like n^3 (about n pivots of O(n^2) each; measured 0.6 s at 800 unknowns,
// 4.8 s at 1600), so an 8000-unknown fallback would run for ten minutes: beyond this a failed
// fast answer is reported as such rather than left to a fallback that looks like a hang.
inline constexpr int max_fallback_lcp = 2000;

// What method = auto means for an FE solve, with the reason in words: fast, for every scene
// (a bilateral foundation: one sparse solve, no LCP; a tensionless one: the sparse active-set
// solver, O(n), which falls back to Lemke itself when it finds no contact set). Dense Lemke is
// O(n^2) in memory and up to O(n^3) in time, and the primal form is fragile (issue 10): it runs
// only when asked for by name.
struct MethodChoice {
  Method method = Method::fast;
  std::string reason;
};
MethodChoice choose_fe_method(const fe::Discretisation& discretisation);

// Throws SolverFailure when the dual form is asked for a structure that is not stable by
// itself; every other outcome is in summary.termination.
ContactSolution solve_contact(const fe::Discretisation& discretisation, const ContactOptions& options);

}  // namespace liftoff::contact

namespace liftoff {
template <>  // the names' one table is in contact_solver.cpp
std::optional<contact::ContactTermination> from_string(std::string_view);
}  // namespace liftoff
