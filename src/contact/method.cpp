#include "contact/method.hpp"

namespace liftoff::contact {

namespace {
constexpr EnumName<Method> method_names[] = {
    {Method::dual, "dual"},
    {Method::primal, "primal"},
    {Method::fast, "fast"},
    {Method::automatic, "auto"},
};
}  // namespace

std::string_view to_string(Method method) { return name_in<Method>(method_names, method); }

}  // namespace liftoff::contact

namespace liftoff {
template <>
std::optional<contact::Method> from_string(std::string_view name) {
  return value_in<contact::Method>(contact::method_names, name);
}
}  // namespace liftoff
