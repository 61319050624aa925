// The whole state a load path records at a step (continuation/step_state.hpp) is `liftoff solve`'s
// answer of the same scene at the same lambda: the scene with its live loads scaled by lambda (solve
// applies every load once; a beam-column's axial force becomes a load of the step's value), solved on
// the same mesh (Ritz: the same modes). Fields at every node (M and V by statics on beams, where solve
// samples them), design values with their positions, support reactions, for the linear FE path (a
// beam, an arch), the FE beam-column path (the upheaval buckle before its limit point), the FE von
// Karman path and the Ritz path.
//
// Tolerances. The two sides solve the same discrete equations by different routes, so they agree
// to those solvers' accuracy, not bitwise: each field within the tolerance of its largest
// magnitude, each design value of its own, each position within it of the member's length. The FE
// paths' states are certified at a backward error of 1e-8 of their terms (the certificate's
// tolerance): 1e-8. The von Karman corrector leaves a state within 1e-7 of w_ref where it is least accurate
// (models/fe_member.hpp; polished to the certificate's backward error otherwise): 1e-7. The Ritz
// corrector converges to 1e-11 of its scaled residual: 1e-8. Measured (printed): 2.5e-12 (FE
// beam, design 7.8e-12), 6.7e-13 (arch), 2.2e-15 (beam-column), 3.2e-11 (von Karman), 5.3e-14
// (Ritz). A wrong record is far off: another step's fields differ by the change of the load between
// steps (percent), V and M by derivatives instead of statics by the element's truncation (1e-3).
#include "continuation/step_state.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "app/solve_command.hpp"
#include "app/trace_command.hpp"
#include "continuation/models/fe_member.hpp"
#include "continuation/models/ritz.hpp"
#include "model/from_scene.hpp"
#include "scene/scene_reader.hpp"
#include "support/trace_scene.hpp"

using namespace liftoff;
using continuation::TraceStep;

namespace {

scene::Scene shipped(const std::string& relative) {
  return scene::read_scene_file(std::string(LIFTOFF_SOURCE_DIR) + "/" + relative);
}

// The scene with its live loads scaled by lambda: `solve` applies every load once.
scene::Scene at_load_factor(scene::Scene scene, double lambda) {
  for (scene::Load& load : scene.loads) {
    if (load.load_case != scene::LoadCase::live) continue;
    load.value *= lambda;
    for (double& v : load.table_value) v *= lambda;
  }
  return scene;
}

double largest(const std::vector<double>& values) {
  double m = 0.0;
  for (double v : values) m = std::max(m, std::abs(v));
  return m;
}

// The largest difference of two fields relative to the larger's largest magnitude.
double relative_difference(const std::vector<double>& a, const std::vector<double>& b) {
  REQUIRE(a.size() == b.size());
  double d = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, std::abs(a[i] - b[i]));
  const double scale = std::max(largest(a), largest(b));
  return scale > 0.0 ? d / scale : d;
}

// The values of solve's sampled field at the nodes: the last sample at each node's coordinate
// (right of a jump), as the step's nodal values take them.
std::vector<double> at_nodes(const io::FieldTable& samples, const std::vector<double>& field,
                             const std::vector<double>& nodes) {
  std::vector<double> out;
  for (double x : nodes) {
    const auto it = std::find(samples.coordinate.rbegin(), samples.coordinate.rend(), x);
    REQUIRE(it != samples.coordinate.rend());
    out.push_back(field[samples.coordinate.size() - 1 - static_cast<std::size_t>(it - samples.coordinate.rbegin())]);
  }
  return out;
}

struct Measured {
  double fields = 0.0, design = 0.0, positions = 0.0, supports = 0.0;
};

// The step against solve's report; `nodes`: the report's node table holds the step's nodes (FE);
// `mirror`: the member and its loads are symmetric about the middle of [0, length], where an
// extreme is attained twice (|V| at both ends) and round-off picks the one reported: either
// position is the extreme's.
Measured compare(const TraceStep& step, const io::SolveReport& r, double length, bool nodes, bool mirror = false) {
  REQUIRE(r.usable);
  Measured m;
  const post::FieldTable& f = step.fields;
  REQUIRE(f.coordinate.size() > 2);
  const auto field = [&](const std::vector<double>& mine, const std::vector<double>& theirs) {
    m.fields = std::max(m.fields, relative_difference(mine, theirs));
  };
  if (nodes) {
    REQUIRE(f.coordinate == r.nodes.coordinate);
    field(f.w, r.nodes.w);
    field(f.rotation, r.nodes.rotation);
    field(f.reaction, r.nodes.reaction);
    if (!r.nodes.u.empty()) field(f.u, r.nodes.u);
  } else {
    field(f.w, at_nodes(r.fields, r.fields.w, f.coordinate));
    field(f.reaction, at_nodes(r.fields, r.fields.reaction, f.coordinate));
    if (!r.fields.u.empty()) field(f.u, at_nodes(r.fields, r.fields.u, f.coordinate));
  }
  field(f.bending_moment, at_nodes(r.fields, r.fields.bending_moment, f.coordinate));
  field(f.shear_force, at_nodes(r.fields, r.fields.shear_force, f.coordinate));
  if (!r.fields.normal_force.empty())
    field(f.normal_force, at_nodes(r.fields, r.fields.normal_force, f.coordinate));
  else if (r.axial_force)  // a beam-column: -N all along (tension positive)
    field(f.normal_force, std::vector<double>(f.coordinate.size(), -*r.axial_force));
  // The gap: g - w where lifted (no ground gap in these scenes), 0 in contact.
  for (std::size_t i = 0; i < f.w.size(); ++i) CHECK(f.gap[i] == std::max(0.0, -f.w[i]));

  REQUIRE(step.design.has_value() == r.design.has_value());
  if (step.design) {
    CHECK(step.design->from_statics == r.design->from_statics);
    // Each design value with the step's field it is the extreme of (|V| for the shear).
    const std::pair<post::DesignValue post::DesignTable::*, const std::vector<double>*> values[] = {
        {&post::DesignTable::moment_max, &f.bending_moment},
        {&post::DesignTable::moment_min, &f.bending_moment},
        {&post::DesignTable::shear_max_abs, &f.shear_force},
        {&post::DesignTable::pressure_max, &f.reaction},
        {&post::DesignTable::uplift_max, &f.gap}};
    for (const auto& [value, field] : values) {
      const post::DesignValue &a = (*step.design).*value, &b = (*r.design).*value;
      const double scale = std::max({std::abs(a.value), std::abs(b.value), 1e-300});
      m.design = std::max(m.design, std::abs(a.value - b.value) / scale);
      REQUIRE(a.at.has_value() == b.at.has_value());
      if (!a.at) continue;
      double apart = std::min(std::abs(*a.at - *b.at), mirror ? std::abs(*a.at + *b.at - length) : INFINITY);
      // An extreme attained at several nodes (a shear constant in an end element, a plateau of
      // pressure) is reported at any of them as round-off picks: solve's position is the step's
      // extreme too if the step's field there reaches the value to the fields' round-off (they agree
      // to ~1e-11 here; 1e-10 of the field's largest magnitude).
      const auto node = std::min_element(f.coordinate.begin(), f.coordinate.end(),
                                         [&](double p, double q) { return std::abs(p - *b.at) < std::abs(q - *b.at); });
      const double there = std::abs((*field)[static_cast<std::size_t>(node - f.coordinate.begin())]);
      if (*node == *b.at && std::abs(there - std::abs(a.value)) <= 1e-10 * largest(*field)) apart = 0.0;
      m.positions = std::max(m.positions, apart / length);
    }
  }
  const std::vector<certify::SupportReaction>& theirs = r.certificate_figures.support_reactions;
  REQUIRE(step.supports.size() == theirs.size());
  double force = 1e-300, moment = 1e-300;
  for (const auto& s : theirs)
    force = std::max(force, std::abs(s.force)), moment = std::max(moment, std::abs(s.moment));
  for (std::size_t i = 0; i < theirs.size(); ++i) {
    CHECK(step.supports[i].at == theirs[i].at);
    m.supports = std::max({m.supports, std::abs(step.supports[i].force - theirs[i].force) / force,
                           std::abs(step.supports[i].moment - theirs[i].moment) / moment,
                           std::abs(step.supports[i].tangential - theirs[i].tangential) /
                               std::max({std::abs(theirs[i].tangential), force, 1e-300})});
  }
  return m;
}

void check_agreement(const Measured& m, double tolerance, const std::string& what) {
  INFO(what);
  WARN(fmt::format("{}: fields {:.1e}, design {:.1e}, positions {:.1e}, supports {:.1e}", what, m.fields, m.design,
                   m.positions, m.supports));
  CHECK(m.fields <= tolerance);
  CHECK(m.design <= tolerance);
  CHECK(m.positions <= tolerance);
  CHECK(m.supports <= tolerance);
}

app::SolveRequest solve_request(scene::Method method, int elements) {
  app::SolveRequest request;
  request.method = method;
  request.elements = elements;
  request.fields = true;
  return request;
}

// The FE path's steps of the scene on `elements` elements.
std::vector<TraceStep> fe_steps(const scene::Scene& scene, int elements) {
  app::TraceRequest request;
  request.elements = elements;
  const continuation::TraceResult result = test::trace_fe(scene, app::trace_options(scene, request));
  REQUIRE(result.summary.is_usable());
  return result.steps;
}

// A step inside the path (not its start, where the live load is zero).
const TraceStep& middle(const std::vector<TraceStep>& steps) {
  REQUIRE(steps.size() >= 3);
  return steps[steps.size() / 2];
}

}  // namespace

TEST_CASE("step state: the linear FE path's beam step is solve's answer at its lambda", "[continuation][record]") {
  const scene::Scene scene = shipped("continuation/scenes/simply_supported_end_moments.toml");
  const int elements = 100;
  const std::vector<TraceStep> steps = fe_steps(scene, elements);
  const TraceStep& step = middle(steps);
  const io::SolveReport r =
      app::solve_scene(at_load_factor(scene, step.load_factor), solve_request(scene::Method::fast, elements));
  REQUIRE(step.design.has_value());
  CHECK(step.design->from_statics);  // V and M of a beam by statics, as solve's
  check_agreement(compare(step, r, 6.0, true), 1e-8, fmt::format("FE beam at lambda {}", step.load_factor));
}

TEST_CASE("step state: the linear FE path's arch step is solve's answer at its lambda", "[continuation][record]") {
  const scene::Scene scene = shipped("continuation/scenes/arch_culvert.toml");
  const int elements = 100;
  const std::vector<TraceStep> steps = fe_steps(scene, elements);
  const TraceStep& step = middle(steps);
  const io::SolveReport r =
      app::solve_scene(at_load_factor(scene, step.load_factor), solve_request(scene::Method::fast, elements));
  REQUIRE_FALSE(step.fields.u.empty());  // an arch's tangential displacement
  check_agreement(compare(step, r, 160.0, true), 1e-8, fmt::format("FE arch at lambda {}", step.load_factor));
}

TEST_CASE("step state: the upheaval buckle's step is solve's answer at its axial force", "[continuation][record]") {
  scene::Scene scene = shipped("continuation/scenes/pipeline_upheaval.toml");
  scene.trace->lambda_max = 5.5;  // lifted (from 4.93), below the limit point (5.84): solve holds there
  const int elements = 100;
  const std::vector<TraceStep> steps = fe_steps(scene, elements);
  const TraceStep& step = steps.back();
  REQUIRE(step.load_factor == 5.5);
  REQUIRE(step.lifted_length > 0.0);
  const io::SolveReport r = app::solve_scene(at_load_factor(scene, 5.5), solve_request(scene::Method::fast, elements));
  REQUIRE(r.axial_force.has_value());
  CHECK(step.axial_force == Approx(*r.axial_force).epsilon(1e-15));
  check_agreement(compare(step, r, 200.0, true), 1e-8, "FE beam-column at lambda 5.5");
}

TEST_CASE("step state: the von Karman FE path's step is solve's answer at its lambda", "[continuation][record]") {
  const scene::Scene scene = shipped("verification/scenes/von_karman/steel_strip_membrane.toml");
  const int elements = 100;
  const std::vector<TraceStep> steps = fe_steps(scene, elements);
  const TraceStep& step = steps.back();  // lambda_max = 1: the scene as it is
  REQUIRE(step.load_factor == 1.0);
  const io::SolveReport r = app::solve_scene(scene, solve_request(scene::Method::automatic, elements));
  REQUIRE_FALSE(step.fields.u.empty());  // the axial displacement at the nodes
  check_agreement(compare(step, r, 3.0, true, true), 1e-7, "FE von Karman beam at lambda 1");
}

TEST_CASE("step state: the Ritz path's step is solve's Ritz answer at its lambda", "[continuation][record]") {
  const scene::Scene scene = shipped("continuation/scenes/simply_supported_end_moments.toml");
  const int elements = 50, modes = 32;
  app::TraceRequest request;
  request.elements = elements;
  request.modes = modes;
  request.method = scene::Method::ritz;
  const continuation::TraceResult result =
      continuation::trace_ritz(model::make_member_model(scene), app::trace_options(scene, request));
  REQUIRE(result.summary.is_usable());
  const TraceStep& step = middle(result.steps);
  REQUIRE(step.fields.coordinate.size() == static_cast<std::size_t>(elements) + 1);  // solve's every 16th sample
  app::SolveRequest solve = solve_request(scene::Method::ritz, elements);
  solve.modes = modes;
  const io::SolveReport r = app::solve_scene(at_load_factor(scene, step.load_factor), solve);
  check_agreement(compare(step, r, 6.0, false), 1e-8, fmt::format("Ritz beam at lambda {}", step.load_factor));
}
