#pragma once
// Independent closed-form reference: a finite Euler-Bernoulli beam on a Winkler foundation,
// bilateral (classical Hetenyi beam) or tensionless (compression-only), solved segment by
// segment with the exact homogeneous solutions of the beam ODE. Nothing here includes or
// calls liftoff's own code (src/): a reference that shared our code would share our bugs.
//
// ---------------------------------------------------------------------------------------------
// Physics
// ---------------------------------------------------------------------------------------------
// Beam 0 <= x <= L, bending stiffness EI, Winkler modulus K (force per length per deflection)
// over the whole length. The foundation lies BELOW the beam, x runs to the right.
//   * deflection w(x) > 0 means INTO the foundation (downward);
//   * a point force with value P > 0 pushes toward the foundation (+w);
//   * a uniform load with value q > 0 (force per length) likewise;
//   * a point moment with value M > 0 is counterclockwise; the beam rotation counterclockwise
//     is theta = -w', so the moment does the work -M w'(x0).
// Total potential energy
//   Pi[w] = int_0^L ( EI/2 w''^2 + K/2 max(w,0)^2 - q w ) dx - sum P_i w(x_i) + sum M_j w'(x_j).
// Tensionless foundation: reaction per length (pushing the beam back, i.e. in -w) is
//   r(x) = K max(w, 0): contact where w > 0, lift-off where w <= 0.
// Field equations (stationarity of Pi):
//   contact segment:  EI w'''' + K w = q,  beta = (K / (4 EI))^(1/4);
//   lift-off segment: EI w'''' = q  (cubic + q x^4 / (24 EI)).
// Jump conditions at an interior point x0 carrying a force P and a moment M (derived from the
// boundary terms of delta Pi after integrating by parts on each side of x0; [f] = f(x0+) - f(x0-)):
//   [w] = 0, [w'] = 0,  EI [w''] = +M,  EI [w'''] = +P.
// Check: simply supported, K = 0, central P: w(L/2) = P L^3 / (48 EI) > 0 (tested).
// Stress resultants: bending moment M_b = -EI w'' (sagging positive), shear V = -EI w'''
// (dM_b/dx = V). At a force P the shear V jumps by -P, at a moment M the bending moment M_b
// jumps by -M.
// End conditions (natural conditions from the same boundary terms; P0, M0 = loads applied AT
// x = 0, PL, ML = loads applied AT x = L):
//   pinned : w = 0,  EI w''(0) = M0    |  w = 0,  EI w''(L) = -ML
//   clamped: w = 0,  w' = 0            |  w = 0,  w' = 0       (end loads go into the support)
//   free   : EI w''(0) = M0, EI w'''(0) = P0  |  EI w''(L) = -ML, EI w'''(L) = -PL
//   (a force at a pinned end goes into the support and does not deflect the beam).
// Support force on the beam (in +w) at a pinned/clamped left end: EI w'''(0+) (minus any P0);
// at the right end: -EI w'''(L-) (minus any PL).
//
// Ground models (issue 12). Everything below keeps each segment's ODE linear with constant
// coefficients and a polynomial right-hand side, so the solution stays exact:
//   * foundation segments: pieces [from, to] each with its own modulus K_i; no foundation
//     (a void, K = 0) between them. Without pieces, K acts on the whole beam (the classical case).
//   * initial gap g(x): the foundation surface lies g below the unloaded axis (g > 0: a trench
//     floor or a depression; g < 0: a hump). Contact where w > g, reaction K (w - g). g is
//     piecewise linear (a table; a repeated position is a step, e.g. a trench wall).
//   * distributed loads q(x), linear between from and to (trapezoidal, triangular).
//   * bilinear foundation: where the foundation exists but the beam has lifted off (w < g) the
//     reaction is K_t (w - g) (tension_modulus K_t, default 0: tensionless).
// The foundation term of Pi becomes int K/2 max(w - g, 0)^2 + K_t/2 min(w - g, 0)^2 dx.
// On a segment with modulus k (K_i in contact, K_t or 0 off it, 0 over a void) the equation is
//   EI w'''' + k w = q(x) + k g(x),   q and g linear on the segment,
// whose particular solution is w_p = g + q/k for k > 0 (w_p'''' = 0) and the quartic plus
// quintic q0 s^4/(24 EI) + q1 s^5/(120 EI) (s = x - a) for k = 0. Breakpoints: every load
// point, every foundation-piece end, every gap-table position.
//
// ---------------------------------------------------------------------------------------------
// Beam-columns (issue 15): a constant axial force P along the beam (compression positive,
// P < 0 tension) adds -P/2 int w'^2 to Pi, so every segment's equation becomes
//   EI w'''' + P w'' + k w = q + k g,
// whose characteristic roots (EI r^4 + P r^2 + k = 0) are, on a contact segment, alpha +- i beta
// for |P| < 2 sqrt(k EI), a double imaginary pair at P = 2 sqrt(k EI), two imaginary pairs above
// it (and two real pairs for tension below -2 sqrt(k EI)); on a lift-off segment 1, x and
// cos/sin (cosh/sinh in tension) of mu x, mu^2 = |P| / EI. The P term changes only the free end's
// condition: EI w''' + P w' = P0 at x = 0 (= -PL at x = L), the transverse force on the end;
// interior jumps keep [EI w'''] = P_i since w' is continuous. The axial force is dead: it keeps
// its direction (along the undeformed axis) as the beam deflects.
//
// ---------------------------------------------------------------------------------------------
// Numerics
// ---------------------------------------------------------------------------------------------
// Each segment [a, b] carries four unknown coefficients of a local basis:
//   * contact segment with beta (b - a) > 2: scaled exponentials
//       e^{-beta(x-a)} {cos, sin} beta(x-a),  e^{beta(x-b)} {cos, sin} beta(x-b)
//     (all bounded by 1 on the segment: no overflow for beta L up to well beyond 1000),
//     particular solution q / K;
//   * contact segment with beta (b - a) <= 2: Krylov (Taylor-normalised) functions in
//     u = (x-a)/lambda, phi_j(u) = sum_n (-4 kappa)^n u^(4n+j)/(4n+j)!, kappa = (beta lambda)^4,
//     lambda = min(L, 1/beta); these stay well conditioned for K -> 0; particular solution
//     q lambda^4/EI phi_4(u) (the q x^4/(24 EI) of the beam plus foundation corrections);
//   * lift-off segment (or K = 0): the same functions with kappa = 0 (a cubic), in
//     u = (x-a)/max(b-a, lambda), particular q (x-a)^4 / (24 EI).
// With an axial force (P != 0) every segment is split into pieces of length h <= 1 / r_max,
// r_max = max(sqrt(|P| / EI), (k / EI)^(1/4)), and each piece carries the Taylor-normalised
// basis of its own equation in u = (x - a) / h: phi_j^(i)(0) = delta_ij (i, j = 0..3), Taylor
// coefficients c_{m+4} = -(P h^2/EI) c_{m+2} - (k h^4/EI) c_m; the particular solutions are the
// same recurrence started from c_4 = 1 (uniform load) and c_5 = 1 (linear part). On such a piece
// |P h^2/EI| <= 1 and k h^4/EI <= 1, so the series converge fast without cancellation, and one
// basis covers every regime (complex, double and imaginary roots, tension, and P -> 0) with no
// special case; the extra breakpoints only add continuity rows (multiple shooting). P = 0 keeps
// the bases below unchanged.
// The 4m x 4m system (2 + 2 end conditions, 4 continuity/jump conditions per interior
// breakpoint, derivative equations scaled by lambda^d) is equilibrated (row and column
// scaling), factorised with Eigen's FullPivLU, and improved by one step of iterative
// refinement. The reciprocal condition estimate and the relative residual are reported.
//
// Tensionless problem: the contact limits t_k (interior points where w - g changes sign) solve
//   w(t_k) - g(t_k) = 0  for all k,
// by Newton's method with the exact Jacobian at fixed topology:
//   d (w - g)(t_k)/d t_j = delta_kj (w' - g')(t_k) + s_j (K - K_t) (w - g)(t_j) G(t_k, t_j),
// where G(x, t) is the deflection at x under a unit force at t (same contact set), and
// s_j = +1 when t_j starts a contact region (moving it right removes foundation, i.e. adds the
// force K w(t_j) dt), -1 when it ends one. The steps are damped (limits stay ordered inside
// (0, L) and off voids, backtracking on max |w(t_k) - g(t_k)|). The inequalities w >= g in
// contact and w <= g in lift-off (where a foundation exists) are then checked on a fine grid.
// A contact region may also end where the data jumps (a void edge, a gap step) with w != g
// there: such an end is fixed, not a limit.

#include <stdexcept>
#include <string>
#include <vector>

namespace liftoff::closed_form {

enum class EndCondition { pinned, clamped, free };

struct PointForce {
  double at = 0.0;
  double value = 0.0;  // > 0 toward the foundation (+w)
};

struct PointMoment {
  double at = 0.0;
  double value = 0.0;  // > 0 counterclockwise (work -M w')
};

struct UniformLoad {
  double from = 0.0;
  double to = 0.0;
  double value = 0.0;  // force per length, > 0 toward the foundation
};

// A load varying linearly from start_value at `from` to end_value at `to`.
struct DistributedLoad {
  double from = 0.0;
  double to = 0.0;
  double start_value = 0.0;  // force per length at `from`, > 0 toward the foundation
  double end_value = 0.0;    // at `to`
};

// A piece of foundation with its own modulus; pieces must not overlap.
struct FoundationSegment {
  double from = 0.0;
  double to = 0.0;
  double modulus = 0.0;  // K_i >= 0
};

// Piecewise-linear initial gap g(x) through (at[i], value[i]); positions non-decreasing, a
// repeated position is a step (value[i] left of it, value[i+1] right of it); constant beyond
// the first and last positions. Empty: no gap.
struct GapProfile {
  std::vector<double> at;
  std::vector<double> value;
};

struct BeamProblem {
  double length = 1.0;              // L
  double bending_stiffness = 1.0;   // EI
  double foundation_modulus = 0.0;  // K (>= 0) on the whole beam, used when foundation_segments is empty
  EndCondition left = EndCondition::free;
  EndCondition right = EndCondition::free;
  std::vector<PointForce> forces;
  std::vector<PointMoment> moments;
  std::vector<UniformLoad> uniform_loads;
  std::vector<DistributedLoad> distributed_loads;
  std::vector<FoundationSegment> foundation_segments;  // non-empty: the foundation is these pieces only
  GapProfile gap;
  double tension_modulus = 0.0;  // K_t >= 0 where the foundation exists and w < g
  double axial_force = 0.0;      // P along the whole beam, > 0 compression, < 0 tension (dead)

  // (K_ref / (4 EI))^(1/4), K_ref the largest modulus (foundation_modulus, or the largest piece).
  double beta() const;
  // The foundation's (compression) modulus at x (the piece on the right of x at a piece end).
  double modulus_at(double x) const;
  double gap_at(double x) const;  // g(x), right-continuous at a step
};

struct Interval {
  double start = 0.0;
  double end = 0.0;
};

// Thrown by the segment solver when the linear system is (numerically) singular, e.g. a
// free-free beam with no segment in contact.
class SingularSystem : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// At a breakpoint, which segment evaluates (matters only for w'' at a moment, w''' at a force).
enum class Side { left, right };

namespace detail {
struct Segment {
  double a = 0.0, b = 0.0;
  bool contact = false;
  double ground = 0.0;        // compression modulus of the foundation here (0: void)
  double k = 0.0;             // modulus acting in the ODE (ground, K_t or 0)
  double beta = 0.0;          // (k / (4 EI))^(1/4)
  double q0 = 0.0, q1 = 0.0;  // effective load q + k g = q0 + q1 (x - a)
  double g0 = 0.0, g1 = 0.0;  // gap g = g0 + g1 (x - a)
  int basis = 0;              // 0: Krylov/Taylor series in u = (x-a)/ell, 1: scaled exponentials,
                              // 2: beam-column Taylor series (axial force) in u = (x-a)/ell
  double axial = 0.0;         // P ell^2 / EI (basis 2)
  double ell = 1.0;           // length scale of u
  double kappa = 0.0;         // (beta ell)^4 for the series, 0 when k = 0
};
struct SolutionAccess;
}  // namespace detail

// The solved beam: exact piecewise closed form.
class BeamSolution {
 public:
  BeamSolution() = default;

  bool empty() const { return segments_.empty(); }
  // d^order w / dx^order at x (order 0..3). Outside [0, L] x is clamped to the ends.
  double derivative(double x, int order, Side side = Side::right) const;
  double deflection(double x, Side side = Side::right) const { return derivative(x, 0, side); }
  double slope(double x, Side side = Side::right) const { return derivative(x, 1, side); }
  double bending_moment(double x, Side side = Side::right) const;  // -EI w''
  double shear_force(double x, Side side = Side::right) const;     // -EI w'''
  // Foundation reaction per length (acting in -w): k (w - g), k the segment's acting modulus
  // (K in contact, K_t or 0 in lift-off, 0 over a void).
  double reaction(double x, Side side = Side::right) const;
  double gap(double x, Side side = Side::right) const;             // g(x)
  double gap_slope(double x, Side side = Side::right) const;       // g'(x)
  double acting_modulus(double x, Side side = Side::right) const;  // k on the segment at x
  double ground_modulus(double x, Side side = Side::right) const;  // foundation K (0: void)

  const std::vector<double>& breakpoints() const { return breakpoints_; }
  std::size_t segment_count() const { return segments_.size(); }
  bool segment_in_contact(std::size_t i) const { return segments_.at(i).contact; }
  std::size_t segment_index(double x, Side side = Side::right) const;

  double length() const { return length_; }
  double bending_stiffness() const { return ei_; }
  double foundation_modulus() const { return k_; }  // K_ref (see BeamProblem::beta)
  double beta() const { return beta_; }

  // 1 / (FullPivLU reciprocal condition estimate) of the equilibrated system.
  double condition_estimate() const { return condition_; }
  // ||A c - b||_inf / (||A||_inf ||c||_inf + ||b||_inf) of the assembled system.
  double relative_residual() const { return residual_; }
  // max |w| over breakpoints and samples_per_segment points in each segment.
  double max_abs_deflection(int samples_per_segment = 64) const;

 private:
  friend struct detail::SolutionAccess;
  double length_ = 0.0, ei_ = 1.0, k_ = 0.0, beta_ = 0.0, lambda_ = 1.0;
  std::vector<double> breakpoints_;
  std::vector<detail::Segment> segments_;
  std::vector<double> coefficients_;  // 4 per segment
  double condition_ = 0.0, residual_ = 0.0;
};

// Sorted {0, L, every load position, every uniform/distributed-load end, every foundation-piece
// end, every gap position} (clipped to [0, L], merged): the points where the data changes.
std::vector<double> load_points(const BeamProblem& problem);

// Linear segment solver. `breakpoints` must be strictly increasing from 0 to L and contain
// every load point (load_points); `in_contact[i]` says whether the foundation acts on
// [breakpoints[i], breakpoints[i+1]]. Throws std::invalid_argument on bad input and
// SingularSystem when the system is singular.
BeamSolution solve_segments(const BeamProblem& problem, const std::vector<double>& breakpoints,
                            const std::vector<bool>& in_contact);

// Foundation acting exactly on the given (disjoint) regions; breakpoints = load points plus
// region ends.
BeamSolution solve_with_contact(const BeamProblem& problem, const std::vector<Interval>& regions);

// Classical (bilateral) Hetenyi beam: foundation acts everywhere, tension included.
BeamSolution solve_bilateral(const BeamProblem& problem);

// The maximal intervals where w > g and a foundation exists (roots refined by bisection to
// round-off; a region may end at a void edge or a gap step). A sample with |w - g| <=
// zero_tolerance * max|w| counts as a zero.
std::vector<Interval> contact_regions(const BeamSolution& solution, int samples_per_segment = 256,
                                      double zero_tolerance = 1e-12);

// ---------------------------------------------------------------------------------------------
// Tensionless foundation
// ---------------------------------------------------------------------------------------------
enum class TensionlessStatus {
  converged,              // |w(t_k)| <= tolerance max|w| and the inequalities hold
  no_convergence,         // Newton failed (iteration limit, line search, region collapse)
  inequalities_violated,  // the limits solve w(t_k) = 0 but w < 0 in contact or w > 0 off it
  singular_system,        // the segment system is singular (e.g. floating beam)
  invalid_input,          // bad problem or initial regions
};
std::string to_string(TensionlessStatus status);

struct TensionlessOptions {
  int max_iterations = 60;
  double tolerance = 1e-13;            // |w(t_k)| <= tolerance * max|w|
  double inequality_tolerance = 1e-9;  // allowed wrong-sign |w| relative to max|w|
  int samples_per_segment = 400;       // grid for the inequality check (at least)
  double max_step = 1.0;               // trust radius of a limit step, in units of 1/beta
  int max_rounds = 100;                // solve_tensionless_auto: contact-set rounds
};

struct TensionlessResult {
  TensionlessStatus status = TensionlessStatus::invalid_input;
  std::string message;
  std::vector<double> limits;     // interior contact limits t_k, increasing
  std::vector<Interval> contact;  // contact regions at the end of the iteration
  int iterations = 0;             // Newton steps taken (last Newton run)
  int rounds = 0;                 // solve_tensionless_auto: contact-set rounds used
  double residual = 0.0;          // max_k |w(t_k)| / max|w|
  double max_violation = 0.0;     // worst wrong-sign |w| / max|w| on the grid
  BeamSolution solution;
};

// Newton on the contact limits starting from `initial_contact_regions` (disjoint intervals in
// [0, L]; an end at 0 or L is a beam end, not a limit). The number of regions (the topology) is
// kept fixed; an empty list means the beam is entirely lifted off.
TensionlessResult solve_tensionless(const BeamProblem& problem, const std::vector<Interval>& initial_contact_regions,
                                    const TensionlessOptions& options = {});

// Without a topology guess: a contact-set iteration (the semismooth Newton map of
// EI w'''' + K max(w - g, 0) = q is C -> {w_C > g}, w_C the solution with foundation on C),
// started from the bilateral solution (C_0 = [0, L]). Each round takes the shrink-only step
// C_{n+1} = C_n & {w_n > 0}, or, when that step is stuck, the full step C_{n+1} = {w_n > 0};
// after every round the limit Newton above polishes C_{n+1}, and the first polished solution
// that passes the checks is returned. (The plain map cycles on long beams: the bilateral
// solution's far, tiny positive lobes keep reappearing.) A heuristic driver: a failure is
// reported, never hidden.
TensionlessResult solve_tensionless_auto(const BeamProblem& problem, const TensionlessOptions& options = {});

// The limit equations at given regions (for tests): F_k = w(t_k) and the exact Jacobian
// dF_k/dt_j described above.
struct LimitEquations {
  std::vector<double> limits;
  std::vector<double> residuals;
  std::vector<std::vector<double>> jacobian;  // jacobian[k][j]
  BeamSolution solution;
};
LimitEquations limit_equations(const BeamProblem& problem, const std::vector<Interval>& regions);

}  // namespace liftoff::closed_form
