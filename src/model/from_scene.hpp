#pragma once
// The one boundary between the scene (the problem as the user wrote it, scene/scene.hpp) and the
// member model (the nondimensional problem the numerics see, model/member_model.hpp): the scene's
// enums become the model's and its values are scaled (member_model.hpp says how). Nothing below
// this file includes the scene.

#include "model/member_model.hpp"
#include "scene/scene.hpp"

namespace liftoff::model {

MemberModel make_member_model(const scene::Scene& scene);

StructureKind to_model(scene::StructureKind);
EndSupport to_model(scene::EndSupport);
// A distributed (table) load has no model kind: make_member_model makes it uniform pieces; asking
// for its kind is a programming error (throws).
LoadKind to_model(scene::LoadKind);
Theory to_model(scene::Theory);
LoadCase to_model(scene::LoadCase);
LoadDirection to_model(scene::LoadDirection);
LoadBasis to_model(scene::LoadBasis);

}  // namespace liftoff::model
