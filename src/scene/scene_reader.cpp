#include "scene/scene_reader.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <sstream>
#include <tuple>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "scene/schema.hpp"
#include "scene/unit_library.hpp"

namespace liftoff::scene {
namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

std::string header(const TableSpec& spec) {
  return spec.array_of_tables ? fmt::format("[[{}]]", spec.name) : fmt::format("[{}]", spec.name);
}

// ---------------------------------------------------------------------------------------------
// Message text. Everything the user wrote is escaped so that a message stays on one line.

std::string escaped(std::string_view s) {
  std::string out;
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\')
      out += {'\\', c};
    else if (c == '\n')
      out += "\\n";
    else if (c == '\r')
      out += "\\r";
    else if (c == '\t')
      out += "\\t";
    else if (u < 0x20 || u == 0x7f)
      out += fmt::format("\\x{:02x}", u);
    else
      out += c;
  }
  return out;
}

std::string in_quotes(std::string_view s) { return '"' + escaped(s) + '"'; }

// A float as TOML writes it, so that 200.0 does not read as the integer 200.
std::string toml_float(double x) {
  std::string s = fmt::format("{}", x);
  if (std::isfinite(x) && s.find_first_of(".e") == std::string::npos) s += ".0";
  return s;
}

// A value as the user wrote it, for "got ...".
std::string describe(const toml::node& node) {
  switch (node.type()) {
    case toml::node_type::string:
      return in_quotes(node.as_string()->get());
    case toml::node_type::integer:
      return std::to_string(node.as_integer()->get());
    case toml::node_type::floating_point:
      return toml_float(node.as_floating_point()->get());
    case toml::node_type::boolean:
      return node.as_boolean()->get() ? "true" : "false";
    case toml::node_type::table:
      return "a table";
    case toml::node_type::array:
      return "an array";
    case toml::node_type::date:
      return "a date";
    case toml::node_type::time:
      return "a time";
    case toml::node_type::date_time:
      return "a date-time";
    default:
      return "nothing";
  }
}

// "a", "a or b", "a, b or c"
std::string one_of(const std::vector<std::string>& items) {
  std::string out;
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (i > 0) out += i + 1 == items.size() ? " or " : ", ";
    out += items[i];
  }
  return out;
}

std::string joined(const std::vector<std::string_view>& items) { return fmt::format("{}", fmt::join(items, ", ")); }

// Case-insensitive edit distance, to suggest the key a typo meant.
std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const bool same =
          std::tolower(static_cast<unsigned char>(a[i - 1])) == std::tolower(static_cast<unsigned char>(b[j - 1]));
      const std::size_t next = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (same ? 0 : 1)});
      diagonal = row[j];
      row[j] = next;
    }
  }
  return row[b.size()];
}

// " (did you mean 'x'?)" for the known name nearest to a misspelt one, if one is near.
std::string suggestion(std::string_view name, const std::vector<std::string_view>& known) {
  std::string_view best;
  std::size_t best_distance = std::max<std::size_t>(2, name.size() / 3) + 1;
  for (const std::string_view k : known) {
    if (const std::size_t d = edit_distance(name, k); d < best_distance) {
      best = k;
      best_distance = d;
    }
  }
  return best.empty() ? std::string() : fmt::format(" (did you mean '{}'?)", best);
}

// The one way a scene is refused: "FILE:LINE: key 'PATH': PROBLEM" (LINE where it is known).
[[noreturn]] void fail(std::string_view source, const toml::source_region* where, std::string_view path,
                       std::string_view problem) {
  const std::string location =
      where != nullptr && where->begin.line > 0 ? fmt::format("{}:{}", source, where->begin.line) : std::string(source);
  throw InputError(fmt::format("{}: key '{}': {}", location, escaped(path), problem));
}

// ---------------------------------------------------------------------------------------------
// The values a number may take, and how a message says so. A closed end accepts values up to
// `tolerance` beyond it and snaps them onto the end; an open end needs a margin of `tolerance`.
// Non-finite numbers are never accepted.
struct Range {
  std::string expected;  // "a number > 0"
  double lo = -inf;
  double hi = inf;
  bool open_lo = false;
  bool open_hi = false;
  double tolerance = 0.0;

  std::optional<double> accept(double x) const {
    if (!std::isfinite(x)) return std::nullopt;
    if (open_lo ? !(x > lo + tolerance) : x < lo - tolerance) return std::nullopt;
    if (open_hi ? !(x < hi - tolerance) : x > hi + tolerance) return std::nullopt;
    return std::clamp(x, lo, hi);
  }
};

Range any_number() { return {"a finite number"}; }
Range positive() { return {"a number > 0", 0.0, inf, true}; }
Range tolerance_range() {
  return {fmt::format("a number in [{:g}, {:g}] (the contact limits' accuracy relative to the length; below {:g} "
                      "double precision cannot honour it)",
                      min_tolerance, max_tolerance, min_tolerance),
          min_tolerance, max_tolerance};
}

// The member in the user's coordinate: x in [0, L] (beam) or theta in [-gamma, gamma] degrees.
struct Member {
  double begin;
  double end;
  bool arch;

  double tolerance() const { return 1e-12 * (end - begin); }
  std::string interval(bool open) const {
    return open ? fmt::format("({}, {})", begin, end) : fmt::format("[{}, {}]", begin, end);
  }
  std::string noun() const { return arch ? "an angle in degrees" : "a position"; }
  Range position() const {  // loads, extents: ends included
    return {fmt::format("{} in {}", noun(), interval(false)), begin, end, false, false, tolerance()};
  }
  Range inside() const {  // interior supports: ends excluded
    return {fmt::format("{} strictly inside {}", noun(), interval(true)), begin, end, true, true, tolerance()};
  }
};

// For an enum value that is refused with a hint: when the user wrote `when`, add `hint`.
struct Hint {
  std::string_view when;
  std::string_view text;
};

// ---------------------------------------------------------------------------------------------
// What a number written with its unit needs to be read: the scene's [units] (read first), the
// member's kind (a position is a length on a beam, an angle on an arch) and, inside a load, the
// load's kind (its value's dimension). Shared by every Section of one scene; a load's Sections
// point to a copy that adds the kind.
struct Context {
  std::string source;
  std::optional<Units> units;                     // [units], when the scene states them
  bool arch = false;                              // known after [structure]
  std::optional<LoadKind> load_kind;              // inside a load's table
  Dimension live_load = Dimension::none;          // trace.report_at's dimension (after [[loads]])
  std::vector<std::string>* with_unit = nullptr;  // the paths of numbers written with a unit

  // A key's dimension with position, load_value and live_load made concrete.
  Dimension resolve(Dimension d) const {
    if (d == Dimension::position) return arch ? Dimension::angle : Dimension::length;
    if (d == Dimension::load_value) return load_kind ? load_value_dimension(*load_kind) : Dimension::none;
    if (d == Dimension::live_load) return live_load;
    return d;
  }
};

// ---------------------------------------------------------------------------------------------
// One table of the scene with its path for messages ("structure", "loads[2]"). Each getter
// returns nothing when the key is absent, the validated value when it is present, and throws
// InputError otherwise; the required_* forms also refuse an absent key.
class Section {
 public:
  Section(const Context& context, const toml::table& table, std::string path)
      : context_(&context), source_(context.source), table_(table), path_(std::move(path)) {}

  const toml::table& table() const { return table_; }
  const std::string& source() const { return source_; }
  const Context& context() const { return *context_; }
  // The same table read with another context (a load's, once its kind is known).
  Section with(const Context& context) const { return {context, table_, path_}; }
  const toml::node* find(std::string_view key) const { return table_.get(key); }
  std::string path(std::string_view key) const {
    return path_.empty() ? std::string(key) : fmt::format("{}.{}", path_, key);
  }

  // At the key's value if present, else at the table (the root table has no useful line).
  [[noreturn]] void fail(std::string_view key, std::string_view problem) const {
    const toml::node* node = find(key);
    const toml::source_region* where = node != nullptr ? &node->source() : path_.empty() ? nullptr : &table_.source();
    scene::fail(source_, where, path(key), problem);
  }
  // "FILE:LINE: key 'PATH'" of a present key, as fail() starts its message (for warnings).
  std::string located(std::string_view key) const {
    const toml::node* node = find(key);
    const auto line = node != nullptr ? node->source().begin.line : 0;
    return fmt::format("{}{}: key '{}'", source_, line > 0 ? fmt::format(":{}", line) : "", escaped(path(key)));
  }
  [[noreturn]] void wrong(std::string_view key, std::string_view expected, std::string_view hint = {}) const {
    fail(key, fmt::format("expected {}, got {}{}", expected, describe(*find(key)),
                          hint.empty() ? "" : fmt::format(" ({})", hint)));
  }
  [[noreturn]] void missing(std::string_view key, std::string_view expected) const {
    fail(key, fmt::format("missing (expected {})", expected));
  }
  void refuse(std::string_view key, std::string_view why) const {
    if (find(key) != nullptr) fail(key, fmt::format("not allowed {}", why));
  }

  // A sub-table; an absent optional one reads as empty, so every key takes its default.
  Section section(std::string_view key) const {
    static const toml::table empty;
    const toml::node* node = find(key);
    return {*context_, node != nullptr ? *node->as_table() : empty, path(key)};
  }
  Section required_section(std::string_view key) const {
    if (find(key) == nullptr) missing(key, fmt::format("a table [{}]", key));
    return section(key);
  }

  std::optional<double> number(std::string_view key, const Range& range) const {
    const toml::node* node = find(key);
    if (node == nullptr) return std::nullopt;
    return checked(*node, path(key), range);
  }
  double required_number(std::string_view key, const Range& range) const {
    return required(number(key, range), key, range.expected);
  }
  // One number given as a node (an array's item), at item_path for messages.
  double number_at(const toml::node& node, const std::string& item_path, const Range& range) const {
    return checked(node, item_path, range);
  }

  // An array of distinct numbers, each within the range.
  std::vector<double> numbers(std::string_view key, const Range& range) const {
    const toml::node* node = find(key);
    if (node == nullptr) return {};
    const toml::array* array = node->as_array();
    if (array == nullptr) wrong(key, "an array of numbers");
    std::vector<double> values;
    for (std::size_t i = 0; i < array->size(); ++i) {
      const toml::node& item = *array->get(i);
      const std::string item_path = fmt::format("{}[{}]", path(key), i);
      const double x = checked(item, item_path, range);
      for (const double earlier : values) {
        if (std::abs(x - earlier) <= range.tolerance) {
          scene::fail(source_, &item.source(), item_path,
                      fmt::format("expected distinct positions, got {} twice", describe(item)));
        }
      }
      values.push_back(x);
    }
    return values;
  }

  // A non-empty array of numbers, each within the range (repeats allowed: a table's steps).
  std::vector<double> number_array(std::string_view key, const Range& range, std::string_view expected) const {
    const toml::node* node = find(key);
    if (node == nullptr) missing(key, expected);
    const toml::array* array = node->as_array();
    if (array == nullptr || array->empty()) wrong(key, expected);
    std::vector<double> values;
    for (std::size_t i = 0; i < array->size(); ++i)
      values.push_back(checked(*array->get(i), fmt::format("{}[{}]", path(key), i), range));
    return values;
  }

  std::optional<int> integer(std::string_view key, int lo, int hi) const {
    const toml::node* node = find(key);
    if (node == nullptr) return std::nullopt;
    const toml::value<std::int64_t>* value = node->as_integer();
    if (value == nullptr || value->get() < lo || value->get() > hi) {
      wrong(key, fmt::format("an integer in [{}, {}]", lo, hi));
    }
    return static_cast<int>(value->get());
  }

  std::optional<bool> flag(std::string_view key) const {
    const toml::node* node = find(key);
    if (node == nullptr) return std::nullopt;
    if (!node->is_boolean()) wrong(key, "true or false");
    return node->as_boolean()->get();
  }

  // A string naming one of `allowed` (spelt by to_string).
  template <class Enum>
  std::optional<Enum> choice(std::string_view key, std::initializer_list<Enum> allowed, Hint hint = {}) const {
    const toml::node* node = find(key);
    if (node == nullptr) return std::nullopt;
    if (const toml::value<std::string>* text = node->as_string()) {
      for (const Enum e : allowed) {
        if (to_string(e) == text->get()) return e;
      }
      if (!hint.when.empty() && text->get() == hint.when) wrong(key, names(allowed), hint.text);
    }
    wrong(key, names(allowed));
  }
  template <class Enum>
  Enum required_choice(std::string_view key, std::initializer_list<Enum> allowed) const {
    return required(choice(key, allowed), key, names(allowed));
  }

  // Refuses keys and sub-tables the schema does not list.
  void check_keys(const TableSpec& spec) const {
    const std::vector<std::string_view> names = spec.key_names();
    for (const auto& [key, node] : table_) {
      if (std::find(names.begin(), names.end(), key.str()) == names.end()) {
        scene::fail(source_, &key.source(), path(key.str()),
                    fmt::format("unknown key{}; the keys of {} are {}", suggestion(key.str(), names), header(spec),
                                joined(names)));
      }
    }
  }

 private:
  template <class T>
  T required(std::optional<T> value, std::string_view key, std::string_view expected) const {
    if (!value) missing(key, expected);
    return *value;
  }

  // Integers are accepted where a double holds them exactly (|n| <= 2^53, or a multiple of a
  // power of two beyond); any other integer is refused with a hint rather than rounded, since
  // toml++ reads it as no double at all.
  double checked(const toml::node& node, const std::string& node_path, const Range& range) const {
    std::optional<double> x;
    if (const toml::value<std::int64_t>* integer = node.as_integer()) {
      const std::int64_t n = integer->get();
      const double d = static_cast<double>(n);  // correctly rounded; d <= 2^63
      if (d >= 0x1p63 || static_cast<std::int64_t>(d) != n) {
        scene::fail(source_, &node.source(), node_path,
                    fmt::format("expected {}, got {}, an integer that a double cannot hold exactly (write it as "
                                "a float, e.g. {:.16e}, to use the nearest double)",
                                range.expected, n, d));
      }
      x = range.accept(d);
    } else if (const toml::value<double>* floating = node.as_floating_point()) {
      x = range.accept(floating->get());
    } else if (const toml::value<std::string>* text = node.as_string()) {
      if (const std::optional<double> converted = with_unit(node, text->get(), node_path, range)) {
        x = range.accept(*converted);
        if (!x)
          scene::fail(source_, &node.source(), node_path,
                      fmt::format("expected {}, got {} ({} in the scene's units)", range.expected, describe(node),
                                  toml_float(*converted)));
      }
    }
    if (!x) {
      scene::fail(source_, &node.source(), node_path,
                  fmt::format("expected {}, got {}", range.expected, describe(node)));
    }
    return *x;
  }

  // A number written with its unit ("30 MN/m^2"), converted to the scene's unit of the key's
  // dimension (schema.hpp); every way it cannot be is refused with the key. nullopt for a string
  // that does not start with a number.
  std::optional<double> with_unit(const toml::node& node, const std::string& text, const std::string& node_path,
                                  const Range& range) const {
    const auto refuse = [&](const std::string& expected, const std::string& why) {
      scene::fail(source_, &node.source(), node_path,
                  fmt::format("expected {}, got {}{}", expected, describe(node), why.empty() ? "" : " (" + why + ")"));
    };
    const std::optional<unit_library::Quantity> quantity = unit_library::split(text);
    if (!quantity) return std::nullopt;  // no number at all: the plain "expected ..., got ..."
    const Dimension dimension = context_->resolve(key_dimension(node_path).value_or(Dimension::none));
    if (dimension == Dimension::none || dimension == Dimension::not_a_number)
      refuse(fmt::format("{}, a plain number", range.expected), "this key is nondimensional: it takes no unit");
    const std::string named =
        fmt::format("{} {} ({})", dimension == Dimension::angle ? "an" : "a", to_string(dimension), range.expected);
    if (quantity->unit.empty())
      refuse(fmt::format("{}: a plain number, or a number and its unit", named), "a string without a unit");
    const Units& units = context_->units ? *context_->units : Units{};
    const std::string target = unit_in(dimension, units);
    const bool scene_based = dimension != Dimension::angle && dimension != Dimension::temperature &&
                             dimension != Dimension::inverse_temperature;
    if (scene_based && !units.stated())
      refuse(fmt::format("{} as a plain number", named),
             "a unit needs the scene's [units] to convert to: add [units] system = \"kN-m\" or another system");
    if (scene_based && !unit_library::known(target))
      refuse(fmt::format("{} as a plain number", named),
             fmt::format("the scene's [units] labels make its unit \"{}\", which UDUNITS-2 does not know, so no "
                         "unit converts to it",
                         escaped(target)));
    if (!unit_library::known(quantity->unit))
      refuse(fmt::format("{} with a unit UDUNITS-2 knows (e.g. \"{}\")", named, si_unit(dimension)),
             fmt::format("unknown unit \"{}\"", escaped(quantity->unit)));
    const unit_library::Conversion conversion =
        unit_library::convert(quantity->number, quantity->unit, target, dimension == Dimension::temperature);
    if (conversion.outcome != unit_library::Outcome::converted) {
      std::string actual;  // the dimension the user's unit has, when it is one of ours
      for (const Dimension d : {Dimension::length, Dimension::force, Dimension::force_length, Dimension::force_length2,
                                Dimension::force_per_length, Dimension::force_per_length2, Dimension::inverse_length,
                                Dimension::temperature, Dimension::inverse_temperature})
        if (actual.empty() && unit_library::convertible(quantity->unit, si_unit(d)))
          actual = fmt::format("\"{}\" is a {}", escaped(quantity->unit), to_string(d));
      if (actual.empty() && unit_library::dimensionless(quantity->unit))
        actual = fmt::format("\"{}\" is a pure number", escaped(quantity->unit));
      if (actual.empty()) actual = fmt::format("\"{}\" is of another dimension", escaped(quantity->unit));
      refuse(fmt::format("{} in {} or a unit convertible to it", named, target), actual);
    }
    if (context_->with_unit != nullptr) context_->with_unit->push_back(node_path);
    return conversion.value;
  }

  template <class Enum>
  static std::string names(std::initializer_list<Enum> allowed) {
    std::vector<std::string> quoted_names;
    for (const Enum e : allowed) quoted_names.push_back(in_quotes(to_string(e)));
    return one_of(quoted_names);
  }

  const Context* context_;
  const std::string& source_;
  const toml::table& table_;
  std::string path_;
};

// ---------------------------------------------------------------------------------------------
// The shape of the document: known tables only, each a table or an array of tables as the
// schema says, with known keys only. Checked before any value so that a typo is reported as
// the typo, not as the missing key it hides.
void check_schema(const Section& root, const std::string& source) {
  std::vector<std::string_view> table_names;
  std::vector<std::string> headers;
  for (const TableSpec& spec : top_level_tables()) {
    table_names.push_back(spec.name);
    headers.push_back(header(spec));
  }
  for (const auto& [key, node] : root.table()) {
    const auto spec = std::find_if(top_level_tables().begin(), top_level_tables().end(),
                                   [&](const TableSpec& s) { return s.name == key.str(); });
    if (spec == top_level_tables().end()) {
      fail(source, &key.source(), key.str(),
           fmt::format("unknown {}{}; the tables of a scene are {}", node.is_table() ? "table" : "key",
                       suggestion(key.str(), table_names), fmt::join(headers, ", ")));
    }
    if (!spec->array_of_tables) {
      if (!node.is_table()) root.wrong(key.str(), fmt::format("a table {}", header(*spec)));
      root.section(key.str()).check_keys(*spec);
      continue;
    }
    const toml::array* array = node.as_array();
    if (array == nullptr) root.wrong(key.str(), fmt::format("an array of tables {}", header(*spec)));
    for (std::size_t i = 0; i < array->size(); ++i) {
      const toml::node& item = *array->get(i);
      const std::string item_path = fmt::format("{}[{}]", spec->name, i);
      if (!item.is_table()) {
        fail(source, &item.source(), item_path,
             fmt::format("expected a table {}, got {}", header(*spec), describe(item)));
      }
      Section(root.context(), *item.as_table(), item_path).check_keys(*spec);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// The tables, one reader each.

Structure read_structure(const Section& s) {
  Structure st;
  st.kind = s.required_choice("kind", {StructureKind::beam, StructureKind::arch});
  st.bending_stiffness = s.required_number("EI", positive());
  st.theory = s.choice("theory", {Theory::linear, Theory::von_karman}).value_or(Theory::linear);
  // Arches under von Karman: the circular arch's Marguerre/Donnell form (fe/arch_von_karman_element.hpp),
  // EA required as for every arch; the ends' u is the support kind's (read_support_table).
  if (st.kind == StructureKind::beam) {
    for (const auto key : {"radius", "half_angle_deg"}) s.refuse(key, "for a beam (arches only)");
    st.length = s.required_number("length", positive());
    st.axial_stiffness = s.number("EA", positive());  // optional but under von Karman
    if (st.theory == Theory::von_karman && !st.axial_stiffness)
      s.missing("EA", "a number > 0 with theory = \"von_karman\": the membrane stiffness EA L^2/EI");
  } else {
    s.refuse("length", "for an arch (beams only; an arch has radius and half_angle_deg)");
    st.radius = s.required_number("radius", positive());
    st.half_angle_deg = s.required_number("half_angle_deg", {"an angle in degrees in (0, 180)", 0, 180, true, true});
    st.axial_stiffness = s.required_number("EA", positive());
  }
  // The numerics are nondimensional (model/member_model.hpp): K l^4/EI, P l^2/EI and EA R^2/EI must
  // be finite doubles, so the length scale's fourth power must neither overflow nor vanish.
  const double l = st.kind == StructureKind::beam ? st.length : st.radius;
  const double l4 = l * l * l * l, ratio = l4 / st.bending_stiffness;
  const char* key = st.kind == StructureKind::beam ? "length" : "radius";
  if (!std::isfinite(l4) || !(l4 > 0) || !std::isfinite(ratio) || !(ratio > 0))
    s.fail(key, fmt::format("expected a size whose fourth power over EI is a finite, nonzero double (the "
                            "nondimensional numbers K l^4/EI, P l^2/EI overflow), got {}",
                            l));
  if (st.kind == StructureKind::arch || st.theory == Theory::von_karman) {  // the membrane stiffness is read
    const double membrane = *st.axial_stiffness * l * l / st.bending_stiffness;
    if (!std::isfinite(membrane) || !(membrane > 0))
      s.fail("EA", fmt::format("expected EA {}^2/EI to be a finite, nonzero double, got EA = {}",
                               st.kind == StructureKind::arch ? "R" : "L", *st.axial_stiffness));
  }
  return st;
}

// An end's axial restraint by default: held at pinned and clamped ends, free at free and spring
// ends. Beams only: an arch's u is a discretisation unknown held or released by the end's kind.
bool axially_restrained_by_default(EndSupport kind, bool spring) {
  return !spring && (kind == EndSupport::pinned || kind == EndSupport::clamped);
}

// The table form of a support: { kind, stiffness, rotational_stiffness, settlement, axial } (ends)
// or { at, kind, ... } (interior points: kind pinned or spring; they hold w only). Returns the kind
// (free for a spring); `axially_restrained` (ends only) is the end's axial restraint, `axial` read
// only under von Karman theory.
EndSupport read_support_table(const Section& t, const Member& member, Theory theory, bool interior,
                              SupportDetail& detail, bool* axially_restrained = nullptr) {
  const std::string name = t.path("");
  const TableSpec spec{std::string_view(name).substr(0, name.size() - 1), false,
                       (interior ? nested::interior_support() : nested::end_support()).keys};
  t.check_keys(spec);
  const toml::node* kind_node = t.find("kind");
  const toml::value<std::string>* kind_text = kind_node != nullptr ? kind_node->as_string() : nullptr;
  const std::string expected = interior      ? R"("pinned" or "spring")"
                               : member.arch ? R"("spring", "pinned", "roller", "clamped" or "free")"
                                             : R"("spring", "pinned", "clamped" or "free")";
  if (kind_node == nullptr) t.missing("kind", expected);
  EndSupport kind = EndSupport::free;
  if (kind_text != nullptr && kind_text->get() == "spring") {
    detail.spring = true;
  } else if (interior) {
    if (kind_text == nullptr || kind_text->get() != "pinned") t.wrong("kind", expected);
    kind = EndSupport::pinned;
  } else {
    const std::string text = kind_text != nullptr ? kind_text->get() : std::string();
    if (text != "pinned" && text != "clamped" && text != "free" && text != "roller") t.wrong("kind", expected);
    const auto choice =
        member.arch ? t.choice("kind", {EndSupport::pinned, EndSupport::roller, EndSupport::clamped, EndSupport::free})
                    : t.choice("kind", {EndSupport::pinned, EndSupport::clamped, EndSupport::free},
                               {"roller", "for a beam, roller is the same as pinned"});
    kind = *choice;
  }
  const Range non_negative{"a number >= 0", 0.0, inf};
  if (detail.spring) {
    detail.stiffness = t.number("stiffness", non_negative).value_or(0.0);
    detail.rotational_stiffness = t.number("rotational_stiffness", non_negative).value_or(0.0);
    if (!(detail.stiffness > 0.0) && !(detail.rotational_stiffness > 0.0))
      t.fail(t.find("stiffness") != nullptr ? "stiffness" : "rotational_stiffness",
             "expected a spring with stiffness > 0 or rotational_stiffness > 0 (or both), got neither");
  } else {
    for (const auto key : {"stiffness", "rotational_stiffness"})
      t.refuse(key, fmt::format("on a support of kind \"{}\" (springs only: kind = \"spring\")", to_string(kind)));
  }
  if (kind == EndSupport::free && !detail.spring)
    t.refuse("settlement", "on a free end (a free end has no support to settle)");
  if (detail.spring && !(detail.stiffness > 0.0))
    t.refuse("settlement",
             "on a spring without translational stiffness (the settlement displaces the spring's far end along w)");
  detail.settlement = t.number("settlement", any_number()).value_or(0.0);
  if (axially_restrained == nullptr) return kind;
  *axially_restrained = axially_restrained_by_default(kind, detail.spring);
  const toml::node* axial = t.find("axial");
  if (axial == nullptr) return kind;
  if (member.arch)
    t.fail("axial", fmt::format("not allowed for an arch (an arch end's kind sets its tangential displacement u under "
                                "either theory: pinned and clamped hold u, roller and free release it; got kind "
                                "\"{}\")",
                                detail.spring ? "spring" : std::string(to_string(kind))));
  if (theory != Theory::von_karman)
    t.fail("axial", fmt::format("not allowed with theory = \"{}\" (an axial restraint acts only with theory = "
                                "\"von_karman\", [structure] theory: linear theory has no membrane strain)",
                                to_string(theory)));
  const toml::value<std::string>* text = axial->as_string();
  if (text == nullptr || (text->get() != "restrained" && text->get() != "free"))
    t.wrong("axial", R"("restrained" or "free")");
  if (text->get() == "restrained" && kind == EndSupport::free && !detail.spring)
    t.wrong("axial", R"("free" on a free end)", "nothing holds a free end axially; a spring end may be restrained");
  *axially_restrained = text->get() == "restrained";
  return kind;
}

Supports read_supports(const Section& s, const Member& member, Theory theory) {
  Supports sp;
  for (const auto& [key, end, detail, restrained] :
       {std::tuple{"left", &sp.left, &sp.left_detail, &sp.left_axially_restrained},
        std::tuple{"right", &sp.right, &sp.right_detail, &sp.right_axially_restrained}}) {
    if (const toml::node* node = s.find(key); node != nullptr && node->is_table()) {
      *end = read_support_table(s.section(key), member, theory, false, *detail, restrained);
      continue;
    }
    const auto support =
        member.arch ? s.choice(key, {EndSupport::pinned, EndSupport::roller, EndSupport::clamped, EndSupport::free})
                    : s.choice(key, {EndSupport::pinned, EndSupport::clamped, EndSupport::free},
                               {"roller", "for a beam, roller is the same as pinned"});
    if (!support) {
      s.missing(key, member.arch ? R"("pinned", "roller", "clamped" or "free", or a table { kind = ... })"
                                 : R"("pinned", "clamped" or "free", or a table { kind = ... })");
    }
    *end = *support;
    *restrained = axially_restrained_by_default(*end, false);
  }
  // interior: numbers (rigid points) or tables { at, kind = "pinned" | "spring", ... }.
  std::vector<std::pair<double, SupportDetail>> points;
  if (const toml::node* node = s.find("interior"); node != nullptr) {
    const toml::array* array = node->as_array();
    if (array == nullptr) s.wrong("interior", "an array of positions or tables { at = ..., kind = ... }");
    const Range inside = member.inside();
    for (std::size_t i = 0; i < array->size(); ++i) {
      const toml::node& item = *array->get(i);
      const std::string item_path = fmt::format("{}[{}]", s.path("interior"), i);
      SupportDetail detail;
      double at = 0.0;
      if (item.is_table()) {
        const Section t(s.context(), *item.as_table(), item_path);
        read_support_table(t, member, theory, true, detail);
        at = t.required_number("at", inside);
      } else {
        at = s.number_at(item, item_path, inside);
      }
      for (const auto& [earlier, unused] : points)
        if (std::abs(at - earlier) <= inside.tolerance)
          fail(s.source(), &item.source(), item_path, fmt::format("expected distinct positions, got {} twice", at));
      points.emplace_back(at, detail);
    }
  }
  std::sort(points.begin(), points.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  bool settles = false;
  for (const auto& [at, detail] : points) {
    if (detail.spring) {
      sp.interior_springs.push_back({at, detail});
      continue;
    }
    sp.interior.push_back(at);
    sp.interior_settlement.push_back(detail.settlement);
    settles = settles || detail.settlement != 0.0;
  }
  if (!settles) sp.interior_settlement.clear();
  return sp;
}

// The optional extent `from`..`to` of a foundation or a uniform load; the whole member by default.
std::pair<double, double> read_extent(const Section& s, const Member& member) {
  const double from = s.number("from", member.position()).value_or(member.begin);
  const double to = s.number("to", member.position()).value_or(member.end);
  if (!(from < to)) {
    s.fail(s.find("to") != nullptr ? "to" : "from",
           fmt::format("expected from < to, got from = {} and to = {}", from, to));
  }
  return {from, to};
}

// The key of a nondimensional modulus in `s`: `name` (nondimensional_k, tension_nondimensional_k),
// or its old name (k, tension_k), read with a warning that says what it is and what the
// dimensional K's key is: engineers call the subgrade modulus K "k", and k = 2.5e7 meant as
// N/m^2 used to be read, silently, as K L^4/EI. Both names at once: refused.
std::string_view renamed_key(const Section& s, std::string_view name, std::string_view old,
                             std::vector<std::string>& warnings) {
  const toml::node* node = s.find(old);
  if (node == nullptr) return name;
  if (s.find(name) != nullptr)
    s.fail(old, fmt::format("expected one of '{}' and '{}' (its old name), got both", name, old));
  warnings.push_back(fmt::format(
      "{}: '{}' is the old name of '{}' (K l^4/EI, nondimensional; l = L for a beam, R for an arch): read as {} "
      "= {}; the dimensional foundation modulus K (force per length per length) is 'modulus'",
      s.located(old), old, name, name, describe(*node)));
  return old;
}

// One [[foundation.segments]] entry: from < to inside the member, exactly one of nondimensional_k
// and modulus.
FoundationSegment read_segment(const Section& s, const Member& member, std::vector<std::string>& warnings) {
  s.check_keys(nested::foundation_segment());
  FoundationSegment piece;
  piece.from = s.required_number("from", member.position());
  piece.to = s.required_number("to", member.position());
  if (!(piece.from < piece.to))
    s.fail("to", fmt::format("expected from < to, got from = {} and to = {}", piece.from, piece.to));
  // A number, or [at from, at to] for a linear variation (equal ends: constant).
  auto value = [&](std::string_view key) -> std::optional<double> {
    const toml::node* node = s.find(key);
    if (node == nullptr || !node->is_array()) return s.number(key, positive());
    const char* expected = "a number > 0, or two numbers > 0 [at from, at to] for a linear variation";
    const std::vector<double> ends = s.number_array(key, positive(), expected);
    if (ends.size() != 2) s.wrong(key, expected);
    if (ends[1] != ends[0]) piece.at_to = ends[1];
    return ends[0];
  };
  const std::string_view k = renamed_key(s, "nondimensional_k", "k", warnings);
  piece.k = value(k);
  piece.modulus = value("modulus");
  if (piece.k && piece.modulus)
    s.fail("modulus", fmt::format("expected exactly one of '{}' and 'modulus', got both", k));
  if (!piece.k && !piece.modulus)
    s.missing("nondimensional_k", "exactly one of 'nondimensional_k' (K l^4/EI) and 'modulus' (K), a number > 0");
  return piece;
}

Foundation read_foundation_moduli(const Section& s, const Member& member, std::vector<std::string>& warnings);

// A ground-gap table's positions: non-decreasing, each at most twice (a step).
void check_gap_positions(const std::vector<double>& at, const std::function<void(std::string)>& fail) {
  for (std::size_t i = 1; i < at.size(); ++i) {
    if (at[i] < at[i - 1])
      fail(
          fmt::format("expected non-decreasing positions (a repeated one is a step), got at[{}] = {} after at[{}] = {}",
                      i, at[i], i - 1, at[i - 1]));
    if (i >= 2 && at[i] == at[i - 2])
      fail(fmt::format("expected each position at most twice (a step), got {} three times", at[i]));
  }
}

// `gap = { at = [...], value = [...] }`: at least one point; positions may lie beyond the member
// (g is constant beyond the table's ends).
void read_gap_table(const Section& s, Foundation& f) {
  const toml::node* node = s.find("gap");
  if (!node->is_table())
    s.wrong("gap", "a table { at = [...], value = [...] } of the ground's distance below the axis");
  const Section table(s.context(), *node->as_table(), s.path("gap"));
  table.check_keys(nested::foundation_gap());
  f.gap_at = table.number_array("at", any_number(), "a non-empty array of non-decreasing positions");
  check_gap_positions(f.gap_at, [&](const std::string& problem) { table.fail("at", problem); });
  f.gap_value = table.number_array("value", any_number(), "an array of gaps (length), one per position in 'at'");
  if (f.gap_value.size() != f.gap_at.size())
    table.fail("value", fmt::format("expected one value per position in 'at' ({}), got {}", f.gap_at.size(),
                                    f.gap_value.size()));
}

// `gap_file = "x.csv"` (relative to the scene's directory): two numbers a line, position and gap,
// separated by a comma, semicolon or whitespace; lines that do not start with a number (headers,
// blank lines) are skipped.
void read_gap_file(const Section& s, Foundation& f) {
  const toml::node* node = s.find("gap_file");
  if (!node->is_string() || node->as_string()->get().empty())
    s.wrong("gap_file", "the name of a two-column CSV file (position, gap)");
  f.gap_file = node->as_string()->get();
  std::filesystem::path file(f.gap_file);
  if (file.is_relative()) file = std::filesystem::path(s.source()).parent_path() / file;
  const std::string name = escaped(file.string());
  std::ifstream in(file);
  if (!in) s.fail("gap_file", fmt::format("cannot read {} ({})", name, std::strerror(errno)));
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    std::size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos) continue;
    const char c = line[first];
    if (!(std::isdigit(static_cast<unsigned char>(c)) || c == '-' || c == '+' || c == '.')) continue;  // a header
    std::string separated = line;
    for (char& ch : separated)
      if (ch == ',' || ch == ';' || ch == '\t' || ch == '\r') ch = ' ';
    std::istringstream fields(separated);
    double position = 0.0, gap = 0.0;
    std::string rest;
    if (!(fields >> position >> gap) || (fields >> rest) || !std::isfinite(position) || !std::isfinite(gap))
      s.fail("gap_file", fmt::format("{}:{}: expected two finite numbers (position, gap), got \"{}\"", name, number,
                                     escaped(line.substr(first))));
    f.gap_at.push_back(position);
    f.gap_value.push_back(gap);
  }
  if (in.bad()) s.fail("gap_file", fmt::format("cannot read {} ({})", name, std::strerror(errno)));
  if (f.gap_at.empty())
    s.fail("gap_file", fmt::format("{}: expected at least one line of two numbers, got none", name));
  check_gap_positions(f.gap_at,
                      [&](const std::string& problem) { s.fail("gap_file", fmt::format("{}: {}", name, problem)); });
}

// The ground gap and the bilinear foundation's tension modulus (after the compression moduli).
void read_gap_and_tension(const Section& s, Foundation& f, std::vector<std::string>& warnings) {
  if (s.find("gap") != nullptr && s.find("gap_file") != nullptr)
    s.fail("gap_file", "expected one of 'gap' and 'gap_file', got both");
  if (s.find("gap") != nullptr) read_gap_table(s, f);
  if (s.find("gap_file") != nullptr) read_gap_file(s, f);

  const Range non_negative{"a number >= 0", 0.0, inf};
  f.tension_modulus = s.number("tension_modulus", non_negative);
  const std::string_view tension_k = renamed_key(s, "tension_nondimensional_k", "tension_k", warnings);
  f.tension_k = s.number(tension_k, non_negative);
  if (!f.tension_modulus && !f.tension_k) return;
  const std::string_view key = f.tension_modulus ? "tension_modulus" : tension_k;
  if (f.tension_modulus && f.tension_k)
    s.fail(tension_k, fmt::format("expected one of 'tension_modulus' and '{}', got both", tension_k));
  if (!f.tensionless)
    s.fail(key, "not allowed with tensionless = false (a bilateral foundation resists tension with its full modulus)");
  // The compression moduli, of the kind the tension modulus must share.
  std::vector<FoundationSegment> compression = f.segments;
  if (f.segments.empty()) compression.push_back({f.from, f.to, f.k, f.modulus});
  const double tension = f.tension_modulus ? *f.tension_modulus : *f.tension_k;
  for (const FoundationSegment& piece : compression) {
    if (f.tension_modulus && !piece.modulus)
      s.fail(key,
             "expected 'tension_nondimensional_k' for a foundation given by 'nondimensional_k', got 'tension_modulus'");
    if (f.tension_k && !piece.k)
      s.fail(key, fmt::format("expected 'tension_modulus' for a foundation given by 'modulus', got '{}'", key));
    const double c = piece.k ? *piece.k : *piece.modulus;
    if (!piece.at_to && tension > c)
      s.fail(key, fmt::format("expected at most the compression modulus {} everywhere, got {}", c, tension));
    // A linear piece: the tensionless part k(s) - K_t must stay positive over it (at a point where it
    // vanished its flexibility 1/(k - K_t) would be infinite).
    if (piece.at_to && !(tension < std::min(c, *piece.at_to)))
      s.fail(key, fmt::format("expected below the compression modulus on a linear segment (its least value {}), got {}",
                              std::min(c, *piece.at_to), tension));
  }
}

Foundation read_foundation(const Section& s, const Member& member, std::vector<std::string>& warnings) {
  Foundation f = read_foundation_moduli(s, member, warnings);
  read_gap_and_tension(s, f, warnings);
  return f;
}

Foundation read_foundation_moduli(const Section& s, const Member& member, std::vector<std::string>& warnings) {
  Foundation f;
  f.tensionless = s.flag("tensionless").value_or(true);
  if (const toml::node* segments = s.find("segments"); segments != nullptr) {
    const toml::array* array = segments->as_array();
    if (array == nullptr || array->empty()) s.wrong("segments", "a non-empty array of tables [[foundation.segments]]");
    for (const auto key : {"nondimensional_k", "k", "modulus", "from", "to"})
      s.refuse(key, "together with [[foundation.segments]] (each segment gives its own extent and modulus)");
    std::vector<std::pair<FoundationSegment, std::size_t>> pieces;
    for (std::size_t i = 0; i < array->size(); ++i) {
      const toml::node& item = *array->get(i);
      const std::string path = s.path(fmt::format("segments[{}]", i));
      if (!item.is_table()) s.wrong("segments", "an array of tables [[foundation.segments]]");
      pieces.emplace_back(read_segment(Section(s.context(), *item.as_table(), path), member, warnings), i);
    }
    std::sort(pieces.begin(), pieces.end(), [](const auto& a, const auto& b) { return a.first.from < b.first.from; });
    for (std::size_t i = 1; i < pieces.size(); ++i) {
      const auto& [before, before_index] = pieces[i - 1];
      const auto& [after, after_index] = pieces[i];
      if (after.from < before.to - member.tolerance()) {
        const toml::node& item = *array->get(after_index);
        scene::fail(
            s.source(), &item.source(), s.path(fmt::format("segments[{}]", after_index)),
            fmt::format("expected segments that do not overlap, got [{}, {}] overlapping segments[{}] = [{}, {}]",
                        after.from, after.to, before_index, before.from, before.to));
      }
    }
    for (auto& [piece, index] : pieces) f.segments.push_back(piece);
    for (std::size_t i = 1; i < f.segments.size(); ++i)  // abutting within round-off: exactly
      if (f.segments[i].from < f.segments[i - 1].to) f.segments[i].from = f.segments[i - 1].to;
    f.from = f.segments.front().from;
    f.to = f.segments.back().to;
    return f;
  }
  const std::string_view k = renamed_key(s, "nondimensional_k", "k", warnings);
  f.k = s.number(k, positive());
  f.modulus = s.number("modulus", positive());
  if (f.k && f.modulus) {
    s.fail("modulus", fmt::format("expected exactly one of '{}' and 'modulus', got both", k));
  }
  if (!f.k && !f.modulus) {
    s.missing("nondimensional_k", "exactly one of 'nondimensional_k' (K l^4/EI) and 'modulus' (K), a number > 0");
  }
  std::tie(f.from, f.to) = read_extent(s, member);
  if (member.arch) {
    f.side = s.choice("side", {FoundationSide::inside, FoundationSide::outside}).value_or(f.side);
  } else {
    s.refuse("side", "for a beam (arches only: the foundation inside or outside the arch)");
  }
  return f;
}

// distributed: the tables at/value, piecewise linear; positions non-decreasing, at least two.
void read_distributed(const Section& s, const Member& member, Load& load) {
  for (const auto key : {"from", "to"})
    s.refuse(key, "for a distributed load (its table 'at' gives where it acts; zero outside the table)");
  const std::string positions = fmt::format("an array of at least two non-decreasing {}s in {}",
                                            member.arch ? "angle" : "position", member.interval(false));
  load.table_at = s.number_array("at", member.position(), positions);
  if (load.table_at.size() < 2) s.wrong("at", positions);
  for (std::size_t i = 1; i < load.table_at.size(); ++i) {
    if (load.table_at[i] < load.table_at[i - 1])
      s.fail("at", fmt::format("expected non-decreasing positions (a repeated one is a step), got at[{}] = {} after "
                               "at[{}] = {}",
                               i, load.table_at[i], i - 1, load.table_at[i - 1]));
    if (i >= 2 && load.table_at[i] == load.table_at[i - 2])
      s.fail("at", fmt::format("expected each position at most twice (a step), got {} three times", load.table_at[i]));
  }
  if (!(load.table_at.back() > load.table_at.front()))
    s.fail("at", "expected a table spanning a positive length, got all its positions equal");
  load.table_value = s.number_array("value", any_number(), "an array of numbers, one per position in 'at'");
  if (load.table_value.size() != load.table_at.size())
    s.fail("value", fmt::format("expected one value per position in 'at' ({}), got {}", load.table_at.size(),
                                load.table_value.size()));
}

// Arches: `direction` and `per` (a beam's loads are transverse, a moment has no direction). A
// uniform load is radial or vertical; a point force any of the four. `per` goes with vertical
// uniform loads only, and "projection" only where the arch is not steeper than vertical
// (|theta| <= 90 deg): below the springing the horizontal projection folds back on itself.
void read_load_direction(const Section& s, const Member& member, Load& load) {
  if (!member.arch) {
    for (const auto key : {"direction", "per"}) s.refuse(key, "for a beam (a beam's loads are transverse)");
    return;
  }
  if (load.kind == LoadKind::moment) {
    for (const auto key : {"direction", "per"}) s.refuse(key, "for a moment (it turns the arch in its plane)");
    return;
  }
  const bool spread = load.kind == LoadKind::uniform || load.kind == LoadKind::distributed;
  if (spread) {
    load.direction = s.choice("direction", {LoadDirection::radial, LoadDirection::vertical},
                              {"tangential", "a uniform or distributed load on an arch is radial or vertical"})
                         .value_or(LoadDirection::radial);
  } else {
    load.direction = s.choice("direction", {LoadDirection::radial, LoadDirection::tangential, LoadDirection::vertical,
                                            LoadDirection::horizontal})
                         .value_or(LoadDirection::radial);
  }
  if (!spread) {
    s.refuse("per", "for a point force (per goes with vertical uniform and distributed loads)");
    return;
  }
  if (load.direction != LoadDirection::vertical) {
    s.refuse("per", fmt::format("with direction = \"{}\" (per goes with direction = \"vertical\")",
                                to_string(load.direction)));
    return;
  }
  load.per = s.choice("per", {LoadBasis::arc, LoadBasis::projection}).value_or(LoadBasis::arc);
  const double from = load.kind == LoadKind::distributed ? load.table_at.front() : load.from;
  const double to = load.kind == LoadKind::distributed ? load.table_at.back() : load.to;
  if (load.per == LoadBasis::projection && (from < -90.0 || to > 90.0)) {
    s.fail("per", fmt::format("expected a load per unit horizontal projection within theta = -90..90 deg (where "
                              "the arch is not steeper than vertical), got a load on {} .. {}",
                              from, to));
  }
}

// `case`: "dead", "live" (the default) or a free name for [[combinations]] ("G", "Q", "W").
std::string read_case_name(const Section& s) {
  const toml::node* node = s.find("case");
  if (node == nullptr) return "live";
  const char* expected = "\"dead\", \"live\" or a load case name of letters, digits, '_' and '-' (\"G\", \"Q\")";
  if (!node->is_string()) s.wrong("case", expected);
  const std::string& name = node->as_string()->get();
  const bool word = !name.empty() && name.size() <= 64 && std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '-';
  });
  if (!word) s.wrong("case", expected);
  return name;
}

Load read_load(const Section& table, const Member& member) {
  Load load;
  load.kind =
      table.required_choice("kind", {LoadKind::force, LoadKind::moment, LoadKind::uniform, LoadKind::distributed,
                                     LoadKind::curvature, LoadKind::axial, LoadKind::temperature, LoadKind::sine});
  Context of_kind = table.context();  // the value's dimension is its kind's
  of_kind.load_kind = load.kind;
  const Section s = table.with(of_kind);
  if (load.kind == LoadKind::sine && member.arch)
    s.fail("kind",
           "expected \"force\", \"moment\", \"uniform\" or \"distributed\" for an arch, got \"sine\" (a sinusoidal "
           "load is supported on beams only)");
  if (load.kind == LoadKind::sine)
    load.half_waves = s.integer("n", 1, 1'000'000).value_or(1);
  else
    s.refuse("n", "but with kind = \"sine\" (the number of half-waves)");
  const bool axial = load.kind == LoadKind::axial || load.kind == LoadKind::temperature;
  if (axial && member.arch)
    s.fail("kind", fmt::format("expected \"force\", \"moment\", \"uniform\" or \"distributed\" for an arch, got \"{}\" "
                               "(an axial force is supported on beams only)",
                               to_string(load.kind)));
  if (load.kind != LoadKind::temperature) s.refuse("alpha", "but with kind = \"temperature\"");
  if (axial) {
    // Constant along the member: no position, no extent.
    const std::string why = fmt::format("for a {} load (it acts along the whole member)", to_string(load.kind));
    for (const auto key : {"at", "from", "to"}) s.refuse(key, why);
    load.value = s.required_number("value", any_number());
    if (load.kind == LoadKind::temperature) load.alpha = s.required_number("alpha", positive());
  } else if (load.kind == LoadKind::distributed) {
    read_distributed(s, member, load);
  } else if (load.kind == LoadKind::uniform || load.kind == LoadKind::curvature || load.kind == LoadKind::sine) {
    if (load.kind == LoadKind::curvature && member.arch)
      s.fail("kind",
             "expected \"force\", \"moment\", \"uniform\" or \"distributed\" for an arch, got "
             "\"curvature\" (an imposed curvature is supported on beams only)");
    s.refuse("at", fmt::format("for a {} load (it acts on from..to)", to_string(load.kind)));
    std::tie(load.from, load.to) = read_extent(s, member);
  } else {
    const std::string why = fmt::format("for a {} (it acts at one point, 'at')", to_string(load.kind));
    for (const auto key : {"from", "to"}) s.refuse(key, why);
    load.at = s.required_number("at", member.position());
  }
  if (load.kind != LoadKind::distributed && !axial) load.value = s.required_number("value", any_number());
  load.case_name = read_case_name(s);
  load.load_case = load.case_name == "dead" ? LoadCase::dead : LoadCase::live;
  read_load_direction(s, member, load);
  return load;
}

// ---------------------------------------------------------------------------------------------
// Load cases, [[combinations]] and [moving] (`liftoff envelope`).

// The most lead positions one [moving] table may give (each is a solve).
constexpr std::size_t max_moving_positions = 100'000;

// All the load cases the scene's loads and its moving group name, in order of appearance.
std::vector<std::string> case_names(const std::vector<Load>& loads, const std::optional<MovingLoads>& moving) {
  std::vector<std::string> names;
  const auto add = [&](const std::string& name) {
    if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  };
  for (const Load& load : loads) add(load.case_name);
  if (moving) add(moving->case_name);
  return names;
}

// [moving]: `loads`, an array of {kind = "force" | "moment", offset, value}; the lead positions
// as `positions` (ascending) or `from`, `to`, `step`; the group's `case`.
MovingLoads read_moving(const Section& s, const Member& member) {
  MovingLoads moving;
  moving.case_name = read_case_name(s);
  const toml::node* loads = s.find("loads");
  const char* expected_group =
      "a non-empty array of loads {kind = \"force\" or \"moment\", offset = <from the lead position>, value = ...}";
  if (loads == nullptr) s.missing("loads", expected_group);
  const toml::array* array = loads->as_array();
  if (array == nullptr || array->empty()) s.wrong("loads", expected_group);
  for (std::size_t i = 0; i < array->size(); ++i) {
    const toml::node& item = *array->get(i);
    const std::string item_path = fmt::format("moving.loads[{}]", i);
    if (!item.is_table())
      fail(s.source(), &item.source(), item_path,
           fmt::format("expected a table {{kind, offset, value}}, got {}", describe(item)));
    const Section one(s.context(), *item.as_table(), item_path);
    one.check_keys(nested::moving_load());
    Load load;
    load.kind = one.required_choice("kind", {LoadKind::force, LoadKind::moment});
    Context of_kind = s.context();  // the value's dimension is its kind's
    of_kind.load_kind = load.kind;
    const Section kind_known = one.with(of_kind);
    load.at = kind_known.required_number("offset", any_number());
    load.value = kind_known.required_number("value", any_number());
    load.case_name = moving.case_name;
    load.load_case = moving.case_name == "dead" ? LoadCase::dead : LoadCase::live;
    moving.group.push_back(load);
  }
  double lowest = inf, highest = -inf;
  for (const Load& load : moving.group) {
    lowest = std::min(lowest, load.at);
    highest = std::max(highest, load.at);
  }
  if (highest - lowest > member.end - member.begin)
    s.fail("loads", fmt::format("expected a group no longer than the member ({}), got offsets spanning {}",
                                member.end - member.begin, highest - lowest));
  // Lead positions that keep every load of the group on the member.
  const Range on_member{fmt::format("a lead position in [{}, {}] (every load of the group, at lead + offset, on the "
                                    "member {})",
                                    member.begin - lowest, member.end - highest, member.interval(false)),
                        member.begin - lowest,
                        member.end - highest,
                        false,
                        false,
                        member.tolerance()};
  if (s.find("positions") != nullptr) {
    for (const auto key : {"from", "to", "step"}) s.refuse(key, "with 'positions' (give one or the other)");
    moving.positions = s.number_array("positions", on_member, "a non-empty array of lead positions");
    if (!std::is_sorted(moving.positions.begin(), moving.positions.end()))
      s.wrong("positions", "lead positions in ascending order");
  } else {
    const double from = s.required_number("from", on_member);
    const Range above_from{fmt::format("a lead position in [from = {}, {}]", from, member.end - highest),
                           from,
                           member.end - highest,
                           false,
                           false,
                           member.tolerance()};
    const double to = s.required_number("to", above_from);
    const double step = s.required_number("step", positive());
    const double count = std::floor((to - from) / step + 1e-9) + 1.0;
    if (!(count <= static_cast<double>(max_moving_positions)))
      s.fail("step", fmt::format("expected at most {} lead positions, got {:.0f} from {} to {} by {}",
                                 max_moving_positions, count, from, to, step));
    for (int i = 0; i < static_cast<int>(count); ++i) moving.positions.push_back(std::min(from + i * step, to));
    // The last position is `to` itself when the step does not divide to - from: the group's end.
    if (to - moving.positions.back() > member.tolerance()) moving.positions.push_back(to);
  }
  if (moving.positions.size() > max_moving_positions)
    s.wrong("positions", fmt::format("at most {} lead positions", max_moving_positions));
  return moving;
}

Combination read_combination(const Section& s, const std::vector<std::string>& cases) {
  Combination c;
  const toml::node* name = s.find("name");
  if (name == nullptr) s.missing("name", "a non-empty string naming the combination (\"ULS\", \"SLS\")");
  if (!name->is_string() || name->as_string()->get().empty()) s.wrong("name", "a non-empty string");
  c.name = name->as_string()->get();
  const toml::node* factors = s.find("factors");
  const std::string expected = fmt::format("a table of partial factors by load case, e.g. {{ {} = 1.35 }}",
                                           cases.empty() ? std::string("G") : cases.front());
  if (factors == nullptr) s.missing("factors", expected);
  if (!factors->is_table() || factors->as_table()->empty()) s.wrong("factors", expected);
  const Section table = s.section("factors");
  std::vector<std::string_view> known(cases.begin(), cases.end());
  for (const auto& [key, node] : *factors->as_table()) {
    if (std::find(cases.begin(), cases.end(), key.str()) == cases.end())
      fail(s.source(), &key.source(), table.path(key.str()),
           fmt::format("unknown load case{}; the cases of this scene's loads are {}", suggestion(key.str(), known),
                       cases.empty() ? std::string("none") : joined(known)));
    const Range factor{"a partial factor >= 0", 0.0, inf};
    c.factors.emplace_back(std::string(key.str()), table.number_at(node, table.path(key.str()), factor));
  }
  return c;
}

SolveSettings read_solve(const Section& s) {
  SolveSettings solve;
  solve.method =
      s.choice("method", {Method::dual, Method::primal, Method::fast, Method::automatic, Method::ritz, Method::all})
          .value_or(solve.method);
  solve.elements = s.integer("elements", 1, 10'000'000).value_or(solve.elements);
  solve.tolerance = s.number("tolerance", tolerance_range());
  return solve;
}

RitzSettings read_ritz(const Section& s, const Foundation& foundation, const Member& member) {
  RitzSettings ritz;
  if (const toml::node* modes = s.find("modes"); modes != nullptr) {
    const auto* text = modes->as_string();
    if (text != nullptr && text->get() == "auto") {
      ritz.modes = 0;
    } else {
      if (text != nullptr) s.wrong("modes", "\"auto\" or an integer in [1, 1000]");
      ritz.modes = *s.integer("modes", 1, 1000);
    }
  }
  ritz.max_modes = s.integer("max_modes", 1, 1000).value_or(ritz.max_modes);
  ritz.mode_tolerance = s.number("mode_tolerance", positive()).value_or(ritz.mode_tolerance);

  if (const toml::node* topology = s.find("topology"); topology != nullptr) {
    const char* expected = "\"auto\" or an array of alternating \"contact\" and \"lift_off\"";
    const auto* text = topology->as_string();
    const auto* array = topology->as_array();
    if (text != nullptr && text->get() == "auto") {
      s.refuse("limits", "with topology = \"auto\" (the FE solution gives them)");
    } else {
      if (array == nullptr || array->empty()) s.wrong("topology", expected);
      for (std::size_t i = 0; i < array->size(); ++i) {
        const auto* piece = array->get(i)->as_string();
        if (piece == nullptr || (piece->get() != "contact" && piece->get() != "lift_off"))
          s.wrong("topology", expected);
        const bool contact = piece->get() == "contact";
        if (i > 0 && contact == ritz.topology.back()) s.wrong("topology", expected);
        ritz.topology.push_back(contact);
      }
      const Range inside{
          fmt::format("{} strictly inside the foundation ({}, {})", member.noun(), foundation.from, foundation.to),
          foundation.from,
          foundation.to,
          true,
          true,
          member.tolerance()};
      ritz.limits = s.numbers("limits", inside);
      if (!ritz.limits.empty() && ritz.limits.size() + 1 != ritz.topology.size())
        s.wrong("limits", fmt::format("{} increasing positions, one per change of piece", ritz.topology.size() - 1));
      if (!std::is_sorted(ritz.limits.begin(), ritz.limits.end())) s.wrong("limits", "increasing positions");
    }
  } else {
    s.refuse("limits", "without a topology");
  }
  return ritz;
}

// [trace]: everything is checked here, so a bad key is refused by `solve` too (it is the same
// file); only the absence of lambda_max is left to `liftoff trace`, the one command that needs it.
TraceSettings read_trace(const Section& s, const Member& member) {
  TraceSettings trace;
  trace.line = static_cast<int>(s.table().source().begin.line);
  trace.lambda_min = s.number("lambda_min", any_number()).value_or(trace.lambda_min);
  const Range above_min{fmt::format("a number > lambda_min = {}", trace.lambda_min), trace.lambda_min, inf, true};
  trace.lambda_max = s.number("lambda_max", above_min);
  trace.method =
      s.choice("method", {Method::dual, Method::primal, Method::fast, Method::automatic, Method::ritz, Method::all});
  trace.control = s.choice("control", {TraceControl::arc_length, TraceControl::load}).value_or(trace.control);
  if (trace.lambda_max) {  // the steps' defaults: fractions of the load range (TraceSettings)
    const double range = *trace.lambda_max - trace.lambda_min;
    trace.max_step *= range, trace.initial_step *= range, trace.min_step *= range;
  }
  trace.max_step = s.number("max_step", positive()).value_or(trace.max_step);
  const Range up_to_max{fmt::format("a number in (0, max_step = {}]", trace.max_step), 0.0, trace.max_step, true};
  trace.initial_step = std::min(trace.initial_step, trace.max_step);
  trace.initial_step = s.number("initial_step", up_to_max).value_or(trace.initial_step);
  const Range up_to_initial{fmt::format("a number in (0, initial_step = {}]", trace.initial_step), 0.0,
                            trace.initial_step, true};
  trace.min_step = std::min(trace.min_step, trace.initial_step);
  trace.min_step = s.number("min_step", up_to_initial).value_or(trace.min_step);
  trace.max_steps = s.integer("max_steps", 1, 100'000'000).value_or(trace.max_steps);
  trace.monitor = s.number("monitor", member.position());
  trace.samples = s.integer("samples", 2, 1'000'000).value_or(trace.samples);
  trace.refine = s.flag("refine").value_or(trace.refine);
  trace.max_amplitude = s.number("max_amplitude", positive());
  trace.switch_branch = s.flag("switch_branch").value_or(trace.switch_branch);
  if (const toml::node* node = s.find("report_at")) {
    trace.report_at = s.number_array("report_at", any_number(),
                                     "a non-empty array of numbers (loads in the live load's unit, or load factors "
                                     "where the live case mixes kinds)");
    trace.report_at_line = static_cast<int>(node->source().begin.line);
  }
  return trace;
}

// trace.report_at's dimension: the live loads' where they share one (and, for temperature rises,
// one alpha: app/trace_load.hpp's physical load), else none (load factors).
Dimension live_load_dimension(const std::vector<Load>& loads) {
  // Kinds of one physical quantity: the distributed ones together; a point force and an axial
  // force are both forces but not one quantity.
  const auto quantity = [](LoadKind k) {
    return k == LoadKind::distributed || k == LoadKind::sine ? LoadKind::uniform : k;
  };
  std::optional<LoadKind> shared;
  std::optional<double> alpha;
  for (const Load& load : loads) {
    if (load.load_case != LoadCase::live) continue;
    if (shared && *shared != quantity(load.kind)) return Dimension::none;
    if (load.kind == LoadKind::temperature) {
      if (alpha && *alpha != load.alpha) return Dimension::none;
      alpha = load.alpha;
    }
    shared = quantity(load.kind);
  }
  return shared ? load_value_dimension(*shared) : Dimension::none;
}

// [compare]: a published result to set beside the answer; `source` says where it comes from.
Comparison read_compare(const Section& s, const Structure& structure) {
  Comparison c;
  const toml::node* source = s.find("source");
  if (source == nullptr) s.missing("source", "a string naming where the value comes from");
  if (!source->is_string() || source->as_string()->get().empty()) s.wrong("source", "a non-empty string");
  c.source = source->as_string()->get();
  const Range half_angle{fmt::format("an angle in degrees in (0, half_angle_deg = {}]", structure.half_angle_deg), 0.0,
                         structure.half_angle_deg, true};
  c.contact_half_angle_deg = s.required_number("contact_half_angle_deg", half_angle);
  return c;
}

// [units]: system = "FORCE-LENGTH", or the free labels length and force; exactly one of the two
// ways. Labels only: nothing numeric depends on them.
Units read_units(const Section& s) {
  const bool labels = s.find("length") != nullptr || s.find("force") != nullptr;
  if (const toml::node* system = s.find("system"); system != nullptr) {
    if (labels)
      s.fail(s.find("length") != nullptr ? "length" : "force",
             "expected either 'system' or the labels 'length' and 'force', got both ways");
    const std::string expected = fmt::format("one of {}", unit_systems());
    if (!system->is_string()) s.wrong("system", expected);
    const std::optional<Units> units = units_of_system(system->as_string()->get());
    if (!units) s.wrong("system", expected, "or give free labels: length = \"m\", force = \"kN\"");
    return *units;
  }
  if (!labels) s.missing("system", fmt::format("one of {}, or the labels 'length' and 'force'", unit_systems()));
  Units units;
  for (const auto& [key, label] : {std::pair{"length", &units.length}, std::pair{"force", &units.force}}) {
    const char* expected = "a label of 1 to 32 printable characters (e.g. \"m\", \"kN\")";
    const toml::node* node = s.find(key);
    if (node == nullptr) s.missing(key, fmt::format("{}, with the other label", expected));
    const toml::value<std::string>* text = node->as_string();
    if (text == nullptr || text->get().empty() || text->get().size() > 32 ||
        std::any_of(text->get().begin(), text->get().end(),
                    [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; }))
      s.wrong(key, expected);
    *label = text->get();
  }
  return units;
}

// [geometry] initial_shape: a table { at = [...], value = [...] } (piecewise linear, positions
// non-decreasing) or a named shape { shape = "half_sine", amplitude } / { shape = "bump",
// amplitude, at, length }, sampled into the table (scene.hpp). Beams only.
InitialShape read_initial_shape(const Section& s, const Member& member) {
  InitialShape shape;
  const toml::node* node = s.find("initial_shape");
  if (node == nullptr) return shape;
  const char* expected =
      "a table { at = [...], value = [...] } or a named shape { shape = \"half_sine\", amplitude = a } or "
      "{ shape = \"bump\", amplitude = a, at = x0, length = l }";
  if (member.arch) s.fail("initial_shape", "not allowed for an arch (an initial shape is supported on beams only)");
  if (!node->is_table()) s.wrong("initial_shape", expected);
  const Section table(s.context(), *node->as_table(), s.path("initial_shape"));
  if (table.find("shape") == nullptr) {
    table.check_keys(nested::initial_shape_points());
    shape.shape = "table";
    shape.at = table.number_array("at", any_number(), "a non-empty array of increasing positions");
    for (std::size_t i = 1; i < shape.at.size(); ++i)  // the member has no steps
      if (!(shape.at[i] > shape.at[i - 1]))
        table.fail("at", fmt::format("expected increasing positions (the member has no steps), got at[{}] = {} after "
                                     "at[{}] = {}",
                                     i, shape.at[i], i - 1, shape.at[i - 1]));
    shape.value =
        table.number_array("value", any_number(), "an array of initial deflections (length), one per position in 'at'");
    if (shape.value.size() != shape.at.size())
      table.fail("value", fmt::format("expected one value per position in 'at' ({}), got {}", shape.at.size(),
                                      shape.value.size()));
    return shape;
  }
  const toml::node* name = table.find("shape");
  if (!name->is_string() || (name->as_string()->get() != "half_sine" && name->as_string()->get() != "bump"))
    table.wrong("shape", "\"half_sine\" or \"bump\"");
  shape.shape = name->as_string()->get();
  const double amplitude = table.required_number("amplitude", any_number());
  double from = member.begin, length = member.end - member.begin;
  if (shape.shape == "half_sine") {
    table.check_keys(nested::initial_shape_half_sine());
  } else {
    table.check_keys(nested::initial_shape_bump());
    const double centre = table.required_number("at", member.position());
    length = table.required_number("length", positive());
    from = centre - 0.5 * length;
    if (from < member.begin - member.tolerance() || from + length > member.end + member.tolerance())
      table.fail("length", fmt::format("expected a bump within the member {}, got {} .. {}", member.interval(false),
                                       from, from + length));
  }
  shape.amplitude = amplitude;
  shape.from = from;
  shape.length = length;
  for (int i = 0; i <= initial_shape_samples; ++i) {
    const double t = static_cast<double>(i) / initial_shape_samples;
    shape.at.push_back(i == initial_shape_samples ? from + length : from + t * length);
    shape.value.push_back(i == 0 || i == initial_shape_samples ? 0.0 : amplitude * std::sin(std::numbers::pi * t));
  }
  return shape;
}

}  // namespace

Scene parse_scene(std::string_view toml_text, std::string source_name) {
  Scene scene;
  scene.source_name = std::move(source_name);
  scene.text = std::string(toml_text);
  const std::string& source = scene.source_name;

  toml::table document;
  try {
    document = toml::parse(scene.text, std::string_view(source));
  } catch (const toml::parse_error& e) {
    std::string description(e.description());
    std::replace(description.begin(), description.end(), '\n', ' ');
    std::replace(description.begin(), description.end(), '\r', ' ');
    throw InputError(fmt::format("{}:{}:{}: TOML syntax error: {}", source, e.source().begin.line,
                                 e.source().begin.column, description));
  }

  Context context;  // [units] first: every number written with its unit is converted to them
  context.source = source;
  context.with_unit = &scene.given_with_unit;
  const Section root(context, document, "");
  check_schema(root, source);
  if (root.find("units") != nullptr) context.units = scene.units = read_units(root.section("units"));
  scene.structure = read_structure(root.required_section("structure"));
  const Member member{scene.begin(), scene.end(), scene.structure.kind == StructureKind::arch};
  context.arch = member.arch;
  scene.supports = read_supports(root.required_section("supports"), member, scene.structure.theory);
  scene.foundation = read_foundation(root.required_section("foundation"), member, scene.warnings);
  if (const toml::node* loads = root.find("loads")) {
    const toml::array& array = *loads->as_array();  // the shape is checked above
    for (std::size_t i = 0; i < array.size(); ++i) {
      const Section load(context, *array.get(i)->as_table(), fmt::format("loads[{}]", i));
      scene.loads.push_back(read_load(load, member));
      const Load& read = scene.loads.back();
      if ((read.kind == LoadKind::axial || read.kind == LoadKind::temperature) &&
          scene.structure.theory == Theory::von_karman)
        load.wrong("kind", "a transverse load with theory = \"von_karman\"",
                   "a given axial force and the membrane force from the deflection are not combined yet");
      if (read.kind == LoadKind::temperature && !scene.structure.axial_stiffness)
        load.fail("kind",
                  "expected [structure] EA for a temperature load (N = EA alpha dT of a fully axially "
                  "restrained member), got none");
      // The numerics see P L^2/EI (model/member_model.hpp).
      const double scaled = read.axial_force(scene.structure) * scene.structure.length * scene.structure.length /
                            scene.structure.bending_stiffness;
      if (!std::isfinite(scaled))
        load.fail("value", fmt::format("expected an axial force whose P L^2/EI is finite, got P = {}",
                                       read.axial_force(scene.structure)));
    }
  }
  if (root.find("geometry") != nullptr) scene.initial_shape = read_initial_shape(root.section("geometry"), member);
  scene.solve = read_solve(root.section("solve"));
  scene.ritz = read_ritz(root.section("ritz"), scene.foundation, member);
  context.live_load = live_load_dimension(scene.loads);
  if (root.find("trace") != nullptr) scene.trace = read_trace(root.section("trace"), member);
  if (root.find("compare") != nullptr) {
    if (!member.arch) root.refuse("compare", "for a beam (arches only: the contact half-angle around the crown)");
    scene.compare = read_compare(root.section("compare"), scene.structure);
  }
  if (root.find("moving") != nullptr) scene.moving = read_moving(root.section("moving"), member);
  if (const toml::node* combinations = root.find("combinations")) {
    const std::vector<std::string> cases = case_names(scene.loads, scene.moving);
    const toml::array& array = *combinations->as_array();  // the shape is checked above
    for (std::size_t i = 0; i < array.size(); ++i) {
      const Section c(context, *array.get(i)->as_table(), fmt::format("combinations[{}]", i));
      scene.combinations.push_back(read_combination(c, cases));
      for (std::size_t j = 0; j < i; ++j)
        if (scene.combinations[j].name == scene.combinations[i].name)
          c.wrong("name", fmt::format("a name not used by an earlier combination (combinations[{}])", j));
    }
  }
  return scene;
}

Scene read_scene_file(const std::filesystem::path& path) {
  const std::string name = escaped(path.string());  // messages stay on one line whatever the name
  const auto cannot_read = [&] {
    return InputError(fmt::format("{}: cannot read the scene file ({})", name, std::strerror(errno)));
  };
  const std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!file) throw cannot_read();
  std::string text;
  char buffer[1 << 16];
  while (const std::size_t n = std::fread(buffer, 1, sizeof buffer, file.get())) {
    text.append(buffer, n);
  }
  if (std::ferror(file.get())) throw cannot_read();
  return parse_scene(text, name);
}

}  // namespace liftoff::scene
