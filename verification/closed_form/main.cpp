// closed_form_reference SCENE.toml: the closed-form (segment-by-segment exact) solution of a beam
// scene, as JSON on stdout: {"method": "closed-form", "status", "contact_regions", "w_max",
// "at_w_max", "w_min", "at_w_min", "moment_max", "at_moment_max", "moment_min", "at_moment_min",
// "shear_max_abs", "at_shear_max_abs"} (moments sagging positive, V = dM/dx, the user's units). It reads the scene with
// toml++ itself and shares no code with liftoff. It reads issue 12's ground keys too: [foundation] from/to,
// [[foundation.segments]] (from, to, modulus or k), gap = {at, value} or gap_file (two-column CSV, relative to the
// scene), tension_modulus, and loads of kind "distributed" (at, value tables) and "axial" (a constant compressive
// force, issue 15). Exit 2 (one line on stderr) for a scene it does not cover: arches, interior point supports, a
// modulus varying within a piece; exit 3 if the solve fails.
//
// closed_form_reference localized-buckle SCENE.toml [--points N] [--max-amplitude A] [--half-lengths a1,a2,...]:
// the perfect member's localized buckle branch (beam_column.hpp, localized_buckle) for the scene's EI, foundation
// modulus K and weight q (issue 15), as JSON on stdout: {"method": "closed-form localized buckle", "length" (the
// scene's member length), "EI", "K", "q",
// "settlement" (q/K), "bilateral_critical" (2 sqrt(K EI)), "hobbs_load_parameter" (P L^2/EI of the rigid-foundation
// limit), "points": [{"half_length" a, "lifted_length" 2a, "axial_force" P(a), "amplitude", "status"}, ...]}. The
// amplitude is what the trace paths call it: the largest lift off the ground, max of -w over the lifted zone (the
// ground at w = 0, so the flat state's settlement q/K is included). The member is taken as infinite (its supports
// and length do not enter; the half-lengths run up to half the member), straight (an initial_shape is the
// imperfection the reference leaves out), weighed by its dead uniform loads over the whole member; axial loads
// are the P of the branch and are ignored. Points run over a = (L/2) (k/N)^2, k = 1..N (default N = 400), stopping
// after the first whose amplitude exceeds A; only the branch's admissible points are listed (status "found", or
// "secondary lift-off" where the contact tail would lift off too: beam_column.hpp). Exit 2 (one line naming the
// key) for a scene that is not a uniform beam with a uniform weight on a uniform tensionless foundation.
#include <toml++/toml.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "closed_form/beam_column.hpp"
#include "closed_form/beam_on_foundation.hpp"
#include "closed_form/shallow_arch.hpp"
#include "closed_form/upheaval.hpp"

using namespace liftoff::closed_form;

namespace {

[[noreturn]] void refuse(const std::string& scene, const std::string& why) {
  std::cerr << "closed_form_reference: " << scene << ": " << why << "\n";
  std::exit(2);
}

EndCondition end(const std::string& scene, const std::string& name) {
  if (name == "pinned") return EndCondition::pinned;
  if (name == "clamped") return EndCondition::clamped;
  if (name == "free") return EndCondition::free;
  refuse(scene, "end support '" + name + "' is not covered");
}

template <typename View>
std::vector<double> numbers(const std::string& scene, const View& node, const std::string& key) {
  std::vector<double> out;
  const toml::array* a = node.as_array();
  if (!a) refuse(scene, key + ": expected an array of numbers");
  for (const toml::node& e : *a) {
    const auto v = e.value<double>();
    if (!v) refuse(scene, key + ": expected an array of numbers");
    out.push_back(*v);
  }
  return out;
}

// A two-column CSV (position, gap); lines that do not start with a number are skipped (header).
GapProfile read_gap_file(const std::string& scene, const std::string& file) {
  const std::filesystem::path path = std::filesystem::path(scene).parent_path() / file;
  std::ifstream in(path);
  if (!in) refuse(scene, "foundation.gap_file: cannot read " + path.string());
  GapProfile g;
  std::string line;
  while (std::getline(in, line)) {
    for (char& c : line)
      if (c == ',' || c == ';' || c == '\t') c = ' ';
    std::istringstream ls(line);
    double x, v;
    if (ls >> x >> v) {
      g.at.push_back(x);
      g.value.push_back(v);
    }
  }
  return g;
}

toml::table read_scene(const std::string& path) {
  try {
    return toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    refuse(path, std::string("not valid TOML: ") + std::string(e.description()));
  }
}

double positive_number(const std::string& scene, const toml::node_view<const toml::node>& node, const std::string& key,
                       const std::string& expected) {
  const auto v = node.value<double>();
  if (!v || !(*v > 0.0) || !std::isfinite(*v)) refuse(scene, key + ": expected " + expected);
  return *v;
}

double option_number(const std::string& name, const std::string& text) {
  try {
    std::size_t used = 0;
    const double v = std::stod(text, &used);
    if (used == text.size() && v > 0.0 && std::isfinite(v)) return v;
  } catch (const std::exception&) {
  }
  std::cerr << "closed_form_reference: " << name << ": expected a positive number, got '" << text << "'\n";
  std::exit(2);
}

// `localized-buckle SCENE.toml [options]`: the perfect member's branch P(a) as JSON (see the top of this file).
int localized_buckle_command(int argc, char** argv) {
  if (argc < 3) {
    std::cerr << "usage: closed_form_reference localized-buckle SCENE.toml [--points N] [--max-amplitude A] "
                 "[--half-lengths a1,a2,...]\n";
    return 2;
  }
  const std::string path = argv[2];
  int points = 400;
  double max_amplitude = INFINITY;
  std::vector<double> half_lengths;
  for (int i = 3; i < argc; ++i) {
    const std::string option = argv[i];
    if (i + 1 >= argc) {
      std::cerr << "closed_form_reference: " << option << ": expected a value after it\n";
      return 2;
    }
    const std::string value = argv[++i];
    if (option == "--points") {
      const double n = option_number(option, value);
      if (n != std::floor(n) || n > 1e6) {
        std::cerr << "closed_form_reference: --points: expected a whole number up to 1e6, got '" << value << "'\n";
        return 2;
      }
      points = static_cast<int>(n);
    } else if (option == "--max-amplitude") {
      max_amplitude = option_number(option, value);
    } else if (option == "--half-lengths") {
      std::istringstream list(value);
      std::string item;
      while (std::getline(list, item, ',')) half_lengths.push_back(option_number(option, item));
    } else {
      std::cerr << "closed_form_reference: " << option
                << ": unknown option; expected --points, --max-amplitude or --half-lengths\n";
      return 2;
    }
  }
  const toml::table scene = read_scene(path);
  if (scene["structure"]["kind"].value_or(std::string()) != "beam")
    refuse(path, "structure.kind: expected \"beam\" (the localized buckle is a straight member's)");
  const double length = positive_number(path, scene["structure"]["length"], "structure.length", "a positive number");
  const double EI =
      positive_number(path, scene["structure"]["EI"], "structure.EI", "one positive number (a uniform member)");
  const auto foundation = scene["foundation"];
  for (const char* key : {"segments", "from", "to", "gap", "gap_file"})
    if (foundation[key])
      refuse(path,
             std::string("foundation.") + key + ": expected none (the reference is a uniform foundation everywhere)");
  if (!foundation["tensionless"].value_or(true)) refuse(path, "foundation.tensionless: expected true");
  if (foundation["tension_modulus"].value_or(0.0) != 0.0) refuse(path, "foundation.tension_modulus: expected 0");
  double K = 0.0;
  if (foundation["nondimensional_k"] || foundation["k"]) {
    const char* key = foundation["nondimensional_k"] ? "nondimensional_k" : "k";
    K = positive_number(path, foundation[key], std::string("foundation.") + key, "one positive number") * EI /
        std::pow(length, 4);
  } else {
    K = positive_number(path, foundation["modulus"], "foundation.modulus",
                        "one positive number (a uniform foundation)");
  }
  double q = 0.0;
  if (const toml::array* loads = scene["loads"].as_array()) {
    for (std::size_t i = 0; i < loads->size(); ++i) {
      const toml::table* load = (*loads)[i].as_table();
      const std::string key = "loads[" + std::to_string(i) + "]";
      if (!load) refuse(path, key + ": expected a table");
      const std::string kind = (*load)["kind"].value_or(std::string());
      if (kind == "axial") continue;  // the branch's P
      if (kind != "uniform")
        refuse(path, key + ".kind: expected \"uniform\" (the weight) or \"axial\", got \"" + kind + "\"");
      if ((*load)["case"].value_or(std::string("live")) != "dead")
        refuse(path, key + ".case: expected \"dead\" (the weight does not grow with the axial force)");
      if ((*load)["from"].value_or(0.0) != 0.0 || (*load)["to"].value_or(length) != length)
        refuse(path, key + ": expected the weight over the whole member (no from/to)");
      const auto value = (*load)["value"].value<double>();
      if (!value) refuse(path, key + ".value: expected a number");
      q += *value;
    }
  }
  if (!(q > 0.0)) refuse(path, "loads: expected a dead uniform weight q > 0 toward the foundation");

  const bool listed = !half_lengths.empty();
  if (!listed)
    for (int k = 1; k <= points; ++k) half_lengths.push_back(0.5 * length * std::pow(double(k) / points, 2));
  std::printf(
      "{\"method\": \"closed-form localized buckle\", \"length\": %.17g, \"EI\": %.17g, \"K\": %.17g, \"q\": "
      "%.17g, \"settlement\": %.17g, \"bilateral_critical\": %.17g, \"hobbs_load_parameter\": %.17g, \"points\": [",
      length, EI, K, q, q / K, long_member_critical(K, EI), hobbs_vertical_mode().load_parameter);
  const char* separator = "";
  for (double a : half_lengths) {
    const LocalizedBuckle b = localized_buckle(K, EI, q, a);
    if (b.status != BuckleStatus::found && b.status != BuckleStatus::secondary_lift_off) continue;
    // The largest lift off the ground over the lifted zone (the crown for this mode; sampled to be sure).
    double amplitude = b.uplift;
    for (int i = 0; i <= 1000; ++i) amplitude = std::max(amplitude, -b.deflection(a * i / 1000.0));
    std::printf(
        "%s\n  {\"half_length\": %.17g, \"lifted_length\": %.17g, \"axial_force\": %.17g, \"amplitude\": "
        "%.17g, \"status\": \"%s\"}",
        separator, a, 2.0 * a, b.axial_force, amplitude, to_string(b.status).c_str());
    separator = ",";
    if (!listed && amplitude > max_amplitude) break;
  }
  std::printf("]}\n");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 2 && std::string(argv[1]) == "localized-buckle") return localized_buckle_command(argc, argv);
  if (argc >= 2 && std::string(argv[1]) == "shallow-arch") return shallow_arch_command(argc, argv);  // --help
  if (argc != 2) {
    std::cerr
        << "usage: closed_form_reference SCENE.toml | localized-buckle SCENE.toml [options] | shallow-arch --help\n";
    return 2;
  }
  const std::string path = argv[1];
  toml::table scene = read_scene(path);
  if (scene["structure"]["kind"].value_or(std::string()) != "beam") refuse(path, "only beams have a closed form");
  if (scene["supports"]["interior"]) refuse(path, "interior point supports are not covered");

  BeamProblem p;
  p.length = scene["structure"]["length"].value_or(0.0);
  p.bending_stiffness = scene["structure"]["EI"].value_or(0.0);
  p.left = end(path, scene["supports"]["left"].value_or(std::string()));
  p.right = end(path, scene["supports"]["right"].value_or(std::string()));
  // The nondimensional K l^4/EI is `nondimensional_k` (`k`, its old name, still read).
  const auto nondimensional = [](const auto& table) {
    return table["nondimensional_k"] ? table["nondimensional_k"] : table["k"];
  };
  if (auto k = nondimensional(scene["foundation"]).value<double>())
    p.foundation_modulus = *k * p.bending_stiffness / std::pow(p.length, 4);
  else
    p.foundation_modulus = scene["foundation"]["modulus"].value_or(0.0);
  const double k_scale = p.bending_stiffness / std::pow(p.length, 4);  // K per unit of k
  if (scene["foundation"]["from"] || scene["foundation"]["to"])
    p.foundation_segments = {{scene["foundation"]["from"].value_or(0.0), scene["foundation"]["to"].value_or(p.length),
                              p.foundation_modulus}};
  if (const toml::array* pieces = scene["foundation"]["segments"].as_array()) {
    p.foundation_segments.clear();
    for (const toml::node& node : *pieces) {
      const toml::table& piece = *node.as_table();
      FoundationSegment f{piece["from"].value_or(0.0), piece["to"].value_or(p.length), 0.0};
      if (piece["modulus"].as_array() || nondimensional(piece).as_array())
        refuse(path, "foundation.segments: a modulus varying within a piece is not covered");
      if (auto k = nondimensional(piece).value<double>())
        f.modulus = *k * k_scale;
      else
        f.modulus = piece["modulus"].value_or(0.0);
      p.foundation_segments.push_back(f);
    }
  }
  if (scene["foundation"]["gap"]) {
    p.gap.at = numbers(path, scene["foundation"]["gap"]["at"], "foundation.gap.at");
    p.gap.value = numbers(path, scene["foundation"]["gap"]["value"], "foundation.gap.value");
  } else if (auto file = scene["foundation"]["gap_file"].value<std::string>()) {
    p.gap = read_gap_file(path, *file);
  }
  p.tension_modulus = scene["foundation"]["tension_modulus"].value_or(0.0);
  const bool tensionless = scene["foundation"]["tensionless"].value_or(true);
  if (const toml::array* loads = scene["loads"].as_array()) {
    for (const toml::node& node : *loads) {
      const toml::table& load = *node.as_table();
      const std::string kind = load["kind"].value_or(std::string());
      const double value = load["value"].value_or(0.0);
      if (kind == "curvature") refuse(path, "loads.kind: an imposed curvature has no closed form here");
      if (kind == "temperature") refuse(path, "loads.kind: a temperature load is not covered (give the axial force)");
      // Issue 15: a constant axial force, compression positive, at full value like every load here.
      if (kind == "axial") p.axial_force += value;
      if (kind == "force") p.forces.push_back({load["at"].value_or(0.0), value});
      if (kind == "moment") p.moments.push_back({load["at"].value_or(0.0), value});
      if (kind == "uniform")
        p.uniform_loads.push_back({load["from"].value_or(0.0), load["to"].value_or(p.length), value});
      if (kind == "distributed") {  // piecewise linear through (at[i], value[i])
        const auto at = numbers(path, load["at"], "loads.at"), v = numbers(path, load["value"], "loads.value");
        if (at.size() != v.size()) refuse(path, "loads.value: expected as many values as positions in loads.at");
        for (std::size_t i = 0; i + 1 < at.size(); ++i)
          if (at[i + 1] > at[i]) p.distributed_loads.push_back({at[i], at[i + 1], v[i], v[i + 1]});
      }
    }
  }

  try {
    load_points(p);  // validates the problem
  } catch (const std::invalid_argument& e) {
    refuse(path, e.what());
  }
  std::string status = "converged";
  BeamSolution solution;
  if (tensionless) {
    const TensionlessResult result = solve_tensionless_auto(p);
    if (result.status != TensionlessStatus::converged) {
      std::cerr << "closed_form_reference: " << path << ": " << result.message << "\n";
      return 3;
    }
    solution = result.solution;
  } else {
    solution = solve_bilateral(p);
  }

  double w_max = -INFINITY, w_min = INFINITY, at_max = 0, at_min = 0;
  constexpr int samples = 20000;
  for (int i = 0; i <= samples; ++i) {
    const double x = p.length * i / samples, w = solution.deflection(x);
    if (w > w_max) w_max = w, at_max = x;
    if (w < w_min) w_min = w, at_min = x;
  }
  std::printf("{\"method\": \"closed-form\", \"status\": \"%s\", \"contact_regions\": [", status.c_str());
  // Bilateral: the foundation acts wherever it exists (the pieces, merged where they touch).
  std::vector<Interval> regions;
  if (tensionless) {
    regions = contact_regions(solution);
  } else {
    const auto& x = solution.breakpoints();
    for (std::size_t i = 0; i + 1 < x.size(); ++i) {
      if (solution.ground_modulus(0.5 * (x[i] + x[i + 1])) == 0.0) continue;
      if (!regions.empty() && regions.back().end == x[i])
        regions.back().end = x[i + 1];
      else
        regions.push_back({x[i], x[i + 1]});
    }
  }
  for (std::size_t i = 0; i < regions.size(); ++i)
    std::printf("%s[%.17g, %.17g]", i ? ", " : "", regions[i].start, regions[i].end);
  std::printf("], \"w_max\": %.17g, \"at_w_max\": %.17g, \"w_min\": %.17g, \"at_w_min\": %.17g", w_max, at_max, w_min,
              at_min);
  // Design values (issue 13): the bending moment's extremes at the breakpoints (both sides) and
  // where the shear changes sign between samples (bisection to round-off), the largest |V| at
  // the breakpoints and the samples (its sampling error O(dx^2 |V''|), dx = L / 20000).
  double m_max = -INFINITY, m_min = INFINITY, v_max = 0, at_m_max = 0, at_m_min = 0, at_v_max = 0;
  auto consider = [&](double x, Side side) {
    const double m = solution.bending_moment(x, side), v = std::abs(solution.shear_force(x, side));
    if (m > m_max) m_max = m, at_m_max = x;
    if (m < m_min) m_min = m, at_m_min = x;
    if (v > v_max) v_max = v, at_v_max = x;
  };
  for (double x : solution.breakpoints()) {
    if (x > 0.0) consider(x, Side::left);
    if (x < p.length) consider(x, Side::right);
  }
  for (int i = 0; i < samples; ++i) {
    double a = p.length * i / samples, b = p.length * (i + 1) / samples;
    consider(a, Side::right);
    double va = solution.shear_force(a, Side::right);
    if (va * solution.shear_force(b, Side::left) >= 0.0) continue;
    for (int step = 0; step < 200; ++step) {
      const double m = 0.5 * (a + b);
      if (m <= a || m >= b) break;
      const double vm = solution.shear_force(m);
      if ((vm < 0.0) == (va < 0.0))
        a = m, va = vm;
      else
        b = m;
    }
    consider(0.5 * (a + b), Side::right);
  }
  std::printf(
      ", \"moment_max\": %.17g, \"at_moment_max\": %.17g, \"moment_min\": %.17g, \"at_moment_min\": %.17g, "
      "\"shear_max_abs\": %.17g, \"at_shear_max_abs\": %.17g}\n",
      m_max, at_m_max, m_min, at_m_min, v_max, at_v_max);
  return 0;
}
