#pragma once
// Closed forms of the sinusoidal shallow arch, von Karman, with or without a Winkler foundation
// (issue 16, item 5). Nothing here includes liftoff's code.
//
// Problem and convention (issue 16's, shared with the FE and Ritz branches): a beam 0 <= x <= L,
// w > 0 toward the foundation, initial shape w0 = -a sin(pi x / L) with a > 0 (the scene key
// `[geometry] initial_shape = { shape = "half_sine", amplitude = -a }`: a hump rising away from its
// bedding), stress-free. Pinned ends with the axial displacement restrained (u = w = w'' = 0 at both
// ends). The load q = lambda q0 sin(pi x / L), q0 > 0 pushing toward the foundation. The foundation
// reacts to the displacement w from the initial shape (the ground follows w0): k w (bilateral) or
// k max(w, 0) (tensionless). EI, EA constant; r = sqrt(EI / EA) the radius of gyration.
//
// Von Karman: the membrane strain of the total shape w0 + w less that of w0,
//   eps = u' + w0' w' + w'^2 / 2,  N = EA / L * integral_0^L (w0' w' + w'^2 / 2) dx  (tension > 0,
// constant along the member; u drops out because u(0) = u(L) = 0). The thrust is -N. Energy
//   Pi = int [EI/2 w''^2 + k/2 w^2 - q w] dx + L N^2 / (2 EA),
// Euler-Lagrange EI w'''' - N (w0 + w)'' + k w = q.
//
// Two-mode solution. With s_n = sin(n pi x / L), beta = pi / L, w = A1 s1 + A2 s2 turns every term
// of the Euler-Lagrange equation into a combination of s1 and s2 (N is a constant), so the Galerkin
// equations in (A1, A2) are the exact equilibrium equations: the two-mode solution is exact (the
// higher modes are not loaded and stay zero on the branches below; mode n could bifurcate only where
// the thrust -N reaches n^2 pi^2 EI / L^2 + k L^2 / (n^2 pi^2), and along the symmetric path the
// thrust grows monotonically up to the flat state, so the least of these over n >= 2 is met first:
// n = 2 while k < 36 EI beta^4 (9 + kappa/9 > 4 + kappa/4). For a stiffer foundation a higher mode
// bifurcates first and this reference does not cover it: analyse() says so (critical_mode,
// covered = false) and its bifurcation figures are then the second mode's, not the first event).
// Nondimensional: xi = A1 / r, eta = A2 / r, alpha = a / r,
// kappa = k / (EI beta^4), p = lambda q0 / (EI beta^4 r), and
//   N = (EI beta^2 / 4) E,  E = xi^2 + 4 eta^2 - 2 alpha xi,
//   Pi = (L EI beta^4 r^2 / 4) Pihat,  Pihat = (1 + kappa) xi^2 + (16 + kappa) eta^2 + E^2 / 8 - 2 p xi.
// Equilibrium (dPihat = 0):
//   (1 + kappa) xi + E (xi - alpha) / 4 = p,        eta (16 + kappa + E) = 0.
//
// 1. Symmetric path (eta = 0). With xi = alpha + t, E = t^2 - alpha^2 and
//   p = (1 + kappa) alpha + t^3 / 4 + (1 + kappa - alpha^2 / 4) t,
// a cubic point-symmetric about (t = 0, p = (1 + kappa) alpha) (the flat state xi = alpha carries
// the load (1 + kappa) alpha on bending and foundation alone, N = -EI beta^2 alpha^2 / 4 there).
// dp/dt = 3 t^2 / 4 + 1 + kappa - alpha^2 / 4 = 0 at t = -+ tL, tL = sqrt((alpha^2 - 4 (1 + kappa)) / 3):
// the upper (snap-through) limit point at xi = alpha - tL, p = (1 + kappa) alpha + tL^3 / 2, the
// lower one at xi = alpha + tL, p = (1 + kappa) alpha - tL^3 / 2. They exist iff
//   a / r > 2 sqrt(1 + kappa).
// For p >= 0 every root has xi >= 0 (p < 0 for xi < 0: all three terms of
// p = xi^3 / 4 - 3 alpha xi^2 / 4 + (1 + kappa + alpha^2 / 2) xi are negative).
//
// 2. Asymmetric bifurcation: eta != 0 needs E = -(16 + kappa), i.e. the thrust
//   -N = 4 pi^2 EI / L^2 + k L^2 / (4 pi^2), the second mode's critical load with the foundation.
// On the symmetric path t^2 = alpha^2 - 16 - kappa: bifurcation points at t = -+ tB,
// tB = sqrt(alpha^2 - 16 - kappa), which exist iff a / r > sqrt(16 + kappa). The bifurcated branch
// (E fixed) is the straight line
//   p = (1 + kappa) alpha + 3 (kappa - 4) t / 4,   4 eta^2 = tB^2 - t^2,   |t| <= tB,
// joining the two points: lambda is not constant but linear in A1, falling for kappa < 4 (the
// bare arch: dp/dxi = -3), constant for kappa = 4, rising for kappa > 4. Stability from the
// second variation (Hessian of Pihat):
//   H_xixi = 2 (1 + kappa) + (xi - alpha)^2 + E / 2 (= 2 dp/dxi on the symmetric path),
//   H_etaeta = 2 (16 + kappa + E) + 16 eta^2,   H_xieta = 4 eta (xi - alpha).
// Symmetric path: stable iff dp/dxi > 0 and |t| > tB (E > -(16 + kappa)). Bifurcated branch
// (E = -(16 + kappa)): H_etaeta = 16 eta^2 > 0 and det H = 24 eta^2 (kappa - 4): unstable (a saddle)
// for kappa < 4, stable for kappa > 4, neutral at kappa = 4.
// Which comes first along the loading (t from -alpha upward): the bifurcation precedes the upper
// limit point iff tB > tL, i.e. alpha^2 > 22 - kappa / 2 (and alpha^2 > 16 + kappa). For
// kappa < 4, 22 - kappa / 2 > 16 + kappa, so:
//   a / r <= 2 sqrt(1 + kappa): no snap-through, the symmetric path is stable throughout;
//   2 sqrt(1 + kappa) < a / r <= sqrt(22 - kappa / 2): limit-point (symmetric) snap-through at
//     p = (1 + kappa) alpha + tL^3 / 2 (the bifurcation points, if any, lie on the unstable part);
//   a / r > sqrt(22 - kappa / 2): asymmetric (unstable-symmetric) bifurcation at
//     p = (1 + kappa) alpha + 3 (4 - kappa) tB / 4, before the limit point.
// For kappa = 0 these thresholds (derived above, not copied) are those of the classical analyses of
// the sinusoidal arch under a sinusoidal load (Fung & Kaplan 1952, "Buckling of low arches or
// curved beams of small curvature", NACA TN 2840; Hoff & Bruce 1954, "Dynamic analysis of the
// buckling of laterally loaded flat arches", J. Math. Phys. 32; cited from memory, not checked
// against the papers, whose rise parameters may be scaled differently): no snap-through for
// a / r < 2, symmetric (limit-point) snap-through for 2 < a / r < sqrt(22) = 4.690, asymmetric
// (bifurcation) snap-through for a / r > 4.690; bifurcation points on the path from a / r = 4.
// For kappa > 4 the bifurcation exists from a / r = sqrt(16 + kappa) on (below the limit-point
// threshold 2 sqrt(1 + kappa)), it always precedes the limit point, and its branch is stable and
// rising: under load control the arch leaves the symmetric path there, follows the asymmetric
// branch and rejoins the symmetric path at t = +tB, beyond the lower limit point (if there are
// limit points): no snap-through with a bilateral foundation.
// At kappa = 4 the branch is neutral (constant load 5 alpha, the bifurcation load).
//
// 3. Tensionless foundation. w = r sin(theta) (xi + 2 eta cos theta), theta = pi x / L. On the
// symmetric path w = A1 s1 >= 0 wherever A1 >= 0, which holds for every lambda >= 0 (above), so
// the whole loaded symmetric path is in contact and the tensionless problem has the bilateral
// solution (the energies agree there, with the same second variation). On the bifurcated branch
// w >= 0 everywhere iff xi >= 2 |eta|; the first contact event (lift-off) is where xi = 2 |eta|:
// w = r xi sin theta (1 -+ cos theta) then touches zero at an end with w' = 0 there (a lift-off zone
// opens at x = 0 when A2 < 0, at x = L when A2 > 0). With 4 eta^2 = tB^2 - t^2 this is
//   2 xi^2 - 2 alpha xi + 16 + kappa = 0,  xi = (alpha -+ sqrt(alpha^2 - 2 (16 + kappa))) / 2,
// |A2| = A1 / 2, p = (1 + kappa) alpha + 3 (kappa - 4) (xi - alpha) / 4. It exists iff
// a / r >= sqrt(2 (16 + kappa)); otherwise the whole bifurcated branch stays in contact. Between
// the two roots the bilateral branch would pull on the foundation; the tensionless branch there
// is no longer two-mode (not covered). From the bifurcation point up to the first root
// (the smaller xi) tensionless and bilateral agree.

#include <Eigen/Dense>
#include <string>
#include <vector>

namespace liftoff::closed_form {

struct ShallowArch {
  double length = 1.0;              // L
  double bending_stiffness = 1.0;   // EI
  double axial_stiffness = 1.0;     // EA
  double rise = 0.0;                // a > 0: w0 = -a sin(pi x / L)
  double foundation_modulus = 0.0;  // k >= 0 (0: the bare arch)
  double load_amplitude = 1.0;      // q0 > 0: q = lambda q0 sin(pi x / L)
  void validate() const;            // throws std::invalid_argument naming the field

  double radius_of_gyration() const;  // r = sqrt(EI / EA)
  double relative_rise() const;       // alpha = a / r
  double relative_modulus() const;    // kappa = k L^4 / (pi^4 EI)
  double load_unit() const;           // EI (pi/L)^4 r / q0: lambda per unit of p
};

// lambda on the symmetric path (A2 = 0) at crown deflection A1.
double symmetric_load(const ShallowArch& arch, double deflection);
// The roots A1 of the cubic symmetric_load(A1) = lambda, ascending (one to three).
std::vector<double> symmetric_deflections(const ShallowArch& arch, double lambda);
// The thrust -N (compression positive) of w = A1 s1 + A2 s2.
double thrust(const ShallowArch& arch, double a1, double a2);
// The bifurcated branch: lambda at A1 and |A2| (negative if A1 is off the branch).
double bifurcated_load(const ShallowArch& arch, double a1);
double bifurcated_asymmetry(const ShallowArch& arch, double a1);

// The energy Pi(A1, A2) at load lambda, by composite Gauss quadrature of the continuous
// functional (not the modal algebra): tensionless uses k max(w, 0)^2 / 2.
double potential_energy(const ShallowArch& arch, double lambda, double a1, double a2, bool tensionless);
// Its Hessian in (A1, A2), in closed form (the bilateral foundation).
Eigen::Matrix2d energy_hessian(const ShallowArch& arch, double a1, double a2);

struct ArchPoint {
  double deflection = 0.0;  // A1
  double asymmetry = 0.0;   // A2 (>= 0; the mirror branch has -A2)
  double load = 0.0;        // lambda
  double thrust = 0.0;      // -N
};

enum class BranchStability { stable, unstable, neutral };
enum class FirstCritical { none, limit_point, unstable_bifurcation, neutral_bifurcation, stable_bifurcation };
std::string to_string(BranchStability);
std::string to_string(FirstCritical);

struct ShallowArchAnalysis {
  // Thresholds on a / r.
  double limit_rise = 0.0;              // 2 sqrt(1 + kappa): limit points beyond it
  double bifurcation_rise = 0.0;        // sqrt(16 + kappa): bifurcation points beyond it
  double bifurcation_first_rise = 0.0;  // sqrt(22 - kappa/2) (kappa < 4): bifurcation before the limit point beyond it
  double contact_event_rise = 0.0;      // sqrt(2 (16 + kappa)): the bifurcated branch lifts off beyond it
  bool has_limit_points = false;
  ArchPoint upper_limit, lower_limit;  // upper: the snap-through load (smaller A1)
  bool has_bifurcation = false;
  ArchPoint first_bifurcation, second_bifurcation;  // smaller A1 first
  double branch_slope = 0.0;                        // d lambda / d A1 on the bifurcated branch
  BranchStability branch_stability = BranchStability::stable;
  bool has_contact_event = false;
  ArchPoint first_lift_off, last_lift_off;  // on the bifurcated branch, |A2| = A1 / 2; lift-off between
  FirstCritical first = FirstCritical::none;
  int critical_mode = 2;  // the n >= 2 of the least thrust n^2 + kappa / n^2 (in EI beta^2)
  bool covered = true;    // critical_mode == 2, or no mode n >= 2 is reached (a/r below its threshold)
  std::string reason;     // readable: what happens under increasing load
};
ShallowArchAnalysis analyse(const ShallowArch& arch);

// `closed_form_reference shallow-arch [options]`: the analysis as JSON (shallow_arch.cpp).
int shallow_arch_command(int argc, char** argv);

}  // namespace liftoff::closed_form
