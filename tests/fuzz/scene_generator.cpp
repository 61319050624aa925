#include "fuzz/scene_generator.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace liftoff::fuzz {

// ---------------------------------------------------------------------------------------------
// Random

std::uint64_t Random::next() {
  std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

double Random::uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
double Random::uniform(double a, double b) { return a + (b - a) * uniform(); }
double Random::log_uniform(double a, double b) { return a * std::pow(b / a, uniform()); }
int Random::integer(int lo, int hi) { return lo + static_cast<int>(next() % static_cast<std::uint64_t>(hi - lo + 1)); }

// ---------------------------------------------------------------------------------------------
// Draft

Table* Draft::find(std::string_view name) {
  for (Table& t : tables)
    if (t.name == name) return &t;
  return nullptr;
}

Entry* Draft::find(std::string_view table, std::string_view key) {
  if (Table* t = find(table))
    for (Entry& e : t->entries)
      if (e.key == key) return &e;
  return nullptr;
}

bool Draft::has(std::string_view table, std::string_view key) const {
  for (const Table& t : tables)
    if (t.name == table &&
        (key.empty() || std::any_of(t.entries.begin(), t.entries.end(), [&](const Entry& e) { return e.key == key; })))
      return true;
  return false;
}

std::string Draft::text() const {
  std::string out;
  for (const Table& t : tables) {
    out += t.array ? fmt::format("[[{}]]\n", t.name) : fmt::format("[{}]\n", t.name);
    for (const Entry& e : t.entries) out += fmt::format("{} = {}\n", e.key, e.value);
    out += "\n";
  }
  return out;
}

std::string toml_number(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  std::string s = fmt::format("{}", x);
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s;
}

namespace {

std::string quoted(std::string_view s) { return fmt::format("\"{}\"", s); }

// A number as a user writes it: mostly a float, sometimes an integer when it is one.
std::string written(Random& random, double x) {
  if (random.chance(0.15)) {
    const double r = std::round(x);
    if (r != 0.0 && std::abs(r) < 1e15) return fmt::format("{}", static_cast<long long>(r));
  }
  return toml_number(x);
}

// A position in [begin, end]: anywhere, at an end, mid-member, on a simple fraction (a likely
// node), or at one of `special` (supports and other loads).
double position(Random& random, double begin, double end, const std::vector<double>& special) {
  const double span = end - begin;
  const int choice = random.integer(0, 9);
  if (choice == 0) return begin;
  if (choice == 1) return end;
  if (choice == 2) return begin + 0.5 * span;
  if (choice == 3) return begin + span * random.integer(1, 7) / 8.0;
  if (choice == 4 && !special.empty()) return random.pick(special);
  return random.uniform(begin, end);
}

// An extent from < to inside [begin, end] (an end or all of it, sometimes).
std::pair<double, double> extent(Random& random, double begin, double end) {
  const double span = end - begin;
  double from = random.chance(0.3) ? begin : random.uniform(begin, begin + 0.6 * span);
  double to = random.chance(0.3) ? end : random.uniform(from + 0.05 * span, end);
  if (!(from < to)) to = end;
  return {from, to};
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Valid scenes

Draft valid_scene(Random& random, const SceneLimits& limits) {
  Draft d;
  d.arch = random.chance(0.3);
  Table structure{"structure", false, {}};
  double force_scale = 1.0, length_scale = 1.0;
  const double EI = random.log_uniform(1e-2, 1e9);
  if (d.arch) {
    const double radius = random.log_uniform(0.5, 500.0);
    const double gamma = random.chance(0.1) ? random.uniform(120.0, 179.0) : random.uniform(2.0, 90.0);
    d.begin = -gamma;
    d.end = gamma;
    // EA R^2 / EI from 10 (thick) to 1e7 (thin: locking territory)
    const double EA = EI / (radius * radius) * random.log_uniform(10.0, 1e7);
    structure.entries = {{"kind", quoted("arch"), Type::name},
                         {"radius", written(random, radius)},
                         {"half_angle_deg", toml_number(gamma)},
                         {"EI", written(random, EI)},
                         {"EA", written(random, EA)}};
    length_scale = radius * gamma * M_PI / 180.0;
  } else {
    const double length = random.log_uniform(0.05, 500.0);
    d.begin = 0.0;
    d.end = length;
    structure.entries = {{"kind", quoted("beam"), Type::name},
                         {"length", toml_number(length)},  // exact: positions depend on it
                         {"EI", written(random, EI)}};
    if (random.chance(0.1)) structure.entries.push_back({"EA", written(random, EI * random.log_uniform(10, 1e6))});
    length_scale = length;
  }
  if (random.chance(0.3)) std::swap(structure.entries[1], structure.entries.back());  // key order is free
  force_scale = EI / (length_scale * length_scale);
  d.tables.push_back(structure);

  // Supports, with interior points strictly inside.
  const std::vector<std::string> ends = d.arch ? std::vector<std::string>{"pinned", "roller", "clamped", "free"}
                                               : std::vector<std::string>{"pinned", "clamped", "free"};
  Table supports{"supports", false, {}};
  supports.entries.push_back({"left", quoted(random.pick(ends)), Type::name});
  supports.entries.push_back({"right", quoted(random.pick(ends)), Type::name});
  // Issue 12: an end as a table, a spring (a free end's) or a settlement (a supported end's).
  for (Entry& end : supports.entries) {
    if (!random.chance(0.15)) continue;
    const std::string kind = end.value.substr(1, end.value.size() - 2);
    const std::string settlement =
        toml_number((random.chance(0.5) ? 1.0 : -1.0) * random.log_uniform(1e-6, 1e-3) * length_scale);
    if (kind == "free")
      end.value = "{ kind = \"spring\", stiffness = " +
                  toml_number(random.log_uniform(1e-2, 1e4) * force_scale / length_scale) +
                  (random.chance(0.4) ? ", rotational_stiffness = " +
                                            toml_number(random.log_uniform(1e-2, 1e3) * force_scale * length_scale)
                                      : "") +
                  (random.chance(0.3) ? ", settlement = " + settlement : "") + " }";
    else
      end.value = "{ kind = " + end.value + ", settlement = " + settlement + " }";
  }
  std::vector<double> interior;
  if (random.chance(d.arch ? 0.1 : 0.15)) {
    const int n = random.integer(1, 2);
    for (int i = 0; i < n; ++i) {
      const double x = random.chance(0.3)
                           ? d.begin + 0.5 * (d.end - d.begin)
                           : random.uniform(d.begin + 0.05 * (d.end - d.begin), d.end - 0.05 * (d.end - d.begin));
      if (std::none_of(interior.begin(), interior.end(),
                       [&](double y) { return std::abs(x - y) < 1e-3 * (d.end - d.begin); }))
        interior.push_back(x);
    }
    std::string list;
    for (double x : interior)  // issue 12: some as tables, elastic or settled
      list += (list.empty() ? "" : ", ") +
              (random.chance(0.7)   ? toml_number(x)
               : random.chance(0.5) ? "{ at = " + toml_number(x) + ", kind = \"spring\", stiffness = " +
                                          toml_number(random.log_uniform(1e-2, 1e4) * force_scale / length_scale) + " }"
                                    : "{ at = " + toml_number(x) + ", kind = \"pinned\", settlement = " +
                                          toml_number(random.log_uniform(1e-6, 1e-3) * length_scale) + " }");
    supports.entries.push_back({"interior", "[" + list + "]", Type::positions});
  }
  d.tables.push_back(supports);

  // Foundation: k or modulus, all or part of the member.
  Table foundation{"foundation", false, {}};
  const double k = random.log_uniform(1e-1, 1e9);
  if (random.chance(0.6))
    foundation.entries.push_back({"nondimensional_k", written(random, k)});
  else
    foundation.entries.push_back({"modulus", written(random, k * EI / std::pow(length_scale, 4))});
  if (random.chance(0.3))
    foundation.entries.push_back({"tensionless", random.chance(0.8) ? "true" : "false", Type::flag});
  if (d.arch && random.chance(0.25))  // issue 12: soil around the extrados (a buried arch)
    foundation.entries.push_back({"side", quoted(random.chance(0.8) ? "outside" : "inside"), Type::name});
  double f_from = d.begin, f_to = d.end;
  if (random.chance(0.25)) {
    std::tie(f_from, f_to) = extent(random, d.begin, d.end);
    if (f_from != d.begin || random.chance(0.3)) foundation.entries.push_back({"from", toml_number(f_from)});
    if (f_to != d.end || random.chance(0.3)) foundation.entries.push_back({"to", toml_number(f_to)});
  }
  if (random.chance(0.15)) {  // issue 12: a ground gap (a trench or a hump), sometimes with a step
    const double span = d.end - d.begin, depth = random.log_uniform(1e-5, 1e-2) * length_scale;
    const double a = d.begin + random.uniform(0.0, 0.5) * span, b = a + random.uniform(0.0, 0.5) * span;
    const std::string g = written(random, random.chance(0.5) ? depth : -depth);
    const std::string table = random.chance(0.3) ? "{ at = [" + toml_number(a) + "], value = [" + g + "] }"
                                                 : "{ at = [" + toml_number(a) + ", " + toml_number(a) + ", " +
                                                       toml_number(b) + "], value = [0.0, " + g + ", " + g + "] }";
    foundation.entries.push_back({"gap", table, Type::positions});
  }
  const bool bilateral = std::any_of(foundation.entries.begin(), foundation.entries.end(),
                                     [](const Entry& e) { return e.key == "tensionless" && e.value == "false"; });
  if (!bilateral && random.chance(0.1)) {  // issue 12: the bilinear foundation, at most the compression modulus
    const bool by_k = foundation.entries.front().key == "nondimensional_k";
    const double fraction = random.chance(0.2) ? 1.0 : random.uniform(0.0, 1.0);
    foundation.entries.push_back({by_k ? "tension_nondimensional_k" : "tension_modulus",
                                  toml_number(fraction * (by_k ? k : k * EI / std::pow(length_scale, 4)))});
  }
  // Issue 12: sometimes the foundation as [[foundation.segments]] instead: pieces with voids
  // between them, abutting ones sharing an end exactly, k or modulus, constant or linear
  // [at from, at to], listed in any order.
  std::vector<Table> segments;
  std::vector<double> piece_ends;
  if (random.chance(0.25)) {
    std::erase_if(foundation.entries, [](const Entry& e) {
      return e.key == "nondimensional_k" || e.key == "modulus" || e.key == "from" || e.key == "to" ||
             e.key == "tension_nondimensional_k" || e.key == "tension_modulus";  // a tension key names the pieces' kind
    });
    const double span = d.end - d.begin;
    std::vector<double> at{d.begin, d.end};
    for (int i = random.integer(1, 4); i > 0; --i) {
      const double x = random.chance(0.3) ? d.begin + span * random.integer(1, 7) / 8.0
                                          : random.uniform(d.begin + 0.02 * span, d.end - 0.02 * span);
      if (std::none_of(at.begin(), at.end(), [&](double y) { return std::abs(x - y) < 1e-3 * span; })) at.push_back(x);
    }
    std::sort(at.begin(), at.end());
    for (std::size_t i = 0; i + 1 < at.size(); ++i) {
      if (!random.chance(0.7) && !(i + 2 == at.size() && segments.empty())) continue;  // a void
      Table piece{"foundation.segments", true, {{"from", toml_number(at[i])}, {"to", toml_number(at[i + 1])}}};
      const double k_here = k * random.log_uniform(0.1, 10.0);
      const bool modulus = random.chance(0.4);
      const double scale = modulus ? EI / std::pow(length_scale, 4) : 1.0;
      std::string value = written(random, k_here * scale);
      if (random.chance(0.35))
        value = "[" + value + ", " + written(random, k_here * random.log_uniform(0.2, 5.0) * scale) + "]";
      piece.entries.push_back({modulus ? "modulus" : "nondimensional_k", value});
      if (random.chance(0.2)) std::reverse(piece.entries.begin(), piece.entries.end());
      segments.push_back(piece);
      piece_ends.push_back(at[i]);
      piece_ends.push_back(at[i + 1]);
    }
    f_from = piece_ends.front();
    f_to = piece_ends.back();
    if (random.chance(0.4)) std::reverse(segments.begin(), segments.end());
  }
  d.tables.push_back(foundation);
  for (const Table& piece : segments) d.tables.push_back(piece);

  // Loads: every kind and case, often at special points.
  const int loads = random.chance(0.05) ? 0 : random.integer(1, 4);
  std::vector<double> special = interior;
  special.push_back(f_from);
  special.push_back(f_to);
  special.insert(special.end(), piece_ends.begin(), piece_ends.end());
  for (int i = 0; i < loads; ++i) {
    Table load{"loads", true, {}};
    const int kind = random.integer(0, 9);
    const double sign = random.chance(0.75) ? 1.0 : -1.0;
    const double size = random.log_uniform(1e-3, 1e3) * (random.chance(0.5) ? force_scale : 1.0);
    if (kind < 5) {
      const double at = position(random, d.begin, d.end, special);
      special.push_back(at);
      load.entries = {
          {"kind", quoted("force"), Type::name}, {"at", toml_number(at)}, {"value", written(random, sign * size)}};
      if (d.arch && random.chance(0.3))  // issue 12: a point force on an arch in any direction
        load.entries.push_back(
            {"direction",
             quoted(random.pick(std::vector<std::string>{"radial", "tangential", "vertical", "horizontal"})),
             Type::name});
    } else if (kind < 7) {
      const double at = position(random, d.begin, d.end, special);
      special.push_back(at);
      load.entries = {{"kind", quoted("moment"), Type::name},
                      {"at", toml_number(at)},
                      {"value", written(random, (random.chance(0.5) ? 1 : -1) * size * length_scale)}};
    } else if (kind == 7 && random.chance(0.5)) {  // a piecewise-linear table, sometimes with a step
      const int points = random.integer(2, 5);
      std::vector<double> at;
      for (int j = 0; j < points; ++j) at.push_back(random.uniform(d.begin, d.end));
      std::sort(at.begin(), at.end());
      if (points >= 3 && random.chance(0.3)) at[2] = at[1];  // a step
      if (random.chance(0.3)) at.front() = d.begin;
      if (random.chance(0.3)) at.back() = d.end;
      if (!(at.back() > at.front())) at.back() = d.end, at.front() = d.begin;
      std::string at_list, value_list;
      for (int j = 0; j < points; ++j) {
        at_list += (j > 0 ? ", " : "") + toml_number(at[j]);
        value_list += (j > 0 ? ", " : "") + toml_number(sign * size / length_scale * random.uniform(0.0, 2.0));
      }
      load.entries = {{"kind", quoted("distributed"), Type::name},
                      {"at", "[" + at_list + "]", Type::positions},
                      {"value", "[" + value_list + "]", Type::positions}};
    } else if (kind == 8 && !d.arch && random.chance(0.3)) {  // an imposed curvature (beams)
      load.entries = {{"kind", quoted("curvature"), Type::name},
                      {"value", written(random, (random.chance(0.5) ? 1 : -1) * size / length_scale)}};
      if (random.chance(0.4)) {
        const auto [from, to] = extent(random, d.begin, d.end);
        load.entries.push_back({"from", toml_number(from)});
        load.entries.push_back({"to", toml_number(to)});
      }
    } else {
      load.entries = {{"kind", quoted("uniform"), Type::name}, {"value", written(random, sign * size / length_scale)}};
      double from = d.begin, to = d.end;
      if (random.chance(0.4)) {
        std::tie(from, to) = extent(random, d.begin, d.end);
        load.entries.push_back({"from", toml_number(from)});
        load.entries.push_back({"to", toml_number(to)});
      }
      if (d.arch && random.chance(0.3)) {  // issue 12: gravity on an arch, per arc or per projection
        load.entries.push_back({"direction", quoted(random.chance(0.8) ? "vertical" : "radial"), Type::name});
        const bool vertical = load.entries.back().value == quoted("vertical");
        if (vertical && random.chance(0.6))  // per unit projection only within |theta| <= 90 deg
          load.entries.push_back(
              {"per", quoted(from >= -90.0 && to <= 90.0 && random.chance(0.7) ? "projection" : "arc"), Type::name});
      }
    }
    const int load_case = random.integer(0, 9);
    if (load_case >= 5) load.entries.push_back({"case", quoted(load_case >= 7 ? "dead" : "live"), Type::name});
    if (random.chance(0.2)) std::reverse(load.entries.begin(), load.entries.end());
    d.tables.push_back(load);
  }

  const std::vector<std::string> methods{"dual", "primal", "fast", "auto", "ritz", "all"};
  if (random.chance(0.7)) {
    Table solve{"solve", false, {}};
    if (random.chance(0.7)) solve.entries.push_back({"method", quoted(random.pick(methods)), Type::name});
    if (random.chance(0.8))
      solve.entries.push_back({"elements",
                               std::to_string(static_cast<int>(random.log_uniform(1.0, limits.max_elements + 1.0))),
                               Type::integer});
    d.tables.push_back(solve);
  }

  // [ritz]: always cheap when present (auto modes stop at 32).
  if (random.chance(limits.ritz_cheap ? 0.85 : 0.4)) {
    Table ritz{"ritz", false, {}};
    if (random.chance(0.6)) {
      ritz.entries.push_back({"modes", std::to_string(random.integer(1, 16)), Type::modes});
    } else {
      ritz.entries.push_back({"modes", quoted("auto"), Type::modes});
      ritz.entries.push_back({"max_modes", std::to_string(random.integer(4, 32)), Type::integer});
      if (random.chance(0.5))
        ritz.entries.push_back({"mode_tolerance", written(random, random.log_uniform(1e-8, 1e-2))});
    }
    if (random.chance(0.15)) {
      const int pieces = random.integer(1, 3);
      bool contact = random.chance(0.6);
      std::string topology;
      for (int i = 0; i < pieces; ++i, contact = !contact)
        topology += (i ? ", " : "") + quoted(contact ? "contact" : "lift_off");
      ritz.entries.push_back({"topology", "[" + topology + "]", Type::pieces});
      if (pieces > 1 && random.chance(0.6)) {
        std::string list;
        for (int i = 1; i < pieces; ++i)
          list += (i > 1 ? ", " : "") + toml_number(f_from + (f_to - f_from) * i / pieces);
        ritz.entries.push_back({"limits", "[" + list + "]", Type::positions});
      }
    } else if (random.chance(0.2)) {
      ritz.entries.push_back({"topology", quoted("auto"), Type::pieces});
    }
    d.tables.push_back(ritz);
  }

  if (limits.trace || random.chance(0.15)) {
    Table trace{"trace", false, {}};
    const double lambda_min = random.chance(0.7) ? 0.0 : random.uniform(-1.0, 0.5);
    if (lambda_min != 0.0 || random.chance(0.2)) trace.entries.push_back({"lambda_min", toml_number(lambda_min)});
    trace.entries.push_back({"lambda_max", toml_number(lambda_min + random.uniform(0.2, 4.0))});
    if (random.chance(0.5)) trace.entries.push_back({"method", quoted(random.pick(methods)), Type::name});
    if (random.chance(0.2))
      trace.entries.push_back({"control", quoted(random.chance(0.5) ? "load" : "arc_length"), Type::name});
    if (random.chance(0.3)) {
      const double max_step = random.uniform(0.05, 0.5), initial = random.uniform(0.01, 1.0) * max_step;
      trace.entries.push_back({"max_step", toml_number(max_step)});
      trace.entries.push_back({"initial_step", toml_number(initial)});
      trace.entries.push_back({"min_step", toml_number(initial * random.log_uniform(1e-8, 1.0))});
    }
    trace.entries.push_back(
        {"max_steps", std::to_string(random.integer(5, limits.ritz_trace ? 60 : 300)), Type::integer});
    if (random.chance(0.3))
      trace.entries.push_back({"monitor", toml_number(position(random, d.begin, d.end, special))});
    if (random.chance(0.4)) trace.entries.push_back({"samples", std::to_string(random.integer(2, 201)), Type::integer});
    if (random.chance(0.1)) trace.entries.push_back({"refine", "true", Type::flag});
    d.tables.push_back(trace);
  }
  // The tables in any order, now and then.
  if (random.chance(0.1)) std::reverse(d.tables.begin(), d.tables.end());
  return d;
}

// ---------------------------------------------------------------------------------------------
// Mutations

namespace {

const std::map<std::string, std::vector<std::string>>& schema_keys() {
  static const std::map<std::string, std::vector<std::string>> keys = {
      {"structure", {"kind", "length", "radius", "half_angle_deg", "EI", "EA"}},
      {"supports", {"left", "right", "interior"}},
      {"foundation",
       {"nondimensional_k", "modulus", "tensionless", "from", "to", "side", "gap", "gap_file", "tension_modulus",
        "tension_nondimensional_k"}},
      {"foundation.segments", {"from", "to", "nondimensional_k", "modulus"}},
      {"loads", {"kind", "at", "value", "from", "to", "case", "direction", "per"}},
      {"solve", {"method", "elements"}},
      {"ritz", {"modes", "max_modes", "mode_tolerance", "topology", "limits"}},
      {"trace",
       {"lambda_max", "lambda_min", "method", "control", "initial_step", "min_step", "max_step", "max_steps", "monitor",
        "samples", "refine"}},
  };
  return keys;
}

struct Place {
  Table* table;
  Entry* entry;
};

std::vector<Place> entries(Draft& d) {
  std::vector<Place> places;
  for (Table& t : d.tables)
    for (Entry& e : t.entries) places.push_back({&t, &e});
  return places;
}

std::vector<Place> entries_of(Draft& d, Type type) {
  std::vector<Place> places;
  for (const Place& p : entries(d))
    if (p.entry->type == type) places.push_back(p);
  return places;
}

std::string random_bytes(Random& random, int n) {
  std::string s;
  for (int i = 0; i < n; ++i) s += static_cast<char>(random.next() & 0xff);
  return s;
}

// A name that no table of the schema holds: a typo of a real key, or something else.
std::string unknown_key(Random& random, const std::string& table) {
  const auto& known = schema_keys().at(table);
  for (int attempt = 0; attempt < 20; ++attempt) {
    std::string key = random.pick(known);
    switch (random.integer(0, 4)) {
      case 0:
        key += "s";
        break;
      case 1:
        if (key.size() > 2) std::swap(key[1], key[2]);
        break;
      case 2:
        for (char& c : key) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
        break;
      case 3:
        key = random.pick(std::vector<std::string>{"colour", "x", "load", "Length", "tension_less", "k_"});
        break;
      default:
        key = "\"" + key + " \"";
        break;  // a quoted key with a trailing blank
    }
    if (std::find(known.begin(), known.end(), key) == known.end()) return key;
  }
  return "no_such_key";
}

// A value of another type than the key holds.
std::string wrong_type(Random& random, Type type) {
  switch (type) {
    case Type::number:
      return random.pick(std::vector<std::string>{"\"1.0\"", "true", "[1.0]", "{ a = 1 }", "1979-05-27", "07:32:00"});
    case Type::integer:
      return random.pick(std::vector<std::string>{"2.5", "10.0", "\"10\"", "true", "[10]", "1e3"});
    case Type::name:
      return random.pick(
          std::vector<std::string>{"1", "true", "[\"beam\"]", "\"bogus\"", "\"\"", "{ kind = \"beam\" }"});
    case Type::flag:
      return random.pick(std::vector<std::string>{"1", "\"true\"", "\"yes\"", "[true]"});
    case Type::positions:
      return random.pick(std::vector<std::string>{"0.5", "[\"a\"]", "[true]", "{ x = 1 }", "[[0.5]]"});
    case Type::modes:
      return random.pick(std::vector<std::string>{"\"Auto\"", "2.5", "true", "[4]", "\"8\""});
    case Type::pieces:
      return random.pick(
          std::vector<std::string>{"1", "[]", "[\"contact\", \"contact\"]", "[\"x\"]", "\"none\"", "[1, 2]"});
  }
  return "true";
}

// A value the key's type allows but its range does not; empty if none applies.
std::string out_of_range(Random& random, const Draft& d, const Table& t, const Entry& e) {
  const double span = d.end - d.begin;
  const std::string outside = toml_number(random.chance(0.5) ? d.end + random.log_uniform(1e-9, 2.0) * span
                                                             : d.begin - random.log_uniform(1e-9, 2.0) * span);
  const std::string& k = e.key;
  if (t.name == "structure" && (k == "length" || k == "EI" || k == "EA" || k == "radius"))
    return random.pick(std::vector<std::string>{"0.0", "-1.5", "0", "-0.0", "-1e-300"});
  if (k == "half_angle_deg") return random.pick(std::vector<std::string>{"0.0", "180.0", "181", "-10.0", "360.0"});
  const bool foundation = t.name == "foundation" || t.name == "foundation.segments";
  if (foundation && (k == "nondimensional_k" || k == "modulus"))
    return random.pick(std::vector<std::string>{"0.0", "-3.0", "0", "[0.0, 1.0]", "[1.0, -2.0]"});
  if (k == "at" || k == "monitor" || ((k == "from" || k == "to") && (t.name == "loads" || foundation))) return outside;
  if (k == "interior")
    return random.pick(std::vector<std::string>{
        "[" + toml_number(d.begin) + "]", "[" + outside + "]",
        "[" + toml_number(d.begin + 0.5 * span) + ", " + toml_number(d.begin + 0.5 * span) + "]"});
  if (k == "elements") return random.pick(std::vector<std::string>{"0", "-5", "10000001", "2147483648"});
  if (k == "modes") return random.pick(std::vector<std::string>{"0", "1001", "-1"});
  if (k == "max_modes") return random.pick(std::vector<std::string>{"0", "1001"});
  if (k == "mode_tolerance" || k == "max_step" || k == "initial_step" || k == "min_step")
    return random.pick(std::vector<std::string>{"0.0", "-1.0"});
  if (k == "samples") return random.pick(std::vector<std::string>{"1", "0", "1000001"});
  if (k == "max_steps") return random.pick(std::vector<std::string>{"0", "-1", "100000001"});
  if (k == "lambda_max") return random.pick(std::vector<std::string>{"-2.0", "-1e9"});  // lambda_min is <= 0.5
  return {};
}

// Issue 12: [[foundation.segments]] malformed. The foundation becomes two valid abutting pieces
// [begin, middle] (k) and [middle, end] (modulus, linear), then one rule is broken.
Mutant malformed_segments(Random& random, Draft d) {
  std::erase_if(d.tables, [](const Table& t) { return t.name == "foundation.segments"; });
  Table& foundation = *d.find("foundation");
  std::erase_if(foundation.entries, [](const Entry& e) {
    return e.key == "nondimensional_k" || e.key == "modulus" || e.key == "from" || e.key == "to";
  });
  const double span = d.end - d.begin, middle = d.begin + 0.5 * span;
  auto piece = [](double from, double to, const char* key, const char* value) {
    return Table{"foundation.segments", true, {{"from", toml_number(from)}, {"to", toml_number(to)}, {key, value}}};
  };
  std::vector<Table> pieces{piece(d.begin, middle, "nondimensional_k", "100.0"),
                            piece(middle, d.end, "modulus", "[2.0, 3.0]")};
  Table& p = pieces[random.next() % 2];
  std::string what;
  switch (random.integer(0, 9)) {
    case 0:
      pieces[1].entries[0].value = toml_number(d.begin + random.uniform(0.0, 0.45) * span);
      what = "overlapping";
      break;
    case 1:
      if (random.chance(0.5))
        pieces[1].entries[1].value = toml_number(d.end + random.log_uniform(1e-6, 1.0) * span);
      else
        pieces[0].entries[0].value = toml_number(d.begin - random.log_uniform(1e-6, 1.0) * span);
      what = "outside the member";
      break;
    case 2:
      p.entries[1].value = &p == &pieces[0] || random.chance(0.5) ? p.entries[0].value  // to = from
                                                                  : toml_number(d.begin + 0.25 * span);
      what = "from >= to";
      break;
    case 3:
      p.entries.push_back({p.entries[2].key == "nondimensional_k" ? "modulus" : "nondimensional_k", "1.0"});
      what = "both k and modulus";
      break;
    case 4:
      p.entries[2].value =
          random.pick(std::vector<std::string>{"0.0", "-1.0", "[0.0, 2.0]", "[2.0, -1.0]", "[2.0, 0]"});
      what = "modulus <= 0";
      break;
    case 5:
      foundation.entries.push_back(
          {random.pick(std::vector<std::string>{"nondimensional_k", "modulus", "from", "to"}), toml_number(d.begin)});
      if (foundation.entries.back().key == "nondimensional_k" || foundation.entries.back().key == "modulus")
        foundation.entries.back().value = "10.0";
      what = "with [foundation] k, modulus, from or to";
      break;
    case 6:
      p.entries[2].value = random.pick(
          std::vector<std::string>{"[1.0]", "[1.0, 2.0, 3.0]", "[]", "[\"a\", 1.0]", "[[1.0, 2.0]]", "[1.0, true]"});
      what = "a linear form that is not two numbers";
      break;
    case 7: {
      const std::string key = random.pick(std::vector<std::string>{"from", "to", p.entries[2].key});
      std::erase_if(p.entries, [&](const Entry& e) { return e.key == key; });
      what = "a key missing";
      break;
    }
    case 8:
      pieces.clear();
      foundation.entries.push_back(
          {"segments", random.pick(std::vector<std::string>{"3", "[]", "[1.0, 2.0]", "{ from = 0.0 }", "\"none\""})});
      what = "segments not an array of tables";
      break;
    default:
      p.entries.push_back({random.pick(std::vector<std::string>{"modulos", "at", "value", "K", "tensionless"}), "1.0"});
      what = "an unknown key";
      break;
  }
  if (random.chance(0.3)) std::reverse(pieces.begin(), pieces.end());
  const auto after =
      std::find_if(d.tables.begin(), d.tables.end(), [](const Table& t) { return t.name == "foundation"; });
  d.tables.insert(after + 1, pieces.begin(), pieces.end());
  return {"malformed foundation segments: " + what, d.text(), true};
}

}  // namespace

Mutant mutate(Random& random, Draft d) {
  Mutant m;
  const int family = random.integer(0, 14);
  auto done = [&](std::string kind, bool invalid) {
    m.kind = std::move(kind);
    if (m.text.empty()) m.text = d.text();
    m.certainly_invalid = invalid;
    return m;
  };
  switch (family) {
    case 0: {  // a required key or table missing
      std::vector<std::pair<std::string, std::string>> required = {
          {"structure", "kind"}, {"structure", "EI"}, {"supports", "left"}, {"supports", "right"}};
      if (d.arch) {
        for (const char* key : {"radius", "half_angle_deg", "EA"}) required.push_back({"structure", key});
      } else {
        required.push_back({"structure", "length"});
      }
      if (const Table* piece = d.find("foundation.segments")) {  // the first piece's from, to, k or modulus
        for (const char* key : {"from", "to", "nondimensional_k", "modulus"})
          if (d.has("foundation.segments", key) &&
              std::any_of(piece->entries.begin(), piece->entries.end(), [&](const Entry& e) { return e.key == key; }))
            required.push_back({"foundation.segments", key});
      } else {
        required.push_back(
            {"foundation", d.find("foundation", "nondimensional_k") != nullptr ? "nondimensional_k" : "modulus"});
      }
      if (random.chance(0.2)) {
        const std::string table = random.pick(std::vector<std::string>{"structure", "supports", "foundation"});
        std::erase_if(d.tables, [&](const Table& t) {  // [[foundation.segments]] would make [foundation]
          return t.name == table || (table == "foundation" && t.name == "foundation.segments");
        });
        return done("missing table [" + table + "]", true);
      }
      std::vector<Table*> loads;
      for (Table& t : d.tables)
        if (t.name == "loads") loads.push_back(&t);
      if (!loads.empty() && random.chance(0.3)) {
        Table& load = *random.pick(loads);
        std::vector<std::string> keys{"kind", "value"};
        if (load.entries.end() !=
            std::find_if(load.entries.begin(), load.entries.end(), [](const Entry& e) { return e.key == "at"; }))
          keys.push_back("at");
        const std::string key = random.pick(keys);
        std::erase_if(load.entries, [&](const Entry& e) { return e.key == key; });
        return done("missing loads key " + key, true);
      }
      const auto [table, key] = random.pick(required);
      std::erase_if(d.find(table)->entries, [&](const Entry& e) { return e.key == key; });
      return done("missing " + table + "." + key, true);
    }
    case 1: {                    // an unknown key or table
      if (random.chance(0.2)) {  // issue 12: direction / per where they do not belong
        std::vector<Table*> loads;
        for (Table& t : d.tables)
          if (t.name == "loads") loads.push_back(&t);
        if (!loads.empty()) {
          Table& load = *random.pick(loads);
          std::erase_if(load.entries, [](const Entry& e) { return e.key == "direction" || e.key == "per"; });
          const auto kind_entry =
              std::find_if(load.entries.begin(), load.entries.end(), [](const Entry& e) { return e.key == "kind"; });
          const std::string kind = kind_entry != load.entries.end() ? kind_entry->value : "";
          const int misuse = random.integer(0, 2);
          if (!d.arch || misuse == 0) {  // a beam's loads have no direction; no arch load goes "up"
            load.entries.push_back({"direction", quoted(d.arch ? "up" : "vertical"), Type::name});
          } else if (misuse == 1) {  // per with a radial direction
            load.entries.push_back({"direction", quoted("radial"), Type::name});
            load.entries.push_back({"per", quoted("arc"), Type::name});
          } else {  // per on something other than a uniform load, or an unknown basis
            load.entries.push_back({"per", quoted(kind == quoted("uniform") ? "length" : "arc"), Type::name});
          }
          return done("misplaced load direction or per", true);
        }
      }
      if (random.chance(0.1)) {  // issue 12: side on a beam, or a side that does not exist
        Table& foundation = *d.find("foundation");
        std::erase_if(foundation.entries, [](const Entry& e) { return e.key == "side"; });
        foundation.entries.push_back({"side", quoted(d.arch ? "below" : "outside"), Type::name});
        return done("foundation side misplaced or unknown", true);
      }
      if (random.chance(0.25)) {
        const int kind = random.integer(0, 3);
        if (kind == 0) d.tables.push_back({"extra", false, {{"x", "1.0"}}});
        if (kind == 1) d.tables.push_back({"load", true, {{"kind", "\"force\""}}});
        if (kind == 2) d.tables.push_back({"Structure", false, {{"kind", "\"beam\""}}});
        if (kind == 3) m.text = "title = \"fuzz\"\n" + d.text();
        return done("unknown table", true);
      }
      Table& t = d.tables[random.next() % d.tables.size()];
      t.entries.insert(t.entries.begin() + static_cast<long>(random.next() % (t.entries.size() + 1)),
                       {unknown_key(random, t.name), random.chance(0.5) ? "1.0" : "\"x\""});
      return done("unknown key in [" + t.name + "]", true);
    }
    case 2:
    case 3: {  // a value of the wrong type
      auto places = entries(d);
      Place p = random.pick(places);
      p.entry->value = wrong_type(random, p.entry->type);
      return done("wrong type for " + p.table->name + "." + p.entry->key, true);
    }
    case 4:
    case 5: {  // out of range
      auto places = entries(d);
      for (int attempt = 0; attempt < 30; ++attempt) {
        Place p = random.pick(places);
        std::string bad = out_of_range(random, d, *p.table, *p.entry);
        if (bad.empty()) continue;
        p.entry->value = bad;
        return done("out of range " + p.table->name + "." + p.entry->key + " = " + bad, true);
      }
      d.find("structure", "EI")->value = "-1.0";
      return done("out of range structure.EI", true);
    }
    case 6: {  // nan or inf
      auto places = entries_of(d, Type::number);
      Place p = random.pick(places);
      const std::string bad = random.pick(std::vector<std::string>{"nan", "inf", "-inf", "+nan", "-nan", "+inf"});
      p.entry->value = bad;
      return done("non-finite " + p.table->name + "." + p.entry->key + " = " + bad, true);
    }
    case 7: {  // extreme finite numbers: anything but a crash or a wrong answer
      auto places = entries_of(d, Type::number);
      Place p = random.pick(places);
      const std::string bad =
          random.pick(std::vector<std::string>{"1e308", "-1e308", "1.7976931348623157e308", "1e-308", "4.9e-324",
                                               "1e300", "-1e-300", "-0.0", "0.0", "1e-30", "1e30"});
      p.entry->value = bad;
      return done("extreme " + p.table->name + "." + p.entry->key + " = " + bad, false);
    }
    case 8: {  // integers a double cannot hold (or an int64 cannot)
      auto places = entries_of(d, random.chance(0.8) ? Type::number : Type::integer);
      if (places.empty()) places = entries_of(d, Type::number);
      Place p = random.pick(places);
      const std::string bad = random.pick(std::vector<std::string>{
          "9007199254740993", "-9007199254740993", "9223372036854775807", "-9223372036854775808", "18014398509481985",
          "9007199254740992", "18446744073709551615", "4611686018427387905"});
      p.entry->value = bad;
      return done("big integer " + p.table->name + "." + p.entry->key + " = " + bad, false);
    }
    case 9: {  // TOML syntax errors
      const int kind = random.integer(0, 7);
      auto places = entries(d);
      Place p = random.pick(places);
      if (kind == 0) p.entry->value = "\"" + p.entry->value;  // unterminated string
      if (kind == 1) p.entry->value = "";                     // key = (nothing)
      if (kind == 2) p.table->entries.push_back(*p.entry);    // duplicate key
      if (kind == 3) p.entry->value = "1.0.0";
      if (kind == 4) p.entry->value = "[1.0, ";
      if (kind == 5) d.tables.push_back({p.table->array ? "structure" : p.table->name, false, {}});  // a table twice
      if (kind == 6) p.entry->key = "a b";
      m.text = d.text();
      if (kind == 7) {
        const auto header = m.text.find(']');
        m.text.erase(header, 1);  // [structure -> unclosed header
      }
      return done("syntax error " + std::to_string(kind), true);
    }
    case 10: {  // issue 12's load keys malformed: tables that do not match, decrease, or a direction on a beam
      if (random.chance(0.3)) {  // or the foundation's gap and tension keys
        Table& foundation = *d.find("foundation");
        std::erase_if(foundation.entries, [](const Entry& e) {
          return e.key == "gap" || e.key == "tension_nondimensional_k" || e.key == "tension_modulus" ||
                 e.key == "tensionless";
        });
        const bool by_k = !foundation.entries.empty() && foundation.entries.front().key == "nondimensional_k";
        const bool by_modulus = !foundation.entries.empty() && foundation.entries.front().key == "modulus";
        int kind = random.integer(0, 6);
        if (kind == 5 && !by_k && !by_modulus) kind = 4;  // segments: which tension key fits depends on them
        if (kind == 0)
          foundation.entries.push_back({"gap", "{ at = [1.0, 0.5], value = [0.0, 0.0] }", Type::positions});
        if (kind == 1) foundation.entries.push_back({"gap", "{ at = [0.5, 1.0], value = [0.0] }", Type::positions});
        if (kind == 2) foundation.entries.push_back({"gap", "{ at = [], value = [] }", Type::positions});
        if (kind == 3) {
          foundation.entries.push_back({"gap", "{ at = [0.5], value = [0.0] }", Type::positions});
          foundation.entries.push_back({"gap_file", "\"seabed.csv\"", Type::name});
        }
        if (kind == 4) foundation.entries.push_back({by_k ? "tension_nondimensional_k" : "tension_modulus", "-1.0"});
        if (kind == 5) foundation.entries.push_back({by_k ? "tension_modulus" : "tension_nondimensional_k", "0.5"});
        if (kind == 6) {
          foundation.entries.push_back({"tensionless", "false", Type::flag});
          foundation.entries.push_back({by_k ? "tension_nondimensional_k" : "tension_modulus", "0.0"});
        }
        return done("malformed gap or tension " + std::to_string(kind), true);
      }
      if (random.chance(0.5)) return malformed_segments(random, std::move(d));
      if (random.chance(0.3)) {  // issue 12: a malformed support table
        const std::string mid = toml_number(d.begin + 0.5 * (d.end - d.begin));
        const std::vector<std::string> bad = {"{ kind = \"spring\", stiffness = -1.0 }",
                                              "{ kind = \"spring\" }",
                                              "{ kind = \"free\", settlement = 0.01 }",
                                              "{ kind = \"hinge\" }",
                                              "{ kind = \"pinned\", stiffness = 5.0 }",
                                              "{ settlement = 0.01 }",
                                              "{ kind = \"spring\", stiffness = 1.0, stifness = 1.0 }"};
        if (random.chance(0.7)) {
          d.find("supports", random.chance(0.5) ? "left" : "right")->value = random.pick(bad);
        } else {
          Table& supports = *d.find("supports");
          std::erase_if(supports.entries, [](const Entry& e) { return e.key == "interior"; });
          supports.entries.push_back(
              {"interior",
               random.pick(std::vector<std::string>{
                   "[{ at = " + toml_number(d.end + (d.end - d.begin)) + ", kind = \"spring\", stiffness = 1.0 }]",
                   "[{ at = " + mid + ", kind = \"clamped\" }]", "[{ kind = \"pinned\" }]",
                   "[{ at = " + mid + ", kind = \"spring\", stiffness = -2.0 }]"}),
               Type::positions});
        }
        return done("malformed support table", true);
      }
      std::vector<Table*> tables;
      for (Table& t : d.tables)
        if (t.name == "loads") tables.push_back(&t);
      const double span = d.end - d.begin;
      if (tables.empty() || random.chance(0.3)) {
        Table load{"loads", true, {{"kind", "\"distributed\"", Type::name}}};
        const int kind = random.integer(0, 4);
        const std::string a = toml_number(d.begin + 0.2 * span), b = toml_number(d.begin + 0.6 * span);
        if (kind == 0) load.entries.push_back({"at", "[" + a + ", " + b + "]", Type::positions});  // no value
        if (kind == 1) {
          load.entries.push_back({"at", "[" + a + ", " + b + "]", Type::positions});
          load.entries.push_back({"value", "[1.0, 2.0, 3.0]", Type::positions});
        }
        if (kind == 2) {
          load.entries.push_back({"at", "[" + b + ", " + a + "]", Type::positions});
          load.entries.push_back({"value", "[1.0, 2.0]", Type::positions});
        }
        if (kind == 3) {
          load.entries.push_back({"at", "[" + a + ", " + b + "]", Type::positions});
          load.entries.push_back({"value", "[1.0, 2.0]", Type::positions});
          load.entries.push_back({"from", toml_number(d.begin)});
        }
        if (kind == 4) {
          load.entries = {{"kind", "\"curvature\"", Type::name},
                          {"value", "0.001"},
                          {"from", toml_number(d.begin + 0.5 * span)},
                          {"to", toml_number(d.begin + 0.25 * span)}};
        }
        d.tables.push_back(load);
        return done("malformed distributed or curvature load " + std::to_string(kind), true);
      }
      Table& load = *random.pick(tables);
      if (d.arch) {  // (direction and per are an arch's keys) an array where a point or nothing belongs
        load.entries.push_back({"at", "[1.0, 2.0]", Type::positions});
        return done("an array 'at' on a load that is no table", true);
      }
      load.entries.push_back({random.chance(0.5) ? "direction" : "per",
                              random.chance(0.5) ? "\"vertical\"" : "\"projection\"", Type::name});
      return done("direction or per on a beam load", true);
    }
    case 11: {  // junk: random bytes, an empty file, blanks, a NUL
      const int kind = random.integer(0, 4);
      if (kind == 0) m.text = random_bytes(random, random.integer(1, 400));
      if (kind == 1) m.text = "\n";  // empty files are written as such below
      if (kind == 2) m.text = "   \n\t\n# only a comment\n";
      if (kind == 3) m.text = d.text() + std::string(1, '\0') + "x";
      if (kind == 4) m.text = std::string(1, '\0');
      if (kind == 1 && random.chance(0.5)) m.text = " ";
      return done("junk " + std::to_string(kind), true);
    }
    case 12: {  // bytes spliced in
      m.text = d.text();
      const std::size_t at = random.next() % (m.text.size() + 1);
      m.text.insert(at, random_bytes(random, random.integer(1, 8)));
      return done("spliced bytes", false);
    }
    case 13: {  // deep nesting, huge strings, control characters and non-ASCII in keys and values
      const int kind = random.integer(0, 4);
      auto places = entries(d);
      Place p = random.pick(places);
      const std::string where = p.table->name + "." + p.entry->key;  // before entries move
      if (kind == 0) {
        const int depth = random.integer(100, 5000);
        p.entry->value = std::string(depth, '[') + "1.0" + std::string(depth, ']');
      }
      if (kind == 1) p.entry->value = "\"" + std::string(random.integer(1000, 200000), 'x') + "\"";
      if (kind == 2) p.table->entries.push_back({"\"a\\u0001b\\nc\\td\"", "1.0"});
      if (kind == 3) p.entry->value = "\"b\\u00e9am\\r\\n\"";
      if (kind == 4) {
        const int depth = random.integer(100, 3000);
        std::string v;
        for (int i = 0; i < depth; ++i) v += "{ a = ";
        v += "1";
        for (int i = 0; i < depth; ++i) v += " }";
        p.entry->value = v;
      }
      return done("odd text " + std::to_string(kind) + " at " + where, true);
    }
    case 14: {  // the same scene with CRLF line ends or a byte-order mark: still valid
      m.text = d.text();
      const int kind = random.integer(0, 1);
      if (kind == 0) {
        std::string crlf;
        for (char c : m.text) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
        m.text = crlf;
      } else {
        m.text = "\xEF\xBB\xBF" + m.text;
      }
      return done(kind == 0 ? "crlf" : "bom", false);
    }
    default: {  // the text cut short: may still be a scene (the optional tables dropped)
      m.text = d.text();
      m.text.resize(random.next() % (m.text.size() + 1));
      return done("truncated", false);
    }
  }
}

}  // namespace liftoff::fuzz
