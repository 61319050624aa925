#pragma once
// The closed-form problem of a beam scene, read from the scene itself in the user's units (not
// from liftoff's member model, so that a wrong member model shows against it), for the tests and
// benchmarks that compare liftoff's beams with the exact solution. Header-only, so that
// liftoff_closed_form itself stays independent of liftoff's code.
//
// It carries the beam, its ends, the foundation (one piece, k or modulus, or constant segments)
// and the point forces, point moments and uniform loads. What it cannot carry (an arch, a
// distributed or curvature load, a linear foundation segment) is refused with
// std::invalid_argument rather than left out, so that a reference never silently drops a load.

#include <cmath>
#include <stdexcept>

#include "closed_form/beam_on_foundation.hpp"
#include "scene/scene.hpp"

namespace liftoff::closed_form {

inline EndCondition end_condition_of(scene::EndSupport e) {
  return e == scene::EndSupport::clamped ? EndCondition::clamped
         : e == scene::EndSupport::free  ? EndCondition::free
                                         : EndCondition::pinned;
}

// The factors of the two load cases: dead loads times `dead`, live loads times `live`; a case
// with factor 0 is left out (not added as zero loads).
struct CaseFactors {
  double dead = 1.0;
  double live = 1.0;
};

inline BeamProblem problem_of(const scene::Scene& s, CaseFactors factors = {}) {
  if (s.structure.kind != scene::StructureKind::beam)
    throw std::invalid_argument("closed_form::problem_of: " + s.source_name + " is not a beam");
  BeamProblem p;
  p.length = s.structure.length;
  p.bending_stiffness = s.structure.bending_stiffness;
  p.left = end_condition_of(s.supports.left);
  p.right = end_condition_of(s.supports.right);
  const double k_scale = p.bending_stiffness / std::pow(p.length, 4);  // K = k EI / L^4
  if (s.foundation.segments.empty()) {
    p.foundation_modulus = s.foundation.modulus ? *s.foundation.modulus : s.foundation.k.value() * k_scale;
  }
  for (const auto& piece : s.foundation.segments) {
    if (piece.at_to)
      throw std::invalid_argument("closed_form::problem_of: " + s.source_name + " has a linear foundation segment");
    p.foundation_segments.push_back({piece.from, piece.to, piece.modulus ? *piece.modulus : piece.k.value() * k_scale});
  }
  for (const auto& l : s.loads) {
    const double factor = l.load_case == scene::LoadCase::dead ? factors.dead : factors.live;
    if (factor == 0.0) continue;
    switch (l.kind) {
      case scene::LoadKind::force:
        p.forces.push_back({l.at, factor * l.value});
        break;
      case scene::LoadKind::moment:
        p.moments.push_back({l.at, factor * l.value});
        break;
      case scene::LoadKind::uniform:
        p.uniform_loads.push_back({l.from, l.to, factor * l.value});
        break;
      case scene::LoadKind::distributed:
      case scene::LoadKind::curvature:
      case scene::LoadKind::sine:
        throw std::invalid_argument("closed_form::problem_of: " + s.source_name +
                                    " has a distributed, sine or curvature load, which the reference does not carry");
      case scene::LoadKind::axial:
      case scene::LoadKind::temperature:  // first-order theory: an axial force is not carried
        throw std::invalid_argument("closed_form::problem_of: " + s.source_name +
                                    " has an axial force, which the (first-order) reference does not carry");
    }
  }
  return p;
}

}  // namespace liftoff::closed_form
