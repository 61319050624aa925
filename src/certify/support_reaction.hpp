#pragma once
// One supported point's reaction (certify/certificate.hpp computes them from an answer's fields).
// Plain data, so that the results that carry it (a trace's steps, continuation/result.hpp) need
// nothing else of the certificate.

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

}  // namespace liftoff::certify
