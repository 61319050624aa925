#include "contact/from_scene.hpp"

#include <stdexcept>
#include <string>

namespace liftoff::contact {

Method to_contact(scene::Method method) {
  switch (method) {
    case scene::Method::dual:
      return Method::dual;
    case scene::Method::primal:
      return Method::primal;
    case scene::Method::fast:
      return Method::fast;
    case scene::Method::automatic:
      return Method::automatic;
    case scene::Method::ritz:
    case scene::Method::all:
      break;
  }
  throw std::logic_error("to_contact: method " + std::string(scene::to_string(method)) +
                         " is no contact method (expected dual, primal, fast or auto)");
}

}  // namespace liftoff::contact
