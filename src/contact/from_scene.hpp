#pragma once
// The scene's method as the contact solver's (contact/method.hpp): the one conversion, at the
// boundary between the scene and the numerics (model/from_scene.hpp says which). Nothing in
// contact/ but this file includes the scene.

#include "contact/method.hpp"
#include "scene/scene.hpp"

namespace liftoff::contact {

// dual, primal, fast and automatic are contact methods; ritz and all are not (the caller picks
// the Ritz model or runs every method itself): asking for them is a programming error (throws
// std::logic_error).
Method to_contact(scene::Method);

}  // namespace liftoff::contact
