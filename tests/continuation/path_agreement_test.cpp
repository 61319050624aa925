// The FE and Ritz paths of one scene agree on every event (issue 5, item 5): on each of the
// three scenes of continuation/scenes, every event of one path has its match in the other (same
// kind, same place, same order) and their loads differ by no more than the two paths' error
// estimates, which are themselves checked: the FE path's against its convergence on finer
// meshes, both against the closed form of the first event.
//
// Error estimates:
//  - FE: estimate_event_errors, |lambda_n - lambda_2n|. With an event load converging at order
//    p, the base run's error is that times 2^p / (2^p - 1): 8/7 for p = 3 (free_free_uplift:
//    a lift-off opening inside full contact), 4/3 for p = 2, 2.3 for p = 0.84 (region_split's
//    limits reaching the free ends: the node-wise contact of the LCP resolves a limit to an
//    element, so the load converges slowly). fe_safety = 3 covers p >= 0.6; the observed
//    orders are asserted below, so that the factor stays justified.
//  - Ritz: the change of the event load from half the modes (16) to all of them (32). With an
//    error decaying like N^-q, the larger run's error is that change over 2^q - 1, at most the
//    change itself for q >= 1 (ritz_safety = 1). A 3/4 ratio (24 -> 32, with a factor 3) was
//    tried first and proved fragile: on region_split the split's load stagnates near 3e-7 from
//    24 to 48 modes (closed form 6.8567342861; 24: +3.6e-7, 32: +3.2e-7, 48: +2.3e-6), so two
//    close mode counts can agree far better than either is right, and round-off changes in the
//    Ritz integrals were enough to flip that check. Halving the modes keeps the estimate
//    dominated by the coarse run's error.
// The FE path also has a round-off floor: its nondimensional stiffness grows like n^4, and
// beyond ~800 elements the event loads move by 1e-8 to 1e-6 relative for no discretisation
// reason (free_free_uplift: 5.4869831 at 800, 5.4869757 at 1600). The refined runs here stay
// at or below 800 elements.

#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "app/trace_command.hpp"
#include "closed_form/scene_problem.hpp"
#include "continuation/models/fe_member.hpp"
#include "continuation/models/ritz.hpp"
#include "scene/scene_reader.hpp"
#include "support/ritz_trace.hpp"
#include "support/scenes.hpp"
#include "support/trace_scene.hpp"

using namespace liftoff;
using continuation::EventKind;
using continuation::TraceEvent;
using continuation::TraceOptions;
using continuation::TraceResult;

namespace {

constexpr double fe_safety = 3.0, ritz_safety = 1.0;
constexpr int ritz_modes = 32, ritz_fewer_modes = 16;

TraceOptions options_for(const scene::Scene& s) { return app::trace_options(s, {}); }

TraceResult fe_run(const scene::Scene& s, int elements) {
  TraceOptions o = options_for(s);
  o.elements = elements;
  TraceResult r = test::trace_fe(s, o);
  REQUIRE(r.summary.is_usable());
  return r;
}

TraceResult ritz_run(const scene::Scene& s, int modes) {
  TraceOptions o = options_for(s);
  o.ritz.modes = modes;
  TraceResult r = test::trace_ritz_scene(s, o);
  INFO(r.summary.message);
  REQUIRE(r.summary.is_usable());
  return r;
}

// One-to-one matching of b's events to a's: same kind, within `at_tolerance` in position,
// nearest in load. index[i] is the match of a.events[i], -1 if none.
std::vector<int> match(const std::vector<TraceEvent>& a, const std::vector<TraceEvent>& b, double at_tolerance) {
  std::vector<int> index(a.size(), -1);
  std::vector<bool> used(b.size(), false);
  for (std::size_t i = 0; i < a.size(); ++i) {
    double best = INFINITY;
    for (std::size_t j = 0; j < b.size(); ++j) {
      if (used[j] || b[j].kind != a[i].kind || std::abs(b[j].at - a[i].at) > at_tolerance) continue;
      const double distance = std::abs(b[j].load_factor - a[i].load_factor);
      if (distance < best) best = distance, index[i] = static_cast<int>(j);
    }
    if (index[i] >= 0) used[index[i]] = true;
  }
  return index;
}

struct Agreement {
  TraceResult fe, ritz;
  std::vector<double> fe_error, ritz_error;  // per FE event
  std::vector<int> ritz_index;               // per FE event
};

// Both paths, their estimates and the pairing; asserts everything the issue asks of one scene.
Agreement check_agreement(const std::string& name) {
  const scene::Scene s = test::continuation_scene(name);
  const double length = std::abs(s.end() - s.begin());
  Agreement g;
  g.fe = fe_run(s, options_for(s).elements);
  const continuation::EventErrors errors = test::estimate_event_errors(s, options_for(s), g.fe);
  g.ritz = ritz_run(s, ritz_modes);
  const TraceResult fewer = ritz_run(s, ritz_fewer_modes);

  INFO(name << ": " << g.fe.events.size() << " FE events, " << g.ritz.events.size() << " Ritz events");
  REQUIRE(!g.fe.events.empty());
  REQUIRE(g.fe.events.size() == g.ritz.events.size());
  REQUIRE(errors.events.size() == g.fe.events.size());
  // Positions: a limit's is the support or end it reaches, an opening's the extreme of w, a
  // vanishing region's its last midpoint (which moves like sqrt(lambda* - lambda), so the two
  // paths place it less sharply than the load): a hundredth of the member tells all apart.
  g.ritz_index = match(g.fe.events, g.ritz.events, 0.01 * length);
  const std::vector<int> fewer_index = match(g.ritz.events, fewer.events, 0.01 * length);
  for (std::size_t i = 0; i < g.fe.events.size(); ++i) {
    const TraceEvent& e = g.fe.events[i];
    INFO("FE event " << i << ": " << continuation::to_string(e.kind) << " at " << e.at << ", lambda " << e.load_factor);
    REQUIRE(g.ritz_index[i] >= 0);
    REQUIRE(errors.events[i].load_factor_error >= 0.0);  // matched in the refined run
    const int r = g.ritz_index[i];
    REQUIRE(fewer_index[r] >= 0);
    g.fe_error.push_back(fe_safety * errors.events[i].load_factor_error);
    g.ritz_error.push_back(ritz_safety *
                           std::abs(g.ritz.events[r].load_factor - fewer.events[fewer_index[r]].load_factor));
    const double difference = std::abs(e.load_factor - g.ritz.events[r].load_factor);
    INFO("Ritz " << g.ritz.events[r].load_factor << ", difference " << difference << ", FE estimate "
                 << g.fe_error.back() << ", Ritz estimate " << g.ritz_error.back());
    CHECK(difference <= g.fe_error.back() + g.ritz_error.back());
  }
  // Same order: events that the estimates separate come in the same order on both paths.
  for (std::size_t i = 0; i < g.fe.events.size(); ++i)
    for (std::size_t j = i + 1; j < g.fe.events.size(); ++j) {
      const double gap = g.fe.events[j].load_factor - g.fe.events[i].load_factor;
      const double blur = g.fe_error[i] + g.fe_error[j] + g.ritz_error[i] + g.ritz_error[j];
      if (gap > blur) CHECK(g.ritz.events[g.ritz_index[j]].load_factor > g.ritz.events[g.ritz_index[i]].load_factor);
    }
  return g;
}

// Observed order of an event load from three runs on n, 2n, 4n elements.
double observed_order(double coarse, double medium, double fine) {
  return std::log2(std::abs(coarse - medium) / std::abs(medium - fine));
}

// The scene on the closed-form beam: the dead loads once and the live ones times lambda.
closed_form::BeamProblem loads_of(const scene::Scene& s, double load_factor) {
  return closed_form::problem_of(s, {.dead = 1.0, .live = load_factor});
}

// The scene's loads of one case alone.
closed_form::BeamProblem one_case(const scene::Scene& s, scene::LoadCase which) {
  return closed_form::problem_of(s, which == scene::LoadCase::dead
                                        ? closed_form::CaseFactors{.dead = 1.0, .live = 0.0}
                                        : closed_form::CaseFactors{.dead = 0.0, .live = 1.0});
}

}  // namespace

TEST_CASE("free_free_uplift: both paths open the central zone at one load, the closed form's",
          "[continuation][agreement]") {
  const Agreement g = check_agreement("free_free_uplift");
  const scene::Scene s = test::continuation_scene("free_free_uplift");
  // In full contact the solution is the bilateral one, affine in lambda: the zone opens where
  // w(5) = w_dead(5) + lambda w_live(5) = 0.
  const double w_dead = closed_form::solve_bilateral(one_case(s, scene::LoadCase::dead)).deflection(5.0);
  const double w_live = closed_form::solve_bilateral(one_case(s, scene::LoadCase::live)).deflection(5.0);
  const double exact = -w_dead / w_live;
  REQUIRE(g.fe.events.front().kind == EventKind::lift_off_opens);
  CHECK(g.ritz.events[g.ritz_index[0]].load_factor == Approx(exact).epsilon(1e-8));
  CHECK(std::abs(g.fe.events.front().load_factor - exact) <= g.fe_error.front());
  // The estimate is no mere bound: the FE event load converges to the closed form at the
  // order that makes fe_safety generous (h^3, see models/fe_member_linear_test).
  const double l100 = fe_run(s, 100).events.front().load_factor;
  const double l200 = g.fe.events.front().load_factor;
  const double l400 = fe_run(s, 400).events.front().load_factor;
  const double p = observed_order(l100, l200, l400);
  INFO("lambda at 100, 200, 400 elements: " << l100 << ", " << l200 << ", " << l400 << "; order " << p);
  CHECK(p > 2.5);
  CHECK(std::abs(l400 - exact) < std::abs(l200 - exact));
}

TEST_CASE(
    "simply_supported_end_moments: the limits leave both supports and the region vanishes at one load on both "
    "paths",
    "[continuation][agreement]") {
  const Agreement g = check_agreement("simply_supported_end_moments");
  REQUIRE(g.fe.events.size() == 3);
  CHECK(g.fe.events[0].kind == EventKind::limit_at_support);
  CHECK(g.fe.events[0].at == Approx(0.0).margin(1e-12));
  CHECK(g.fe.events[1].kind == EventKind::limit_at_support);
  CHECK(g.fe.events[1].at == Approx(6.0).margin(1e-12));
  CHECK(g.fe.events[2].kind == EventKind::region_vanishes);
  // The first: the bilateral solution's slope at the pinned end x = 0 changes sign (a
  // lift-off zone opens there), w'(0) = w'_dead(0) + lambda w'_live(0) = 0.
  const scene::Scene s = test::continuation_scene("simply_supported_end_moments");
  const double slope_dead = closed_form::solve_bilateral(one_case(s, scene::LoadCase::dead)).slope(0.0);
  const double slope_live = closed_form::solve_bilateral(one_case(s, scene::LoadCase::live)).slope(0.0);
  const double exact = -slope_dead / slope_live;
  CHECK(g.ritz.events[g.ritz_index[0]].load_factor == Approx(exact).epsilon(1e-8));
  // (Plus the bracket the event is located to: the refined run can place it on the same bits.)
  CHECK(std::abs(g.fe.events[0].load_factor - exact) <= g.fe_error[0] + options_for(s).event_tolerance);

  // The second: one region [t, 6], its slope at the pinned end x = 6 changes sign (secant on
  // it, the tensionless closed form started from the FE path's region before the event).
  std::vector<closed_form::Interval> regions;
  // (The FE path's state 0.01 before it, asked for: the closed form's start.)
  TraceOptions before = options_for(s);
  before.report_at = {g.fe.events[1].load_factor - 0.01};
  for (const auto& step : test::trace_fe(s, before).steps)
    if (step.requested && step.contact_regions.size() == 1)
      regions = {{step.contact_regions[0].begin, s.structure.length}};
  REQUIRE(regions.size() == 1);
  const auto slope_end = [&](double lambda) {
    const auto r = closed_form::solve_tensionless(loads_of(s, lambda), regions);
    REQUIRE(r.residual <= 1e-12);
    REQUIRE(r.limits.size() == 1);
    return r.solution.slope(s.structure.length);
  };
  double l0 = g.fe.events[1].load_factor - 0.01, l1 = g.fe.events[1].load_factor - 0.005;
  double f0 = slope_end(l0), f1 = slope_end(l1);
  for (int k = 0; k < 50 && std::abs(l1 - l0) > 1e-14 * l1; ++k) {
    const double l2 = l1 - f1 * (l1 - l0) / (f1 - f0);
    l0 = l1, f0 = f1;
    l1 = l2, f1 = slope_end(l1);
  }
  INFO("second event: closed form " << l1 << ", FE " << g.fe.events[1].load_factor << ", Ritz "
                                    << g.ritz.events[g.ritz_index[1]].load_factor);
  CHECK(std::abs(g.fe.events[1].load_factor - l1) <= g.fe_error[1] + options_for(s).event_tolerance);
  CHECK(std::abs(g.ritz.events[g.ritz_index[1]].load_factor - l1) <= g.ritz_error[1]);
}

TEST_CASE("region_split: the split and the limits reaching the free ends at one load on both paths",
          "[continuation][agreement]") {
  const Agreement g = check_agreement("region_split");
  const scene::Scene s = test::continuation_scene("region_split");
  REQUIRE(g.fe.events.size() == 3);
  CHECK(g.fe.events[0].kind == EventKind::lift_off_opens);
  CHECK(g.fe.events[1].kind == EventKind::limit_at_end);
  CHECK(g.fe.events[2].kind == EventKind::limit_at_end);

  // The first event from the closed form: the tensionless solution with one contact region,
  // followed in lambda, w(5) = 0 by the secant method.
  const double at = 5.0;
  const auto w_mid = [&](double lambda) {
    const auto r = closed_form::solve_tensionless(loads_of(s, lambda), {{1.0, 9.0}});
    // Beyond lambda* the one-region solution has w(5) < 0 (its continuation, which the secant
    // needs): the limit equations solved, the inequality check failing is expected there.
    REQUIRE((r.status == closed_form::TensionlessStatus::converged ||
             (r.status == closed_form::TensionlessStatus::inequalities_violated && r.solution.deflection(at) < 0.0)));
    REQUIRE(r.residual <= 1e-12);
    REQUIRE(r.contact.size() == 1);
    return r.solution.deflection(at);
  };
  double l0 = g.fe.events[0].load_factor - 0.05, l1 = g.fe.events[0].load_factor - 0.01;
  double w0 = w_mid(l0), w1 = w_mid(l1);
  for (int k = 0; k < 50 && std::abs(l1 - l0) > 1e-14 * l1; ++k) {
    const double l2 = l1 - w1 * (l1 - l0) / (w1 - w0);
    l0 = l1, w0 = w1;
    l1 = l2, w1 = w_mid(l1);
  }
  const double exact = l1;
  // The Ritz path has limits to resolve here (not so in full contact, as in the other two
  // scenes): 32 modes give 5e-8 relative, within its estimate, not 1e-8.
  CHECK(std::abs(g.ritz.events[g.ritz_index[0]].load_factor - exact) <= g.ritz_error[0]);
  // (Plus the bracket the event is located to: the refined run can place it on the same bits.)
  CHECK(std::abs(g.fe.events[0].load_factor - exact) <= g.fe_error[0] + options_for(s).event_tolerance);

  // The limits reaching the ends, from the closed form: with the regions run to the ends,
  // [0, t1] and [t2, 10] (the topology just after the event), w(0) is smooth in lambda and
  // changes sign at the event (secant on it). Started from the FE path's inner limits at its
  // last step before the event.
  std::vector<closed_form::Interval> regions;
  for (const auto& step : g.fe.steps)
    if (step.load_factor < g.fe.events[1].load_factor - 0.01 && step.contact_regions.size() == 2)
      regions = {{0.0, step.contact_regions[0].end}, {step.contact_regions[1].begin, s.structure.length}};
  REQUIRE(regions.size() == 2);
  const auto w_end = [&](double lambda) {
    const auto r = closed_form::solve_tensionless(loads_of(s, lambda), regions);
    REQUIRE(r.residual <= 1e-12);
    REQUIRE(r.limits.size() == 2);
    return r.solution.deflection(0.0);
  };
  l0 = g.fe.events[1].load_factor - 0.01, l1 = g.fe.events[1].load_factor + 0.01;
  w0 = w_end(l0), w1 = w_end(l1);
  for (int k = 0; k < 50 && std::abs(l1 - l0) > 1e-14 * l1; ++k) {
    const double l2 = l1 - w1 * (l1 - l0) / (w1 - w0);
    l0 = l1, w0 = w1;
    l1 = l2, w1 = w_end(l1);
  }
  const double exact_end = l1;
  for (int i : {1, 2}) {
    INFO("limit_at_end " << i << ": closed form " << exact_end << ", FE " << g.fe.events[i].load_factor << ", Ritz "
                         << g.ritz.events[g.ritz_index[i]].load_factor);
    CHECK(std::abs(g.fe.events[i].load_factor - exact_end) <= g.fe_error[i]);
    CHECK(std::abs(g.ritz.events[g.ritz_index[i]].load_factor - exact_end) <= g.ritz_error[i]);
  }

  // The FE estimates are meaningful: the event loads converge (order 2 for the split, ~0.84
  // for the limits at the free ends; both above 0.6, which fe_safety = 3 assumes), and the
  // refined run is closer to the better of the references.
  const TraceResult r400 = fe_run(s, 400), r800 = fe_run(s, 800);
  REQUIRE(r400.events.size() == 3);
  REQUIRE(r800.events.size() == 3);
  for (int i : {0, 1}) {
    const double p = observed_order(g.fe.events[i].load_factor, r400.events[i].load_factor, r800.events[i].load_factor);
    INFO("event " << i << ": lambda at 200, 400, 800 elements " << g.fe.events[i].load_factor << ", "
                  << r400.events[i].load_factor << ", " << r800.events[i].load_factor << "; order " << p);
    CHECK(p > 0.6);
  }
  CHECK(std::abs(r400.events[0].load_factor - exact) < std::abs(g.fe.events[0].load_factor - exact));
}

TEST_CASE("region_split at 40 modes: a limit reaching a free end is removed, not a zone opened there",
          "[continuation][agreement]") {
  // At 40 modes round-off separates the two ends' events by 4e-6 in lambda, and w(0) reached
  // zero with the limit still 4e-7 L from it: the path opened a contact zone at x = 0, and the
  // limits then ran off the foundation (regions from x = -0.1).
  const scene::Scene s = test::continuation_scene("region_split");
  const TraceResult ritz = ritz_run(s, 40);
  const TraceResult fe = fe_run(s, options_for(s).elements);
  REQUIRE(ritz.events.size() == fe.events.size());
  const std::vector<int> index = match(fe.events, ritz.events, 0.01 * s.structure.length);
  for (int i : index) CHECK(i >= 0);
  for (const auto& step : ritz.steps) {
    INFO("lambda " << step.load_factor);
    CHECK(step.contact_regions.size() <= 2);
    for (const auto& region : step.contact_regions) {
      CHECK(region.begin >= 0.0);
      CHECK(region.end <= s.structure.length);
    }
  }
}
