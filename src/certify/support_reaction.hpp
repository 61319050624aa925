#pragma once
// One supported point's reaction (certify/certificate.hpp computes them from an answer's fields).
// Plain data, so that the results that carry it (a trace's steps, continuation/result.hpp) need
// nothing else of the certificate.

#include <cmath>

namespace liftoff::certify {

// Nondimensional in a Certificate (force in EI/l^2, moment in EI/l, at in s); in the user's units
// (x or theta in degrees, force, moment, length) after user_figures / user_support_reactions.
struct SupportReaction {
  double at = 0.0;          // s
  double force = 0.0;       // pushes the member away from the foundation (beams: upward)
  double moment = 0.0;      // counterclockwise; 0 where the rotation is free
  double tangential = 0.0;  // arches: along increasing theta; von Karman beams: the axial reaction along +x; else 0
  bool spring = false;      // an elastic support: force and moment are its springs'
  double settlement = 0.0;  // the support's (or its spring's far end's) prescribed w, in l
  bool operator==(const SupportReaction&) const = default;
};

// An arch support's reaction as the engineer resolves it: horizontal (H > 0 to the right, the
// thrust) and vertical (V > 0 upward). At theta (radians from the crown, the centre below it) the
// tangent toward increasing theta is t = (cos theta, -sin theta) and `force` pushes against w > 0:
// along (sin theta, cos theta) with the foundation inside (w > 0 toward the centre), the opposite
// with it outside. Units as the force's.
struct HorizontalVertical {
  double horizontal = 0.0, vertical = 0.0;
};
inline HorizontalVertical arch_components(double theta, double force, double tangential, bool foundation_outside) {
  const double away = foundation_outside ? -force : force;
  return {away * std::sin(theta) + tangential * std::cos(theta), away * std::cos(theta) - tangential * std::sin(theta)};
}

}  // namespace liftoff::certify
