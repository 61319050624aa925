// The Ritz load history (continuation/ritz_path.hpp) on the free-free beam that lifts off at
// its centre: the first lift-off load against the closed form, the zone's growth past it, and
// a resumed trace.
//
// Beam L = 10, EI = 1e4, free-free, tensionless foundation k = K L^4/EI = 500 over the whole
// length, dead uniform load q = 1 into the foundation, live central force -1 (pulling the beam
// off). Before lift-off the beam is in full contact, so w = q/K + lambda w_live with w_live the
// bilateral deflection under the live force alone; lift-off begins at the centre when w(5) = 0:
//     lambda* = (q / K) / (-w_live(5)).

#include <catch2/catch.hpp>

#include <cmath>

#include "closed_form/beam_on_foundation.hpp"
#include "continuation/ritz_path.hpp"
#include "support/scenes.hpp"

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
  o.lambda_min = 0.0;
  o.lambda_max = 8.0;
  o.modes = modes;
  o.monitor = 5.0;
  o.sample_points = {0.0, 2.5, 5.0};
  return o;
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
    const TraceResult r = trace_ritz(lift_off_beam(), options_for(modes), sink);
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
  const TraceResult r = trace_ritz(lift_off_beam(), options, sink);
  INFO(r.summary.message);
  REQUIRE(r.summary.termination == TraceTermination::completed);
  REQUIRE(streamed.size() == r.steps.size());
  CHECK(r.steps.front().load_factor == options.lambda_min);
  CHECK(r.steps.back().load_factor == options.lambda_max);
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
      CHECK(step.contact_regions[0][0] == 0.0);
      CHECK(step.contact_regions[0][1] == length);
      // Full contact: w(5) = q/K + lambda w_live(5) falls linearly to 0 at lambda*.
      const double w_centre = step.deflection[2];
      CHECK(std::abs(w_centre - (q / (k * bending_stiffness / std::pow(length, 4))) * (1 - step.load_factor / lambda_star)) <
            1e-9 * q / (k * bending_stiffness / std::pow(length, 4)));
      continue;
    }
    REQUIRE(step.contact_regions.size() == 2);
    const double left = step.contact_regions[0][1], right = step.contact_regions[1][0];
    // Symmetric about the load to round-off (the limits are solved, not mirrored).
    CHECK(std::abs((left + right) / 2 - 5.0) < 1e-9 * length);
    const double width = right - left;
    CHECK(width > previous_width);  // grows monotonically
    previous_width = width;
    CHECK(step.deflection[2] < 0.0);  // the centre has lifted off
    CHECK(step.reaction[2] == 0.0);
    CHECK(step.reaction[0] > 0.0);    // the ends still press on the foundation
    ++zone_steps;
  }
  CHECK(zone_steps >= 5);
  // The steps adapt: one corrector iteration (or none) in full contact, where the problem is
  // linear, so the steps grow to max_step; several past lift-off, so they shrink.
  double largest = 0.0, smallest_after = 1e300;
  for (std::size_t i = 1; i < r.steps.size(); ++i) {
    const double d = r.steps[i].load_factor - r.steps[i - 1].load_factor;
    if (r.steps[i].load_factor <= lambda_star) largest = std::max(largest, d);
    else if (r.steps[i - 1].load_factor > lambda_star) smallest_after = std::min(smallest_after, d);
  }
  CHECK(r.steps[1].load_factor - r.steps[0].load_factor < largest / 2);  // initial_step, then growing
  CHECK(smallest_after < largest);
  CHECK(r.summary.corrector_iterations > 0);
}

TEST_CASE("ritz path: a resumed trace reproduces the original", "[ritz_path]") {
  const TraceOptions options = options_for(32);
  const TraceResult original = trace_ritz(lift_off_beam(), options);
  REQUIRE(original.summary.termination == TraceTermination::completed);
  // Resume from a step in full contact (before the event), from the event's own step (the
  // switch is redone), and from one past it.
  REQUIRE(original.events.size() == 1);
  std::size_t event_step = 0;
  while (original.steps[event_step].load_factor != original.events[0].load_factor) ++event_step;
  const std::size_t last = original.steps.size() - 1;
  for (std::size_t from : {last * 3 / 10, event_step, last * 85 / 100}) {
    CAPTURE(from, original.steps[from].load_factor);
    TraceOptions resumed_options = options;
    resumed_options.resume_from = original.steps[from];
    const TraceResult resumed = trace_ritz(lift_off_beam(), resumed_options);
    REQUIRE(resumed.summary.termination == TraceTermination::completed);
    // The steps after `from`, and nothing already written.
    REQUIRE(resumed.steps.size() == original.steps.size() - from - 1);
    for (std::size_t i = 0; i < resumed.steps.size(); ++i) {
      const TraceStep& a = original.steps[from + 1 + i];
      const TraceStep& b = resumed.steps[i];
      CHECK(b.load_factor == Approx(a.load_factor).epsilon(1e-12));
      CHECK(b.monitor_deflection == Approx(a.monitor_deflection).epsilon(1e-9));
      REQUIRE(b.contact_regions.size() == a.contact_regions.size());
      for (std::size_t j = 0; j < a.contact_regions.size(); ++j) {
        CHECK(std::abs(b.contact_regions[j][0] - a.contact_regions[j][0]) < 1e-9 * length);
        CHECK(std::abs(b.contact_regions[j][1] - a.contact_regions[j][1]) < 1e-9 * length);
      }
    }
    // The events after `from` (an event at `from` itself was written with its step).
    std::vector<TraceEvent> later;
    for (const TraceEvent& e : original.events)
      if (e.load_factor > original.steps[from].load_factor) later.push_back(e);
    CHECK((original.steps[from].state_topology.find(" event ") != std::string::npos) == (from == event_step));
    REQUIRE(resumed.events.size() == later.size());
    for (std::size_t i = 0; i < later.size(); ++i) {
      CHECK(resumed.events[i].kind == later[i].kind);
      CHECK(resumed.events[i].load_factor == Approx(later[i].load_factor).epsilon(1e-12));
    }
  }
}

TEST_CASE("ritz path: load control and arc-length agree where both apply", "[ritz_path]") {
  TraceOptions options = options_for(16);
  options.control = PathControl::load;
  const TraceResult load = trace_ritz(lift_off_beam(), options);
  options.control = PathControl::arc_length;
  const TraceResult arc = trace_ritz(lift_off_beam(), options);
  REQUIRE(load.summary.termination == TraceTermination::completed);
  REQUIRE(arc.summary.termination == TraceTermination::completed);
  REQUIRE(load.events.size() == arc.events.size());
  CHECK(load.events.front().load_factor == Approx(arc.events.front().load_factor).epsilon(1e-10));
  CHECK(load.steps.back().contact_regions[0][1] == Approx(arc.steps.back().contact_regions[0][1]).epsilon(1e-9));
}

TEST_CASE("ritz path: bad options are refused with the field named", "[ritz_path]") {
  TraceOptions options = options_for(16);
  options.lambda_max = options.lambda_min;
  CHECK_THROWS_WITH(trace_ritz(lift_off_beam(), options), Catch::Contains("lambda_max"));
  options = options_for(16);
  options.sample_points = {11.0};
  CHECK_THROWS_WITH(trace_ritz(lift_off_beam(), options), Catch::Contains("sample_points"));
  options = options_for(16);
  options.resume_from = TraceStep{};
  CHECK_THROWS_WITH(trace_ritz(lift_off_beam(), options), Catch::Contains("resume_from"));
}

TEST_CASE("ritz path: the end regions shrink to nothing when the pull equals the weight", "[ritz_path]") {
  // Statics: the foundation's resultant is q L - lambda, so the contact regions at the ends
  // vanish at lambda = q L = 10 and beyond it nothing holds the free-free beam.
  TraceOptions options = options_for(16);
  options.lambda_max = 12.0;
  const TraceResult r = trace_ritz(lift_off_beam(), options);
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
  options.lambda_max = 1.0;
  options.modes = 32;
  options.monitor = 0.0;  // the crown
  const TraceResult r = trace_ritz(arch, options);
  INFO(r.summary.message);
  REQUIRE(r.summary.termination == TraceTermination::completed);
  CHECK(r.events.empty());
  REQUIRE(r.steps.size() >= 3);
  CHECK(r.steps.front().load_factor == options.initial_step);
  const TraceStep& last = r.steps.back();
  REQUIRE(last.contact_regions.size() == 1);
  for (const TraceStep& step : r.steps) {
    REQUIRE(step.contact_regions.size() == 1);
    CHECK(std::abs(step.contact_regions[0][0] - last.contact_regions[0][0]) < 1e-9);  // degrees
    CHECK(std::abs(step.contact_regions[0][1] - last.contact_regions[0][1]) < 1e-9);
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
    options.lambda_max = 1.5;
    options.modes = n == 0 ? 64 : 128;
    options.monitor = 0.5;
    const TraceResult r = trace_ritz(s, options);
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
