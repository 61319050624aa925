// The FE path's events do not depend on where the mesh happens to put a node (issue 10, item 5):
// on the footing trace (continuation/scenes/footing_trace.toml) the heel lifts off at every mesh
// from 50 to 400 elements, and every event load agrees with the closed form within the FE
// error estimate; on region_split no mesh adds an event or fails to start.
//
// The error estimate of an event load at N elements is the discretisation error plus round-off:
//  - discretisation: the event loads of 5, 10 and 20 elements give the observed order p (asserted
//    above a floor p_min, and measured where the differences dwarf the round-off bound, so
//    that it is a discretisation order); the error at N is then at most D (10/N)^p_min /
//    (1 - 2^-p_min), D = |lambda_10 - lambda_20| (the tail of the series of differences, at
//    the asserted order, slower than the observed one, so an overestimate for N > 10);
//  - round-off: the event is the zero of an affine f(lambda) = f_dead + lambda f_live (w at a
//    node, with the contact set of the segment fixed), and the rounding of the system's data
//    moves f_dead and f_live by at most data_error (ActiveSetSystem: eps times Skeel's
//    condition, a worst-case bound) times the size of their states, so the load by
//    (e_dead |u_dead| + lambda e_live |u_live|) / |f_live|.
//  - location: events are bisected to the trace's event_tolerance (1e-10) in lambda.
// With the stiffness form K, round-off dominated this stiff footing on a soft foundation (k = 4.5)
// from about 60 elements on, growing like N^4 (2.2e-5 off the closed form at 357 elements). The
// sparse solves now use the mixed form (src/README.md, "Mesh size and round-off"): the heel event is
// 6e-11 off an independent 40-digit closed form (mpmath) at 130 and 200 elements, which is the
// bisection's tolerance, not the discretisation's or round-off's.

#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "app/trace_command.hpp"
#include "closed_form/beam_on_foundation.hpp"
#include "contact/active_set_system.hpp"
#include "continuation/models/fe_member.hpp"
#include "fe/discretisation.hpp"
#include "model/from_scene.hpp"
#include "model/member_model.hpp"
#include "scene/scene_reader.hpp"
#include "support/scenes.hpp"
#include "support/trace_scene.hpp"

using namespace liftoff;
using continuation::EventKind;
using continuation::TraceEvent;
using continuation::TraceOptions;
using continuation::TraceResult;

namespace {

TraceResult fe_run(const scene::Scene& s, int elements, double lambda_max) {
  TraceOptions o = app::trace_options(s, {});
  o.elements = elements;
  o.arc_length.lambda_max = lambda_max;
  return test::trace_fe(s, o);
}

// The footing (the scene file's numbers) in the closed form, one load case at a time.
closed_form::BeamProblem footing_case(scene::LoadCase which) {
  closed_form::BeamProblem p;
  p.length = 3.0;
  p.bending_stiffness = 5.4e8;
  p.foundation_modulus = 3.0e7;
  p.left = p.right = closed_form::EndCondition::free;
  if (which == scene::LoadCase::dead)
    p.forces.push_back({1.8, 800e3});
  else
    p.moments.push_back({1.8, -100e3});
  return p;
}

// The heel lifts off in full contact (the bilateral solution): w_dead(0) + lambda w_live(0) = 0.
double exact_heel_load() {
  const double dead = closed_form::solve_bilateral(footing_case(scene::LoadCase::dead)).deflection(0.0);
  const double live = closed_form::solve_bilateral(footing_case(scene::LoadCase::live)).deflection(0.0);
  return -dead / live;
}

// The limit reaches the column with contact on [1.8, 3]: w(1.8) = 0 there, and the solution is
// then a tensionless one (w >= 0 on the contact, <= 0 off it; checked).
double exact_column_load() {
  const std::vector<closed_form::Interval> contact{{1.8, 3.0}};
  const auto dead = closed_form::solve_with_contact(footing_case(scene::LoadCase::dead), contact);
  const auto live = closed_form::solve_with_contact(footing_case(scene::LoadCase::live), contact);
  const double lambda = -dead.deflection(1.8) / live.deflection(1.8);
  closed_form::BeamProblem both = footing_case(scene::LoadCase::dead);
  both.moments.push_back({1.8, -100e3 * lambda});
  const auto regions = closed_form::contact_regions(closed_form::solve_with_contact(both, contact));
  REQUIRE(regions.size() == 1);
  CHECK(regions[0].start == Approx(1.8).margin(1e-9));
  CHECK(regions[0].end == Approx(3.0).margin(1e-12));
  return lambda;
}

const TraceEvent* find_event(const TraceResult& r, EventKind kind, double at) {
  for (const auto& e : r.events)
    if (e.kind == kind && std::abs(e.at - at) <= 1e-9) return &e;
  return nullptr;
}

// The round-off bound of an event load (header): f = w at `node` with the contact set `set`.
double round_off_bound(const scene::Scene& s, int elements, const std::vector<bool>& set, int node, double lambda) {
  const auto model = model::make_member_model(s);
  const auto d = fe::discretise(model, elements);
  contact::ActiveSetSystem system(d);
  REQUIRE(system.factorise(set));
  const auto dead = system.solve(d.dead_load), live = system.solve(d.live_load);
  const double e_dead = system.data_error(dead, d.dead_load), e_live = system.data_error(live, d.live_load);
  const Eigen::VectorXd u_dead = d.expand(dead.displacement), u_live = d.expand(live.displacement);
  return (e_dead * u_dead.lpNorm<Eigen::Infinity>() + std::abs(lambda) * e_live * u_live.lpNorm<Eigen::Infinity>()) /
         std::abs(u_live[d.deflection_dof(node)]);
}

struct Convergence {
  double order = 0.0;       // observed, from 5, 10, 20 elements
  double difference = 0.0;  // |lambda_10 - lambda_20|
  double round_off = 0.0;   // the largest round-off bound of the three runs
  double smallest = 0.0;    // the smaller of the two differences
  // The discretisation error at n >= 10 elements, at the asserted order p_min (header): the
  // sum of the differences between n 2^j and n 2^(j+1) elements, D (10/n)^p_min 2^(-j p_min).
  double error_at(int n, double p_min) const {
    return difference * std::pow(10.0 / n, p_min) / (1.0 - std::pow(2.0, -p_min));
  }
};

// Event loads on 5, 10, 20 elements and their convergence; event_at(n) gives the event load on
// n elements and its round-off bound.
template <class EventAt>
Convergence convergence(EventAt event_at) {
  double load[3];
  Convergence c;
  int i = 0;
  for (int n : {5, 10, 20}) {
    const auto [lambda, bound] = event_at(n);
    load[i++] = lambda;
    c.round_off = std::max(c.round_off, bound);
  }
  c.order = std::log2(std::abs(load[0] - load[1]) / std::abs(load[1] - load[2]));
  c.difference = std::abs(load[1] - load[2]);
  c.smallest = std::min(std::abs(load[0] - load[1]), c.difference);
  return c;
}

// The contact set of the step recorded at an event (the set of the segment it lies in).
std::vector<bool> set_at(const TraceResult& r, const TraceEvent& e) {
  for (const auto& step : r.steps)
    if (step.load_factor == e.load_factor) return continuation::fe_contact_set(step);
  FAIL("no step at the event's load");
  return {};
}

}  // namespace

TEST_CASE("footing trace: the heel lifts off at every mesh from 50 to 400 elements, at the closed form's load",
          "[continuation][mesh]") {
  const scene::Scene s = test::continuation_scene("footing_trace");
  const double exact = exact_heel_load();
  // Just past the heel event (1.554; the rigid footing's 1.6): the event falls on the first
  // breakpoint, so the run covers the segments on both sides of it.
  const double lambda_max = 1.6;
  const int heel = 0;  // node of the heel

  // The heel lifts off from full contact, so the event's contact set is every node.
  auto heel_event = [&](int n) {
    const TraceResult r = fe_run(s, n, lambda_max);
    INFO(n << " elements: " << r.summary.message);
    REQUIRE(r.summary.termination == continuation::TraceTermination::completed);
    REQUIRE(r.events.size() == 1);
    REQUIRE(r.events[0].kind == EventKind::limit_at_end);
    REQUIRE(r.events[0].at == 0.0);
    const auto model = model::make_member_model(s);
    const int nodes = fe::discretise(model, n).reactions();
    const double bound = round_off_bound(s, n, std::vector<bool>(nodes, true), heel, r.events[0].load_factor);
    return std::pair{r.events[0].load_factor, bound};
  };

  // The heel event converges fast in full contact (observed order 6.6 from 5 to 20 elements:
  // differences 1.2e-5 and 1.3e-7), far above round-off there (bound 1e-9).
  constexpr double p_min = 3.0;
  const Convergence c = convergence(heel_event);
  INFO("observed order " << c.order << ", differences down to " << c.smallest << ", round-off bound " << c.round_off);
  CHECK(c.order > p_min);
  CHECK(c.smallest > 10.0 * c.round_off);

  // Every mesh from 50 to 400 elements: the one event, within the estimate of the closed form
  // plus the bisection's own tolerance (the mixed-form solves leave round-off far below it).
  const double location = app::trace_options(s, {}).event_tolerance;
  for (int n = 50; n <= 400; ++n) {
    CAPTURE(n);
    const auto [lambda, round_off] = heel_event(n);
    const double estimate = c.error_at(n, p_min) + round_off + location;
    INFO("lambda " << lambda << ", error " << lambda - exact << ", estimate " << estimate);
    CHECK(std::abs(lambda - exact) <= estimate);
  }
}

TEST_CASE("footing trace: the contact limit reaches the column at the closed form's load on a dense sample of meshes",
          "[continuation][mesh]") {
  const scene::Scene s = test::continuation_scene("footing_trace");
  const double exact = exact_column_load();
  const double lambda_max = 6.5;  // past the event (6.395; rigid 6.4)
  const auto model = model::make_member_model(s);

  auto column_event = [&](int n) {
    const TraceResult r = fe_run(s, n, lambda_max);
    INFO(n << " elements: " << r.summary.message);
    REQUIRE(r.summary.termination == continuation::TraceTermination::completed);
    REQUIRE(r.events.size() == 2);
    CHECK(r.events[0].kind == EventKind::limit_at_end);
    const TraceEvent* e = find_event(r, EventKind::limit_at_load, 1.8);
    REQUIRE(e == &r.events[1]);
    const auto d = fe::discretise(model, n);
    const int column = d.mesh.node_at(model.s_from_user(1.8));
    REQUIRE(column >= 0);
    // The limit is at the column node when w there is zero, in the set of the event's segment.
    return std::pair{e->load_factor, round_off_bound(s, n, set_at(r, *e), column, e->load_factor)};
  };

  // A limit crossing a node: order 3 (differences 1.0e-3, 1.5e-4, 1.9e-5 from 5 to 40 elements).
  constexpr double p_min = 2.5;
  const Convergence c = convergence(column_event);
  INFO("observed order " << c.order << ", differences down to " << c.smallest << ", round-off bound " << c.round_off);
  CHECK(c.order > p_min);
  CHECK(c.smallest > 10.0 * c.round_off);

  const double location = app::trace_options(s, {}).event_tolerance;  // the bisection's
  for (int n : {50, 75, 100, 125, 150, 175, 199, 200, 225, 250, 275, 300, 325, 350, 375, 400}) {
    CAPTURE(n);
    const auto [lambda, round_off] = column_event(n);
    const double estimate = c.error_at(n, p_min) + round_off + location;
    INFO("lambda " << lambda << ", error " << lambda - exact << ", estimate " << estimate);
    CHECK(std::abs(lambda - exact) <= estimate);
  }
}

TEST_CASE("region_split: no mesh adds an event at the load or fails to start", "[continuation][mesh]") {
  const scene::Scene s = test::continuation_scene("region_split");
  // At these odd meshes the nodes are shared unevenly between the load's sides, the zone
  // opened a discretisation error off the load and its limit crossed the load at once (a
  // limit_at_load event 5e-10 after the opening). It opens at the load now.
  for (int n : {51, 55, 75, 101, 155}) {
    CAPTURE(n);
    const TraceResult r = fe_run(s, n, 9.0);
    INFO(r.summary.message);
    REQUIRE(r.summary.termination == continuation::TraceTermination::completed);
    REQUIRE(r.events.size() == 3);
    CHECK(r.events[0].kind == EventKind::lift_off_opens);
    CHECK(r.events[0].at == Approx(5.0).margin(1e-12));
    for (int i : {1, 2}) CHECK(r.events[i].kind == EventKind::limit_at_end);
    CHECK(std::min(r.events[1].at, r.events[2].at) == 0.0);
    CHECK(std::max(r.events[1].at, r.events[2].at) == 10.0);
  }
  // At these the start (one region, [1.9, 8.1]) came from dense primal Lemke, which failed
  // numerically ("residual of 4.7e-06"); it comes from the sparse solver now.
  for (int n : {195, 197, 199, 270, 297}) {
    CAPTURE(n);
    const TraceResult r = fe_run(s, n, 0.5);
    INFO(r.summary.message);
    CHECK(r.summary.termination == continuation::TraceTermination::completed);
    REQUIRE(!r.steps.empty());
    REQUIRE(r.steps.front().contact_regions.size() == 1);
    CHECK(r.steps.front().contact_regions[0].begin == Approx(1.88).margin(0.01));
    CHECK(r.steps.front().contact_regions[0].end == Approx(8.12).margin(0.01));
  }
}

TEST_CASE("a member about to tip over: the path stops where round-off decides its states, not after reporting them",
          "[continuation][mesh]") {
  // Free-free beam L = 10, EI = 1e4, k = 1000 on a foundation over [2, 10] only; dead uniform
  // load 1 over the whole beam, live upward force at the free tip x = 0 of the overhang. The
  // heel x = 2 lifts off first (limit_at_end at 2, lambda 2.257); the contact region then
  // shrinks toward x = 10 and the member tips over where the reactions can no longer balance
  // the loads' moment (rigid: lambda = 5; FE 4.9917 at 200 elements). The last contact sets,
  // two or three nodes at x = 10, hold the member by a lever of one element: their system's
  // condition grows like N^5, and at 340, 362 and 393 elements its states were round-off (w(2)
  // from -19 to +60 across one breakpoint at which the state is continuous), reported as steps,
  // and as events once events at breakpoints were no longer dropped.
  auto s = test::beam_scene(10.0, 1e4, scene::EndSupport::free, scene::EndSupport::free, 1000.0);
  s.foundation.from = 2.0;
  s.loads.push_back(test::uniform_load(0.0, 10.0, 1.0, scene::LoadCase::dead));
  s.loads.push_back(test::point_force(0.0, -1.0, scene::LoadCase::live));
  for (int n : {200, 340, 362, 393}) {
    CAPTURE(n);
    TraceOptions o;
    o.arc_length.lambda_max = 6.0;
    o.elements = n;
    const TraceResult r = test::trace_fe(s, o);
    INFO(r.summary.message);
    REQUIRE(r.events.size() == 1);
    CHECK(r.events[0].kind == EventKind::limit_at_end);
    CHECK(r.events[0].at == 2.0);
    if (r.summary.termination == continuation::TraceTermination::solver_failure) {
      CHECK(r.summary.message.find("round-off") != std::string::npos);
    } else {
      REQUIRE(r.summary.termination == continuation::TraceTermination::no_equilibrium);
      CHECK(r.summary.final_load_factor == Approx(5.0).margin(0.01));
    }
    // Every step reported has its contact where the physics puts it: one region ending at x = 10.
    for (const auto& step : r.steps) {
      CAPTURE(step.load_factor);
      REQUIRE(step.contact_regions.size() == 1);
      CHECK(step.contact_regions[0].end == Approx(10.0).margin(1e-9));
    }
  }
}
