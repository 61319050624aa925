#include "scene/units.hpp"

#include <fmt/format.h>

#include <array>

namespace liftoff::scene {
namespace {

// The units a system may name, with their size in SI.
constexpr std::array<std::pair<std::string_view, double>, 5> forces{{
    {"N", 1.0},
    {"kN", 1e3},
    {"MN", 1e6},
    {"lbf", 4.4482216152605},
    {"kip", 4448.2216152605},
}};
constexpr std::array<std::pair<std::string_view, double>, 5> lengths{{
    {"m", 1.0},
    {"cm", 1e-2},
    {"mm", 1e-3},
    {"in", 0.0254},
    {"ft", 0.3048},
}};

template <std::size_t N>
std::optional<double> size_of(const std::array<std::pair<std::string_view, double>, N>& table, std::string_view name) {
  for (const auto& [unit, size] : table)
    if (unit == name) return size;
  return std::nullopt;
}

std::string unless_unstated(const Units& u, std::string text) { return u.stated() ? text : std::string(); }

}  // namespace

std::string Units::moment() const { return unless_unstated(*this, force + " " + length); }
std::string Units::distributed_force() const { return unless_unstated(*this, force + "/" + length); }
std::string Units::modulus() const { return unless_unstated(*this, force + "/" + length + "^2"); }
std::string Units::bending_stiffness() const { return unless_unstated(*this, force + " " + length + "^2"); }
std::string Units::inverse_length() const { return unless_unstated(*this, "1/" + length); }
std::optional<double> Units::metres() const { return size_of(lengths, length); }
std::optional<double> Units::newtons() const { return size_of(forces, force); }

std::optional<Units> units_of_system(std::string_view system) {
  const auto dash = system.find('-');
  if (dash == std::string_view::npos) return std::nullopt;
  const std::string_view force = system.substr(0, dash), length = system.substr(dash + 1);
  if (!size_of(forces, force) || !size_of(lengths, length)) return std::nullopt;
  return Units{std::string(system), std::string(length), std::string(force)};
}

std::vector<Units> sibling_systems(const Units& units) {
  const auto us = [](std::string_view unit) { return unit == "lbf" || unit == "kip" || unit == "in" || unit == "ft"; };
  std::vector<Units> out;
  if (!units.metres() || !units.newtons()) return out;
  for (const auto& [force, unused_f] : forces)
    for (const auto& [length, unused_l] : lengths)
      if (us(force) == us(units.force) && us(length) == us(units.length) &&
          (force != units.force || length != units.length))
        out.push_back({fmt::format("{}-{}", force, length), std::string(length), std::string(force)});
  return out;
}

std::string unit_systems() {
  std::string out;
  for (const auto& [force, unused_f] : forces)
    for (const auto& [length, unused_l] : lengths)
      out += fmt::format("{}\"{}-{}\"", out.empty() ? "" : ", ", force, length);
  return out;
}

std::vector<std::pair<std::string, std::string>> unit_labels(const Units& u) {
  return {{"length", u.length},
          {"force", u.force},
          {"moment", u.moment()},
          {"distributed_force", u.distributed_force()},
          {"modulus", u.modulus()},
          {"bending_stiffness", u.bending_stiffness()},
          {"inverse_length", u.inverse_length()}};
}

}  // namespace liftoff::scene
