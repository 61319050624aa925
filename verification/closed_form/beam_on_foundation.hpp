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
// The 4m x 4m system (2 + 2 end conditions, 4 continuity/jump conditions per interior
// breakpoint, derivative equations scaled by lambda^d) is equilibrated (row and column
// scaling), factorised with Eigen's FullPivLU, and improved by one step of iterative
// refinement. The reciprocal condition estimate and the relative residual are reported.
//
// Tensionless problem: the contact limits t_k (interior points where w changes sign) solve
//   w(t_k) = 0  for all k,
// by Newton's method with the exact Jacobian at fixed topology:
//   d w(t_k)/d t_j = delta_kj w'(t_k) + s_j K w(t_j) G(t_k, t_j),
// where G(x, t) is the deflection at x under a unit force at t (same contact set), and
// s_j = +1 when t_j starts a contact region (moving it right removes foundation, i.e. adds the
// force K w(t_j) dt), -1 when it ends one. The steps are damped (limits stay ordered inside
// (0, L), backtracking on max |w(t_k)|). The inequalities w >= 0 in contact and w <= 0 in
// lift-off are then checked on a fine grid.

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

struct BeamProblem {
  double length = 1.0;              // L
  double bending_stiffness = 1.0;   // EI
  double foundation_modulus = 0.0;  // K (>= 0)
  EndCondition left = EndCondition::free;
  EndCondition right = EndCondition::free;
  std::vector<PointForce> forces;
  std::vector<PointMoment> moments;
  std::vector<UniformLoad> uniform_loads;

  double beta() const;  // (K / (4 EI))^(1/4)
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
  double q = 0.0;      // uniform load on the segment
  int basis = 0;       // 0: Krylov/Taylor series in u = (x-a)/ell, 1: scaled exponentials
  double ell = 1.0;    // length scale of u
  double kappa = 0.0;  // (beta ell)^4 for contact series, 0 for lift-off
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
  // Foundation reaction per length (acting in -w): K w in contact segments, 0 in lift-off.
  double reaction(double x, Side side = Side::right) const;

  const std::vector<double>& breakpoints() const { return breakpoints_; }
  std::size_t segment_count() const { return segments_.size(); }
  bool segment_in_contact(std::size_t i) const { return segments_.at(i).contact; }
  std::size_t segment_index(double x, Side side = Side::right) const;

  double length() const { return length_; }
  double bending_stiffness() const { return ei_; }
  double foundation_modulus() const { return k_; }
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

// Sorted {0, L, every load position, every uniform-load end} (clipped to [0, L], merged).
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

// The maximal intervals where w > 0 (roots refined by bisection to round-off). A sample with
// |w| <= zero_tolerance * max|w| counts as a zero.
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
// EI w'''' + K max(w, 0) = q is C -> {w_C > 0}, w_C the solution with foundation on C), started
// from the bilateral solution (C_0 = [0, L]). Each round takes the shrink-only step
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
