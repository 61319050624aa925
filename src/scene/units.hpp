#pragma once
// The scene's units ([units]): labels only. The numerics are nondimensional (model/member_model.hpp),
// so results never depend on them; they say what the user's numbers mean, in every output.
//
// A scene states them one of two ways: a system "FORCE-LENGTH" (e.g. "N-m", "kN-m", "N-mm",
// "lbf-in", "kip-ft": a force of N, kN, MN, lbf or kip and a length of m, cm, mm, in or ft), or
// free labels `length` and `force` (any text). Every other unit is derived from the two: moment
// "F L", distributed force and spring stiffness "F/L", foundation modulus "F/L^2", EI "F L^2".
// A system's units are also known in SI, which lets liftoff judge a modulus against real soils.

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace liftoff::scene {

struct Units {
  std::string system;  // as written ("kN-m"); empty for free labels or no [units]
  std::string length;  // "m"; empty when the scene states no units
  std::string force;   // "kN"

  bool stated() const { return !length.empty(); }
  std::string moment() const;             // "kN m"
  std::string distributed_force() const;  // "kN/m", also a spring's stiffness
  std::string modulus() const;            // "kN/m^2", the foundation modulus K
  std::string bending_stiffness() const;  // "kN m^2", EI
  std::string inverse_length() const;     // "1/m", beta
  // The size of the units in SI (m, N), when both are known units (a system, or free labels that
  // happen to name one); nullopt otherwise.
  std::optional<double> metres() const;
  std::optional<double> newtons() const;
};

// The units of a system "FORCE-LENGTH"; nullopt if it is not one.
std::optional<Units> units_of_system(std::string_view system);
// The other systems of the same family as `units` (SI: N, kN, MN with m, cm, mm; US customary:
// lbf, kip with in, ft), the units a value might have been written in by mistake; none when the
// scene's units are not a known system (or labels naming one).
std::vector<Units> sibling_systems(const Units& units);
// Every system, quoted and joined ("\"N-m\", \"N-cm\", ..."), for messages.
std::string unit_systems();
// Every label by name, in a fixed order: length, force, moment, distributed_force, modulus,
// bending_stiffness, inverse_length (all empty when no units are stated). The JSON `units` object
// and the HDF5 attributes units_<name> are these.
std::vector<std::pair<std::string, std::string>> unit_labels(const Units& units);

}  // namespace liftoff::scene
