#include "contact/from_scene.hpp"

#include <optional>
#include <stdexcept>
#include <string>

namespace liftoff::contact {

Method to_contact(scene::Method method) {
  // By name: the scene's names of the FE methods are the contact solver's (contact/method.hpp).
  if (const std::optional<Method> contact_method = from_string<Method>(scene::to_string(method)))
    return *contact_method;
  throw std::logic_error("to_contact: method " + std::string(scene::to_string(method)) +
                         " is no contact method (expected dual, primal, fast or auto)");
}

}  // namespace liftoff::contact
