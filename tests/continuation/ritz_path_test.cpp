// The Ritz load history (continuation/models/ritz.hpp) on the free-free beam that lifts off at
// its centre: the first lift-off load against the closed form, the zone's growth past it, and
// a resumed trace.
//
// Beam L = 10, EI = 1e4, free-free, tensionless foundation k = K L^4/EI = 500 over the whole
// length, dead uniform load q = 1 into the foundation, live central force -1 (pulling the beam
// off). Before lift-off the beam is in full contact, so w = q/K + lambda w_live with w_live the
// bilateral deflection under the live force alone; lift-off begins at the centre when w(5) = 0:
//     lambda* = (q / K) / (-w_live(5)).

#include <fmt/format.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <complex>
#include <sstream>
#include <string>

#include "closed_form/beam_on_foundation.hpp"
#include "continuation/models/fe_member.hpp"
#include "continuation/models/ritz.hpp"
#include "scene/scene_reader.hpp"
#include "support/ritz_trace.hpp"
#include "support/scenes.hpp"
#include "support/trace_scene.hpp"

using namespace liftoff;
using namespace liftoff::continuation;

namespace {

constexpr double length = 10.0, bending_stiffness = 1e4, k = 500.0, q = 1.0, pull = -1.0;

scene::Scene lift_off_beam() {
  scene::Scene s = test::beam_scene(length, bending_stiffness, scene::EndSupport::free, scene::EndSupport::free, k);
  s.loads.push_back(test::uniform_load(0.0, length, q, scene::LoadCase::dead));
  s.loads.push_back(test::point_force(5.0, pull, scene::LoadCase::live));
  return s;
}

// lambda* from the closed form (verification/closed_form: an independent exact solution).
double closed_form_lift_off_load() {
  closed_form::BeamProblem problem;
  problem.length = length;
  problem.bending_stiffness = bending_stiffness;
  problem.foundation_modulus = k * bending_stiffness / std::pow(length, 4);
  problem.left = problem.right = closed_form::EndCondition::free;
  problem.forces.push_back({5.0, pull});
  const closed_form::BeamSolution live = closed_form::solve_bilateral(problem);
  return (q / problem.foundation_modulus) / (-live.deflection(5.0));
}

TraceOptions options_for(int modes) {
  TraceOptions o;
  o.arc_length.lambda_min = 0.0;
  o.arc_length.lambda_max = 8.0;
  o.ritz.modes = modes;
  o.monitor = 5.0;
  o.sample_points = {0.0, 2.5, 5.0};
  return o;
}

// The trace of `s` resumed from `original`'s step `from`: required completed and holding exactly
// the steps after `from` (nothing already written), each at the original's load factor.
TraceResult resumed_trace(const scene::Scene& s, TraceOptions options, const TraceResult& original, std::size_t from) {
  options.resume_from = original.steps[from];
  TraceResult resumed = test::trace_ritz_scene(s, options);
  INFO(resumed.summary.message);
  REQUIRE(resumed.summary.termination == TraceTermination::completed);
  REQUIRE(resumed.steps.size() == original.steps.size() - from - 1);
  for (std::size_t i = 0; i < resumed.steps.size(); ++i)
    CHECK(resumed.steps[i].load_factor == Approx(original.steps[from + 1 + i].load_factor).epsilon(1e-12));
  return resumed;
}

}  // namespace

TEST_CASE("ritz path: the first lift-off load matches the closed form", "[ritz_path]") {
  const double exact = closed_form_lift_off_load();
  // Modal convergence: with the load-point enrichment (ritz/basis.hpp) the error of w at the
  // load falls like N^-8 (measured: 2.5e-6, 5.2e-9, 2.2e-11 relative at N = 8, 16, 32). Demand
  // at least a factor 2^4 per doubling, and 1e-8 at N = 32, where the N = 16 -> 32 change
  // (an upper estimate of the N = 16 error) predicts about 2e-11.
  double previous_error = 0.0;
  for (int modes : {16, 32}) {
    std::vector<TraceEvent> seen;
    TraceSink sink;
    sink.on_event = [&](const TraceEvent& e) { seen.push_back(e); };
    const TraceResult r = test::trace_ritz_scene(lift_off_beam(), options_for(modes), sink);
    INFO("N = " << modes << ": " << r.summary.message);
    REQUIRE(r.summary.termination == TraceTermination::completed);
    REQUIRE_FALSE(r.events.empty());
    const TraceEvent& first = r.events.front();
    CHECK(first.kind == EventKind::lift_off_opens);
    CHECK(std::abs(first.at - 5.0) < 1e-9 * length);  // the minimum of w, refined to round-off
    const double error = std::abs(first.load_factor / exact - 1);
    CAPTURE(first.load_factor, exact, error);
    if (modes == 32) {
      CHECK(error < 1e-8);
      CHECK(error < previous_error / 16);
    }
    previous_error = error;
    // Events reach the sink as they are found, the same as in the result.
    REQUIRE(seen.size() == r.events.size());
    CHECK(seen.front().load_factor == first.load_factor);
  }
}

TEST_CASE("ritz path: the lift-off zone grows symmetrically past the first lift-off", "[ritz_path]") {
  std::vector<TraceStep> streamed;
  TraceSink sink;
  sink.on_step = [&](const TraceStep& s) { streamed.push_back(s); };
  const TraceOptions options = options_for(32);
  const TraceResult r = test::trace_ritz_scene(lift_off_beam(), options, sink);
  INFO(r.summary.message);
  REQUIRE(r.summary.termination == TraceTermination::completed);
  REQUIRE(streamed.size() == r.steps.size());
  CHECK(r.steps.front().load_factor == options.arc_length.lambda_min);
  CHECK(r.steps.back().load_factor == options.arc_length.lambda_max);
  // Only the one event on this range: the zone grows from the centre without reaching the ends.
  REQUIRE(r.events.size() == 1);
  const double lambda_star = r.events.front().load_factor;

  double previous_width = 0.0, previous_lambda = -1.0;
  int zone_steps = 0;
  for (const TraceStep& step : r.steps) {
    CHECK(step.load_factor > previous_lambda);  // no folds: lambda grows along the path
    previous_lambda = step.load_factor;
    if (step.load_factor <= lambda_star) {
      REQUIRE(step.contact_regions.size() == 1);  // full contact
      CHECK(step.contact_regions[0].begin == 0.0);
      CHECK(step.contact_regions[0].end == length);
      // Full contact: w(5) = q/K + lambda w_live(5) falls linearly to 0 at lambda*.
      const double w_centre = step.deflection[2];
      CHECK(std::abs(w_centre -
                     (q / (k * bending_stiffness / std::pow(length, 4))) * (1 - step.load_factor / lambda_star)) <
            1e-9 * q / (k * bending_stiffness / std::pow(length, 4)));
      continue;
    }
    REQUIRE(step.contact_regions.size() == 2);
    const double left = step.contact_regions[0].end, right = step.contact_regions[1].begin;
    // Symmetric about the load to round-off (the limits are solved, not mirrored).
    CHECK(std::abs((left + right) / 2 - 5.0) < 1e-9 * length);
    const double width = right - left;
    CHECK(width > previous_width);  // grows monotonically
    previous_width = width;
    CHECK(step.deflection[2] < 0.0);  // the centre has lifted off
    CHECK(step.reaction[2] == 0.0);
    CHECK(step.reaction[0] > 0.0);  // the ends still press on the foundation
    ++zone_steps;
  }
  CHECK(zone_steps >= 5);
  // The steps adapt: one corrector iteration (or none) in full contact, where the problem is
  // linear, so the steps grow to max_step; several past lift-off, so they shrink.
  double largest = 0.0, smallest_after = 1e300;
  for (std::size_t i = 1; i < r.steps.size(); ++i) {
    const double d = r.steps[i].load_factor - r.steps[i - 1].load_factor;
    if (r.steps[i].load_factor <= lambda_star)
      largest = std::max(largest, d);
    else if (r.steps[i - 1].load_factor > lambda_star)
      smallest_after = std::min(smallest_after, d);
  }
  CHECK(r.steps[1].load_factor - r.steps[0].load_factor < largest / 2);  // initial_step, then growing
  CHECK(smallest_after < largest);
  CHECK(r.summary.corrector_iterations > 0);
}

TEST_CASE("ritz path: a resumed trace reproduces the original", "[ritz_path]") {
  const TraceOptions options = options_for(32);
  const TraceResult original = test::trace_ritz_scene(lift_off_beam(), options);
  REQUIRE(original.summary.termination == TraceTermination::completed);
  // Resume from a step in full contact (before the event), from the event's own step (the
  // switch is redone), and from one past it.
  REQUIRE(original.events.size() == 1);
  std::size_t event_step = 0;
  while (original.steps[event_step].load_factor != original.events[0].load_factor) ++event_step;
  const std::size_t last = original.steps.size() - 1;
  for (std::size_t from : {last * 3 / 10, event_step, last * 85 / 100}) {
    CAPTURE(from, original.steps[from].load_factor);
    const TraceResult resumed = resumed_trace(lift_off_beam(), options, original, from);
    for (std::size_t i = 0; i < resumed.steps.size(); ++i) {
      const TraceStep& a = original.steps[from + 1 + i];
      const TraceStep& b = resumed.steps[i];
      CHECK(b.monitor_deflection == Approx(a.monitor_deflection).epsilon(1e-9));
      REQUIRE(b.contact_regions.size() == a.contact_regions.size());
      for (std::size_t j = 0; j < a.contact_regions.size(); ++j) {
        CHECK(std::abs(b.contact_regions[j].begin - a.contact_regions[j].begin) < 1e-9 * length);
        CHECK(std::abs(b.contact_regions[j].end - a.contact_regions[j].end) < 1e-9 * length);
      }
    }
    // The events after `from` (an event at `from` itself was written with its step).
    std::vector<TraceEvent> later;
    for (const TraceEvent& e : original.events)
      if (e.load_factor > original.steps[from].load_factor) later.push_back(e);
    CHECK(std::get<continuation::RitzTopology>(original.steps[from].state_topology).at_event.has_value() ==
          (from == event_step));
    REQUIRE(resumed.events.size() == later.size());
    for (std::size_t i = 0; i < later.size(); ++i) {
      CHECK(resumed.events[i].kind == later[i].kind);
      CHECK(resumed.events[i].load_factor == Approx(later[i].load_factor).epsilon(1e-12));
    }
  }
}

TEST_CASE("ritz path: load control and arc-length agree where both apply", "[ritz_path]") {
  TraceOptions options = options_for(16);
  options.arc_length.control = PathControl::load;
  const TraceResult load = test::trace_ritz_scene(lift_off_beam(), options);
  options.arc_length.control = PathControl::arc_length;
  const TraceResult arc = test::trace_ritz_scene(lift_off_beam(), options);
  REQUIRE(load.summary.termination == TraceTermination::completed);
  REQUIRE(arc.summary.termination == TraceTermination::completed);
  REQUIRE(load.events.size() == arc.events.size());
  CHECK(load.events.front().load_factor == Approx(arc.events.front().load_factor).epsilon(1e-10));
  CHECK(load.steps.back().contact_regions[0].end == Approx(arc.steps.back().contact_regions[0].end).epsilon(1e-9));
}

TEST_CASE("ritz path: bad options are refused with the field named", "[ritz_path]") {
  TraceOptions options = options_for(16);
  options.arc_length.lambda_max = options.arc_length.lambda_min;
  CHECK_THROWS_WITH(test::trace_ritz_scene(lift_off_beam(), options), Catch::Contains("lambda_max"));
  options = options_for(16);
  options.sample_points = {11.0};
  CHECK_THROWS_WITH(test::trace_ritz_scene(lift_off_beam(), options), Catch::Contains("sample_points"));
  options = options_for(16);
  options.resume_from = TraceStep{};
  CHECK_THROWS_WITH(test::trace_ritz_scene(lift_off_beam(), options), Catch::Contains("resume_from"));
}

TEST_CASE("ritz path: the end regions shrink to nothing when the pull equals the weight", "[ritz_path]") {
  // Statics: the foundation's resultant is q L - lambda, so the contact regions at the ends
  // vanish at lambda = q L = 10 and beyond it nothing holds the free-free beam.
  TraceOptions options = options_for(16);
  options.arc_length.lambda_max = 12.0;
  const TraceResult r = test::trace_ritz_scene(lift_off_beam(), options);
  INFO(r.summary.message);
  CHECK(r.summary.termination == TraceTermination::no_equilibrium);
  REQUIRE(r.events.size() == 3);  // lift-off at the centre, then both limits reach the ends
  CHECK(r.events[0].kind == EventKind::lift_off_opens);
  const double weight = q * length;
  for (int i : {1, 2}) {
    CHECK(r.events[i].kind == EventKind::limit_at_end);
    // Located to event_tolerance in lambda; the Ritz statics are exact (the uniform load and
    // the constant mode), so only the location and the corrector's tolerance enter.
    CHECK(std::abs(r.events[i].load_factor - weight) < 10 * options.event_tolerance * weight);
  }
  CHECK(r.events[1].at == 0.0);
  CHECK(r.events[2].at == length);
  CHECK(r.steps.back().load_factor == r.events[2].load_factor);
  for (const TraceStep& step : r.steps) CHECK(step.load_factor <= weight * (1 + 1e-9));
}

TEST_CASE("ritz path: live loads alone scale the solution, the topology stays (seed arch)", "[ritz_path]") {
  // No dead load: w(lambda) = lambda w(1) for lambda > 0, with the same contact limits. The path
  // starts one initial_step above lambda_min = 0 (at 0 every topology fits w = 0).
  const scene::Scene arch = test::shipped_scene("seed_arch_roller");
  TraceOptions options;
  options.arc_length.lambda_max = 1.0;
  options.ritz.modes = 32;
  options.monitor = 0.0;  // the crown
  const TraceResult r = test::trace_ritz_scene(arch, options);
  INFO(r.summary.message);
  REQUIRE(r.summary.termination == TraceTermination::completed);
  CHECK(r.events.empty());
  REQUIRE(r.steps.size() >= 3);
  CHECK(r.steps.front().load_factor == options.arc_length.initial_step);
  const TraceStep& last = r.steps.back();
  REQUIRE(last.contact_regions.size() == 1);
  for (const TraceStep& step : r.steps) {
    REQUIRE(step.contact_regions.size() == 1);
    CHECK(std::abs(step.contact_regions[0].begin - last.contact_regions[0].begin) < 1e-9);  // degrees
    CHECK(std::abs(step.contact_regions[0].end - last.contact_regions[0].end) < 1e-9);
    CHECK(step.monitor_deflection / step.load_factor == Approx(last.monitor_deflection).epsilon(1e-9));
  }
}

TEST_CASE("ritz path: on a long beam two lift-off zones open together at beta x = pi", "[ritz_path]") {
  // The classical result (as in tests/verification/classical_test.cpp): a long free-free beam
  // under its weight q and a central force P lifts off at beta |x - L/2| = pi when
  // P beta / q = 2 e^pi (the finite length changes this by ~e^(-beta L / 2)). Here beta L = 40,
  // q = 1 dead, P = lambda live: lambda* = 2 e^pi / beta. No enrichment at this beta L (the
  // path's rule), so the Ritz error is several 1e-3: the tolerance is the change from N = 64
  // to N = 128, an upper estimate of the N = 128 error for a monotone modal convergence.
  const double beta = 40.0, pi = 3.14159265358979323846;
  scene::Scene s = test::beam_scene(1.0, 1.0, scene::EndSupport::free, scene::EndSupport::free, 4 * std::pow(beta, 4));
  s.loads = {test::uniform_load(0.0, 1.0, 1.0, scene::LoadCase::dead), test::point_force(0.5, 1.0)};
  const double exact = 2 * std::exp(pi) / beta;
  std::vector<TraceEvent> first_events[2];
  for (int n : {0, 1}) {
    TraceOptions options;
    options.arc_length.lambda_max = 1.5;
    options.ritz.modes = n == 0 ? 64 : 128;
    options.monitor = 0.5;
    const TraceResult r = test::trace_ritz_scene(s, options);
    INFO(r.summary.message);
    REQUIRE(r.summary.termination == TraceTermination::completed);
    REQUIRE(r.events.size() == 2);  // both zones, at one lambda
    CHECK(r.events[0].kind == EventKind::lift_off_opens);
    CHECK(r.events[1].kind == EventKind::lift_off_opens);
    CHECK(r.events[0].load_factor == r.events[1].load_factor);
    CHECK(std::abs(r.events[0].at + r.events[1].at - 1.0) < 1e-9);  // symmetric about the load
    REQUIRE(r.steps.back().contact_regions.size() == 3);
    first_events[n] = r.events;
  }
  const double lambda_change = std::abs(first_events[1][0].load_factor - first_events[0][0].load_factor);
  const double position_change = std::abs(first_events[1][0].at - first_events[0][0].at);
  CAPTURE(first_events[1][0].load_factor, exact, lambda_change);
  CHECK(std::abs(first_events[1][0].load_factor - exact) <= lambda_change);
  CHECK(std::abs(beta * std::abs(first_events[1][0].at - 0.5) - pi) <= beta * position_change);
}

// --------------------------------------------------------------------------------------------
// Issue 10, finding 3: the Ritz path reported impossible states as `completed` (the pipeline
// below ended in "full contact" with a reaction of -8426 N/m) and wandered back and forth in
// lambda on the arch culvert. Now every state it records is a contact solution, the path
// agrees with the FE path's events within their estimates, or it stops (solver_failure) saying
// why.

namespace {

// What `liftoff trace` would take from the scene's [trace] table, `samples` points along it.
TraceOptions scene_options(const scene::Scene& s, int samples) {
  TraceOptions o;
  o.arc_length.lambda_min = s.trace->lambda_min;
  o.arc_length.lambda_max = *s.trace->lambda_max;
  o.monitor = 0.5 * (s.begin() + s.end());
  for (int i = 0; i < samples; ++i) o.sample_points.push_back(s.begin() + (s.end() - s.begin()) * i / (samples - 1));
  return o;
}

// The modes a Ritz step was traced with (its state_topology's).
int modes_of(const TraceStep& step) { return std::get<continuation::RitzTopology>(step.state_topology).modes; }

// Every recorded step is a contact solution at its samples: w >= 0 inside its contact regions
// (the reaction there is k w >= 0), w <= 0 outside, and no reaction outside. The path's own
// check allows 1e-9 of max |w| (ritz::check_inequalities); a step at an event may also have w
// touching zero where the event is, by what locating it to 1e-10 in lambda leaves (1e-6 of
// max |w|: the path's own threshold for an extreme "at zero"). Lambda grows along the path.
void check_contact_solutions(const TraceResult& r, const std::vector<double>& samples) {
  std::vector<double> event_loads;
  for (const TraceEvent& e : r.events) event_loads.push_back(e.load_factor);
  double previous = -INFINITY;
  for (const TraceStep& step : r.steps) {
    INFO("step at lambda " << step.load_factor);
    CHECK(step.load_factor >= previous);
    previous = step.load_factor;
    double scale = 0.0;
    for (double w : step.deflection) scale = std::max(scale, std::abs(w));
    const bool at_event = std::find(event_loads.begin(), event_loads.end(), step.load_factor) != event_loads.end();
    const double tolerance = (at_event ? 1e-6 : 1e-9) * scale;
    for (std::size_t i = 0; i < samples.size(); ++i) {
      bool inside = false;
      for (const auto& region : step.contact_regions)
        if (samples[i] >= region.begin && samples[i] <= region.end) inside = true;
      INFO("at " << samples[i] << ": w = " << step.deflection[i] << ", reaction " << step.reaction[i]);
      if (inside) {
        CHECK(step.deflection[i] >= -tolerance);
      } else {
        CHECK(step.deflection[i] <= tolerance);
        CHECK(step.reaction[i] == 0.0);
      }
    }
  }
}

// The path's estimate of how well N modes resolve a point force's local response (documented in
// models/ritz.hpp): e(N) = 8/(3 pi) (beta length / (pi N))^3.
double resolution_error(double beta_length, int modes) {
  const double pi = 3.14159265358979323846, ratio = beta_length / (pi * modes);
  return 8.0 / (3.0 * pi) * ratio * ratio * ratio;
}

}  // namespace

TEST_CASE("ritz path: the pipeline lifts off at Hetenyi's load, as the FE path says, and no step pulls",
          "[ritz_path][issue10]") {
  scene::Scene s = test::continuation_scene("pipeline_uplift");
  // The scene runs to lambda = 3 (tests/stress/ritz_path_stress_test.cpp); the lift-off at 0.2
  // and the zone's first growth are what this test needs, at a fraction of the time.
  s.trace->lambda_max = 0.5;
  const TraceOptions options = scene_options(s, 201);
  const TraceResult r = test::trace_ritz_scene(s, options);
  INFO(r.summary.message);
  REQUIRE(r.summary.termination == TraceTermination::completed);
  REQUIRE(r.events.size() == 1);
  const TraceEvent& lift_off = r.events.front();
  CHECK(lift_off.kind == EventKind::lift_off_opens);
  CHECK(std::abs(lift_off.at - 250.0) < 1e-9 * 500.0);
  check_contact_solutions(r, options.sample_points);

  // Hetenyi: the infinite beam lifts the load point by lambda F beta / (2K) against q/K (the
  // clamped ends are 50 / beta away: e^-50).
  const double K = *s.foundation.modulus, EI = s.structure.bending_stiffness, L = s.structure.length;
  const double beta = std::pow(K / (4.0 * EI), 0.25), q = s.loads[0].value, F = -s.loads[1].value;
  const double hetenyi = 2.0 * q / (F * beta);
  const int modes = modes_of(r.steps.back());
  CHECK(modes >= 256);  // automatic modes from beta L (e <= 1e-3 needs 302, max_modes is 256)
  // The estimate e(N) follows the measured error closely (0.92 to 0.98 of it at N = 64, 128,
  // 256): twice it bounds the error.
  const double ritz_error = 2.0 * resolution_error(beta * L, modes) * hetenyi;
  CAPTURE(lift_off.load_factor, hetenyi, ritz_error);
  CHECK(std::abs(lift_off.load_factor - hetenyi) <= ritz_error);
  CHECK(r.summary.message.find("resolved to about") != std::string::npos);

  // The FE path: its event at 200 elements, with the change to 400 times 3 as its error (the
  // event load converges at h^2 or faster here: 0.19901, 0.19979 against 0.19992).
  TraceOptions fe_options = options;
  const TraceResult fe = test::trace_fe(s, fe_options);
  fe_options.elements = 400;
  const TraceResult fine = test::trace_fe(s, fe_options);
  REQUIRE(fe.events.size() == 1);
  REQUIRE(fine.events.size() == 1);
  const double fe_error = 3.0 * std::abs(fe.events[0].load_factor - fine.events[0].load_factor);
  CAPTURE(fe.events[0].load_factor, fine.events[0].load_factor, fe_error);
  CHECK(std::abs(lift_off.load_factor - fe.events[0].load_factor) <= fe_error + ritz_error);
  CHECK(std::abs(fe.events[0].load_factor - hetenyi) <= fe_error);
}

TEST_CASE("ritz path: too few modes for the pipeline's beta L are refused before any work, with the number needed",
          "[ritz_path][issue10]") {
  scene::Scene s = test::continuation_scene("pipeline_uplift");
  TraceOptions options = scene_options(s, 11);
  const double beta_length =
      std::pow(*s.foundation.modulus / (4.0 * s.structure.bending_stiffness), 0.25) * s.structure.length;
  // The smallest N whose estimate is within 1 %, as the path computes it.
  const int needed = static_cast<int>(
      std::ceil(beta_length / 3.14159265358979323846 * std::cbrt(8.0 / (3.0 * 3.14159265358979323846 * 1e-2))));
  REQUIRE(resolution_error(beta_length, needed) <= 1e-2);
  REQUIRE(resolution_error(beta_length, needed - 1) > 1e-2);
  options.ritz.modes = 64;  // the first lift-off came at 0.219 (Hetenyi: 0.19992)
  TraceResult r = test::trace_ritz_scene(s, options);
  INFO(r.summary.message);
  CHECK(r.summary.termination == TraceTermination::solver_failure);
  CHECK(r.steps.empty());
  CHECK(r.events.empty());
  CHECK(r.summary.message.find("refused") != std::string::npos);
  CHECK(r.summary.message.find(std::to_string(needed) + " modes are needed for 1 %") != std::string::npos);
  // Automatic modes that may not reach the N needed are refused too, and say why.
  options.ritz.modes = 0;
  s.ritz.max_modes = needed / 2;
  r = test::trace_ritz_scene(s, options);
  INFO(r.summary.message);
  CHECK(r.summary.termination == TraceTermination::solver_failure);
  CHECK(r.steps.empty());
  CHECK(r.summary.message.find("max_modes = " + std::to_string(needed / 2)) != std::string::npos);
}

TEST_CASE("ritz path: the arch culvert's events agree with the FE path's, and no step pulls", "[ritz_path][issue10]") {
  const scene::Scene s = test::continuation_scene("arch_culvert");
  TraceOptions options = scene_options(s, 321);  // every half degree
  // Ritz: 72 modes, its error estimated by the change from 36 (with an error falling like
  // N^-q, q >= 1, the change bounds the error of the larger N); FE: 200 elements, its error the
  // change to 400 times 3 (orders above 0.6, as path_agreement_test argues).
  options.ritz.modes = 72;
  const TraceResult ritz = test::trace_ritz_scene(s, options);
  options.ritz.modes = 36;
  const TraceResult fewer = test::trace_ritz_scene(s, options);
  const TraceResult fe = test::trace_fe(s, options);
  options.elements = 400;
  const TraceResult fine = test::trace_fe(s, options);
  INFO(ritz.summary.message << " | " << fewer.summary.message);
  REQUIRE(ritz.summary.termination == TraceTermination::completed);
  REQUIRE(fewer.summary.termination == TraceTermination::completed);
  REQUIRE(fe.summary.termination == TraceTermination::completed);
  check_contact_solutions(ritz, options.sample_points);
  check_contact_solutions(fewer, options.sample_points);
  // Six events, mirror pairs: a zone opening at +-42.5 deg, zones opening at the pinned ends,
  // the regions between vanishing near +-77.7 deg. Same kinds in the same order on every run;
  // positions within 1 deg (a vanishing region's last midpoint moves like sqrt(lambda* -
  // lambda), so the paths place it less sharply than its load).
  REQUIRE(fe.events.size() == 6);
  for (const TraceResult* other : {&ritz, &fewer, &fine}) REQUIRE(other->events.size() == fe.events.size());
  for (std::size_t i = 0; i < fe.events.size(); ++i) {
    const TraceEvent &a = fe.events[i], &b = ritz.events[i];
    INFO("event " << i << ": FE " << to_string(a.kind) << " at " << a.at << ", lambda " << a.load_factor << "; Ritz "
                  << to_string(b.kind) << " at " << b.at << ", lambda " << b.load_factor);
    CHECK(b.kind == a.kind);
    CHECK(fewer.events[i].kind == a.kind);
    CHECK(std::abs(b.at - a.at) < 1.0);
    const double fe_error = 3.0 * std::abs(a.load_factor - fine.events[i].load_factor);
    const double ritz_error = std::abs(b.load_factor - fewer.events[i].load_factor);
    CAPTURE(fe_error, ritz_error);
    CHECK(std::abs(a.load_factor - b.load_factor) <= fe_error + ritz_error);
  }
}

TEST_CASE("ritz path: a path that cannot be refined where its topology turns back stops, and keeps its valid steps",
          "[ritz_path][issue10]") {
  // With the step fixed at 0.1 (min_step = max_step) the culvert's path reaches the ends'
  // openings in steps too long to resolve them: its topology turns back in lambda there (as the
  // unchecked path did, wandering from 0.5117 back to 0.4045). It stops with solver_failure
  // saying so; what it kept is a contact solution at every step, up to where it stopped.
  scene::Scene s = test::continuation_scene("arch_culvert");
  TraceOptions options = scene_options(s, 321);
  options.arc_length.initial_step = options.arc_length.min_step = options.arc_length.max_step = 0.1;
  options.ritz.modes = 36;
  const TraceResult r = test::trace_ritz_scene(s, options);
  INFO(r.summary.message);
  CHECK(r.summary.termination == TraceTermination::solver_failure);
  CHECK(r.summary.message.find("turned back in lambda") != std::string::npos);
  CHECK(r.summary.message.find(std::to_string(r.steps.size()) + " steps") != std::string::npos);
  REQUIRE(!r.steps.empty());
  CHECK(r.steps.back().load_factor < options.arc_length.lambda_max);
  check_contact_solutions(r, options.sample_points);
  // Its events are those of the free run up to there (the first pair, at 0.4037).
  options.arc_length.initial_step = 0.05, options.arc_length.min_step = 1e-8, options.arc_length.max_step = 0.25;
  const TraceResult free = test::trace_ritz_scene(s, options);
  REQUIRE(free.summary.termination == TraceTermination::completed);
  REQUIRE(r.events.size() <= free.events.size());
  for (std::size_t i = 0; i < r.events.size(); ++i) {
    CHECK(r.events[i].kind == free.events[i].kind);
    CHECK(r.events[i].load_factor == Approx(free.events[i].load_factor).epsilon(1e-8));
  }
}

TEST_CASE("ritz path: a state of the wrong topology is refused, naming the inequality, where and by how much",
          "[ritz_path][issue10]") {
  // A deliberately bad step: the free-free beam past its lift-off (a lift-off zone around
  // x = 5), its amplitudes declared as full contact. Resuming from it must not go on.
  const TraceOptions options = options_for(16);
  const TraceResult original = test::trace_ritz_scene(lift_off_beam(), options);
  REQUIRE(original.summary.termination == TraceTermination::completed);
  const TraceStep& lifted = original.steps.back();
  REQUIRE(lifted.contact_regions.size() == 2);
  const int modes = modes_of(lifted);
  REQUIRE(std::get<continuation::RitzTopology>(lifted.state_topology).limits == 2);
  const std::size_t unknowns = (lifted.state.size() - 3) / 2, amplitudes = unknowns - 2;
  TraceStep forged = lifted;
  forged.state_topology = continuation::RitzTopology{true, 0, modes, std::nullopt};  // full contact
  forged.state.assign(2 * amplitudes + 3, 0.0);
  std::copy(lifted.state.begin(), lifted.state.begin() + static_cast<std::ptrdiff_t>(amplitudes), forged.state.begin());
  forged.state[2 * amplitudes] = 1.0;                                  // tangent: lambda only
  forged.state[2 * amplitudes + 1] = options.arc_length.initial_step;  // next step
  forged.state[2 * amplitudes + 2] = lifted.state.back();              // amplitude scale
  TraceOptions resumed = options;
  resumed.resume_from = forged;
  const TraceResult r = test::trace_ritz_scene(lift_off_beam(), resumed);
  INFO(r.summary.message);
  CHECK(r.summary.termination == TraceTermination::solver_failure);
  CHECK(r.steps.empty());
  CHECK(r.summary.message.find("no contact solution") != std::string::npos);
  CHECK(r.summary.message.find("inside a contact piece: the foundation would pull") != std::string::npos);
  // Where: the worst point is in the lifted zone, around x = 5.
  const std::size_t at = r.summary.message.find("at x = ");
  REQUIRE(at != std::string::npos);
  const double x = std::stod(r.summary.message.substr(at + 7));
  CHECK(x > lifted.contact_regions[0].end);
  CHECK(x < lifted.contact_regions[1].begin);
}

TEST_CASE("ritz path: the summary counts what the result holds", "[ritz_path][issue10]") {
  // The message once said "5156 steps ... after 24 steps" (the last topology's count).
  const TraceOptions options = options_for(16);
  const TraceResult r = test::trace_ritz_scene(lift_off_beam(), options);
  INFO(r.summary.message);
  REQUIRE(r.summary.termination == TraceTermination::completed);
  CHECK(r.summary.steps == static_cast<int>(r.steps.size()));
  const auto figures = [](const TraceResult& t) {
    // (The engine's words, continuation/engine.cpp; the Ritz path's note adds its modes.)
    return fmt::format("{} steps ({} rejected), {} event(s), 0 limit point(s), 0 bifurcation(s), 16 modes",
                       t.steps.size(), t.summary.rejected_steps, t.events.size());
  };
  CHECK(r.summary.message.find(figures(r)) != std::string::npos);
  // A resumed run counts its own steps and says from where.
  TraceOptions resumed = options;
  resumed.resume_from = r.steps[r.steps.size() / 2];
  const TraceResult rest = test::trace_ritz_scene(lift_off_beam(), resumed);
  INFO(rest.summary.message);
  REQUIRE(rest.summary.termination == TraceTermination::completed);
  CHECK(rest.summary.message.find(figures(rest) + fmt::format(" after the resumed step at lambda = {:.10g}",
                                                              resumed.resume_from->load_factor)) != std::string::npos);
}

// Issue 15: the Ritz path in the axial force. The heavy pipeline over a hump under growing
// compression (continuation/scenes/pipeline_upheaval.toml): lift-off at the crown, a limit point
// that fixed-N FE solves bracket in (5.5, 6.0) MN (5.5 MN stable with uplift 6.3 mm, 6.0 MN
// refused as unstable; the scene's comments), then the descending branch, the buckle growing and
// lifting more of the pipe while the load falls.
TEST_CASE("ritz path: the upheaval buckle passes its limit point inside the fixed-N bracket", "[ritz_path][axial]") {
  scene::Scene s = test::continuation_scene("pipeline_upheaval");
  TraceOptions options = scene_options(s, 201);
  options.max_amplitude = 0.3;  // the scene's 1 m takes 230 steps; the fold and the branch beyond need 80
  const TraceResult r = test::trace_ritz_scene(s, options);
  INFO(r.summary.message);
  REQUIRE(r.summary.termination == TraceTermination::completed);
  CHECK(r.summary.message.find("max_amplitude") != std::string::npos);
  std::vector<TraceEvent> folds;
  for (const TraceEvent& e : r.events)
    if (e.kind == EventKind::limit_point) folds.push_back(e);
  REQUIRE(folds.size() == 1);
  const double limit = folds[0].load_factor;
  fmt::print("upheaval: limit point at lambda = {:.8g} ({})\n", limit, folds[0].description);
  CHECK(limit > 5.5);
  CHECK(limit < 6.0);
  CHECK(std::abs(folds[0].at - 100.0) < 1e-6);  // at the crown

  // Every step: N = lambda x 1 MN; lambda rises to the fold and falls after it, the amplitude
  // and the lifted length grow all along once lifted; stable before the fold, unstable after.
  double lambda_max = -INFINITY, previous_amplitude = -1.0, previous_lifted = -1.0;
  bool past_fold = false, passed = false;
  for (std::size_t i = 0; i < r.steps.size(); ++i) {
    const TraceStep& step = r.steps[i];
    INFO("step " << i << " at lambda " << step.load_factor);
    CHECK(step.axial_force == Approx(1e6 * step.load_factor).margin(1e-6));
    CHECK(step.stability != continuation::Stability::unknown);
    // Past the fold the tangent points to falling lambda (its lambda component, stored in the state).
    const std::size_t n = (step.state.size() - 3) / 2;
    past_fold = step.state[2 * n] < 0.0;
    CHECK(step.stability == (past_fold ? continuation::Stability::unstable : continuation::Stability::stable));
    CHECK((past_fold || !passed));  // once past, the path stays on the descending branch
    passed = passed || past_fold;
    CHECK(step.amplitude >= previous_amplitude);
    CHECK(step.lifted_length >= previous_lifted);
    previous_amplitude = step.amplitude;
    previous_lifted = step.lifted_length;
    lambda_max = std::max(lambda_max, step.load_factor);
    if (i % 10 == 0 || i + 1 == r.steps.size())
      fmt::print("  lambda {:.6f} N {:.6g} amplitude {:.5g} lifted length {:.5g} {}\n", step.load_factor,
                 step.axial_force, step.amplitude, step.lifted_length, to_string(step.stability));
  }
  CHECK(passed);
  CHECK(lambda_max <= limit + 1e-9);
  CHECK(r.steps.back().amplitude >= 0.3);
  CHECK(r.steps.back().load_factor < limit);
  // The lifted buckle at the end is the one zone around the crown.
  REQUIRE(r.steps.back().contact_regions.size() == 2);
  CHECK(r.steps.back().lifted_length ==
        Approx(r.steps.back().contact_regions[1].begin - r.steps.back().contact_regions[0].end).epsilon(1e-12));
}

TEST_CASE("ritz path: amplitude and lifted length are filled without an axial force too", "[ritz_path][axial]") {
  const TraceResult r = test::trace_ritz_scene(lift_off_beam(), options_for(32));
  REQUIRE(r.summary.termination == TraceTermination::completed);
  const TraceStep& last = r.steps.back();
  CHECK(last.axial_force == 0.0);
  CHECK(last.stability == continuation::Stability::unknown);  // convex: unchecked
  // The beam lifts off at its centre (sample 5.0): the amplitude is at least the lift there and
  // no more than a grid's worth above it (the largest lift is at the centre by symmetry).
  REQUIRE(last.contact_regions.size() == 2);
  CHECK(last.lifted_length == Approx(last.contact_regions[1].begin - last.contact_regions[0].end).epsilon(1e-12));
  CHECK(last.amplitude == Approx(-last.deflection[2]).epsilon(1e-9));
  CHECK(r.steps.front().amplitude == 0.0);
  CHECK(r.steps.front().lifted_length == 0.0);
}

namespace {

// The least n = N L^2 / EI at which the straight free-free member (x in [-1/2, 1/2], EI = L = 1)
// on a bilateral foundation k buckles in an odd mode: w'''' + n w'' + k w = 0, w'' = 0 and
// w''' + n w' = 0 at x = +-1/2. With r^2 a root of s^2 + n s + k = 0 (complex for n < 2 sqrt(k)),
// w = A sinh(r x) + B sinh(conj(r) x), and the determinant of the two end conditions is
// 2 i Im(f conj(g)), f = r^2 sinh(r/2), g = (r^3 + n r) cosh(r/2): its least root by bisection
// from a scan (n in (0, 2 sqrt(k))). (continuation/scenes/free_free_bifurcation.toml: k = 100,
// n = 7.950686; Hermite-cubic FE and `liftoff solve`'s critical load factor agree.)
// The even modes: sinh and cosh swapped (w = A cosh(r x) + B cosh(conj(r) x)).
double free_free_critical(double k, bool odd) {
  const auto determinant = [k, odd](double n) {
    const std::complex<double> r = std::sqrt((-n + std::sqrt(std::complex<double>(n * n - 4.0 * k))) / 2.0);
    const std::complex<double> f = r * r * (odd ? std::sinh(r / 2.0) : std::cosh(r / 2.0)),
                               g = (r * r * r + n * r) * (odd ? std::cosh(r / 2.0) : std::sinh(r / 2.0));
    return (f * std::conj(g)).imag();
  };
  const double top = 2.0 * std::sqrt(k);
  constexpr int samples = 2000;
  for (int i = 0; i < samples; ++i) {
    double a = top * (i + 1e-6) / samples, b = top * (i + 1) / samples - 1e-9;
    if ((determinant(a) > 0) == (determinant(b) > 0)) continue;
    for (int j = 0; j < 200 && b - a > 1e-15 * top; ++j) {
      const double m = 0.5 * (a + b);
      ((determinant(m) > 0) == (determinant(a) > 0) ? a : b) = m;
    }
    return 0.5 * (a + b);
  }
  return NAN;
}

}  // namespace

// Issue 15: a perfect member bifurcates. The heavy free-free member on its foundation stays
// straight (w = q/K, full contact) under any axial force, and loses its stability where the
// bilateral beam-column buckles: at the odd (tilting) mode's critical load, lambda = n_cr here
// (N = lambda 100 kN = lambda EI / L^2). The Ritz path reports a `bifurcation` there (not a
// limit point: lambda keeps growing), its error estimated by modes m against 2 m, and the
// stability of the steps flips there.
TEST_CASE("ritz path: a perfect heavy free-free member bifurcates at its tilting mode's critical load",
          "[ritz_path][axial]") {
  const double exact = free_free_critical(100.0, true);
  REQUIRE(exact == Approx(7.950686).epsilon(1e-6));
  double previous = NAN;
  for (int modes : {16, 32}) {
    INFO("modes " << modes);
    scene::Scene s = test::continuation_scene("free_free_bifurcation");
    TraceOptions options = scene_options(s, 201);
    options.ritz.modes = modes;
    options.switch_branch = false;  // stay on the straight path (the switch: the test below)
    const TraceResult r = test::trace_ritz_scene(s, options);
    INFO(r.summary.message);
    REQUIRE(r.summary.termination == TraceTermination::completed);
    REQUIRE(r.events.size() == 1);
    const TraceEvent& e = r.events[0];
    CHECK(e.kind == EventKind::bifurcation);
    CHECK(r.summary.message.find("0 limit point(s), 1 bifurcation(s)") != std::string::npos);
    CHECK(e.description.find("axial force") != std::string::npos);
    fmt::print("free-free bifurcation, {} modes: lambda = {:.10g} (exact {:.10g}; {})\n", modes, e.load_factor, exact,
               e.description);
    // A Ritz critical load bounds the exact one from above.
    CHECK(e.load_factor >= exact - 1e-9);
    if (!std::isnan(previous)) {
      // The estimate of the error of the coarser (m vs 2 m) covers the finer's.
      CHECK(e.load_factor <= previous);
      CHECK(e.load_factor - exact <= previous - e.load_factor);
    }
    previous = e.load_factor;
    // The straight state all along: stable below the event, unstable above; lambda grows.
    double lambda = -INFINITY;
    for (const TraceStep& step : r.steps) {
      INFO("lambda " << step.load_factor);
      CHECK(step.load_factor > lambda);
      lambda = step.load_factor;
      CHECK(step.monitor_deflection == Approx(0.01).epsilon(1e-9));
      CHECK(step.stability ==
            (step.load_factor < e.load_factor ? continuation::Stability::stable : continuation::Stability::unstable));
    }
    CHECK(r.steps.front().load_factor < e.load_factor);
    CHECK(r.steps.back().load_factor > e.load_factor);
  }
}

// Issue 15: branch switching. At the same bifurcation the path leaves the straight state along
// the critical (tilting) mode, on the side where it lifts the member off: one free end lifts
// (the foundation admits no other side), and the branch of that topology falls in lambda as the
// lifted length grows (unstable: the tilt is resisted by less and less foundation). Every step
// is a contact solution (the path checks it); modes m and 2 m agree on the branch.
TEST_CASE("ritz path: at the perfect member's bifurcation the path switches to the tilted branch, an end lifting",
          "[ritz_path][axial]") {
  const double exact = free_free_critical(100.0, true);
  std::vector<TraceResult> traces;
  for (int modes : {16, 32}) {
    INFO("modes " << modes);
    scene::Scene s = test::continuation_scene("free_free_bifurcation");
    TraceOptions options = scene_options(s, 201);
    options.ritz.modes = modes;
    options.max_amplitude = 0.05;  // 5 q/K: well past the start of the branch
    const TraceResult r = test::trace_ritz_scene(s, options);
    INFO(r.summary.message);
    REQUIRE(r.summary.termination == TraceTermination::completed);
    CHECK(r.summary.message.find("max_amplitude") != std::string::npos);
    REQUIRE(r.events.size() == 1);
    const TraceEvent& e = r.events[0];
    CHECK(e.kind == EventKind::bifurcation);
    CHECK(e.description.find("the path switches to the bifurcated branch") != std::string::npos);
    fmt::print("free-free branch switch, {} modes: {}\n", modes, e.description);
    CHECK(e.load_factor >= exact - 1e-9);
    CHECK(e.load_factor - exact < 1e-3);
    // Before: the straight state, stable, lambda growing (the bifurcation point is no step);
    // after: one end lifted, unstable, lambda falling and the lift growing.
    std::size_t at = 0;
    while (at < r.steps.size() && r.steps[at].lifted_length == 0.0) {
      CHECK(r.steps[at].stability == continuation::Stability::stable);
      CHECK(r.steps[at].load_factor < e.load_factor);
      ++at;
    }
    REQUIRE(at > 0);
    REQUIRE(at + 2 < r.steps.size());
    --at;  // the last straight step
    double lambda = e.load_factor, amplitude = 0.0, lifted = 0.0;
    for (std::size_t i = at + 1; i < r.steps.size(); ++i) {
      const TraceStep& step = r.steps[i];
      INFO("step " << i << " lambda " << step.load_factor);
      CHECK(step.stability == continuation::Stability::unstable);
      CHECK(step.load_factor < lambda);
      CHECK(step.amplitude > amplitude);
      CHECK(step.lifted_length > lifted);
      REQUIRE(step.contact_regions.size() == 1);  // one end lifted
      const bool left_lifted = step.contact_regions[0].begin > 0.0;
      CHECK((left_lifted ? step.contact_regions[0].end : step.contact_regions[0].begin) ==
            Approx(left_lifted ? 10.0 : 0.0));
      lambda = step.load_factor, amplitude = step.amplitude, lifted = step.lifted_length;
    }
    // The branch starts at the bifurcation: its first point within a small lift of it.
    CHECK(r.steps[at + 1].load_factor > e.load_factor - 0.05);
    CHECK(r.steps[at + 1].amplitude < 0.005);
    CHECK(r.steps.back().amplitude >= 0.05);
    traces.push_back(r);
  }
  // Modes m and 2 m on the branch: the lifted length at the last 16-mode step's lambda,
  // interpolated on the 32-mode branch, within 1e-3 (measured 1.5e-5; the critical loads of 16
  // and 32 modes differ by 5e-5).
  const TraceStep& coarse = traces[0].steps.back();
  const std::vector<TraceStep>& fine = traces[1].steps;
  bool compared = false;
  for (std::size_t i = 1; i < fine.size(); ++i) {
    const TraceStep &a = fine[i - 1], &b = fine[i];
    if (a.lifted_length == 0.0 || !(a.load_factor >= coarse.load_factor && b.load_factor <= coarse.load_factor))
      continue;
    const double t = (a.load_factor - coarse.load_factor) / (a.load_factor - b.load_factor);
    const double lifted = a.lifted_length + t * (b.lifted_length - a.lifted_length);
    fmt::print("  lambda {:.6f}: lifted length {:.6f} (16 modes), {:.6f} (32 modes)\n", coarse.load_factor,
               coarse.lifted_length, lifted);
    CHECK(coarse.lifted_length == Approx(lifted).epsilon(1e-3));
    compared = true;
  }
  CHECK(compared);
}

TEST_CASE("ritz path: a trace resumed before or after a branch switch reproduces the original", "[ritz_path][axial]") {
  scene::Scene s = test::continuation_scene("free_free_bifurcation");
  TraceOptions options = scene_options(s, 11);
  options.ritz.modes = 16;
  options.max_amplitude = 0.02;
  const TraceResult original = test::trace_ritz_scene(s, options);
  INFO(original.summary.message);
  REQUIRE(original.summary.termination == TraceTermination::completed);
  REQUIRE(original.events.size() == 1);
  std::size_t straight = 0;  // the last step before the switch
  while (original.steps[straight + 1].lifted_length == 0.0) ++straight;
  for (std::size_t from : {straight, straight + 3}) {
    CAPTURE(from, original.steps[from].load_factor);
    const TraceResult resumed = resumed_trace(s, options, original, from);
    for (std::size_t i = 0; i < resumed.steps.size(); ++i) {
      const TraceStep& a = original.steps[from + 1 + i];
      const TraceStep& b = resumed.steps[i];
      CHECK(b.amplitude == Approx(a.amplitude).epsilon(1e-9));
      CHECK(b.lifted_length == Approx(a.lifted_length).epsilon(1e-9));
    }
    // The bifurcation again when resumed before it, not after.
    REQUIRE(resumed.events.size() == (from == straight ? 1u : 0u));
    if (from == straight) {
      CHECK(resumed.events[0].kind == EventKind::bifurcation);
      CHECK(resumed.events[0].load_factor == Approx(original.events[0].load_factor).epsilon(1e-12));
    }
  }
}

// The branch's states are equilibria of the whole member, checked from the recorded fields
// alone: the rigid motions of the free-free member (a translation and a rotation about the
// centre) take no strain energy, so the reaction r balances the weight, int r dx = q L, and
// its moment about the centre balances that of the axial force at the displaced ends,
// int r (x - L/2) dx = N (w(L) - w(0)) (the variation of -N/2 int w'^2 along the rotation).
// The Ritz basis holds both motions, so the model meets these to its solver's tolerance. The
// integrals: the trapezoid rule over the one contact region, from its limit (r = 0 there, where
// r has its kink) through the samples inside it, on 2001 samples; its error, O(h^2) on that
// smooth integrand, estimated by the rule on every other sample (a third of the difference; the
// difference itself is the bound).
TEST_CASE("ritz path: the tilted branch after the switch balances the weight and the axial force's moment",
          "[ritz_path][axial]") {
  scene::Scene s = test::continuation_scene("free_free_bifurcation");
  TraceOptions options = scene_options(s, 2001);
  options.ritz.modes = 32;
  options.max_amplitude = 0.05;
  const TraceResult r = test::trace_ritz_scene(s, options);
  INFO(r.summary.message);
  REQUIRE(r.summary.termination == TraceTermination::completed);
  const std::vector<double>& x = options.sample_points;
  int checked = 0;
  for (const TraceStep& step : r.steps) {
    if (step.lifted_length == 0.0) continue;
    INFO("lambda " << step.load_factor);
    REQUIRE(step.contact_regions.size() == 1);
    const double a = step.contact_regions[0].begin, b = step.contact_regions[0].end;
    // (position, reaction) through the contact region, every `stride`-th sample inside it.
    const auto nodes = [&](int stride) {
      std::vector<std::pair<double, double>> p;
      std::vector<std::size_t> inside;
      for (std::size_t i = 0; i < x.size(); ++i)
        if (x[i] > a && x[i] < b) inside.push_back(i);
      p.emplace_back(a, a > 0.0 ? 0.0 : step.reaction.front());
      for (std::size_t j = 0; j < inside.size(); j += stride) p.emplace_back(x[inside[j]], step.reaction[inside[j]]);
      p.emplace_back(b, b < length ? 0.0 : step.reaction.back());
      return p;
    };
    const auto trapezoid = [&](int stride, double moment_arm) {
      const auto p = nodes(stride);
      double sum = 0.0;
      for (std::size_t i = 1; i < p.size(); ++i) {
        const double f0 = p[i - 1].second * (moment_arm ? p[i - 1].first - 0.5 * length : 1.0);
        const double f1 = p[i].second * (moment_arm ? p[i].first - 0.5 * length : 1.0);
        sum += 0.5 * (f0 + f1) * (p[i].first - p[i - 1].first);
      }
      return sum;
    };
    const double weight = q * length;
    const double tilt = step.axial_force * (step.deflection.back() - step.deflection.front());
    const double f1 = trapezoid(1, 0.0), f2 = trapezoid(2, 0.0);
    const double m1 = trapezoid(1, 1.0), m2 = trapezoid(2, 1.0);
    CHECK(std::abs(f1 - weight) <= std::abs(f1 - f2) + 1e-12 * weight);
    CHECK(std::abs(m1 - tilt) <= std::abs(m1 - m2) + 1e-12 * weight * length);
    if (checked++ % 10 == 0)
      fmt::print(
          "  lambda {:.6f}: int r = {:.12g} (q L = {}, rule difference {:.1e}), moment {:.12g} vs N dw = "
          "{:.12g} ({:.1e})\n",
          step.load_factor, f1, weight, std::abs(f1 - f2), m1, tilt, std::abs(m1 - m2));
  }
  CHECK(checked > 5);
}

// The same member on a stiffer foundation, k = 300: the even mode comes first (n = 15.52454 from
// the closed form's even branch; odd 20.58365), symmetric, lifting both ends at once. The
// path switches with a lift-off zone at each end, and the branch stays symmetric.
TEST_CASE("ritz path: a symmetric critical mode lifts both ends at once on the switched branch", "[ritz_path][axial]") {
  const double exact = free_free_critical(300.0, false);
  REQUIRE(exact == Approx(15.52454).epsilon(1e-6));
  REQUIRE(free_free_critical(300.0, true) > exact);
  double previous = NAN;
  for (int modes : {16, 32}) {
    INFO("modes " << modes);
    scene::Scene s = test::continuation_scene("free_free_bifurcation");
    s.foundation.k = 300.0;
    s.trace->lambda_max = 18.0;
    TraceOptions options = scene_options(s, 201);
    options.ritz.modes = modes;
    options.max_amplitude = 0.01;
    const TraceResult r = test::trace_ritz_scene(s, options);
    INFO(r.summary.message);
    REQUIRE(r.summary.termination == TraceTermination::completed);
    REQUIRE(r.events.size() == 1);
    const TraceEvent& e = r.events[0];
    CHECK(e.kind == EventKind::bifurcation);
    CHECK(e.description.find("the path switches to the bifurcated branch") != std::string::npos);
    fmt::print("free-free k = 300, {} modes: {}\n", modes, e.description);
    CHECK(e.load_factor >= exact - 1e-9);
    if (!std::isnan(previous)) CHECK(e.load_factor - exact <= previous - e.load_factor);
    previous = e.load_factor;
    int lifted = 0;
    for (const TraceStep& step : r.steps) {
      if (step.lifted_length == 0.0) continue;
      ++lifted;
      INFO("lambda " << step.load_factor);
      CHECK(step.stability == continuation::Stability::unstable);
      CHECK(step.load_factor < e.load_factor);
      REQUIRE(step.contact_regions.size() == 1);
      CHECK(step.contact_regions[0].begin > 0.0);
      CHECK(step.contact_regions[0].begin == Approx(length - step.contact_regions[0].end).epsilon(1e-8));
    }
    CHECK(lifted > 5);
  }
}
