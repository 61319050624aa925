#pragma once
// The fast contact solver: block principal pivoting (a primal-dual active-set method) on the
// sparse system of contact/active_set_system.hpp, O(n) per iteration in time and memory.
//
// The problem is the LCP of the seed's dual form, r >= 0, gap = P r - b >= 0, r.gap = 0 with
// P = C K^-1 C^T + T, but P is never formed: for a guessed contact set A the sparse system
// [K C_A^T; C_A -T_AA] gives u, r_A and gap_I at once (a principal pivot of the LCP). The set
// is wrong where r_A < 0 or gap_I < 0 ("infeasible" nodes); a block step moves every such node
// to the other side, as the primal-dual active-set method does (with r - c gap, any c > 0).
//
// Why it terminates. The energy of structure plus foundation is strictly convex in r (the
// dual energy 1/2 r.P r - b.r, T positive definite), so P is a P-matrix: every principal
// pivot exists and is unique. Plain block pivoting can still cycle between sets. The
// safeguard is Judice and Pires' (Comput. Oper. Res. 21, 1994): block steps are taken while
// they reduce the number of infeasible nodes, or for at most `block_retries` steps without a
// new best; after that single steps flip only the infeasible node of largest index (Murty's
// least-index rule on the reversed order, finite for P-matrices) until the count drops below
// the best again. A set seen before also ends the block steps at once. Every step is thus either a new best count
// (finitely many) or a Murty step, so the iteration ends. When K is singular (a member only
// the foundation holds) P does not exist; the same iteration runs, and a set that leaves a
// rigid motion free is answered by a single flip from the last good set, and the guarantee is
// Lemke's (the fallback), not this iteration's.
//
// Start: every node in contact, i.e. the bilateral solution, whose sign pattern is already the
// answer away from the contact limits; a block step then moves the limits, and the number of
// steps does not grow with the mesh (the limits move by a fraction of the member, not of an
// element). Each step is one numeric factorisation of a fixed pattern. The sets on the way are
// solved only as accurately as their signs need (intermediate_error); the set found is refined
// to round-off and its signs checked again. The limits creep by about a node per step once the
// set is close, so on large meshes solve_active_set_nested below starts from a coarser mesh's
// answer instead (1-2 sets on the fine mesh instead of 11-12 on a long member).
//
// What it does not do: it returns no ray when there is no equilibrium; the caller
// (contact_solver.hpp) falls back to Lemke, with a note, whenever this solver does not end in
// `solved`.

#include <Eigen/Dense>
#include <string>
#include <string_view>
#include <vector>

#include "contact/active_set_system.hpp"
#include "fe/discretisation.hpp"

namespace liftoff::contact {

struct ActiveSetOptions {
  int max_iterations = 100;  // factorised contact sets, at most
  int block_retries = 3;     // block steps allowed without a new best count; -1: never fall
                             // back to single steps (plain primal-dual active set, no safeguard)
  // A reaction or gap counts as negative below -tolerance times the largest reaction or
  // structural gap term (round-off must not flip a node that touches with r = gap = 0); the
  // tolerance grows to 10x the solve's own error estimate on meshes where that is larger.
  double sign_tolerance = 1e-11;
  // Sets on the way are solved only as accurately as their signs need (refinement until the
  // estimated relative error is below this); the set found is then refined to round-off and its
  // signs checked again.
  double intermediate_error = 1e-9;
  // Also compute ActiveSetResult::round_off_bound (Hager's estimate, up to 12 more solves).
  bool estimate_round_off = false;
  // Refine the set found to round-off and check its signs again. False for a mesh whose set only
  // seeds a finer one (coarse_start): its answer stays at intermediate_error, and the finer mesh's
  // own iteration checks every sign again.
  bool refine_answer = true;
  // Read the first set's signs from its solve before any refinement: nodes wrong by more than
  // unrefined_sign_tolerance (of the largest reaction or gap term, far beyond that solve's
  // round-off) are flipped at once, the set left unrefined; if there are none it is refined as
  // any set. For a first set that is a good guess but rarely the answer (a coarser mesh's,
  // solve_active_set_nested and solve_contact set it), where refining a set about to be left is
  // wasted. A sign misread costs one more set, never the answer: the set found is checked refined.
  bool unrefined_first_set = false;
  void validate() const;  // throws std::invalid_argument naming the field
};

enum class ActiveSetTermination {
  solved,           // no infeasible node: u, r, gap solve the contact problem (state.residual)
  iteration_limit,  // max_iterations sets factorised without reaching one; state is the last set's
  cycling,          // (block_retries = -1 only) a contact set came back: plain block pivoting cycles
  singular_system,  // a set left a rigid motion free (singular, or refinement could not solve it to
                    // 1e-6) and no single flip from a good set helped
};
std::string_view to_string(ActiveSetTermination);

struct ActiveSetSummary {
  ActiveSetTermination termination = ActiveSetTermination::iteration_limit;
  std::string message;
  int iterations = -1;      // contact sets tried
  int factorisations = -1;  // numeric factorisations (one per set; the symbolic analysis once)
  int block_steps = -1;
  int single_steps = -1;
  std::vector<int> infeasible_history;  // infeasible nodes after each set
  bool is_usable() const { return termination == ActiveSetTermination::solved; }
};

struct ActiveSetResult {
  ContactState state;
  std::vector<bool> in_contact;
  // solved and options.estimate_round_off only: ActiveSetSystem::data_error of the answer
  double round_off_bound = -1.0;
  ActiveSetSummary summary;
};

// Solves for a load on the equations (nondimensional). `initial`: the first contact set
// (empty: every node in contact). `gap_offset`: the discretisation's ground_gap scaled as the load
// is (empty: none; refused, std::invalid_argument, when the discretisation has a ground gap).
ActiveSetResult solve_active_set(const fe::Discretisation& discretisation, const Eigen::VectorXd& load,
                                 const ActiveSetOptions& options, std::vector<bool> initial = {},
                                 const Eigen::VectorXd& gap_offset = {});

// Nested iteration, for large meshes: the same problem (F = F_dead + load_factor F_live) is
// first solved on a mesh `coarsening` times coarser (recursively; a coarse mesh has at least
// min_elements and elements_per_decay_length per foundation decay length 1/beta, and is used
// only if at most a third of this mesh), and the contact set found there (w > g of the coarse
// answer at each node; at a node a support holds at w = g, the coarse answer's own status there)
// is the first set here.
// The limits then start within a coarse element of their place, so this mesh needs one to
// three sets instead of ten or more from the bilateral start (each a factorisation of the
// largest system). `discretisation` must be discretise(model, ...) of this model.
// A coarse mesh need not resolve the foundation: its set is only a seed, whose every sign the
// finer mesh checks. The defaults (down to 100 elements, 0.1 per decay length) make each level's
// start good enough that the coarse levels together cost less than one more set on this mesh
// (the long member of accuracy_bench ratio at 1e4 elements: 100 -> 1000 -> 1e4 elements).
// The coarse meshes' sets are solved to intermediate_error only, never refined to round-off.
// The summary counts this mesh's sets; coarse_sets counts the coarser meshes'.
struct NestedOptions {
  int coarsening = 10;
  int min_elements = 100;
  double elements_per_decay_length = 0.1;
  void validate() const;
};
struct NestedResult {
  ActiveSetResult result;
  int coarse_sets = 0;
  int levels = 1;  // meshes solved, this one included
};
NestedResult solve_active_set_nested(const model::MemberModel& model, const fe::Discretisation& discretisation,
                                     double load_factor, const ActiveSetOptions& options,
                                     const NestedOptions& nested = {});

// The first contact set of solve_active_set_nested, for a caller that solves this mesh itself
// (contact_solver.cpp, with its own load scaling): the set carried from the coarser meshes'
// answer, or empty (every node in contact) when the mesh is too small to gain or a coarse solve
// failed. The coarse meshes never estimate their round-off.
struct CoarseStart {
  std::vector<bool> initial;
  int coarse_sets = 0;
  int levels = 1;  // meshes solved, this one included
};
CoarseStart coarse_start(const model::MemberModel& model, const fe::Discretisation& discretisation, double load_factor,
                         const ActiveSetOptions& options, const NestedOptions& nested = {});

}  // namespace liftoff::contact
