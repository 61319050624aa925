// The Ritz load path with von Karman's membrane term (issue 16, item 4): the sinusoidal shallow
// arch snapping through its limit point, against verification/closed_form/shallow_arch.hpp.
//
// L = 1, EI = 1, pinned ends axially restrained, w0 = -a sin(pi s) (initial_sine, exact),
// EA = 1e4 (r = 0.01), a / r = 3.5, on a bilateral foundation with kappa = k / (EI pi^4) = 1, so
// that the symmetric path has an upper and a lower limit point and no bifurcation point
// (a / r < sqrt(16 + kappa)). The member is built field by field (the scene has no von Karman
// keys for this seam) and handed to trace_ritz's member seam. The load q0 sin(pi s) is a sine
// load (model::LoadKind::sine), integrated exactly into the Ritz load vector (q0 on the first
// mode, round-off on the others), so the path is the closed form's two-mode path and the limit
// loads agree to the event tolerance, not to a discretisation error. (It used to be a scaled
// piecewise linear interpolant on 64 pieces, whose load vector was also exact to round-off for
// fewer than 127 modes by aliasing: the tolerances, set by the event location, do not change.)
#include <fmt/format.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "closed_form/shallow_arch.hpp"
#include "continuation/models/fe_member.hpp"
#include "continuation/models/ritz.hpp"
#include "model/from_scene.hpp"
#include "support/ritz_trace.hpp"
#include "support/scenes.hpp"

using namespace liftoff;
using namespace liftoff::continuation;

namespace {

constexpr double pi = std::numbers::pi;
constexpr double membrane_stiffness = 1e4;
constexpr double relative_rise = 3.5;
constexpr double k = pi * pi * pi * pi;

closed_form::ShallowArch reference() {
  closed_form::ShallowArch arch;
  arch.axial_stiffness = membrane_stiffness;
  arch.rise = relative_rise * std::sqrt(1.0 / membrane_stiffness);
  arch.foundation_modulus = k;
  arch.load_amplitude = 1.0;
  return arch;
}

scene::Scene arch_scene(bool tensionless = false) {
  scene::Scene s = test::beam_scene(1.0, 1.0, scene::EndSupport::pinned, scene::EndSupport::pinned, k, tensionless);
  s.ritz.topology = {true};  // bilateral: one piece, in contact
  s.ritz.modes = 16;
  return s;
}

model::MemberModel arch_member(const scene::Scene& scene) {
  model::MemberModel m = model::make_member_model(scene);
  m.theory = model::Theory::von_karman;
  m.membrane_stiffness = membrane_stiffness;
  m.left_axially_restrained = m.right_axially_restrained = true;
  m.initial_sine = model::MemberModel::InitialSine{-reference().rise, 0.0, 1.0};
  model::MemberLoad load;
  load.kind = model::LoadKind::sine;
  load.from = 0.0;
  load.to = 1.0;
  load.value = 1.0;
  m.loads = {load};
  return m;
}

// a / r = 8 on a bilateral foundation kappa = k / (EI pi^4): the asymmetric bifurcation first.
closed_form::ShallowArch bifurcating_arch(double kappa) {
  closed_form::ShallowArch arch = reference();
  arch.rise = 8.0 * std::sqrt(1.0 / membrane_stiffness);
  arch.foundation_modulus = kappa * pi * pi * pi * pi;
  return arch;
}

scene::Scene bifurcating_scene(const closed_form::ShallowArch& arch) {
  scene::Scene scene = arch_scene();
  scene.foundation.k = arch.foundation_modulus;
  return scene;
}

model::MemberModel bifurcating_member(const scene::Scene& scene, const closed_form::ShallowArch& arch) {
  model::MemberModel member = arch_member(scene);
  member.initial_sine = model::MemberModel::InitialSine{-arch.rise, 0.0, 1.0};
  return member;
}

// From zero past both bifurcation points, switching at the first.
TraceOptions switching_options(const closed_form::ShallowArchAnalysis& analysis) {
  const double bifurcation = analysis.first_bifurcation.load;
  TraceOptions options;
  options.arc_length.lambda_min = 0.0;
  options.arc_length.lambda_max = 1.3 * std::max(bifurcation, analysis.second_bifurcation.load);
  options.arc_length.initial_step = 0.25 * bifurcation;
  options.arc_length.max_step = 0.5 * bifurcation;
  options.monitor = 0.5;
  options.sample_points = {0.25, 0.5};
  options.switch_branch = true;
  return options;
}

std::vector<TraceEvent> bifurcations_of(const TraceResult& result) {
  std::vector<TraceEvent> out;
  for (const TraceEvent& e : result.events)
    if (e.kind == EventKind::bifurcation) out.push_back(e);
  return out;
}

}  // namespace

TEST_CASE("Ritz path, von Karman: the shallow arch snaps through at the closed form's limit point",
          "[continuation][ritz][von_karman]") {
  const closed_form::ShallowArchAnalysis analysis = closed_form::analyse(reference());
  REQUIRE(analysis.has_limit_points);
  REQUIRE(!analysis.has_bifurcation);
  const double upper = analysis.upper_limit.load, lower = analysis.lower_limit.load;
  REQUIRE(lower > 0.0);

  const scene::Scene scene = arch_scene();
  TraceOptions options;
  options.arc_length.lambda_min = 0.0;
  options.arc_length.lambda_max = 1.3 * upper;
  options.arc_length.initial_step = 0.25;
  options.arc_length.max_step = 0.5;
  options.monitor = 0.5;
  options.sample_points = {0.25, 0.5};
  const TraceResult result = test::trace_ritz_scene(scene, arch_member(scene), options);
  INFO(result.summary.message);
  REQUIRE(result.summary.termination == TraceTermination::completed);

  std::vector<TraceEvent> folds;
  for (const TraceEvent& e : result.events)
    if (e.kind == EventKind::limit_point) folds.push_back(e);
  REQUIRE(folds.size() == 2);
  // The snap-through load, then the lower limit point on the way back up (events located to
  // event_tolerance in lambda; the Ritz path is the closed form's up to round-off).
  CHECK(std::abs(folds[0].load_factor - upper) <= 10 * options.event_tolerance * upper);
  CHECK(std::abs(folds[1].load_factor - lower) <= 10 * options.event_tolerance * upper);
  CHECK(folds[0].description.find("maximum") != std::string::npos);
  CHECK(folds[1].description.find("minimum") != std::string::npos);

  // Stability changes sign at each limit point: stable below the upper one on the loading
  // branch, unstable between the two, stable again beyond the lower one. Along the path the
  // crown deflection grows monotonically; it tells the branches apart.
  const double crown_upper = analysis.upper_limit.deflection, crown_lower = analysis.lower_limit.deflection;
  int stable = 0, unstable = 0;
  for (const TraceStep& step : result.steps) {
    INFO("lambda = " << step.load_factor << ", crown " << step.monitor_deflection);
    REQUIRE(step.stability != continuation::Stability::unknown);
    const double w = step.monitor_deflection;
    // Within 1e-6 of a limit point the sign of the margin is round-off's: not asserted there.
    if (w < crown_upper * (1 - 1e-6)) {
      CHECK(step.stability == continuation::Stability::stable);
      ++stable;
    }
    if (w > crown_upper * (1 + 1e-6) && w < crown_lower * (1 - 1e-6)) {
      CHECK(step.stability == continuation::Stability::unstable);
      ++unstable;
    }
    if (w > crown_lower * (1 + 1e-6)) {
      CHECK(step.stability == continuation::Stability::stable);
      ++stable;
    }
    // On the symmetric path of the closed form, every step: lambda(A1) and the thrust.
    CHECK(step.load_factor == Approx(closed_form::symmetric_load(reference(), w)).epsilon(1e-9));
    CHECK(step.axial_force == Approx(closed_form::thrust(reference(), w, 0.0)).epsilon(1e-8));
  }
  CHECK(stable > 2);
  CHECK(unstable > 2);
}

TEST_CASE("Ritz path, von Karman: on a tensionless foundation the symmetric snap-through is the bilateral one",
          "[continuation][ritz][von_karman]") {
  // On the symmetric path w = A1 sin(pi s) >= 0 for every lambda >= 0 (shallow_arch.hpp, item 3):
  // no contact event, and the tensionless path is the bilateral path step for step.
  TraceOptions options;
  options.arc_length.lambda_min = 0.0;
  options.arc_length.lambda_max = 1.3 * closed_form::analyse(reference()).upper_limit.load;
  options.arc_length.initial_step = 0.25;
  options.arc_length.max_step = 0.5;
  options.monitor = 0.5;
  const scene::Scene bilateral_scene = arch_scene(false), tensionless_scene = arch_scene(true);
  const TraceResult bilateral = test::trace_ritz_scene(bilateral_scene, arch_member(bilateral_scene), options);
  const TraceResult tensionless = test::trace_ritz_scene(tensionless_scene, arch_member(tensionless_scene), options);
  INFO(tensionless.summary.message);
  REQUIRE(tensionless.summary.termination == TraceTermination::completed);
  REQUIRE(tensionless.events.size() == bilateral.events.size());
  for (std::size_t i = 0; i < tensionless.events.size(); ++i) {
    CHECK(tensionless.events[i].kind == EventKind::limit_point);
    CHECK(tensionless.events[i].load_factor == Approx(bilateral.events[i].load_factor).epsilon(1e-12));
  }
  REQUIRE(tensionless.steps.size() == bilateral.steps.size());
  for (std::size_t i = 0; i < tensionless.steps.size(); ++i) {
    CHECK(tensionless.steps[i].load_factor == Approx(bilateral.steps[i].load_factor).epsilon(1e-12));
    CHECK(tensionless.steps[i].monitor_deflection == Approx(bilateral.steps[i].monitor_deflection).epsilon(1e-12));
    CHECK(tensionless.steps[i].contact_regions.size() == 1);
  }
}

TEST_CASE(
    "Ritz path, von Karman: a / r = 8 bifurcates at the closed form's load, switches branch and ends where "
    "the branch rejoins the symmetric path",
    "[continuation][ritz][von_karman]") {
  // a / r = 8 > sqrt(22 - kappa / 2): the asymmetric bifurcation comes before the limit point
  // (shallow_arch.hpp, item 2), at p = (1 + kappa) alpha + 3 (4 - kappa) tB / 4, on the bare arch
  // and on a bilateral foundation. The symmetric path is stable up to it; the path switches onto
  // the asymmetric branch, where p = (1 + kappa) alpha + 3 (kappa - 4) t / 4 is linear in A1,
  // 4 eta^2 = tB^2 - t^2, unstable for kappa < 4 and stable for kappa > 4 (det H = 24 eta^2
  // (kappa - 4)); kappa = 8 < 36 keeps mode 2 the critical one (analysis.covered).
  // kappa = 0: the branch falls to lambda_min = 0 before its end (p < 0 at t = +tB).
  // kappa = 2 (falling) and 8 (rising): the branch rejoins the symmetric path at the second
  // bifurcation point t = +tB (p > 0 there); the trace ends there with a second bifurcation
  // event at its closed-form load (it used to switch again and shuttle between the two points:
  // 1533 steps, 8 bifurcations).
  // A1 = w(L/2) (the antisymmetric mode vanishes there), A2 = w(L/4) - A1 sin(pi/4).
  for (const double kappa : {0.0, 2.0, 8.0}) {
    const closed_form::ShallowArch arch = bifurcating_arch(kappa);
    const closed_form::ShallowArchAnalysis analysis = closed_form::analyse(arch);
    REQUIRE(analysis.has_bifurcation);
    REQUIRE(analysis.covered);
    const bool stable_branch = kappa > 4.0;
    REQUIRE(analysis.first == (stable_branch ? closed_form::FirstCritical::stable_bifurcation
                                             : closed_form::FirstCritical::unstable_bifurcation));
    REQUIRE(analysis.branch_stability ==
            (stable_branch ? closed_form::BranchStability::stable : closed_form::BranchStability::unstable));
    const double bifurcation = analysis.first_bifurcation.load, crown = analysis.first_bifurcation.deflection;
    const double second = analysis.second_bifurcation.load;
    const bool rejoins = second > 0.0;
    const scene::Scene scene = bifurcating_scene(arch);
    const TraceOptions options = switching_options(analysis);
    const TraceResult result = test::trace_ritz_scene(scene, bifurcating_member(scene, arch), options);
    INFO("kappa = " << kappa << ": " << result.summary.message << "; closed form bifurcations " << bifurcation << ", "
                    << second);
    REQUIRE(result.summary.termination == TraceTermination::completed);
    // A bounded trace (the shuttle took 1533 steps).
    CHECK(result.summary.steps <= 100);
    const std::vector<TraceEvent> bifurcations = bifurcations_of(result);
    REQUIRE(bifurcations.size() == (rejoins ? 2u : 1u));
    INFO(bifurcations[0].description);
    // Located to event_tolerance in lambda, as the limit points above.
    CHECK(std::abs(bifurcations[0].load_factor - bifurcation) <= 10 * options.event_tolerance * bifurcation);
    CHECK(bifurcations[0].description.find("switches to the bifurcated branch") != std::string::npos);
    if (rejoins) {
      INFO(bifurcations[1].description);
      CHECK(std::abs(bifurcations[1].load_factor - second) <= 10 * options.event_tolerance * bifurcation);
      CHECK(bifurcations[1].description.find("the switched branch ends here") != std::string::npos);
      CHECK(result.summary.message.find("met the path it left again") != std::string::npos);  // the engine's words
      CHECK(result.steps.back().load_factor == bifurcations[1].load_factor);
    }
    int stable = 0, on_branch = 0, branch_stable = 0;
    for (const TraceStep& step : result.steps) {
      const double a1 = step.monitor_deflection, a2 = step.deflection[0] - a1 * std::sqrt(0.5);
      INFO("lambda = " << step.load_factor << ", A1 " << a1 << ", A2 " << a2);
      if (rejoins && &step == &result.steps.back()) {
        // The second bifurcation point: both paths' (A1 = alpha + tB, A2 = 0). Its load is
        // checked above (to the event tolerance); A1 to the same relative accuracy over the
        // symmetric path's d ln lambda / d ln A1 (of order 1 here; seen: 1e-12): 1e-9.
        // A2 only to 1e-5 of A1 (seen: 5.5e-7 and 1.1e-7): the Hessian is singular at the
        // crossing, the linearised equations leave the mode's amplitude free and Newton's
        // round-off moves it; on the branch lambda moves with A2^2 (1e-12 relative at most).
        // The branch's first point is 1e-3 of w off: a point still on it fails this.
        CHECK(a1 == Approx(analysis.second_bifurcation.deflection).epsilon(1e-9));
        CHECK(std::abs(a2) <= 1e-5 * a1);
        continue;
      }
      if (std::abs(a2) <= 1e-9 * std::abs(a1)) {  // the symmetric path
        CHECK(step.load_factor == Approx(closed_form::symmetric_load(arch, a1)).epsilon(1e-9));
        if (a1 < crown * (1 - 1e-6)) {
          CHECK(step.stability == continuation::Stability::stable);
          ++stable;
        }
        continue;
      }
      ++on_branch;
      CHECK(std::abs(step.load_factor - closed_form::bifurcated_load(arch, a1)) <= 1e-8 * bifurcation);
      // On A2^2 (linear in t, 4 eta^2 = tB^2 - t^2): A2 itself is ill-conditioned at the branch points.
      const double asymmetry = closed_form::bifurcated_asymmetry(arch, a1);
      CHECK(std::abs(a2 * a2 - asymmetry * asymmetry) <= 1e-8 * a1 * a1);
      // The margin goes like A2^2 at the branch's ends (det H = 24 eta^2 (kappa - 4)): its sign
      // is asserted where A2 is at least the first point's offset (1e-3 of w).
      if (std::abs(a2) >= 1e-3 * std::abs(a1)) {
        CHECK(step.stability == (stable_branch ? continuation::Stability::stable : continuation::Stability::unstable));
        if (step.stability == continuation::Stability::stable) ++branch_stable;
      }
    }
    CHECK(stable >= 1);
    CHECK(on_branch >= 2);
    if (stable_branch) CHECK(branch_stable >= 2);
  }
}

TEST_CASE("Ritz and FE von Karman paths agree on the bifurcation load and the switched branch's stability",
          "[continuation][ritz][fe][von_karman]") {
  // The scene above (a / r = 8, kappa = 2 falling and kappa = 8 rising branch) traced by the FE
  // path too (continuation/models/fe_member.hpp: it also ends its switched branch where the
  // branch meets the path again). The FE bifurcation load converges at order 4 (its test); its
  // error is estimated by Richardson from 16 and 32 elements, |e32| ~ |l16 - l32| / 15 (8 elements
  // are too coarse here: on kappa = 2's branch their inertia changes twice). The Ritz load is the
  // closed form's to the event tolerance (above), so the two agree within the FE estimate (twice
  // it, the estimate's own uncertainty), and the branch's stability agrees.
  for (const double kappa : {2.0, 8.0}) {
    const closed_form::ShallowArch arch = bifurcating_arch(kappa);
    const closed_form::ShallowArchAnalysis analysis = closed_form::analyse(arch);
    const scene::Scene scene = bifurcating_scene(arch);
    const model::MemberModel member = bifurcating_member(scene, arch);
    TraceOptions options = switching_options(analysis);
    const TraceResult ritz = test::trace_ritz_scene(scene, member, options);
    std::vector<std::vector<TraceEvent>> fe;
    std::vector<TraceResult> fe_results;
    for (const int elements : {16, 32}) {
      options.elements = elements;
      options.arc_length.max_steps = 2000;
      fe_results.push_back(trace_fe_von_karman(member, options));
      INFO("kappa = " << kappa << ", " << elements << " elements: " << fe_results.back().summary.message);
      REQUIRE(fe_results.back().summary.termination == TraceTermination::completed);
      fe.push_back(bifurcations_of(fe_results.back()));
    }
    const std::vector<TraceEvent> r = bifurcations_of(ritz);
    INFO("kappa = " << kappa << ": Ritz " << ritz.summary.message << "; FE " << fe_results[1].summary.message);
    REQUIRE(r.size() == 2);
    REQUIRE(fe[0].size() == 2);
    REQUIRE(fe[1].size() == 2);
    const double estimate = std::abs(fe[0][0].load_factor - fe[1][0].load_factor) / 15;
    INFO("first bifurcation: Ritz " << r[0].load_factor << ", FE " << fe[0][0].load_factor << " / "
                                    << fe[1][0].load_factor << " (estimate " << estimate << ")");
    CHECK(std::abs(fe[1][0].load_factor - r[0].load_factor) <= 2 * estimate);
    // The second: both paths end their branch there, the FE path on the crossing located by a
    // secant on the tangent's eigenvalue nearest zero (models/fe_member.cpp, refine_return).
    // Its FE load converges at the first's order 4 (16 / 32 / 64 / 128 elements, errors against
    // the closed form: kappa = 2, 7.35e-4, 4.63e-5, 2.90e-6, 1.8e-7; kappa = 8, 6.50e-4, 4.15e-5,
    // 2.61e-6, round-off), so it is compared as the first. Without the secant the located point
    // lay on the symmetric path off the crossing (13.4290 / 13.4329 and 88.6184 / 89.3594).
    const double second_estimate = std::abs(fe[0][1].load_factor - fe[1][1].load_factor) / 15;
    INFO("second bifurcation: Ritz " << r[1].load_factor << ", FE " << fe[0][1].load_factor << " / "
                                     << fe[1][1].load_factor << " (estimate " << second_estimate << ")");
    CHECK(std::abs(fe[1][1].load_factor - r[1].load_factor) <= 2 * second_estimate);
    CHECK(std::abs(r[1].load_factor - analysis.second_bifurcation.load) <=
          10 * options.event_tolerance * analysis.second_bifurcation.load);
    // The FE branch's stability: the steps between the two events.
    int on_branch = 0;
    for (const TraceStep& step : fe_results[1].steps) {
      const double a1 = step.monitor_deflection, a2 = step.deflection[0] - a1 * std::sqrt(0.5);
      if (std::abs(a2) < 1e-2 * arch.rise) continue;  // the symmetric path, or next to the branch's ends
      ++on_branch;
      CHECK(step.stability == (kappa > 4.0 ? continuation::Stability::stable : continuation::Stability::unstable));
    }
    CHECK(on_branch >= 2);
  }
}

TEST_CASE(
    "Ritz path, von Karman: on a tensionless foundation the asymmetric branch lifts off at an end where "
    "|A2| = A1 / 2 and lands again",
    "[continuation][ritz][von_karman]") {
  // shallow_arch.hpp, item 3: tensionless and bilateral agree until the first contact event; on
  // the bifurcated branch w = r sin(theta) (xi + 2 eta cos theta) >= 0 while xi >= 2 |eta|, and it
  // touches zero at an end (x = 0 where A2 < 0, x = L where A2 > 0) with w' = 0 at the roots of
  // 2 xi^2 - 2 alpha xi + 16 + kappa = 0 (a / r = 8 >= sqrt(2 (16 + kappa)) for kappa = 2 and 8).
  // The switch stays in contact (the mode lifts nothing off until |A2| = A1 / 2); the path meets
  // limit_at_support at the first root (a zone opens at the pinned end), follows the branch with
  // the zone (no longer two-mode), and the zone closes again where the bilateral branch is back
  // in contact (the second root: a state in full contact is a bilateral solution, and it touches
  // zero at the end there); then the bilateral branch to the second bifurcation point.
  // All four loads to the event tolerance.
  for (const double kappa : {2.0, 8.0}) {
    const closed_form::ShallowArch arch = bifurcating_arch(kappa);
    const closed_form::ShallowArchAnalysis analysis = closed_form::analyse(arch);
    REQUIRE(analysis.has_contact_event);
    scene::Scene scene = bifurcating_scene(arch);
    scene.foundation.tensionless = true;
    const TraceOptions options = switching_options(analysis);
    const TraceResult result = test::trace_ritz_scene(scene, bifurcating_member(scene, arch), options);
    INFO("kappa = " << kappa << ": " << result.summary.message);
    std::string events;
    for (const TraceEvent& e : result.events)
      events += fmt::format("{:.17g}", e.load_factor) + " " + e.description + "\n";
    INFO(events);
    REQUIRE(result.summary.termination == TraceTermination::completed);
    REQUIRE(result.events.size() == 4);
    const double tolerance = 10 * options.event_tolerance * analysis.first_bifurcation.load;
    const std::vector<TraceEvent>& e = result.events;
    CHECK(e[0].kind == EventKind::bifurcation);
    CHECK(std::abs(e[0].load_factor - analysis.first_bifurcation.load) <= tolerance);
    CHECK(e[1].kind == EventKind::limit_at_support);
    CHECK(std::abs(e[1].load_factor - analysis.first_lift_off.load) <= tolerance);
    CHECK(e[2].kind == EventKind::limit_at_support);
    CHECK(std::abs(e[2].load_factor - analysis.last_lift_off.load) <= tolerance);
    CHECK(e[2].at == e[1].at);
    CHECK(e[3].kind == EventKind::bifurcation);
    CHECK(std::abs(e[3].load_factor - analysis.second_bifurcation.load) <= tolerance);
    // The end that lifts is the one A2's sign says; in full contact on the branch, the two-mode
    // branch's lambda; a lift-off zone on the steps between the two contact events.
    int lifted = 0;
    for (const TraceStep& step : result.steps) {
      const double a1 = step.monitor_deflection, a2 = step.deflection[0] - a1 * std::sqrt(0.5);
      INFO("lambda = " << step.load_factor << ", A1 " << a1 << ", A2 " << a2);
      if (step.lifted_length > 0.0) {
        ++lifted;
        CHECK(e[1].at == (a2 < 0.0 ? 0.0 : 1.0));
        continue;
      }
      if (std::abs(a2) >= 1e-3 * std::abs(a1))
        CHECK(std::abs(step.load_factor - closed_form::bifurcated_load(arch, a1)) <=
              1e-8 * analysis.first_bifurcation.load);
    }
    CHECK(lifted >= 2);
  }
}
