#pragma once
// Ritz bases: complete families of TrigPolynomials in the member coordinate s that satisfy the
// KINEMATIC end conditions only (the static ones come out of the energy). basis.cpp gives, for
// every family, the argument why it is complete in the energy space.
//
// With xi = (s - s_begin)/(s_end - s_begin) in [0, 1] (psi for arches), and N = modes:
//
// Beams (w = 0 at a pinned end, w = w' = 0 at a clamped one; "roller" is taken as pinned):
//   pinned-pinned    sin(j pi xi)                               j = 1..N   (the seed's eq. 5.1)
//   clamped-clamped  sin(pi xi) sin(j pi xi)                    j = 1..N
//   pinned-clamped   sin(j pi xi) cos(pi xi/2)                  j = 1..N
//   clamped-free     1 - cos((j - 1/2) pi xi)                   j = 1..N
//   pinned-free      xi, sin((j - 1/2) pi xi)                   j = 1..N-1 (xi: rotation about the pin)
//   free-free        1, xi, xi^2, cos(j pi xi)                  j = 1..N-3 (1, xi: rigid motions)
//   and the mirror images (xi -> 1 - xi) for clamped-pinned, free-clamped, free-pinned.
//   The rigid motions the supports allow come first, so any N >= 1 is meaningful.
//
// Arches (u tangential, w radial): w takes the beam family of its own end conditions (w = 0 at
// pinned, roller and clamped ends, w' = 0 too at clamped ones). u has two parts:
//  - PARTNERS: antiderivatives of w functions, u_j(s) = integral of w_j + constant, the constant
//    (and for u fixed at both ends one linear combination) chosen to meet u's conditions (u = 0
//    at pinned and clamped ends). So each has its inextensional partner w = u' in the basis, and
//    the basis is free of membrane locking (EA R^2/EI = 3e6 for the seed's arch) by construction.
//  - END-STRAIN functions, one per end where u is fixed: the partners have u' = w = 0 there,
//    which would force the membrane strain u' - w to vanish at a pinned or clamped end where the
//    thrust is not zero (at roller and free ends it is zero, a natural condition). In psi:
//    fixed at both ends sin(pi psi), sin(2 pi psi); left only sin(pi psi/2); right only
//    cos(pi psi/2).
// N means N functions for w and N for u: N - e partners (at least 1) then e end-strain functions,
// e = number of ends where u is fixed. Examples:
//   roller-roller    w: sin(j pi psi) (the seed's cos((2j-1) pi theta/(2 gamma)) for odd j, and
//                    the antisymmetric sin(j' pi theta/gamma) for even j = 2j'),
//                    u: cos(j pi psi) (the seed's sin((2j-1) pi theta/(2 gamma)) and the even
//                    cos(j' pi theta/gamma)). All u have zero mean: the rigid rotation about the
//                    centre (u = const, w = 0), which nothing resists, is excluded as a gauge.
//   pinned-pinned    w: sin(j pi psi); u: combinations of 1 - cos(j pi psi) with u = 0 at both ends
//                    (the span of sin(pi psi) sin(j pi psi)), then sin(pi psi), sin(2 pi psi).
//   clamped-clamped  w: sin(pi psi) sin(j pi psi); u: sines with u' in that span, then the two.
// Whenever u is free at both ends (roller or free ends) the u functions have zero mean (gauge).
// Free arch ends: the arch's rigid translations (u, w) = (cos t, -sin t), (-sin t, -cos t) are
// inextensional but not exactly in the span (w would need sin t, cos t); they are approximated
// like any smooth field, so a rigid translation stores a small spurious bending energy that
// vanishes as N grows. Only the foundation resists those motions anyway.
//
// Every function is scaled to a largest absolute value of 1 over the member, so amplitudes are
// displacements in units of the length scale.

#include <array>
#include <string>
#include <vector>

#include "model/member_model.hpp"
#include "ritz/trig_polynomial.hpp"

namespace liftoff::ritz {

// Load-point enrichment (beams, on request): a point force makes w''' jump, which no smooth family
// approximates faster than about N^-3 at the load. So beams get, for every point force strictly
// inside the member, one kinked function
//     e(s) = |s - a|^3 + p(s),   p a polynomial of degree <= 5 (minimum norm in xi)
// that carries exactly that jump; p gives e the kinematic end conditions and the exact
// solution's natural ones (w'' = 0 at a pinned end, w'' = w''' = 0 at a free end), so that
// w - c e is as smooth as a solution without the point force and the family converges on it
// at its smooth-solution rate. e is stored as its two smooth halves, left and right of a.
// Where the foundation is stiff (beta L of 40, say) the deflection is local while e is not:
// the smooth amplitudes must cancel e's far field, and Newton stalls on the round-off that
// leaves (seen at 3e-8). Orthogonalising e against the smooth family moves the cancellation
// into e's own coefficients instead (measured: worse). So it is not the default.
enum class Enrichment {
  none,         // the family alone
  load_points,  // beams: plus one kinked function per interior point force (below)
};

struct KinkedFunction {
  double kink = 0.0;                     // a (s)
  std::array<TrigPolynomial, 2> halves;  // the expression for s < a and for s >= a
};

struct Basis {
  std::vector<TrigPolynomial> w;         // N functions of s
  std::vector<TrigPolynomial> u;         // arches: N functions of s; empty for beams
  std::vector<KinkedFunction> kinked_w;  // beams: the load-point enrichment, after the N (see above)
  std::string description;               // the family in words, for reports
};

// Throws std::invalid_argument for modes < 1, or s_begin >= s_end.
Basis beam_basis(model::EndSupport left, model::EndSupport right, double s_begin, double s_end, int modes);
Basis arch_basis(model::EndSupport left, model::EndSupport right, double s_begin, double s_end, int modes);
// The family of the member's end conditions; with Enrichment::load_points, beams with interior
// point forces also get the kinked functions (kinked_w); see above for when not to.
Basis make_basis(const model::MemberModel& model, int modes, Enrichment enrichment = Enrichment::none);

}  // namespace liftoff::ritz
