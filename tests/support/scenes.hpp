#pragma once
// Helpers shared by the tests: shipped scenes by name (verification/scenes, and the trace tests'
// continuation/scenes), and small scenes built in code.

#include <string>

#include "scene/scene.hpp"
#include "scene/scene_reader.hpp"

namespace liftoff::test {

inline scene::Scene shipped_scene(const std::string& name) {
  return scene::read_scene_file(std::string(LIFTOFF_SOURCE_DIR) + "/verification/scenes/" + name + ".toml");
}

inline scene::Scene continuation_scene(const std::string& name) {
  return scene::read_scene_file(std::string(LIFTOFF_SOURCE_DIR) + "/continuation/scenes/" + name + ".toml");
}

// A beam of length L with EI, the given supports and foundation parameter k, no loads.
inline scene::Scene beam_scene(double length, double bending_stiffness, scene::EndSupport left, scene::EndSupport right,
                               double k, bool tensionless = true) {
  scene::Scene s;
  s.source_name = "<test beam>";
  s.structure.kind = scene::StructureKind::beam;
  s.structure.length = length;
  s.structure.bending_stiffness = bending_stiffness;
  s.supports.left = left;
  s.supports.right = right;
  s.foundation.k = k;
  s.foundation.tensionless = tensionless;
  s.foundation.from = 0.0;
  s.foundation.to = length;
  return s;
}

inline scene::Load point_force(double at, double value, scene::LoadCase c = scene::LoadCase::live) {
  scene::Load l;
  l.kind = scene::LoadKind::force;
  l.at = at;
  l.value = value;
  l.load_case = c;
  return l;
}

inline scene::Load point_moment(double at, double value) {
  scene::Load l;
  l.kind = scene::LoadKind::moment;
  l.at = at;
  l.value = value;
  return l;
}

inline scene::Load uniform_load(double from, double to, double value, scene::LoadCase c = scene::LoadCase::live) {
  scene::Load l;
  l.kind = scene::LoadKind::uniform;
  l.from = from;
  l.to = to;
  l.value = value;
  l.load_case = c;
  return l;
}

// The B70 sleeper of verification/scenes/engineering/sleeper_b70_ballast.toml (N, m) as scene
// text: L = 2.6, EI = 4.5e6, free ends, two rail-seat loads of 125 kN; the [foundation] table
// holds the lines `foundation` (its first on line 10), and `tail` follows the loads (line 19 on).
inline std::string sleeper_b70(const std::string& foundation, const std::string& tail = "") {
  return R"(
[structure]
kind = "beam"
length = 2.6
EI = 4.5e6
[supports]
left = "free"
right = "free"
[foundation]
)" + foundation +
         R"(
[[loads]]
kind = "force"
at = 0.55
value = 125.0e3
[[loads]]
kind = "force"
at = 2.05
value = 125.0e3
)" + tail;
}

}  // namespace liftoff::test
