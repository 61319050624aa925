#pragma once
// Independent closed forms for the buckling of beam-columns on Winkler foundations (issue 15).
// Nothing here includes liftoff's code. Conventions as in beam_on_foundation.hpp: w > 0 into the
// foundation, q > 0 toward it, P > 0 compression, K the foundation modulus (force per length per
// deflection), EI the bending stiffness.
//
// Critical loads of a straight, weightless member:
//   * bilateral pinned strut of length L: the sine modes w = sin(n pi x / L) turn
//     EI w'''' + P w'' + K w = 0 into P = n^2 pi^2 EI / L^2 + K L^2 / (n^2 pi^2); the least over n
//     is the critical load (Timoshenko & Gere, Theory of Elastic Stability, ch. 2, bars on elastic foundations);
//   * a long bilateral member: minimising EI a + K / a over a = (n pi / L)^2 > 0 gives
//     2 sqrt(K EI), approached from above with 0 <= P_cr(L) - 2 sqrt(K EI) <= pi^2 EI / L^2
//     (the nearest a lies within the spacing 2 sqrt(a*) pi / L of a* = sqrt(K / EI), where the
//     second difference K / a*^3 bounds the excess);
//   * tensionless pinned strut: a perturbation w <= 0 lifts the member off the foundation, which
//     then gives no help: the lifted mode sin(pi x / L) (sign chosen upward) solves EI w'''' + P w''
//     = 0 at P = pi^2 EI / L^2, the Euler load, for every K (the member buckles away from the
//     foundation). tests/verification/beam_column_test.cpp shows it with the closed form itself.
//
// Localized buckle of a heavy infinite member on a tensionless foundation (no imperfection): the
// flat state is w = q / K. On the symmetric branch parametrised by the lifted half-length a:
//   lifted zone |x| < a (no foundation): EI w'''' + P w'' = q, mu^2 = P / EI,
//     w = A + B cos(mu x) + q x^2 / (2 P);
//   contact zone x > a: EI w'''' + P w'' + K w = q, roots -alpha +- i beta (P < 2 sqrt(K EI)),
//     alpha^2 = (sqrt(K / EI) - P / (2 EI)) / 2, beta^2 = (sqrt(K / EI) + P / (2 EI)) / 2,
//     w = q / K + e^{-alpha s} (C1 cos(beta s) + C2 sin(beta s)), s = x - a (decays to the flat state);
//   at x = a the foundation reaction K w reaches zero: w(a) = 0 on both sides (so C1 = -q / K), and
//   w', w'', w''' are continuous (no concentrated force: the reaction is finite). The unknowns
//   A, B, C2, P meet these four equations: w'' and w''' give B, C2 linearly for a given P, w'
//   leaves one equation in P, whose least root in (0, 2 sqrt(K EI)) is the branch (the larger
//   roots are inadmissible or higher modes); A follows from w(a) = 0. As a -> 0 the branch starts
//   at P -> 2 sqrt(K EI) (the bilateral critical load of the long member); as K -> infinity at
//   fixed a it tends to Hobbs' vertical mode (upheaval.hpp) with lifted length L = 2 a, at the rate
//   K^(-1/4) of the contact zone's decay length 1 / alpha. This is the descending path an imperfect
//   member's trace approaches after its limit load (which lies below 2 sqrt(K EI)).
//   Two facts the tests show: (1) this single-lift-off solution is the tensionless one only where
//   its contact tail stays in contact; the tail oscillates about q/K with the decay e^{-alpha s},
//   and near 2 sqrt(K EI) (small a, slow decay) or for a stiff foundation (large K, where C2 ~
//   w'(a) / beta dwarfs q/K) it dips below w = 0 a wavelength 2 pi / beta away: the member would
//   lift off there too (status secondary_lift_off; the numbers are still the single-zone ones).
//   With q = EI = K = 1 that happens for a <= 0.48, not for a >= 0.6; at K = 1e9, a = 0.5 the dip
//   is 3e-7 of the uplift (of the order of q/K), so the Hobbs trend is unaffected. (2) At P(a)
//   the fixed-contact-set problem is singular: the buckle is a neutral mode of that contact set,
//   its amplitude set by the contact condition w(a) = 0, as in Hobbs' analysis.

#include <string>

namespace liftoff::closed_form {

struct StrutBuckling {
  double load = 0.0;   // critical compressive force
  int half_waves = 0;  // n of the critical mode sin(n pi x / L)
};

// min over n of n^2 pi^2 EI / L^2 + K L^2 / (n^2 pi^2) (K >= 0; n = 1 when K = 0).
StrutBuckling bilateral_pinned_strut_critical(double length, double bending_stiffness, double modulus);

// 2 sqrt(K EI): the critical load of a long member on a bilateral foundation.
double long_member_critical(double modulus, double bending_stiffness);

// pi^2 EI / L^2 for every K >= 0: the tensionless pinned strut buckles away from the foundation.
double tensionless_pinned_strut_critical(double length, double bending_stiffness);

// The least critical load of a straight free-free member of length L on a bilateral foundation
// (a heavy member lying on it, uniform weight: its flat state w = q / K does not bend, so this is
// where the path of the perfect member bifurcates): the least P > 0 at which
// EI w'''' + P w'' + K w = 0 with free ends (w'' = 0, EI w''' + P w' = 0 at both) has a solution
// w != 0. The transfer matrix exp(A L) of y = (w, w', w'', w''') (Taylor series with scaling and
// squaring) carries the two free-end solutions at x = 0 to x = L, where the 2 x 2 determinant of
// the end conditions is searched for its first sign change from P = 0 up to K L^2 / 12 (the
// Rayleigh quotient of the rigid rotation, an upper bound), then bisected to round-off. Returns
// NaN for K L^4 / EI outside (0, 1e4] (the series would lose its digits).
double free_free_bilateral_critical(double length, double bending_stiffness, double modulus);

enum class BuckleStatus {
  found,               // the branch's point at this a, admissible (wrong-sign |w| <= 1e-9 of the scale)
  no_root,             // no root of the lift-off equation in (0, 2 sqrt(K EI))
  secondary_lift_off,  // a root, but the contact tail dips below w = 0 (the member would lift off there)
  inadmissible,        // a root, but w > 0 in the lifted zone
  invalid_input,
};
std::string to_string(BuckleStatus status);

struct LocalizedBuckle {
  BuckleStatus status = BuckleStatus::invalid_input;
  std::string message;
  double half_length = 0.0;    // a: the lifted zone is |x| < a
  double axial_force = 0.0;    // P on the branch
  double uplift = 0.0;         // -w(0) > 0: the crown's height above the ground
  double amplitude = 0.0;      // w(0) - q / K < 0: measured from the flat state
  double crown_moment = 0.0;   // -EI w''(0), sagging positive
  double max_violation = 0.0;  // worst wrong-sign |w| / (q / K + uplift) on a grid (both zones)
  double tail_dip = 0.0;       // the contact tail's worst -w / (q / K + uplift) (secondary lift-off)
  // The solution's constants (see above) and the characteristic numbers.
  double A = 0.0, B = 0.0, C1 = 0.0, C2 = 0.0, mu = 0.0, alpha = 0.0, beta = 0.0;
  double q = 0.0, EI = 0.0, K = 0.0;

  // w at x (even in x): the lifted form for |x| < a, the decaying contact form beyond.
  double deflection(double x) const;
};

// The branch's point with lifted half-length a (> 0) for weight q > 0, modulus K > 0, EI > 0.
LocalizedBuckle localized_buckle(double modulus, double bending_stiffness, double weight, double half_length);

}  // namespace liftoff::closed_form
