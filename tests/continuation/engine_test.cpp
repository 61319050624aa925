// The path engine (continuation/engine.hpp) on the FE von Karman model: what it does for every
// model, the loads asked for (TraceOptions::report_at) on a folding path.
#include "continuation/engine.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "contact/von_karman_solve.hpp"
#include "continuation/models/fe_member.hpp"
#include "fe/discretisation.hpp"
#include "model/from_scene.hpp"
#include "scene/scene_reader.hpp"

using namespace liftoff;
using namespace liftoff::continuation;

namespace {

model::MemberModel snap_through() {
  return model::make_member_model(scene::read_scene_file(
      std::string(LIFTOFF_SOURCE_DIR) + "/verification/scenes/von_karman/shallow_arch_snap_through.toml"));
}

std::vector<TraceStep> requested_at(const TraceResult& r, double lambda) {
  std::vector<TraceStep> out;
  for (const TraceStep& s : r.steps)
    if (s.requested && s.load_factor == lambda) out.push_back(s);
  return out;
}

}  // namespace

TEST_CASE("engine: a load asked for is located wherever the path passes it, at exactly that load",
          "[continuation][engine]") {
  // The shallow arch snaps through: lambda rises to a limit point (21.13), falls to another (13.54)
  // and rises again. lambda = 15 is passed three times (rising, falling, rising), 25 once (after the
  // snap), 30 is the end of the range.
  const model::MemberModel m = snap_through();
  TraceOptions o;
  o.arc_length.lambda_max = 30.0;
  o.elements = 32;
  o.monitor = 0.5;
  o.report_at = {15.0, 25.0, 30.0};
  const TraceResult r = trace_fe_von_karman(m, o);
  CAPTURE(r.summary.message);
  REQUIRE(r.summary.termination == TraceTermination::completed);
  const std::vector<TraceStep> at_15 = requested_at(r, 15.0), at_25 = requested_at(r, 25.0);
  REQUIRE(at_15.size() == 3);
  REQUIRE(at_25.size() == 1);
  // In the order of the path, the crown deflection grows: three distinct states at one load.
  CHECK(at_15[0].monitor_deflection < at_15[1].monitor_deflection);
  CHECK(at_15[1].monitor_deflection < at_15[2].monitor_deflection);
  CHECK(at_15[2].monitor_deflection < at_25[0].monitor_deflection);
  // Stable on the rising branches, unstable between the limit points.
  CHECK(at_15[0].stability == Stability::stable);
  CHECK(at_15[1].stability == Stability::unstable);
  CHECK(at_15[2].stability == Stability::stable);
  // The end of the range is recorded once, not again as a requested step.
  CHECK(std::count_if(r.steps.begin(), r.steps.end(), [](const TraceStep& s) { return s.load_factor == 30.0; }) <= 2);
  // The first is the contact solve's equilibrium at 15 from the unloaded state (the same discrete
  // problem, both certified to their backward error: they agree to the solves' accuracy).
  const fe::Discretisation d = fe::discretise(m, o.elements);
  const contact::VonKarmanSystem system(m, d);
  const contact::VonKarmanResult solved = system.solve(15.0, contact::VonKarmanOptions{});
  REQUIRE(solved.is_usable());
  CHECK(at_15[0].monitor_deflection == Approx(solved.w[o.elements / 2] * m.scales.displacement()).epsilon(1e-8));
}
