// The Ritz load history of the 500 m pipeline (continuation/scenes/pipeline_uplift.toml) over
// its whole range, lambda = 0 to 3 (issue 10, finding 3: the path once ended there `completed`
// in "full contact" with a reaction of -8426 N/m). About 5 s of one core: 256 modes, and the
// lift-off zone grows from nothing to 215 m. ritz_path_test runs the same scene to 0.5.

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <sstream>
#include <string>

#include "continuation/models/fe_member.hpp"
#include "continuation/models/ritz.hpp"
#include "model/from_scene.hpp"
#include "model/member_model.hpp"
#include "ritz/ritz_solver.hpp"
#include "scene/scene_reader.hpp"
#include "support/ritz_trace.hpp"
#include "support/scenes.hpp"
#include "support/trace_scene.hpp"

using namespace liftoff;
using namespace liftoff::continuation;

TEST_CASE("ritz path stress: the pipeline to lambda = 3, every step a contact solution, the end as the FE path's",
          "[ritz_path][stress]") {
  const scene::Scene s = test::continuation_scene("pipeline_uplift");
  TraceOptions options;
  options.arc_length.lambda_max = *s.trace->lambda_max;
  options.monitor = 250.0;
  for (int i = 0; i <= 500; ++i) options.sample_points.push_back(i);  // every metre
  const TraceResult ritz = test::trace_ritz_scene(s, options);
  INFO(ritz.summary.message);
  REQUIRE(ritz.summary.termination == TraceTermination::completed);
  CHECK(ritz.summary.steps == static_cast<int>(ritz.steps.size()));
  REQUIRE(ritz.events.size() == 1);  // the one zone opening at the load, then growing
  CHECK(ritz.events[0].kind == EventKind::lift_off_opens);

  // Every step: w >= 0 in its contact regions, w <= 0 and no reaction outside (the path's own
  // check allows 1e-9 of max |w|; at the event step, w touching zero at the load by what
  // locating the event leaves, 1e-6 of max |w|).
  double previous = -INFINITY;
  for (const TraceStep& step : ritz.steps) {
    INFO("lambda " << step.load_factor);
    CHECK(step.load_factor >= previous);
    previous = step.load_factor;
    double scale = 0.0;
    for (double w : step.deflection) scale = std::max(scale, std::abs(w));
    const double tolerance = (step.load_factor == ritz.events[0].load_factor ? 1e-6 : 1e-9) * scale;
    for (std::size_t i = 0; i < options.sample_points.size(); ++i) {
      const double x = options.sample_points[i];
      bool inside = false;
      for (const auto& region : step.contact_regions) inside = inside || (x >= region.begin && x <= region.end);
      INFO("x = " << x << ": w = " << step.deflection[i] << ", reaction " << step.reaction[i]);
      if (inside) {
        CHECK(step.deflection[i] >= -tolerance);
        CHECK(step.reaction[i] >= -tolerance * *s.foundation.modulus);
      } else {
        CHECK(step.deflection[i] <= tolerance);
        CHECK(step.reaction[i] == 0.0);
      }
    }
  }

  // The end state: two contact regions [0, a] and [L - a, L]. The FE path's a at 200 elements,
  // its error the change to 400 times 3 (h^2 or faster); the Ritz a's error the change from a
  // solve of the same state with half the modes (with an error falling like N^-q, q >= 1, the
  // change bounds the error of the larger N).
  const TraceStep& end = ritz.steps.back();
  REQUIRE(end.load_factor == options.arc_length.lambda_max);
  REQUIRE(end.contact_regions.size() == 2);
  const double a_ritz = end.contact_regions[0].end;
  CHECK(std::abs(end.contact_regions[1].begin - (500.0 - a_ritz)) < 1e-9 * 500.0);  // symmetric
  const TraceResult fe = test::trace_fe(s, options);
  TraceOptions fine_options = options;
  fine_options.elements = 400;
  const TraceResult fine = test::trace_fe(s, fine_options);
  REQUIRE(fe.summary.termination == TraceTermination::completed);
  REQUIRE(fine.summary.termination == TraceTermination::completed);
  REQUIRE(fe.steps.back().contact_regions.size() == 2);
  REQUIRE(fine.steps.back().contact_regions.size() == 2);
  const double a_fe = fe.steps.back().contact_regions[0].end;
  const double fe_error = 3.0 * std::abs(a_fe - fine.steps.back().contact_regions[0].end);

  const auto& topology = std::get<continuation::RitzTopology>(end.state_topology);
  const int modes = topology.modes;
  REQUIRE(topology.limits == 2);
  const model::MemberModel member = model::make_member_model(s);
  ritz::RitzOptions half;
  half.modes = modes / 2;
  half.load_factor = options.arc_length.lambda_max;
  const ritz::RitzSolution coarse =
      ritz::solve_ritz(member, {true, 2}, {member.s_from_user(a_ritz), member.s_from_user(500.0 - a_ritz)}, half);
  INFO(coarse.summary.message);
  REQUIRE(coarse.summary.is_usable());
  const double ritz_error = std::abs(member.user_from_s(coarse.unknowns[coarse.model->limit_offset()]) - a_ritz);
  CAPTURE(a_ritz, a_fe, fe_error, ritz_error);
  CHECK(std::abs(a_ritz - a_fe) <= fe_error + ritz_error);
  // And the load point's rise, as the FE path has it (w is smooth there: the same estimates,
  // relative, bound it generously).
  CHECK(end.monitor_deflection == Approx(fe.steps.back().monitor_deflection).epsilon(1e-3));
}
