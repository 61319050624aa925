#pragma once
// The member in nondimensional form, the only form the numerics see.
//
// Scales: the length scale is L for beams and R for arches, the stiffness scale is EI. So the
// member coordinate s is x/L in [0, 1] for beams and theta (radians) in [-gamma, gamma] for
// arches; displacements come out in units of the length scale; the foundation modulus becomes
// k = K l^4/EI; a force P becomes P l^2/EI, a moment M l/EI, a distributed load q l^3/EI.
// Results therefore do not depend on the user's units, and `Scales` converts back.

#include <vector>

#include "scene/scene.hpp"

namespace liftoff::fe {

using scene::EndSupport;
using scene::LoadBasis;
using scene::LoadCase;
using scene::LoadDirection;
using scene::LoadKind;
using scene::StructureKind;

struct Scales {
  double length = 1.0;             // L or R
  double bending_stiffness = 1.0;  // EI
  double displacement() const { return length; }
  double force() const { return bending_stiffness / (length * length); }
  double moment() const { return bending_stiffness / length; }
  double force_per_length() const { return bending_stiffness / (length * length * length); }
};

struct MemberLoad {
  LoadKind kind = LoadKind::force;
  double at = 0.0;     // s
  double value = 0.0;  // nondimensional
  double from = 0.0;   // s, uniform loads
  double to = 0.0;
  LoadCase load_case = LoadCase::live;
  LoadDirection direction = LoadDirection::radial;  // arches (fe/arch_loads.hpp)
  LoadBasis per = LoadBasis::arc;
};

struct MemberModel {
  StructureKind kind = StructureKind::beam;
  double s_begin = 0.0;
  double s_end = 1.0;
  double membrane_stiffness = 0.0;  // arches: EA R^2 / EI
  EndSupport left = EndSupport::pinned;
  EndSupport right = EndSupport::pinned;
  std::vector<double> point_supports;  // s
  double foundation_modulus = 0.0;     // k
  bool tensionless = true;
  double foundation_begin = 0.0;  // s
  double foundation_end = 1.0;
  // Arches: the foundation lies outside (around the extrados), so w > 0 is outward.
  bool foundation_outside = false;
  std::vector<MemberLoad> loads;
  Scales scales;

  // User coordinate (x, or theta in degrees) <-> member coordinate s.
  double s_from_user(double position) const;
  double user_from_s(double s) const;
  double length() const { return s_end - s_begin; }
};

MemberModel make_member_model(const scene::Scene& scene);

}  // namespace liftoff::fe
