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
#include <cstdio>

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

TEST_CASE("explore", "[.explore]") {
  const double exact = closed_form_lift_off_load();
  for (int modes : {8, 16, 32, 64, 128}) {
    const TraceResult r = trace_ritz(lift_off_beam(), options_for(modes));
    std::printf("N=%d %s: %s steps %d\n", modes, std::string(to_string(r.summary.termination)).c_str(),
                r.summary.message.c_str(), r.summary.steps);
    for (const TraceEvent& e : r.events)
      std::printf("  event %s lambda %.15g at %.12g rel err %.3e\n", std::string(to_string(e.kind)).c_str(),
                  e.load_factor, e.at, e.load_factor / exact - 1);
    if (modes == 32)
      for (const TraceStep& s : r.steps) {
        std::printf("   lambda %.10g it %d regions:", s.load_factor, s.iterations);
        for (auto& c : s.contact_regions) std::printf(" [%.8g, %.8g]", c[0], c[1]);
        std::printf("\n");
      }
  }
}
