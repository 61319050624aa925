// The FE load history of a linear member (continuation/models/fe_member.hpp): every recorded state
// the contact solve's at its load (against fresh Lemke solves), no event missed between steps, the
// number of steps independent of the mesh, events where independent solves say the topology
// changes, and event loads converging to the closed form as the mesh is refined.

#include <catch2/catch.hpp>
#include <cmath>
#include <set>

#include "app/trace_command.hpp"
#include "certify/certificate.hpp"
#include "closed_form/beam_on_foundation.hpp"
#include "contact/active_set_system.hpp"
#include "continuation/events.hpp"
#include "continuation/models/fe_member.hpp"
#include "fe/discretisation.hpp"
#include "model/from_scene.hpp"
#include "model/member_model.hpp"
#include "scene/scene_reader.hpp"
#include "support/scenes.hpp"
#include "support/solve.hpp"
#include "support/trace_scene.hpp"

using namespace liftoff;
using continuation::EventKind;
using continuation::TraceOptions;
using continuation::TraceResult;
using continuation::TraceStep;

namespace {

using scene::EndSupport;
using scene::LoadCase;

// The shared scene: free-free beam L = 10, EI = 1e4, k = 500 over the whole length, dead
// uniform q = 1 into the foundation, live upward force 1 at the centre.
scene::Scene free_free_uplift() {
  auto s = test::beam_scene(10.0, 1e4, EndSupport::free, EndSupport::free, 500.0);
  s.loads.push_back(test::uniform_load(0.0, 10.0, 1.0, LoadCase::dead));
  s.loads.push_back(test::point_force(5.0, -1.0, LoadCase::live));
  return s;
}

// Simply supported beam (the seed's first example) under a dead uniform load and live end
// moments of one sense, which lift its left part off.
scene::Scene pinned_end_moments() {
  auto s = test::beam_scene(1.0, 1.0, EndSupport::pinned, EndSupport::pinned, 1e4);
  s.loads.push_back(test::uniform_load(0.0, 1.0, 100.0, LoadCase::dead));
  s.loads.push_back(test::point_moment(0.0, 1.0));
  s.loads.push_back(test::point_moment(1.0, 1.0));
  return s;
}

// Free-free beam with the dead load only over its middle, so it presses a central region only,
// and a live central uplift that splits that region in two.
scene::Scene central_region_split() {
  auto s = test::beam_scene(10.0, 1e4, EndSupport::free, EndSupport::free, 1e4);
  s.loads.push_back(test::uniform_load(3.0, 7.0, 1.0, LoadCase::dead));
  s.loads.push_back(test::point_force(5.0, -1.0, LoadCase::live));
  return s;
}

TraceOptions options_for(double lambda_min, double lambda_max, int elements) {
  TraceOptions o;
  o.arc_length.lambda_min = lambda_min;
  o.arc_length.lambda_max = lambda_max;
  o.elements = elements;
  return o;
}

// Sample points at every mesh node (user coordinate), so that a step records the nodal w and r.
std::vector<double> node_positions(const scene::Scene& scene, int elements) {
  const auto model = model::make_member_model(scene);
  const auto d = fe::discretise(model, elements);
  std::vector<double> x;
  for (double s : d.mesh.nodes) x.push_back(model.user_from_s(s));
  return x;
}

std::vector<bool> lemke_contact_set(const test::Solved& solved) {
  const auto& r = solved.solution.reaction;
  const auto& g = solved.solution.gap;
  // The gap's size is that of its terms (T r): in full contact the gaps are round-off.
  const double r_scale = std::max(r.lpNorm<Eigen::Infinity>(), 1e-300);
  const double g_scale = std::max((solved.discretisation.flexibility * r).lpNorm<Eigen::Infinity>(), 1e-300);
  std::vector<bool> set(r.size());
  for (Eigen::Index i = 0; i < r.size(); ++i) set[i] = r[i] / r_scale > g[i] / g_scale;
  return set;
}

std::vector<bool> set_of(const TraceStep& step) { return continuation::fe_contact_set(step); }

// Nodal w and r of a Lemke solve in user units, like a step's samples at the nodes.
struct NodalState {
  std::vector<double> w, r;
};
NodalState nodal_state(const test::Solved& solved) {
  NodalState n;
  const auto& d = solved.discretisation;
  const auto& scales = solved.model.scales;
  for (int node = 0; node < static_cast<int>(d.mesh.nodes.size()); ++node) {
    n.w.push_back(solved.solution.displacement[d.deflection_dof(node)] * scales.displacement());
    n.r.push_back(solved.solution.reaction[node] * scales.force_per_length());  // foundation over the whole member
  }
  return n;
}

double max_abs(const std::vector<double>& v) {
  double m = 0.0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

double max_relative_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double m = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) m = std::max(m, std::abs(a[i] - b[i]));
  const double scale = std::max(max_abs(a), max_abs(b));
  return scale == 0.0 ? 0.0 : m / scale;
}

const continuation::TraceEvent* first_event(const TraceResult& result, EventKind kind) {
  for (const auto& e : result.events)
    if (e.kind == kind) return &e;
  return nullptr;
}

// The exact lift-off load of the shared scene: in full contact the deflection is the bilateral
// one, w = q/K + lambda w_live (a uniform load on a free-free beam in full contact only
// settles it), so w(5) first reaches zero at lambda* = (q/K) / (-w_live(5)).
double closed_form_lift_off_load() {
  closed_form::BeamProblem live;
  live.length = 10.0;
  live.bending_stiffness = 1e4;
  live.foundation_modulus = 500.0 * 1e4 / std::pow(10.0, 4);
  live.left = live.right = closed_form::EndCondition::free;
  live.forces.push_back({5.0, -1.0});
  const double w_live = closed_form::solve_bilateral(live).deflection(5.0);
  return (1.0 / live.foundation_modulus) / -w_live;
}

}  // namespace

TEST_CASE("the shared scene's first lift-off converges to the closed form as the mesh is refined") {
  const double exact = closed_form_lift_off_load();
  std::vector<double> h, error, load;
  for (int elements : {20, 40, 80, 160}) {
    const TraceResult result = test::trace_fe(free_free_uplift(), options_for(0.0, 8.0, elements));
    INFO(elements << " elements: " << result.summary.message);
    REQUIRE(result.summary.termination == continuation::TraceTermination::completed);
    const auto* event = first_event(result, EventKind::lift_off_opens);
    REQUIRE(event != nullptr);
    // It is the first event: full contact until the centre lifts off.
    CHECK(event == &result.events.front());
    CHECK(event->at == Approx(5.0).margin(1e-9));
    h.push_back(10.0 / elements);
    load.push_back(event->load_factor);
    error.push_back(std::abs(event->load_factor - exact));
  }
  const double order = test::observed_order(h, error);
  INFO("lambda* = " << exact << "; event loads " << load[0] << " " << load[1] << " " << load[2] << " " << load[3]
                    << "; errors " << error[0] << " " << error[1] << " " << error[2] << " " << error[3]
                    << "; observed order " << order);
  // Each halving of h shrinks the error (no plateau from round-off or a wrong limit).
  for (std::size_t i = 1; i < error.size(); ++i) CHECK(error[i] < error[i - 1]);
  // Observed: 2.97 (error ratios 7.7, 7.8, 7.9 per halving, i.e. h^3). The breakpoint at which
  // the centre node's reaction vanishes converges only at h^2 (errors 2.4e-2, 6.1e-3, 1.6e-3,
  // 3.9e-4 on these meshes): locating the event where w touches zero is what this checks.
  CHECK(order > 2.5);
  // The finest mesh's error is what Richardson extrapolation from the two finest runs predicts
  // at the observed order, within a factor of 2 (the asymptotic range).
  const double estimate = std::abs(load[3] - load[2]) / (std::pow(2.0, order) - 1.0);
  CHECK(error[3] < 2.0 * estimate);
  CHECK(error[3] > 0.5 * estimate);
  // And estimate_event_errors, which traces on twice the elements, bounds the error of the
  // 80-element run by the same argument.
  const TraceResult coarse = test::trace_fe(free_free_uplift(), options_for(0.0, 8.0, 80));
  const auto estimates = test::estimate_event_errors(free_free_uplift(), options_for(0.0, 8.0, 80), coarse);
  REQUIRE(estimates.refined_elements == 160);
  REQUIRE(!estimates.events.empty());
  REQUIRE(estimates.events.front().refined.has_value());
  CHECK(estimates.events.front().load_factor_error == Approx(std::abs(load[2] - load[3])).epsilon(1e-9));
  CHECK(error[2] < 2.0 * estimates.events.front().load_factor_error);
}

TEST_CASE("every recorded state is the contact solve's at its load, and no event is missed between steps") {
  // The linear path runs on the engine (one contact set at a time, a node switch that changes no
  // event taken at a step's end): its recorded states are the exact solutions at their loads (the
  // corrector's Newton step on a linear system is exact to round-off; the mixed form keeps it well
  // conditioned), and between two steps the contact topology does not change, or the change would
  // be an event with a step of its own. Tolerance: the exact solutions on both sides, 1e-9 of the
  // largest value (the condition of the 40-element system times eps, orders below).
  struct Case {
    const char* name;
    scene::Scene scene;
    double lambda_max;
    int elements;
  };
  for (const Case& c : {Case{"free-free uplift", free_free_uplift(), 8.0, 40},
                        Case{"pinned, end moments", pinned_end_moments(), 5.0, 40},
                        Case{"central region split", central_region_split(), 3.0, 40}}) {
    CAPTURE(c.name);
    TraceOptions options = options_for(0.0, c.lambda_max, c.elements);
    options.sample_points = node_positions(c.scene, c.elements);
    const TraceResult result = test::trace_fe(c.scene, options);
    INFO(result.summary.message);
    REQUIRE(result.summary.termination == continuation::TraceTermination::completed);
    REQUIRE(result.steps.size() >= 3);
    for (const TraceStep& step : result.steps) {
      CAPTURE(step.load_factor);
      const auto lemke = test::solve(c.scene, contact::Method::automatic, c.elements, step.load_factor);
      REQUIRE(lemke.solution.summary.is_usable());
      const NodalState exact = nodal_state(lemke);
      CHECK(max_relative_difference(step.deflection, exact.w) < 1e-9);
      CHECK(max_relative_difference(step.reaction, exact.r) < 1e-9);
    }
    int compared = 0;
    for (std::size_t k = 0; k + 1 < result.steps.size(); ++k) {
      const TraceStep &a = result.steps[k], &b = result.steps[k + 1];
      if (b.load_factor - a.load_factor < 1e-9 * c.lambda_max) continue;  // an event step at a crossing
      CAPTURE(a.load_factor, b.load_factor);
      const auto midpoint =
          test::solve(c.scene, contact::Method::automatic, c.elements, 0.5 * (a.load_factor + b.load_factor));
      // (A step at an event holds the topology of either side.)
      const std::size_t regions = midpoint.regions.size();
      CHECK((regions == a.contact_regions.size() || regions == b.contact_regions.size()));
      ++compared;
    }
    CHECK(compared >= 2);
  }
}

TEST_CASE("the number of steps does not grow with the mesh") {
  // A contact limit moving on by a node is no event and ends no step (the engine takes such a switch
  // at the step's end): steps follow the events and the path's curvature, not the nodes. Were
  // every breakpoint a step, four times the elements would take about four times the steps.
  for (const auto& [scene, lambda_max] : {std::pair{free_free_uplift(), 8.0}, std::pair{pinned_end_moments(), 8.0},
                                          std::pair{central_region_split(), 3.9}}) {
    const TraceResult coarse = test::trace_fe(scene, options_for(0.0, lambda_max, 80));
    const TraceResult fine = test::trace_fe(scene, options_for(0.0, lambda_max, 320));
    INFO(coarse.summary.message << " | " << fine.summary.message);
    REQUIRE(coarse.summary.termination == continuation::TraceTermination::completed);
    REQUIRE(fine.summary.termination == continuation::TraceTermination::completed);
    std::set<std::vector<bool>> sets;
    for (const auto& step : fine.steps) sets.insert(set_of(step));
    CAPTURE(coarse.summary.steps, fine.summary.steps, sets.size());
    CHECK(fine.summary.steps < 2 * coarse.summary.steps);
    CHECK(fine.events.size() == coarse.events.size());
  }
}

namespace {

// The contact topology of an independent Lemke solve at lambda.
continuation::ContactTopology lemke_topology(const scene::Scene& scene, int elements, double lambda) {
  const auto solved = test::solve(scene, contact::Method::automatic, elements, lambda);
  REQUIRE(solved.solution.summary.is_usable());
  return continuation::contact_topology(solved.model, solved.discretisation, solved.solution.displacement,
                                        continuation::special_points(solved.model));
}

// Every event of the trace is what independent Lemke solves just before and just after its
// load say happens: classified from their two topologies, it has the same kind and place.
void check_events_against_lemke(const scene::Scene& scene, const TraceOptions& options, const TraceResult& result) {
  const auto model = model::make_member_model(scene);
  const auto points = continuation::special_points(model);
  const double h = model.user_from_s(model.length()) / options.elements;
  for (std::size_t k = 0; k < result.events.size(); ++k) {
    const auto& event = result.events[k];
    CAPTURE(event.description, event.load_factor);
    // Closer to the event than any other event or the ends of the range, but far above the
    // tolerance it was located to.
    double room =
        std::min(event.load_factor - options.arc_length.lambda_min, options.arc_length.lambda_max - event.load_factor);
    for (const auto& other : result.events)
      if (other.load_factor != event.load_factor)
        room = std::min(room, std::abs(other.load_factor - event.load_factor));
    const double offset = std::min(1e-5 * (options.arc_length.lambda_max - options.arc_length.lambda_min), 0.25 * room);
    REQUIRE(offset > 1e3 * options.event_tolerance);
    const auto before = lemke_topology(scene, options.elements, event.load_factor - offset);
    const auto after = lemke_topology(scene, options.elements, event.load_factor + offset);
    CHECK_FALSE(before.same_as(after));
    const auto independent = continuation::classify_events(model, points, before, after, event.load_factor);
    bool found = false;
    for (const auto& e : independent) found = found || (e.kind == event.kind && std::abs(e.at - event.at) <= h);
    CHECK(found);
  }
}

}  // namespace

TEST_CASE("simply supported beam under end moments: events agree with Lemke on either side") {
  const TraceOptions options = options_for(0.0, 5.0, 80);
  const TraceResult result = test::trace_fe(pinned_end_moments(), options);
  INFO(result.summary.message);
  REQUIRE(result.summary.termination == continuation::TraceTermination::completed);
  // Full contact at first; the moments then lift the left end: a lift-off zone opens at the
  // pinned end (the limit leaves the support).
  REQUIRE(!result.events.empty());
  CHECK(result.steps.front().contact_regions.size() == 1);
  CHECK(result.events.front().kind == EventKind::limit_at_support);
  CHECK(result.events.front().at == Approx(0.0).margin(1e-12));
  check_events_against_lemke(pinned_end_moments(), options, result);
}

TEST_CASE("a central contact region splits in two") {
  const TraceOptions options = options_for(0.0, 3.9, 80);
  const TraceResult result = test::trace_fe(central_region_split(), options);
  INFO(result.summary.message);
  REQUIRE(result.summary.termination == continuation::TraceTermination::completed);
  // The dead load over the middle presses a central region only: both ends are lifted off.
  REQUIRE(result.steps.front().contact_regions.size() == 1);
  CHECK(result.steps.front().contact_regions[0].begin > 1.0);
  CHECK(result.steps.front().contact_regions[0].end < 9.0);
  const auto* split = first_event(result, EventKind::lift_off_opens);
  REQUIRE(split != nullptr);
  CHECK(split == &result.events.front());
  CHECK(split->at == Approx(5.0).margin(1e-9));
  // Lemke on both sides: one central region before, two after with x = 5 between them.
  const double offset = 1e-4;
  const auto before = lemke_topology(central_region_split(), 80, split->load_factor - offset);
  const auto after = lemke_topology(central_region_split(), 80, split->load_factor + offset);
  REQUIRE(before.pieces.size() == 3);  // lift-off, contact, lift-off
  CHECK(before.pieces[1].region.in_contact);
  CHECK(before.pieces[1].region.begin < 0.5);
  CHECK(before.pieces[1].region.end > 0.5);
  REQUIRE(after.pieces.size() == 5);  // lift-off, contact, lift-off, contact, lift-off
  CHECK(!after.pieces[2].region.in_contact);
  CHECK(after.pieces[2].region.begin < 0.5);
  CHECK(after.pieces[2].region.end > 0.5);
  check_events_against_lemke(central_region_split(), options, result);
}

TEST_CASE("a free-free beam lifted off by its loads stops with no equilibrium at the load that does it") {
  // Beyond lambda = q L / P = 10 the upward force exceeds the weight: nothing holds the beam.
  // The load is exact in the discrete model too (the consistent loads have the same
  // resultants), located by bisection to event_tolerance.
  for (int elements : {80, 200}) {
    CAPTURE(elements);
    const TraceOptions options = options_for(0.0, 12.0, elements);
    const TraceResult result = test::trace_fe(free_free_uplift(), options);
    INFO(result.summary.message);
    CHECK(result.summary.termination == continuation::TraceTermination::no_equilibrium);
    CHECK(result.summary.final_load_factor == Approx(10.0).margin(10 * options.event_tolerance));
    CHECK(result.summary.message.find("lambda = 10") != std::string::npos);
    CHECK(result.steps.back().load_factor == result.summary.final_load_factor);
  }
}

TEST_CASE("the path does not depend on units") {
  // The shared scene in millimetres and newtons: L = 1e4 mm, EI = 1e4 N m^2 = 1e10 N mm^2,
  // q = 1 N/m = 1e-3 N/mm, P = 1 N, k = K L^4/EI unchanged.
  auto millimetres = test::beam_scene(1e4, 1e10, EndSupport::free, EndSupport::free, 500.0);
  millimetres.loads.push_back(test::uniform_load(0.0, 1e4, 1e-3, LoadCase::dead));
  millimetres.loads.push_back(test::point_force(5e3, -1.0, LoadCase::live));
  TraceOptions metres_options = options_for(0.0, 8.0, 40), millimetres_options = metres_options;
  metres_options.sample_points = {2.5};
  millimetres_options.sample_points = {2.5e3};
  const TraceResult a = test::trace_fe(free_free_uplift(), metres_options);
  const TraceResult b = test::trace_fe(millimetres, millimetres_options);
  REQUIRE(a.steps.size() == b.steps.size());
  REQUIRE(a.events.size() == b.events.size());
  for (std::size_t k = 0; k < a.events.size(); ++k) {
    CHECK(a.events[k].load_factor == Approx(b.events[k].load_factor).epsilon(1e-9));
    CHECK(1e3 * a.events[k].at == Approx(b.events[k].at).epsilon(1e-9));
  }
  for (std::size_t k = 0; k < a.steps.size(); ++k) {
    CHECK(a.steps[k].load_factor == Approx(b.steps[k].load_factor).epsilon(1e-9));
    CHECK(1e3 * a.steps[k].deflection[0] == Approx(b.steps[k].deflection[0]).epsilon(1e-9));
    CHECK(1e-3 * a.steps[k].reaction[0] == Approx(b.steps[k].reaction[0]).epsilon(1e-9));
  }
}

TEST_CASE("a resumed trace reproduces the rest of the path and its events") {
  TraceOptions options = options_for(0.0, 3.9, 80);
  options.sample_points = {2.0, 5.0, 8.0};
  options.monitor = 5.0;
  const TraceResult full = test::trace_fe(central_region_split(), options);
  REQUIRE(full.summary.termination == continuation::TraceTermination::completed);
  REQUIRE(full.events.size() >= 2);
  // Resume from the last step before the first event: every event is still ahead.
  std::size_t from = 0;
  while (from + 1 < full.steps.size() && full.steps[from + 1].load_factor < full.events.front().load_factor) ++from;
  REQUIRE(from > 0);
  options.resume_from = full.steps[from];
  std::vector<TraceStep> written;
  std::vector<continuation::TraceEvent> events;
  const TraceResult resumed = test::trace_fe(central_region_split(), options,
                                             {[&](const TraceStep& s) { written.push_back(s); },
                                              [&](const continuation::TraceEvent& e) { events.push_back(e); }});
  REQUIRE(resumed.summary.termination == continuation::TraceTermination::completed);
  REQUIRE(written.size() == full.steps.size() - from - 1);
  // The resumed run starts from the step's state re-solved at its load on its set: the same steps up
  // to round-off (the step lengths and states within 1e-10 of their size; the 80-element mixed
  // system's condition times eps is orders below), the same sets.
  double monitor_scale = 0.0;
  for (const TraceStep& s : full.steps) monitor_scale = std::max(monitor_scale, std::abs(s.monitor_deflection));
  for (std::size_t k = 0; k < written.size(); ++k) {
    const TraceStep &a = written[k], &b = full.steps[from + 1 + k];
    CHECK(a.load_factor == Approx(b.load_factor).epsilon(1e-12));
    CHECK(set_of(a) == set_of(b));
    REQUIRE(a.state.size() == b.state.size());
    for (std::size_t i = a.state.size() - continuation::fe_state_tail; i < a.state.size(); ++i)
      CHECK(a.state[i] == Approx(b.state[i]).epsilon(1e-10));
    CHECK(a.contact_regions.size() == b.contact_regions.size());
    CHECK(max_relative_difference(a.deflection, b.deflection) < 1e-10);
    CHECK(std::abs(a.monitor_deflection - b.monitor_deflection) <= 1e-10 * monitor_scale);
  }
  REQUIRE(events.size() == full.events.size());
  for (std::size_t k = 0; k < events.size(); ++k) {
    CHECK(events[k].kind == full.events[k].kind);
    CHECK(events[k].at == Approx(full.events[k].at).margin(1e-9));
    CHECK(events[k].load_factor == Approx(full.events[k].load_factor).epsilon(1e-12));
  }
  // It did not start over: no Lemke, one factorisation per set from the resumed one on.
  CHECK(resumed.summary.factorisations < full.summary.factorisations);
}

TEST_CASE("a path through zero load: the unloaded state, where every set holds, is passed, and the path stays exact") {
  // End moments alone, lambda from -1 to 1: at lambda = 0 every reaction and gap is zero, and
  // the contact set of the reversed moments is not the complement of the first one.
  auto scene = test::beam_scene(1.0, 1.0, EndSupport::pinned, EndSupport::pinned, 1e4);
  scene.loads.push_back(test::point_moment(0.0, 1.0));
  scene.loads.push_back(test::point_moment(1.0, 1.0));
  TraceOptions options = options_for(-1.0, 1.0, 40);
  options.sample_points = node_positions(scene, 40);
  const TraceResult result = test::trace_fe(scene, options);
  INFO(result.summary.message);
  REQUIRE(result.summary.termination == continuation::TraceTermination::completed);
  for (double lambda : {-0.7, -0.2, 0.3, 0.9}) {
    CAPTURE(lambda);
    std::size_t k = 0;
    while (result.steps[k + 1].load_factor < lambda) ++k;
    const TraceStep &a = result.steps[k], &b = result.steps[k + 1];
    const double t = (lambda - a.load_factor) / (b.load_factor - a.load_factor);
    const NodalState exact = nodal_state(test::solve(scene, contact::Method::automatic, 40, lambda));
    std::vector<double> w;
    for (std::size_t i = 0; i < exact.w.size(); ++i) w.push_back((1 - t) * a.deflection[i] + t * b.deflection[i]);
    CHECK(max_relative_difference(w, exact.w) < 1e-9);
    CHECK(lemke_contact_set(test::solve(scene, contact::Method::automatic, 40, lambda)) == set_of(a));
  }
}

TEST_CASE("a shipped arch traced from no load to lambda = 1 ends where solve does") {
  // Live loads only: the path is one ray from the unloaded arch, with one contact set.
  const auto scene = test::shipped_scene("seed_arch_roller");
  TraceOptions options = options_for(0.0, 1.0, 80);
  options.monitor = 0.0;
  const TraceResult result = test::trace_fe(scene, options);
  INFO(result.summary.message);
  REQUIRE(result.summary.termination == continuation::TraceTermination::completed);
  for (const auto& step : result.steps) CHECK(set_of(step) == set_of(result.steps.back()));
  CHECK(result.events.empty());
  const auto solved = test::solve(scene, contact::Method::dual, 80, 1.0);
  const auto& end = result.steps.back();
  REQUIRE(end.contact_regions.size() == solved.regions.size());
  for (std::size_t i = 0; i < solved.regions.size(); ++i) {
    CHECK(end.contact_regions[i].begin == Approx(solved.model.user_from_s(solved.regions[i].begin)).epsilon(1e-9));
    CHECK(end.contact_regions[i].end == Approx(solved.model.user_from_s(solved.regions[i].end)).epsilon(1e-9));
  }
  const int crown = solved.discretisation.mesh.node_at(0.0);
  REQUIRE(crown >= 0);
  CHECK(end.monitor_deflection == Approx(solved.solution.displacement[solved.discretisation.deflection_dof(crown)] *
                                         solved.model.scales.displacement())
                                      .epsilon(1e-9));
}

TEST_CASE("limits reaching a point support and point loads are events, as Lemke confirms") {
  // Pinned left end, a point support at x = 3, free right end; dead weight and a dead force
  // at x = 6, a live uplift at x = 8.
  auto scene = test::beam_scene(10.0, 1e4, EndSupport::pinned, EndSupport::free, 2000.0);
  scene.supports.interior = {3.0};
  scene.loads.push_back(test::uniform_load(0.0, 10.0, 1.0, LoadCase::dead));
  scene.loads.push_back(test::point_force(6.0, 0.5, LoadCase::dead));
  scene.loads.push_back(test::point_force(8.0, -1.0, LoadCase::live));
  const TraceOptions options = options_for(0.0, 6.0, 80);
  const TraceResult result = test::trace_fe(scene, options);
  INFO(result.summary.message);
  REQUIRE(result.summary.termination == continuation::TraceTermination::completed);
  std::set<EventKind> kinds;
  for (const auto& e : result.events) kinds.insert(e.kind);
  CHECK(kinds.count(EventKind::limit_at_support) > 0);
  CHECK(kinds.count(EventKind::limit_at_load) > 0);
  CHECK(kinds.count(EventKind::lift_off_opens) > 0);
  for (const auto& e : result.events) {
    if (e.kind == EventKind::limit_at_support) CHECK(e.at == Approx(3.0).margin(1e-9));
    if (e.kind == EventKind::limit_at_load) CHECK((std::abs(e.at - 6.0) < 1e-9 || std::abs(e.at - 8.0) < 1e-9));
  }
  check_events_against_lemke(scene, options, result);
}

TEST_CASE("the refined run's estimate of the event loads' discretisation error falls with the mesh") {
  // The split scene has several events (the split, then both ends coming back into contact):
  // each is matched in the run on twice the elements, and the difference shrinks like the
  // error it estimates (at least halving per halving of h; test 1 measures h^3).
  const auto coarse_options = options_for(0.0, 3.9, 40), fine_options = options_for(0.0, 3.9, 80);
  const auto coarse = test::estimate_event_errors(central_region_split(), coarse_options,
                                                  test::trace_fe(central_region_split(), coarse_options));
  const auto fine = test::estimate_event_errors(central_region_split(), fine_options,
                                                test::trace_fe(central_region_split(), fine_options));
  REQUIRE(coarse.events.size() >= 2);
  REQUIRE(coarse.events.size() == fine.events.size());
  for (std::size_t k = 0; k < coarse.events.size(); ++k) {
    CAPTURE(coarse.events[k].event.description, coarse.events[k].load_factor_error, fine.events[k].load_factor_error);
    REQUIRE(coarse.events[k].refined.has_value());
    REQUIRE(fine.events[k].refined.has_value());
    CHECK(fine.events[k].event.kind == coarse.events[k].event.kind);
    CHECK(fine.events[k].load_factor_error < 0.5 * coarse.events[k].load_factor_error);
  }
}

TEST_CASE("FE path: every reported state passes the certificate, and a wrong contact set there does not",
          "[continuation][certify]") {
  // The culvert (a closing lift-off zone) and the footing: each step's state is rebuilt from the
  // contact set it records and certified with the path's options (nodal checks, backward error to
  // the path's 1e-8, signs to the same 1e-8 on the member's scale); the same state with one contact
  // node dropped from the set must fail (a reaction forced to zero where the member presses in).
  for (const char* name : {"arch_culvert", "footing_trace"}) {
    const scene::Scene s = test::continuation_scene(name);
    TraceOptions o = app::trace_options(s, {});
    o.elements = 60;
    const TraceResult r = test::trace_fe(s, o);
    CAPTURE(name, r.summary.message);
    REQUIRE(r.summary.termination == continuation::TraceTermination::completed);
    const auto model = model::make_member_model(s);
    const auto d = fe::discretise(model, o.elements);
    certify::CertifyOptions c;
    c.round_off = false;
    c.pointwise = false;
    c.backward_tolerance = 1e-8;
    c.sign_floor = 1e-8;
    c.global_scale = true;
    int wrong_caught = 0, wrong_tried = 0;
    for (const TraceStep& step : r.steps) {
      const std::vector<bool> set = set_of(step);
      auto certify_set = [&](const std::vector<bool>& with) {
        contact::ActiveSetSystem system(d);
        REQUIRE(system.factorise(with));
        const contact::ContactState state = system.solve(d.load(step.load_factor));
        contact::ContactSolution answer;
        answer.displacement = d.expand(state.displacement);
        answer.reaction = state.reaction;
        c.load_factor = step.load_factor;
        return certify::certify(model, d, answer, c);
      };
      const certify::Certificate good = certify_set(set);
      CAPTURE(step.load_factor, good.message);
      CHECK(good.passed);
      // Drop the contact node with the largest reaction (clearly pressed, not at a tie).
      int strongest = -1;
      {
        contact::ActiveSetSystem system(d);
        REQUIRE(system.factorise(set));
        const contact::ContactState state = system.solve(d.load(step.load_factor));
        double largest = 0.0;
        for (int i = 0; i < d.reactions(); ++i)
          if (set[i] && state.reaction[i] > largest) {
            largest = state.reaction[i];
            strongest = i;
          }
      }
      if (strongest < 0) continue;
      std::vector<bool> wrong = set;
      wrong[strongest] = false;
      contact::ActiveSetSystem probe(d);
      if (!probe.factorise(wrong)) continue;  // the set would leave the member floating
      ++wrong_tried;
      wrong_caught += !certify_set(wrong).passed;
    }
    CHECK(wrong_tried > 0);
    CHECK(wrong_caught == wrong_tried);
  }
}

namespace {

// The path of `scene` from lambda = 0 to 1 on `elements` elements, and solve's answer (fast) at
// lambda = 1 on the same mesh: the path ends on it, with the same contact set and nodal w to the
// round-off of the two fixed-set solves (1e-12 of max |w| is 1e4 times that).
struct PathEnd {
  TraceStep end;
  test::Solved solved;
  NodalState exact;
};

PathEnd path_ends_on_solve(const scene::Scene& scene, int elements) {
  TraceOptions options = options_for(0.0, 1.0, elements);
  options.sample_points = node_positions(scene, elements);
  const TraceResult result = test::trace_fe(scene, options);
  INFO(result.summary.message);
  REQUIRE(result.summary.termination == continuation::TraceTermination::completed);
  test::Solved solved = test::solve(scene, contact::Method::fast, elements, 1.0);
  REQUIRE(solved.solution.summary.is_usable());
  const NodalState exact = nodal_state(solved);
  const TraceStep& end = result.steps.back();
  CHECK(end.load_factor == 1.0);
  CHECK(max_relative_difference(end.deflection, exact.w) < 1e-12);
  CHECK(set_of(end) == lemke_contact_set(solved));
  return {end, std::move(solved), exact};
}

}  // namespace

TEST_CASE("a ground gap and settlements: the path from lambda = 0 ends where solve does", "[issue12][gap]") {
  // The gap (and a settlement's dead load and gap offset) is the constant part of the path, not
  // scaled by lambda: the state at lambda = 0 is the answer under them alone (w = 1e-3 at the
  // settled ends, a free-free beam floating over the trench), and at lambda = 1 the path must end
  // on the answer of `liftoff solve` on the same mesh: the same contact set, nodal w to the
  // round-off of the two fixed-set solves (1e-12 of max |w| is 1e4 times that), contact regions
  // at the same roots of the same cubics.
  const std::string dir = std::string(LIFTOFF_SOURCE_DIR) + "/verification/dolfinx/scenes/issue12/";
  // (Not interior_settlement: a free-free beam hung on a raised interior pin reaches no ground at
  // small lambda, and its rotation about the pin is free there: the path cannot start at 0.)
  for (const char* name :
       {"gap_trench", "gap_file_seabed", "settlement_pinned", "settlement_clamped_gap", "settlement_clamped"}) {
    CAPTURE(name);
    const scene::Scene scene = scene::read_scene_file(dir + name + ".toml");
    const int elements = 200;
    const PathEnd path = path_ends_on_solve(scene, elements);
    const test::Solved& solved = path.solved;
    const NodalState& exact = path.exact;
    REQUIRE(path.end.contact_regions.size() == solved.regions.size());
    for (std::size_t i = 0; i < solved.regions.size(); ++i) {
      CHECK(path.end.contact_regions[i].begin ==
            Approx(solved.model.user_from_s(solved.regions[i].begin)).epsilon(1e-9));
      CHECK(path.end.contact_regions[i].end == Approx(solved.model.user_from_s(solved.regions[i].end)).epsilon(1e-9));
    }
    // Would it fail if the path dropped the constant part? The answer without it (the same
    // scene with no gap and no settlement) is another, by 1e6 times the tolerance above at least
    // (6.4e-6 of max |w| measured for settlement_clamped_gap, where a lifting force dominates).
    scene::Scene plain = scene;
    plain.foundation.gap_at.clear();
    plain.foundation.gap_value.clear();
    plain.supports.left_detail.settlement = plain.supports.right_detail.settlement = 0.0;
    for (double& s : plain.supports.interior_settlement) s = 0.0;
    const auto without = test::solve(plain, contact::Method::fast, elements, 1.0);
    if (without.solution.summary.is_usable()) CHECK(max_relative_difference(nodal_state(without).w, exact.w) > 1e-6);
  }
}

TEST_CASE("a bilinear foundation: the path ends where solve does", "[issue12][tension]") {
  // K_t (w - g) is a bilateral Winkler part: in K (and its load K_t g in the dead load), so the
  // path's fixed-set solves carry it like the member's stiffness. tension_k.toml, and the seabed
  // (gap_file) with K_t = 1e3: at lambda = 1 the path is on solve's answer, as above.
  const std::string dir = std::string(LIFTOFF_SOURCE_DIR) + "/verification/dolfinx/scenes/issue12/";
  for (const char* name : {"tension_k", "gap_file_seabed"}) {
    CAPTURE(name);
    scene::Scene scene = scene::read_scene_file(dir + name + ".toml");
    scene.foundation.tension_k = 1e3;
    REQUIRE(model::make_member_model(scene).has_tension_k());
    const int elements = 200;
    const NodalState exact = path_ends_on_solve(scene, elements).exact;
    // Would it fail if the path dropped K_t? The tensionless answer is another.
    scene::Scene plain = scene;
    plain.foundation.tension_k.reset();
    const auto without = test::solve(plain, contact::Method::fast, elements, 1.0);
    if (without.solution.summary.is_usable()) CHECK(max_relative_difference(nodal_state(without).w, exact.w) > 1e-6);
  }
}

TEST_CASE("FE path: the states at requested loads, in order, as the path's end there", "[fe_path]") {
  // The free-free beam to lambda = 8 asked for its states at 2.5 and 6 (between breakpoints):
  // each a step flagged requested, between its neighbours in lambda, and the same state as a trace
  // that ends there (its last step computed on another run, from its own breakpoints).
  const scene::Scene scene = free_free_uplift();
  TraceOptions options = options_for(0.0, 8.0, 80);
  options.sample_points = node_positions(scene, 80);
  options.report_at = {6.0, 2.5};
  const TraceResult result = test::trace_fe(scene, options);
  REQUIRE(result.summary.termination == continuation::TraceTermination::completed);
  std::vector<std::size_t> requested;
  for (std::size_t i = 0; i < result.steps.size(); ++i)
    if (result.steps[i].requested) requested.push_back(i);
  REQUIRE(requested.size() == 2);
  for (std::size_t k = 0; k < 2; ++k) {
    const std::size_t i = requested[k];
    const double load = k == 0 ? 2.5 : 6.0;
    INFO("lambda " << load);
    REQUIRE(result.steps[i].load_factor == load);
    REQUIRE((i > 0 && i + 1 < result.steps.size()));
    CHECK(result.steps[i - 1].load_factor < load);
    CHECK(result.steps[i + 1].load_factor > load);
    TraceOptions to_load = options_for(0.0, load, 80);
    to_load.sample_points = options.sample_points;
    const TraceResult ending = test::trace_fe(scene, to_load);
    REQUIRE(ending.summary.termination == continuation::TraceTermination::completed);
    const TraceStep& there = ending.steps.back();
    REQUIRE(there.load_factor == load);
    // Two affine evaluations of one state: round-off of the largest deflection.
    REQUIRE(there.deflection.size() == options.sample_points.size());
    CHECK(max_relative_difference(result.steps[i].deflection, there.deflection) < 1e-12);
    REQUIRE(result.steps[i].design.has_value());
    CHECK(result.steps[i].design->moment_max.value == Approx(there.design->moment_max.value).epsilon(1e-12));
  }
  // Without report_at no step is requested.
  for (const TraceStep& step : test::trace_fe(scene, options_for(0.0, 8.0, 80)).steps) CHECK(!step.requested);
}
