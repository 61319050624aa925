#pragma once
// How the contact problem of a discretised member is solved (contact_solver.hpp says what each
// does): dual or primal, the LCPs by Lemke; fast, the sparse active-set solver; automatic, chosen
// from the discretisation (choose_fe_method). The contact solver's own enum: the scene's
// scene::Method also names the Ritz model and "all", which are no contact methods; it becomes this
// one once, at the boundary (contact/from_scene.hpp). Names from one table (core/enum_names.hpp),
// the scene's spellings ("auto" for automatic), which reach the JSON and HDF5 outputs.

#include <optional>
#include <string_view>

#include "core/enum_names.hpp"

namespace liftoff::contact {

enum class Method { dual, primal, fast, automatic };
std::string_view to_string(Method);

}  // namespace liftoff::contact

namespace liftoff {
template <>  // the names' one table is in method.cpp
std::optional<contact::Method> from_string(std::string_view);
}  // namespace liftoff
