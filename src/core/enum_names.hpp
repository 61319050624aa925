#pragma once
// One table per enum of its values' names, read by both to_string and from_string, so that what
// a writer writes a reader parses back (Ceres' types.h gives every enum a to-string and a
// from-string function). The names that reach JSON and HDF5 are a public contract: an entry, once
// shipped, keeps its spelling.
//
// An enum's header declares `std::string_view to_string(E)` and the specialisation
// `template <> std::optional<E> from_string<E>(std::string_view)`; its .cpp holds the table and
// defines both with name_in / value_in.

#include <optional>
#include <span>
#include <string_view>

namespace liftoff {

template <class Enum>
struct EnumName {
  Enum value;
  std::string_view name;
};

// The name of `value` in `table`; "unknown" when the table lacks it (a bug the enum's test sees).
template <class Enum>
constexpr std::string_view name_in(std::span<const EnumName<Enum>> table, Enum value) {
  for (const EnumName<Enum>& entry : table)
    if (entry.value == value) return entry.name;
  return "unknown";
}

// The value named `name` in `table`, nullopt for a name it does not hold.
template <class Enum>
constexpr std::optional<Enum> value_in(std::span<const EnumName<Enum>> table, std::string_view name) {
  for (const EnumName<Enum>& entry : table)
    if (entry.name == name) return entry.value;
  return std::nullopt;
}

// Specialised for each enum next to its to_string (see the top).
template <class Enum>
std::optional<Enum> from_string(std::string_view name);

}  // namespace liftoff
