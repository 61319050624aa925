// The FE load path of a von Karman beam (the von Karman kinematics of continuation/models/member_kinematics.hpp):
// the sinusoidal shallow arch under q0 sin(pi x / L) against verification/closed_form/shallow_arch.hpp
// (its limit point, its bifurcation and the asymmetric branch, with the orders of the FE error), a
// bilateral against a tensionless foundation, and the snap-through of issue 16's scene with a contact
// event on the way against the Ritz path.
//
// L = 1, EI = 1, pinned ends axially restrained, w0 = -a sin(pi s) (MemberModel::initial_sine),
// EA = 1e4 (r = 0.01). The sine load is the consistent load of q0 sin(pi s) (5-point Gauss rule per
// element: exact to ~h^10), built here and handed to the path's live-load seam (the scene's sine
// load is another branch's).
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "closed_form/shallow_arch.hpp"
#include "contact/von_karman_solve.hpp"
#include "continuation/models/fe_member.hpp"
#include "continuation/models/ritz.hpp"
#include "fe/shape_functions.hpp"
#include "model/from_scene.hpp"
#include "scene/scene_reader.hpp"
#include "support/ritz_trace.hpp"

using namespace liftoff;
using namespace liftoff::continuation;
using Eigen::VectorXd;

namespace {

const double pi = M_PI, pi4 = M_PI * M_PI * M_PI * M_PI;
constexpr double membrane_stiffness = 1e4;

closed_form::ShallowArch arch(double relative_rise, double kappa) {
  closed_form::ShallowArch a;
  a.axial_stiffness = membrane_stiffness;
  a.rise = relative_rise / std::sqrt(membrane_stiffness);
  a.foundation_modulus = kappa * pi4;
  a.load_amplitude = 1.0;
  return a;
}

model::MemberModel member(const closed_form::ShallowArch& a, bool tensionless) {
  model::MemberModel m;
  m.kind = model::StructureKind::beam;
  m.theory = model::Theory::von_karman;
  m.membrane_stiffness = a.axial_stiffness;
  m.k = a.foundation_modulus;
  m.tensionless = tensionless;
  m.left_axially_restrained = m.right_axially_restrained = true;
  m.initial_sine = model::MemberModel::InitialSine{-a.rise, 0.0, 1.0};
  return m;
}

// The consistent load of sin(pi s) on the unknowns.
VectorXd sine_load(const fe::Discretisation& d, const contact::VonKarmanSystem& system) {
  VectorXd f = VectorXd::Zero(system.unknowns());
  for (int e = 0; e < d.mesh.elements(); ++e) {
    const double s0 = d.mesh.nodes[e], h = d.mesh.element_size(e);
    const std::vector<int> dofs = d.element_dofs(e);
    for (const fe::GaussPoint& point : fe::gauss5) {
      const Eigen::Vector4d shape = fe::hermite_cubic(point.xi, h).value;
      const double q = std::sin(pi * (s0 + point.xi * h)) * point.weight * h;
      for (int i = 0; i < 4; ++i)
        if (d.equation_of_dof[dofs[i]] >= 0) f[d.equation_of_dof[dofs[i]]] += q * shape[i];
    }
  }
  return f;
}

TraceOptions options(double lambda_max, int elements) {
  TraceOptions o;
  o.arc_length.lambda_min = 0.0;
  o.arc_length.lambda_max = lambda_max;
  o.arc_length.initial_step = 0.25;
  o.arc_length.max_step = 1.0;
  o.arc_length.max_steps = 2000;
  o.elements = elements;
  o.monitor = 0.5;
  o.sample_points = {0.25, 0.5};
  return o;
}

std::vector<TraceEvent> of_kind(const TraceResult& r, EventKind kind) {
  std::vector<TraceEvent> out;
  for (const TraceEvent& e : r.events)
    if (e.kind == kind) out.push_back(e);
  return out;
}

// The observed order of errors on meshes doubling.
double order(double coarse, double fine) { return std::log2(std::abs(coarse) / std::abs(fine)); }

}  // namespace

TEST_CASE("FE von Karman path: the shallow arch's limit point at the closed form's load, at order 4",
          "[continuation][fe][von_karman]") {
  // a / r = 4.5, kappa = 0: 2 < a / r < sqrt(22), the limit point precedes the bifurcation points
  // (which lie on the unstable part: a bifurcation event there, no switch).
  const closed_form::ShallowArch a = arch(4.5, 0.0);
  const closed_form::ShallowArchAnalysis analysis = closed_form::analyse(a);
  REQUIRE(analysis.first == closed_form::FirstCritical::limit_point);
  const double upper = analysis.upper_limit.load;
  std::vector<double> errors, distances;
  for (int elements : {4, 8, 16}) {
    const TraceResult r = trace_fe_von_karman(member(a, false), options(1.3 * upper, elements), {}, sine_load);
    CAPTURE(elements, r.summary.message);
    REQUIRE(r.summary.termination == TraceTermination::completed);
    const std::vector<TraceEvent> folds = of_kind(r, EventKind::limit_point);
    REQUIRE(folds.size() == 1);  // the lower one lies below lambda = 0, where the path ends
    CHECK(folds[0].description.find("maximum") != std::string::npos);
    errors.push_back(folds[0].load_factor - upper);
    // Past the limit point, on the unstable part, the bifurcation points of the symmetric path.
    const std::vector<TraceEvent> bifurcations = of_kind(r, EventKind::bifurcation);
    REQUIRE(bifurcations.size() >= 1);
    CHECK(bifurcations[0].load_factor == Approx(analysis.first_bifurcation.load).epsilon(1e-2));
    // Every step on the closed form's symmetric path (crown = A1): the largest distance in lambda,
    // whose order is checked below; stable before the limit point, unstable after it.
    double distance = 0.0;
    for (const TraceStep& step : r.steps) {
      CAPTURE(step.load_factor, step.monitor_deflection);
      distance =
          std::max(distance, std::abs(step.load_factor - closed_form::symmetric_load(a, step.monitor_deflection)));
      if (step.monitor_deflection < analysis.upper_limit.deflection * (1 - 1e-3))
        CHECK(step.stability == continuation::Stability::stable);
      if (step.monitor_deflection > analysis.upper_limit.deflection * (1 + 1e-3))
        CHECK(step.stability == continuation::Stability::unstable);
    }
    distances.push_back(distance);
  }
  CAPTURE(errors[0], errors[1], errors[2], distances[0], distances[1], distances[2]);
  // Within the discretisation error: Richardson's estimate of the finest mesh's error at order 4,
  // |e_16| ~ |lambda_8 - lambda_16| / 15, with a factor 2 for the order's spread (3.9 to 4.0).
  CHECK(std::abs(errors[2]) <= 2 * std::abs(errors[1] - errors[2]) / 15);
  CHECK(order(errors[0], errors[1]) > 3.5);
  CHECK(order(errors[1], errors[2]) > 3.5);
  CHECK(order(distances[0], distances[1]) > 3.5);
  CHECK(order(distances[1], distances[2]) > 3.5);
}

TEST_CASE("FE von Karman path: the arch bifurcates at the closed form's load onto the unstable asymmetric branch",
          "[continuation][fe][von_karman]") {
  // a / r = 8, kappa = 0: the asymmetric bifurcation precedes the limit point; the bifurcated
  // branch has lambda linear in A1, falling (d lambda / d A1 = -3 in p), and is unstable.
  const closed_form::ShallowArch a = arch(8.0, 0.0);
  const closed_form::ShallowArchAnalysis analysis = closed_form::analyse(a);
  REQUIRE(analysis.first == closed_form::FirstCritical::unstable_bifurcation);
  const double critical = analysis.first_bifurcation.load;
  std::vector<double> errors, load_distances, asymmetry_distances;
  for (int elements : {4, 8, 16}) {
    const TraceResult r = trace_fe_von_karman(member(a, false), options(1.2 * critical, elements), {}, sine_load);
    CAPTURE(elements, r.summary.message);
    REQUIRE(r.summary.termination == TraceTermination::completed);
    const std::vector<TraceEvent> bifurcations = of_kind(r, EventKind::bifurcation);
    REQUIRE(!bifurcations.empty());
    CHECK(of_kind(r, EventKind::limit_point).empty());
    CHECK(bifurcations[0].description.find("switches") != std::string::npos);
    errors.push_back(bifurcations[0].load_factor - critical);
    // The switched branch: the steps with A2 = w(1/4) - A1 / sqrt 2 away from zero. Its distance to
    // the closed form's branch, in lambda at the step's A1 and in A2^2 (4 eta^2 = tB^2 - t^2, smooth
    // where A2 is not), is checked for its order below.
    int on_branch = 0;
    double in_load = 0.0, in_asymmetry = 0.0;
    for (const TraceStep& step : r.steps) {
      const double a1 = step.monitor_deflection, a2 = step.deflection[0] - a1 / std::sqrt(2.0);
      if (std::abs(a2) < 1e-2 * a.rise) continue;  // the symmetric path
      ++on_branch;
      CAPTURE(step.load_factor, a1, a2);
      in_load = std::max(in_load, std::abs(step.load_factor - closed_form::bifurcated_load(a, a1)));
      in_asymmetry = std::max(
          in_asymmetry, std::abs(a2 * a2 - std::pow(closed_form::bifurcated_asymmetry(a, a1), 2)) / (a.rise * a.rise));
      CHECK(step.stability == continuation::Stability::unstable);
    }
    CHECK(on_branch >= 3);
    load_distances.push_back(in_load);
    asymmetry_distances.push_back(in_asymmetry);
  }
  CAPTURE(errors[0], errors[1], errors[2]);
  CAPTURE(load_distances[0], load_distances[1], load_distances[2]);
  CAPTURE(asymmetry_distances[0], asymmetry_distances[1], asymmetry_distances[2]);
  CHECK(std::abs(errors[2]) <= 2 * std::abs(errors[1] - errors[2]) / 15);
  CHECK(order(errors[0], errors[1]) > 3.5);
  CHECK(order(errors[1], errors[2]) > 3.5);
  CHECK(order(load_distances[0], load_distances[1]) > 3.5);
  CHECK(order(load_distances[1], load_distances[2]) > 3.5);
  CHECK(order(asymmetry_distances[0], asymmetry_distances[1]) > 3.5);
  CHECK(order(asymmetry_distances[1], asymmetry_distances[2]) > 3.5);
}

TEST_CASE("FE von Karman path: bilateral and tensionless foundations agree until the first contact event",
          "[continuation][fe][von_karman]") {
  // a / r = 8, kappa = 1 (< 4: the asymmetric branch is unstable and falling): the symmetric path
  // is in contact throughout (w = A1 sin >= 0), the bifurcated branch lifts off where A1 = 2 |A2|
  // (closed form: first_lift_off). Up to that event the two foundations are one problem.
  const closed_form::ShallowArch a = arch(8.0, 1.0);
  const closed_form::ShallowArchAnalysis analysis = closed_form::analyse(a);
  REQUIRE(analysis.first == closed_form::FirstCritical::unstable_bifurcation);
  REQUIRE(analysis.has_contact_event);
  const double critical = analysis.first_bifurcation.load;
  std::vector<double> errors;
  for (int elements : {16, 32}) {
    const TraceOptions o = options(1.2 * critical, elements);
    const TraceResult bilateral = trace_fe_von_karman(member(a, false), o, {}, sine_load);
    const TraceResult tensionless = trace_fe_von_karman(member(a, true), o, {}, sine_load);
    CAPTURE(elements, bilateral.summary.message, tensionless.summary.message);
    REQUIRE(bilateral.summary.termination == TraceTermination::completed);
    CHECK(of_kind(bilateral, EventKind::lift_off_opens).empty());
    // The tensionless path's first contact event: a lift-off zone opening at a pinned end (the
    // closed form's w = r xi sin(theta) (1 -+ cos(theta)) touching zero there).
    auto first_contact = std::find_if(tensionless.events.begin(), tensionless.events.end(), [](const TraceEvent& e) {
      return e.kind != EventKind::bifurcation && e.kind != EventKind::limit_point;
    });
    REQUIRE(first_contact != tensionless.events.end());
    CAPTURE(first_contact->load_factor, first_contact->at, first_contact->description);
    CHECK(first_contact->kind == EventKind::limit_at_support);
    CHECK(first_contact->description.find("lift-off zone opens at the end") != std::string::npos);
    errors.push_back(first_contact->load_factor - analysis.first_lift_off.load);
    // Until the tensionless path's contact set first changes (fe_contact_set of the step: one per
    // reaction; the first change may be the pinned end's node, whose sign is w' there, no event), the two paths solve
    // the same equations: the same steps, to the last bit.
    std::size_t until = 0;
    const auto full = [](const TraceStep& step) {
      const std::vector<bool> set = continuation::fe_contact_set(step);
      return !set.empty() && std::all_of(set.begin(), set.end(), [](bool c) { return c; });
    };
    while (until < tensionless.steps.size() && full(tensionless.steps[until])) ++until;
    REQUIRE(until < tensionless.steps.size());
    REQUIRE(bilateral.steps.size() > until);
    CHECK(tensionless.steps[until].load_factor >= first_contact->load_factor);
    // (Step until - 1 is where the set changes: located there by the tensionless path alone.)
    REQUIRE(until >= 2);
    for (std::size_t i = 0; i + 1 < until; ++i) {
      CAPTURE(i);
      CHECK(tensionless.steps[i].load_factor == bilateral.steps[i].load_factor);
      CHECK(tensionless.steps[i].monitor_deflection == bilateral.steps[i].monitor_deflection);
      CHECK(tensionless.steps[i].stability == bilateral.steps[i].stability);
    }
    REQUIRE(!of_kind(tensionless, EventKind::bifurcation).empty());
    CHECK(of_kind(tensionless, EventKind::bifurcation)[0].load_factor ==
          of_kind(bilateral, EventKind::bifurcation)[0].load_factor);
  }
  CAPTURE(errors[0], errors[1]);
  CHECK(std::abs(errors[1]) < std::abs(errors[0]));
}

TEST_CASE("FE von Karman path: issue 16's shallow arch snaps through with a contact event, as the Ritz path does",
          "[continuation][fe][ritz][von_karman]") {
  // verification/dolfinx/scenes/issue16/shallow_arch_tensionless.toml: rise 6 r, k = 100,
  // tensionless, uniform load on the left half. The unloaded half lifts off at once (the start is
  // taken at lambda = 1, past that degenerate point), the arch snaps through (a limit point; the
  // dolfinx reference: lambda 21.14 at 64 elements) and the unloaded half comes back into contact
  // on the falling branch (20.50 there): its lift-off zone closes at the pinned end.
  scene::Scene s = scene::read_scene_file(std::string(LIFTOFF_SOURCE_DIR) +
                                          "/verification/dolfinx/scenes/issue16/shallow_arch_tensionless.toml");
  const model::MemberModel m = model::make_member_model(s);
  std::vector<TraceResult> fe;
  for (int elements : {64, 128}) {
    TraceOptions o = options(30.0, elements);
    o.arc_length.lambda_min = 1.0;
    fe.push_back(trace_fe_von_karman(m, o));
    const TraceResult& r = fe.back();
    CAPTURE(elements, r.summary.message);
    REQUIRE(r.summary.termination == TraceTermination::completed);
    // Through the snap-through (maximum), the zone closing on the falling branch, the lower limit
    // point (minimum) and up again to lambda_max, in that order.
    REQUIRE(r.events.size() == 3);
    CHECK(r.events[0].kind == EventKind::limit_point);
    CHECK(r.events[0].description.find("maximum") != std::string::npos);
    CHECK(r.events[1].kind == EventKind::limit_at_support);
    CHECK(r.events[1].description.find("lift-off zone closes at the end") != std::string::npos);
    CHECK(r.events[1].load_factor < r.events[0].load_factor);
    CHECK(r.events[2].kind == EventKind::limit_point);
    CHECK(r.events[2].description.find("minimum") != std::string::npos);
    // Stable up to the snap-through, unstable on the falling branch.
    for (const TraceStep& step : r.steps) {
      if (step.load_factor < r.events[0].load_factor - 1.0 && step.monitor_deflection < 0.02)
        CHECK(step.stability == continuation::Stability::stable);
    }
  }
  const double limit_64 = fe[0].events[0].load_factor, limit_128 = fe[1].events[0].load_factor;
  const double closing_64 = fe[0].events[1].load_factor, closing_128 = fe[1].events[1].load_factor;
  CAPTURE(limit_64, limit_128, closing_64, closing_128);
  // The dolfinx reference at 64 elements (von_karman_reference.py --json, run 2026-12-03: limit point
  // 21.1414344, zone closing 20.5031489, both bisected to 2e-12): an independent discretisation whose
  // own error is not estimated (one mesh), so this is a cross-check, not a derived bound: the gaps
  // observed are 4.6e-4 (limit) and 8e-5 (closing) relative, while ours move by 2.3e-6 and 1.1e-4
  // from 64 to 128 elements. Bound: 1e-3 relative.
  CHECK(std::abs(limit_64 - 21.1414344) <= 1e-3 * 21.1414344);
  CHECK(std::abs(closing_64 - 20.5031489) <= 1e-3 * 20.5031489);
  // The closing converges like h^2 at most (a node joins: the limit is placed to within an element).
  CHECK(std::abs(closing_64 - closing_128) <= 1e-3 * closing_64);

  // The Ritz path of the same member, started on the FE path's topology at lambda_min (the linear
  // FE solve its automatic start would take knows nothing of the arch: the straight beam stays in
  // contact): the same limit point within the FE estimate |lambda_64 - lambda_128| (the Ritz
  // path's own is below: 32 modes, a sine series of a smooth field).
  REQUIRE(fe[0].steps[0].contact_regions.size() == 1);
  const ContactRegion first = fe[0].steps[0].contact_regions[0];
  REQUIRE(first.begin == 0.0);
  s.ritz.topology = {true, false};
  s.ritz.limits = {first.end};
  TraceOptions o = options(30.0, 64);
  o.arc_length.lambda_min = 1.0;
  const TraceResult ritz = test::trace_ritz_scene(s, m, o);
  INFO(ritz.summary.message);
  const std::vector<TraceEvent> ritz_folds = of_kind(ritz, EventKind::limit_point);
  REQUIRE(!ritz_folds.empty());
  CHECK(ritz_folds[0].description.find("maximum") != std::string::npos);
  CHECK(std::abs(ritz_folds[0].load_factor - limit_128) <= 2 * std::abs(limit_64 - limit_128));
  // Since the Ritz path approaches a zone closing at a pinned end from the side where the zone
  // exists, it follows the same history as the FE path: the zone closing on the falling branch and
  // the lower limit point, in that order, up to lambda_max. Their loads are compared with dolfinx
  // (above) and between the paths by snap_lift_off_agreement_test's imperfect arch, not here.
  CHECK(ritz.summary.termination == TraceTermination::completed);
  REQUIRE(ritz_folds.size() == 2);
  CHECK(ritz_folds[1].description.find("minimum") != std::string::npos);
  const std::vector<TraceEvent> ritz_closings = of_kind(ritz, EventKind::limit_at_support);
  REQUIRE(ritz_closings.size() == 1);
  CHECK(ritz_closings[0].load_factor < ritz_folds[0].load_factor);
  CHECK(ritz_closings[0].load_factor > ritz_folds[1].load_factor);
}

TEST_CASE("FE von Karman path: load control stops at the limit point that arc-length control passes",
          "[continuation][fe][von_karman]") {
  // The comparison option: load control cannot pass a fold in lambda; it ends step_too_small just
  // below the limit load that the arc-length path locates (same mesh).
  const closed_form::ShallowArch a = arch(4.5, 0.0);
  const double upper = closed_form::analyse(a).upper_limit.load;
  const TraceResult arc = trace_fe_von_karman(member(a, false), options(1.3 * upper, 16), {}, sine_load);
  REQUIRE(arc.summary.termination == TraceTermination::completed);
  const double fold = of_kind(arc, EventKind::limit_point).at(0).load_factor;
  TraceOptions o = options(1.3 * upper, 16);
  o.arc_length.control = PathControl::load;
  const TraceResult load = trace_fe_von_karman(member(a, false), o, {}, sine_load);
  INFO(load.summary.message);
  CHECK(load.summary.termination == TraceTermination::step_too_small);
  REQUIRE(!load.steps.empty());
  // At the fold the Jacobian is singular, so the corrector's residual tolerance (1e-11, scaled)
  // resolves lambda only to about its square root there: within 1e-6 of the fold, either side.
  CHECK(std::abs(load.steps.back().load_factor - fold) <= 1e-6 * fold);
  CHECK(of_kind(load, EventKind::limit_point).empty());
}

namespace {

model::MemberModel demo_arch() {
  const scene::Scene s = scene::read_scene_file(std::string(LIFTOFF_SOURCE_DIR) +
                                                "/verification/dolfinx/scenes/issue16/shallow_arch_tensionless.toml");
  return model::make_member_model(s);
}

}  // namespace

TEST_CASE("FE von Karman path: every recorded state is certified, and a state that fails ends the path",
          "[continuation][fe][von_karman][certify]") {
  const model::MemberModel m = demo_arch();
  TraceOptions o = options(30.0, 64);
  o.arc_length.lambda_min = 1.0;
  // The seam sees the unknowns of every state the certificate checks; untouched, all pass.
  int certified = 0;
  const TraceResult clean = trace_fe_von_karman(m, o, {}, {}, [&](double, VectorXd&) { ++certified; });
  INFO(clean.summary.message);
  REQUIRE(clean.summary.termination == TraceTermination::completed);
  CHECK(certified >= static_cast<int>(clean.steps.size()));
  // The limit points are recorded as steps of their own, at their event's load.
  for (const TraceEvent& e : of_kind(clean, EventKind::limit_point)) {
    CAPTURE(e.load_factor);
    CHECK(std::any_of(clean.steps.begin(), clean.steps.end(),
                      [&](const TraceStep& s) { return s.load_factor == e.load_factor; }));
  }

  // One reaction made to pull beyond lambda = 10: that state fails its certificate (balance and
  // the reaction's sign) and is not recorded; the path ends there, the steps before it kept.
  const TraceResult spoilt = trace_fe_von_karman(m, o, {}, {}, [&](double lambda, VectorXd& y) {
    // y = (x, r_A): the last entry is a reaction on the set (the loaded half is in contact).
    if (lambda > 10.0) y[y.size() - 1] = -1.0;
  });
  INFO(spoilt.summary.message);
  CHECK(spoilt.summary.termination == TraceTermination::solver_failure);
  CHECK(spoilt.summary.message.find("failed its certificate") != std::string::npos);
  REQUIRE(!spoilt.steps.empty());
  CHECK(spoilt.steps.back().load_factor <= 10.0);
  for (std::size_t i = 0; i < spoilt.steps.size(); ++i)
    CHECK(spoilt.steps[i].load_factor == clean.steps[i].load_factor);
}

TEST_CASE("FE von Karman path: max_amplitude stops the path; resume_from is refused by name",
          "[continuation][fe][von_karman]") {
  const model::MemberModel m = demo_arch();
  TraceOptions o = options(30.0, 64);
  o.arc_length.lambda_min = 1.0;
  const TraceResult full = trace_fe_von_karman(m, o);
  REQUIRE(full.summary.termination == TraceTermination::completed);
  // The unloaded half lifts off from the start: its amplitude grows along the path. Stop at half
  // its largest value: the first step at or past it, and no step after.
  double largest = 0.0;
  for (const TraceStep& s : full.steps) largest = std::max(largest, s.amplitude);
  REQUIRE(largest > 0.0);
  o.max_amplitude = 0.5 * largest;
  const TraceResult bounded = trace_fe_von_karman(m, o);
  INFO(bounded.summary.message);
  CHECK(bounded.summary.termination == TraceTermination::completed);
  CHECK(bounded.summary.message.find("max_amplitude") != std::string::npos);
  REQUIRE(!bounded.steps.empty());
  CHECK(bounded.steps.back().amplitude >= *o.max_amplitude);
  for (std::size_t i = 0; i + 1 < bounded.steps.size(); ++i) CHECK(bounded.steps[i].amplitude < *o.max_amplitude);
  CHECK(bounded.steps.size() < full.steps.size());

  o.max_amplitude.reset();
  o.resume_from = full.steps[3];
  const TraceResult resumed = trace_fe_von_karman(m, o);
  CHECK(resumed.summary.termination == TraceTermination::solver_failure);
  CHECK(resumed.summary.message.find("TraceOptions.resume_from") != std::string::npos);
  CHECK(resumed.steps.empty());
}

TEST_CASE("FE von Karman path: a circular arch is traced, every state the von Karman solve's at its load",
          "[continuation][fe][von_karman][arch]") {
  // The seed's pinned arch under von Karman theory (verification/scenes/von_karman/): traced to
  // lambda = 2, where the lift-off zones at both ends close again (its contact region reaches the
  // supports). Each recorded state is the FE von Karman contact solve's at the step's load factor,
  // solved on its own from zero (contact/von_karman_solve.hpp): the same discrete problem, so they
  // agree to the solves' accuracy (both certified to their backward error, ~1e-12 of w).
  scene::Scene s = scene::read_scene_file(std::string(LIFTOFF_SOURCE_DIR) +
                                          "/verification/scenes/von_karman/seed_arch_pinned_von_karman.toml");
  const model::MemberModel m = model::make_member_model(s);
  REQUIRE(m.kind == model::StructureKind::arch);
  TraceOptions o;
  o.arc_length.lambda_min = 0.0;
  o.arc_length.lambda_max = 2.0;
  o.elements = 50;
  o.monitor = 0.0;
  const TraceResult r = trace_fe_von_karman(m, o);
  CAPTURE(r.summary.message);
  REQUIRE(r.summary.termination == TraceTermination::completed);
  CHECK(r.steps.back().load_factor == 2.0);
  // Both ends' zones close together (the arch is symmetric).
  const std::vector<TraceEvent> closing = of_kind(r, EventKind::limit_at_support);
  REQUIRE(closing.size() == 2);
  CHECK(closing[0].load_factor == Approx(closing[1].load_factor).epsilon(1e-9));
  const fe::Discretisation d = fe::discretise(m, o.elements);
  const contact::VonKarmanSystem system(m, d);
  const double scale = m.scales.displacement();
  for (std::size_t i = 1; i < r.steps.size(); i += 7) {
    const TraceStep& step = r.steps[i];
    CAPTURE(i, step.load_factor);
    const contact::VonKarmanResult solved = system.solve(step.load_factor, contact::VonKarmanOptions{});
    REQUIRE(solved.is_usable());
    const int crown = o.elements / 2;
    CHECK(step.monitor_deflection == Approx(solved.w[crown] * scale).epsilon(1e-8));
    // The contact regions: the solve's nodes in contact lie inside the step's region (the region's
    // limits are on the element cubics, between a node in contact and the next one lifted).
    REQUIRE(step.contact_regions.size() == 1);
    for (int node = 0; node <= o.elements; ++node) {
      const double theta = m.user_from_s(d.mesh.nodes[node]);
      const bool inside = theta >= step.contact_regions[0].begin - 1e-9 && theta <= step.contact_regions[0].end + 1e-9;
      if (solved.w[node] > 1e-9 * solved.w.cwiseAbs().maxCoeff()) CHECK(inside);
    }
  }
}
