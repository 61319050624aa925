// closed_form_reference SCENE.toml: the closed-form (segment-by-segment exact) solution of a beam
// scene, as JSON on stdout: {"method": "closed-form", "status", "contact_regions", "w_max",
// "at_w_max", "w_min", "at_w_min"}. It reads the scene with toml++ itself and shares no code
// with liftoff. Exit 2 (one line on stderr) for a scene it does not cover: arches, interior
// point supports, a foundation on part of the member; exit 3 if the solve fails.
#include <toml++/toml.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>

#include "closed_form/beam_on_foundation.hpp"

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

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: closed_form_reference SCENE.toml\n";
    return 2;
  }
  const std::string path = argv[1];
  toml::table scene;
  try {
    scene = toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    refuse(path, std::string("not valid TOML: ") + std::string(e.description()));
  }
  if (scene["structure"]["kind"].value_or(std::string()) != "beam") refuse(path, "only beams have a closed form");
  if (scene["supports"]["interior"]) refuse(path, "interior point supports are not covered");
  if (scene["foundation"]["from"] || scene["foundation"]["to"]) refuse(path, "a partial foundation is not covered");

  BeamProblem p;
  p.length = scene["structure"]["length"].value_or(0.0);
  p.bending_stiffness = scene["structure"]["EI"].value_or(0.0);
  p.left = end(path, scene["supports"]["left"].value_or(std::string()));
  p.right = end(path, scene["supports"]["right"].value_or(std::string()));
  if (auto k = scene["foundation"]["k"].value<double>())
    p.foundation_modulus = *k * p.bending_stiffness / std::pow(p.length, 4);
  else
    p.foundation_modulus = scene["foundation"]["modulus"].value_or(0.0);
  const bool tensionless = scene["foundation"]["tensionless"].value_or(true);
  if (const toml::array* loads = scene["loads"].as_array()) {
    for (const toml::node& node : *loads) {
      const toml::table& load = *node.as_table();
      const std::string kind = load["kind"].value_or(std::string());
      const double value = load["value"].value_or(0.0);
      if (kind == "force") p.forces.push_back({load["at"].value_or(0.0), value});
      if (kind == "moment") p.moments.push_back({load["at"].value_or(0.0), value});
      if (kind == "uniform")
        p.uniform_loads.push_back({load["from"].value_or(0.0), load["to"].value_or(p.length), value});
    }
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
  const auto regions = tensionless ? contact_regions(solution) : std::vector<Interval>{{0.0, p.length}};
  for (std::size_t i = 0; i < regions.size(); ++i)
    std::printf("%s[%.17g, %.17g]", i ? ", " : "", regions[i].start, regions[i].end);
  std::printf("], \"w_max\": %.17g, \"at_w_max\": %.17g, \"w_min\": %.17g, \"at_w_min\": %.17g}\n", w_max, at_max,
              w_min, at_min);
  return 0;
}
