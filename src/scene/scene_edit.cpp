#include "scene/scene_edit.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <charconv>
#include <cmath>
#include <limits>
#include <sstream>
#include <string_view>
#include <utility>

#include "core/error.hpp"

namespace liftoff::scene {

namespace {

// "loads[1]" -> {"loads", 1, "1"}; "foundation" -> {"foundation", -1}; not of either form: -2.
// An index too large for a long long reads as the largest one (no scene has that many tables).
struct PathPart {
  std::string name;
  long long index;
  std::string index_text;
};
PathPart split_index(std::string_view part) {
  const auto open = part.find('[');
  if (open == std::string_view::npos || part.back() != ']') return {std::string(part), -1, {}};
  const std::string_view index = part.substr(open + 1, part.size() - open - 2);
  if (index.empty() || index.find_first_not_of("0123456789") != std::string_view::npos)
    return {std::string(part), -2, {}};
  long long value = 0;
  if (std::from_chars(index.data(), index.data() + index.size(), value).ec != std::errc())
    value = std::numeric_limits<long long>::max();
  return {std::string(part.substr(0, open)), value, std::string(index)};
}

// The scene keys renamed (scene_reader.cpp reads the old names with a warning): a key the table
// lacks under the name asked for but holds under its other name is edited there, so that a sweep
// of foundation.nondimensional_k works on an old scene and one of foundation.k on a new one.
std::string edited_name(const toml::table& table, const std::string& name) {
  static const std::pair<std::string_view, std::string_view> renamed[] = {{"nondimensional_k", "k"},
                                                                          {"tension_nondimensional_k", "tension_k"}};
  if (table.contains(name)) return name;
  for (const auto& [now, old] : renamed) {
    if (name == now && table.contains(old)) return std::string(old);
    if (name == old && table.contains(now)) return std::string(now);
  }
  return name;
}

}  // namespace

std::string with_value(std::string_view toml_text, std::string_view key, double value, const std::string& source) {
  auto fail = [&](const std::string& why) { throw InputError(fmt::format("{}: key '{}': {}", source, key, why)); };
  toml::table document;
  try {
    document = toml::parse(toml_text, std::string_view(source));
  } catch (const toml::parse_error& e) {
    fail(fmt::format("the scene is not valid TOML ({})", e.description()));
  }

  toml::table* table = &document;
  std::string_view rest = key;
  while (true) {
    const auto dot = rest.find('.');
    const std::string_view part = rest.substr(0, dot);
    if (dot == std::string_view::npos) {
      const auto [written, index, index_text] = split_index(part);
      if (index != -1 || written.empty()) fail("expected a key name as the last part of the path");
      const std::string name = edited_name(*table, written);
      const toml::node* existing = table->get(name);
      if (existing != nullptr && (existing->is_table() || existing->is_array()))
        fail(fmt::format("'{}' is a table or an array, expected a key that holds a number", name));
      const bool integral = std::floor(value) == value && std::abs(value) < 9e15;
      if (existing != nullptr && existing->is_integer() && integral)
        table->insert_or_assign(name, static_cast<std::int64_t>(value));
      else
        table->insert_or_assign(name, value);
      break;
    }
    const auto [name, index, index_text] = split_index(part);
    toml::node* node = table->get(name);
    if (index == -2) fail(fmt::format("'{}' is not of the form name[index]", part));
    if (node == nullptr) fail(fmt::format("the scene has no [{}] table", name));
    if (index >= 0) {
      toml::array* array = node->as_array();
      if (array == nullptr || index >= static_cast<long long>(array->size()) ||
          !array->get(static_cast<std::size_t>(index))->is_table())
        fail(fmt::format("the scene has no [[{}]] number {} (counted from 0)", name, index_text));
      table = array->get(static_cast<std::size_t>(index))->as_table();
    } else {
      table = node->as_table();
      if (table == nullptr) fail(fmt::format("'{}' is not a table", name));
    }
    rest = rest.substr(dot + 1);
  }
  std::ostringstream text;
  text << document << "\n";
  return text.str();
}

}  // namespace liftoff::scene
