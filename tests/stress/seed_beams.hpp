#pragma once
// The seed's beam scenes (pinned-pinned, point forces and moments) as closed-form problems, the
// exact reference of the stress tests that check contact limits.

#include <cmath>

#include "closed_form/beam_on_foundation.hpp"
#include "scene/scene.hpp"

namespace liftoff::test {

inline closed_form::BeamProblem seed_problem(const scene::Scene& s) {
  closed_form::BeamProblem p;
  p.length = s.structure.length;
  p.bending_stiffness = s.structure.bending_stiffness;
  p.foundation_modulus = *s.foundation.stiffness_parameter * p.bending_stiffness / std::pow(p.length, 4);
  p.left = p.right = closed_form::EndCondition::pinned;
  for (const auto& l : s.loads) {
    if (l.kind == scene::LoadKind::force) p.forces.push_back({l.at, l.value});
    if (l.kind == scene::LoadKind::moment) p.moments.push_back({l.at, l.value});
  }
  return p;
}

}  // namespace liftoff::test
