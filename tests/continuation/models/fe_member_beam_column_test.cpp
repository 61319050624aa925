// The FE path of a beam-column (the second-order kinematics of continuation/models/member_kinematics.hpp
// on the path engine) on the upheaval buckle (continuation/scenes/pipeline_upheaval.toml) and on a pinned strut bowed
// away from a tensionless foundation: every step checked against independent solves of the same scene with its axial
// force as a dead load (solve_contact, and the fixed-set system of the step's contact set on a member discretised at
// that N, certified), the limit load bracketed by fixed-N solves, the stability indicator, and the strut's approach to
// the Euler load.

#include <catch2/catch.hpp>
#include <cmath>
#include <iomanip>
#include <numbers>

#include "app/trace_command.hpp"
#include "certify/certificate.hpp"
#include "closed_form/beam_column.hpp"
#include "contact/active_set_system.hpp"
#include "contact/contact_solver.hpp"
#include "contact/stability.hpp"
#include "continuation/models/fe_member.hpp"
#include "fe/discretisation.hpp"
#include "model/from_scene.hpp"
#include "model/member_model.hpp"
#include "post/fields.hpp"
#include "scene/scene_reader.hpp"
#include "support/scene_text.hpp"
#include "support/trace_scene.hpp"

using namespace liftoff;
using continuation::EventKind;
using continuation::TraceOptions;
using continuation::TraceResult;

namespace {

scene::Scene upheaval() {
  return scene::read_scene_file(std::string(LIFTOFF_SOURCE_DIR) + "/continuation/scenes/pipeline_upheaval.toml");
}

// A straight weightless pinned strut lying on a tensionless foundation, live axial force 1 MN per
// lambda (L = 6 m, EI = 1e7 N m^2, K = 1e6 N/m^2).
scene::Scene straight_strut() {
  return scene::read_scene_file(std::string(LIFTOFF_SOURCE_DIR) + "/continuation/scenes/strut_bifurcation.toml");
}

TraceOptions options_for(const scene::Scene& scene, int elements) {
  app::TraceRequest request;
  request.elements = elements;
  TraceOptions options = app::trace_options(scene, request);
  for (int i = 0; i <= 40; ++i) options.sample_points.push_back(scene.begin() + i * (scene.end() - scene.begin()) / 40);
  return options;
}

// The scene with its axial force N(lambda) = N_dead + lambda N_live as one dead load.
scene::Scene with_dead_axial(scene::Scene scene, double lambda) {
  for (scene::Load& load : scene.loads)
    if (load.kind == scene::LoadKind::axial && load.load_case == scene::LoadCase::live) {
      load.value *= lambda;
      load.load_case = scene::LoadCase::dead;
      load.case_name = "dead";
    }
  return scene;
}

// w at the sample points (user length) of a displacement on every dof.
std::vector<double> sampled(const model::MemberModel& model, const fe::Discretisation& d,
                            const Eigen::VectorXd& displacement, const std::vector<double>& points) {
  std::vector<double> w;
  for (double x : points) {
    const double s = std::clamp(model.s_from_user(x), model.s_begin, model.s_end);
    const int e = d.mesh.element_containing(s);
    w.push_back(post::evaluate(d, displacement, e, (s - d.mesh.nodes[e]) / d.mesh.element_size(e)).w *
                model.scales.displacement());
  }
  return w;
}

double largest_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double worst = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(a[i] - b[i]));
  return worst;
}

double largest(const std::vector<double>& a) {
  double m = 0.0;
  for (double v : a) m = std::max(m, std::abs(v));
  return m;
}

contact::ContactSolution fixed_n_solve(const scene::Scene& scene, double lambda, int elements) {
  const model::MemberModel model = model::make_member_model(with_dead_axial(scene, lambda));
  const fe::Discretisation d = fe::discretise(model, elements);
  contact::ContactOptions options;
  options.method = contact::Method::fast;
  options.load_factor = lambda;
  return contact::solve_contact(d, options);
}

double limit_load_factor(const TraceResult& result) {
  for (const auto& event : result.events)
    if (event.kind == EventKind::limit_point) return event.load_factor;
  return -1.0;
}

}  // namespace

TEST_CASE("upheaval buckle: through the limit point, every step an independent equilibrium", "[beam_column]") {
  const scene::Scene scene = upheaval();
  const int elements = 200;
  TraceOptions options = options_for(scene, elements);
  // States asked for on the rising branch (the path's own steps are few: a step goes on across
  // the node switches of a growing lift-off zone), each compared below with a solve at its load;
  // on the descending branch the path passes 3, 4 and 5 again, unstable.
  options.report_at = {1.0, 2.0, 3.0, 4.0, 4.5, 5.0, 5.5};
  const TraceResult result = test::trace_fe(scene, options);
  INFO(result.summary.message);
  REQUIRE(result.summary.termination == continuation::TraceTermination::completed);
  REQUIRE(result.steps.back().amplitude == Approx(1.0).epsilon(1e-6));  // stopped by max_amplitude

  // One fold, in the bracket of the scene's fixed-N solves (5.5, 6.0) MN, and the path's lambda
  // rises to it and falls after it while the lifted length grows.
  int folds = 0;
  for (const auto& event : result.events) folds += event.kind == EventKind::limit_point;
  CHECK(folds == 1);
  const double limit = limit_load_factor(result);
  CHECK(limit > 5.5);
  CHECK(limit < 6.0);
  std::size_t fold_step = 0;
  while (fold_step < result.steps.size() && result.steps[fold_step].load_factor != limit) ++fold_step;
  REQUIRE(fold_step < result.steps.size());
  for (std::size_t i = 1; i < result.steps.size(); ++i) {
    const auto& a = result.steps[i - 1];
    const auto& b = result.steps[i];
    CHECK(b.lifted_length >= a.lifted_length - 1e-9);
    CHECK(b.amplitude >= a.amplitude - 1e-12);
    if (i <= fold_step) CHECK(b.load_factor >= a.load_factor);
    if (i > fold_step) CHECK(b.load_factor <= a.load_factor);
    CHECK(b.axial_force == Approx(1e6 * b.load_factor).epsilon(1e-14));
  }
  CHECK(result.steps.back().lifted_length > 40.0);

  // (d) The stability indicator flips at the limit point: stable up to it, unstable from it (the
  // fold's step is on the new contact set, beyond its critical load).
  for (std::size_t i = 0; i < result.steps.size(); ++i) {
    INFO("step " << i << " lambda " << result.steps[i].load_factor);
    CHECK(result.steps[i].stability ==
          (i < fold_step ? continuation::Stability::stable : continuation::Stability::unstable));
  }

  // (a) Every stable step is the contact solver's answer for its N as a dead load, to round-off:
  // both solve the same discrete equations by different routes (the solver searches the contact
  // set; the path inherits it), and both refine to round-off in the mixed form, whose condition
  // number grows like elements^2 (contact/active_set_system.hpp): ~1e-11 relative at 200
  // elements; the bound is 1e-9 of the largest |w| (the path's own acceptance, tie_tolerance).
  int compared = 0;
  for (const auto& step : result.steps) {
    if (step.stability != continuation::Stability::stable) continue;
    const contact::ContactSolution solution = fixed_n_solve(scene, step.load_factor, elements);
    INFO("lambda " << step.load_factor << ": " << solution.summary.message);
    REQUIRE(solution.summary.is_usable());
    const model::MemberModel model = model::make_member_model(with_dead_axial(scene, step.load_factor));
    const fe::Discretisation d = fe::discretise(model, elements);
    const std::vector<double> w = sampled(model, d, solution.displacement, options.sample_points);
    CHECK(largest_difference(w, step.deflection) <= 1e-9 * largest(w));
    ++compared;
  }
  CHECK(compared >= 10);

  // (c) Every step, stable or not, is an equilibrium with the contact inequalities in the user's
  // terms: its contact set solved on the member discretised with N(lambda) as a dead load (not the
  // path's K(N(1)) - (N - N(1)) K_g update), certified (certify/ takes the axial term), and equal
  // to the step.
  for (const auto& step : result.steps) {
    const model::MemberModel model = model::make_member_model(with_dead_axial(scene, step.load_factor));
    const fe::Discretisation d = fe::discretise(model, elements);
    const std::vector<bool> set = continuation::fe_contact_set(step);
    contact::ActiveSetSystem system(d);
    REQUIRE(system.factorise(set));
    const contact::ContactState state = system.solve(d.load(step.load_factor), d.ground_gap);
    contact::ContactSolution answer;
    answer.displacement = d.expand_displacement(state.displacement);
    answer.reaction = state.reaction;
    certify::CertifyOptions certify_options;
    certify_options.load_factor = step.load_factor;
    certify_options.round_off = false;
    certify_options.backward_tolerance = 1e-8;
    certify_options.pointwise = false;
    certify_options.sign_floor = 1e-8;
    certify_options.global_scale = true;
    const certify::Certificate certificate = certify::certify(model, d, answer, certify_options);
    INFO("lambda " << step.load_factor << ": " << certificate.message);
    CHECK(certificate.passed);
    const std::vector<double> w = sampled(model, d, answer.displacement, options.sample_points);
    CHECK(largest_difference(w, step.deflection) <= 1e-9 * largest(w));
  }
}

TEST_CASE("upheaval buckle: the limit load lies between the fixed-N solves that succeed and those refused",
          "[beam_column]") {
  const scene::Scene scene = upheaval();
  const int elements = 200;
  const TraceResult result = test::trace_fe(scene, options_for(scene, elements));
  const double limit = limit_load_factor(result);
  REQUIRE(limit > 0.0);
  // Bisect the fixed-N solves: lo solved (stable), hi refused.
  double lo = 5.5, hi = 6.0;
  REQUIRE(fixed_n_solve(scene, lo, elements).summary.is_usable());
  REQUIRE_FALSE(fixed_n_solve(scene, hi, elements).summary.is_usable());
  for (int i = 0; i < 14; ++i) {
    const double mid = 0.5 * (lo + hi);
    (fixed_n_solve(scene, mid, elements).summary.is_usable() ? lo : hi) = mid;
  }
  INFO("limit " << limit << ", solved up to " << lo << ", refused from " << hi);
  CHECK(lo <= limit + 1e-9);
  CHECK(hi >= limit - 1e-9);
}

TEST_CASE("upheaval buckle: the limit load converges with the mesh", "[beam_column][slow]") {
  // The limit load on 200, 400 and 800 elements. The discrete path's fold is at a breakpoint (a
  // node pair lifting), so its lambda samples the smooth maximum lambda(a) of the lifted length a
  // at spacings of h: an error O(h^2) whose constant depends on where the exact fold falls between
  // nodes, so the order measured on three meshes scatters about 2 (1.7 here; 100 elements, h = 2 m
  // against a buckle of ~20 m, is not yet in that range: its limit load lies between those of 400
  // and 200). The test holds the order above 1 (no worse than the contact limit's own O(h)) and
  // the differences shrinking: 400 against 800 is the discretisation estimate liftoff prints
  // (refine).
  const scene::Scene scene = upheaval();
  std::vector<double> limits;
  for (int elements : {200, 400, 800}) {
    TraceOptions options = options_for(scene, elements);
    options.max_amplitude = 0.1;  // well past the fold
    limits.push_back(limit_load_factor(test::trace_fe(scene, options)));
    REQUIRE(limits.back() > 0.0);
  }
  const double d1 = std::abs(limits[0] - limits[1]), d2 = std::abs(limits[1] - limits[2]);
  const double order = std::log2(d1 / d2);
  INFO("limits " << limits[0] << " " << limits[1] << " " << limits[2] << ", order " << order);
  CHECK(order > 1.0);
  CHECK(order < 4.5);
  // The 800-element limit load is within d2 / (2^order - 1) of the converged one (Richardson):
  // well inside the scene's bracket of fixed-N solves, (5.5, 6.0) MN.
  const double richardson = d2 / (std::pow(2.0, order) - 1.0);
  CHECK(richardson < 1e-3 * limits[2]);
}

TEST_CASE("a pinned weightless strut bowed away from a tensionless foundation buckles at the Euler load",
          "[beam_column]") {
  // The foundation follows the bow, so it carries nothing and the member lifts off it at once: the
  // amplitude a0 / (1 - P / P_E) of the half-sine bow grows without bound as P approaches
  // P_E = pi^2 EI / L^2 whatever k, and the trace stops at max_amplitude = 1000 a0, where
  // P = (1 - 1e-3) P_E (plus the FE error of P_E, ~1e-6 at 64 elements).
  const std::string text = std::string("\n") + test::beam_text("10.0", "1.0e4") + R"(modulus = 1.0e3
[geometry]
initial_shape = { shape = "half_sine", amplitude = -1.0e-4 }
[[loads]]
kind = "axial"
value = 1.0
case = "live"
[solve]
elements = 64
[trace]
lambda_max = 2000.0
max_amplitude = 0.1
)";
  const scene::Scene scene = scene::parse_scene(text, "strut.toml");
  const TraceOptions options = options_for(scene, 64);
  const TraceResult result = test::trace_fe(scene, options);
  INFO(result.summary.message);
  REQUIRE(result.summary.termination == continuation::TraceTermination::completed);
  const double euler = std::numbers::pi * std::numbers::pi * 1e4 / 100.0;
  CHECK(result.steps.back().amplitude == Approx(0.1).epsilon(1e-6));
  CHECK(result.steps.back().axial_force / euler == Approx(1.0 - 1e-3).epsilon(2e-5));
  for (const auto& step : result.steps) CHECK(step.stability == continuation::Stability::stable);
}

TEST_CASE("a straight weightless strut lying on a tensionless foundation is stable below the Euler load only",
          "[beam_column]") {
  // Nothing presses the strut on its foundation: every node touches it with neither reaction nor
  // gap (weakly active). Its full contact set's tangent (bilateral springs) stays positive definite
  // up to the bilateral load min_n (n^2 pi^2 + k / (n^2 pi^2)) EI / L^2 = 23.0 EI / L^2 (k = 129.6);
  // the cone of admissible perturbations lets it buckle away at P_E = pi^2 EI / L^2 (issue 15), and
  // the steps' stability must say so: stable below P_E, unstable above it.
  const scene::Scene scene = straight_strut();
  TraceOptions options = options_for(scene, 64);
  options.switch_branch = false;  // stay on the straight path (the next test switches)
  options.max_amplitude.reset();
  const TraceResult result = test::trace_fe(scene, options);
  INFO(result.summary.message);
  REQUIRE(result.summary.termination == continuation::TraceTermination::completed);
  const double euler = closed_form::tensionless_pinned_strut_critical(6.0, 1.0e7);  // 2.74e6 N
  // The cone's loss of stability is the one bifurcation reported (not the bilateral set's).
  REQUIRE(result.events.size() == 1);
  CHECK(result.events[0].kind == EventKind::bifurcation);
  CHECK(result.events[0].load_factor * 1e6 / euler == Approx(1.0).epsilon(1e-6));
  int above = 0;
  for (const auto& step : result.steps) {
    CAPTURE(step.axial_force);
    // The FE Euler load at 64 elements is within 1e-6 of P_E: steps within 1e-3 of it are skipped.
    if (std::abs(step.axial_force / euler - 1.0) < 1e-3) continue;
    CHECK(step.stability ==
          (step.axial_force < euler ? continuation::Stability::stable : continuation::Stability::unstable));
    above += step.axial_force > euler;
  }
  CHECK(above >= 1);
}

// Branch switching (issue 15): a perfect member's path meets a bifurcation where it loses its
// stability; with [trace] switch_branch (the default) the trace leaves it along the critical mode.

// The strut above without its bow (continuation/scenes/strut_bifurcation.toml): nothing presses it on the foundation
// (every node weakly active), so the cone decides: the straight state is stable up to P_E = pi^2 EI / L^2, where the
// lifting half-sine is a neutral mode (second-order theory: any amplitude at P_E). The trace
// reports the bifurcation there and follows that branch at fixed lambda to max_amplitude, the
// member lifting off everywhere in a half-sine. P_E to the FE error: at most the change from 32 to
// 64 elements (an estimate that holds for any order >= 1); the shape to the mode's FE error.
TEST_CASE("a straight weightless strut on a tensionless foundation: the bifurcation at P_E and its lifted branch",
          "[beam_column]") {
  const scene::Scene scene = straight_strut();                                      // max_amplitude 0.03 m
  const double euler = closed_form::tensionless_pinned_strut_critical(6.0, 1.0e7);  // 2.74e6 N
  auto bifurcation = [&](int elements) {
    const TraceResult result = test::trace_fe(scene, options_for(scene, elements));
    INFO(result.summary.message);
    REQUIRE(result.summary.termination == continuation::TraceTermination::completed);
    REQUIRE(result.events.size() == 1);
    REQUIRE(result.events[0].kind == EventKind::bifurcation);
    return std::pair{result, result.steps.back().axial_force};
  };
  const auto [result, n64] = bifurcation(64);
  const auto [coarse, n32] = bifurcation(32);
  const auto [coarser, n16] = bifurcation(16);
  const double order = std::log2((n16 - euler) / (n32 - euler)), finer = std::log2((n32 - euler) / (n64 - euler));
  INFO(std::setprecision(12) << "N at the bifurcation: 16 el. " << n16 << ", 32 el. " << n32 << ", 64 el. " << n64
                             << ", P_E " << euler << "; observed orders " << order << ", " << finer);
  CHECK(std::abs(n64 - euler) <= std::abs(n32 - n64));
  // Hermite cubics with the consistent geometric stiffness: h^4 (Rayleigh quotient of the mode).
  CHECK(order > 3.7);
  CHECK(order < 4.3);
  CHECK(finer > 3.7);
  CHECK(finer < 4.3);
  // The lifted branch: at the bifurcation's lambda, amplitude growing to max_amplitude, the
  // member off its foundation in the half-sine -A sin(pi x / L) (A the amplitude).
  const double lambda_c = result.events[0].load_factor;
  int on_branch = 0;
  double previous = 0.0;
  for (const auto& step : result.steps) {
    CAPTURE(step.load_factor, step.amplitude);
    if (step.load_factor < lambda_c - 1e-9) {
      CHECK(step.amplitude == 0.0);
      CHECK(step.stability == continuation::Stability::stable);
      continue;
    }
    if (step.amplitude == 0.0) continue;  // the straight state at the bifurcation
    ++on_branch;
    CHECK(step.amplitude > previous);
    previous = step.amplitude;
    CHECK(std::abs(step.load_factor - lambda_c) < 1e-9);
    CHECK(step.stability == continuation::Stability::unstable);  // neutral: not positive definite
    for (std::size_t i = 0; i < step.deflection.size(); ++i) {
      const double x = options_for(scene, 64).sample_points[i];
      CHECK(std::abs(step.deflection[i] + step.amplitude * std::sin(std::numbers::pi * x / 6.0)) <
            1e-6 * step.amplitude);
    }
  }
  CHECK(on_branch >= 2);
  CHECK(result.steps.back().amplitude == Approx(0.03).epsilon(1e-9));
}

// A short heavy free-free member lying on a bilateral-stiffness foundation settles flat
// (w = q / K, no bending), so its path in a growing axial force stays flat and stable up to the
// member's least bilateral critical load, where it bifurcates (closed form: the free-free
// characteristic determinant, verification/closed_form, here a tilting mode a little below the
// rigid rotation's K L^2 / 12). The bifurcated branch tilts at that load until one end's reaction
// falls to zero, then lifts that end off and descends in lambda (the lifted end's lost springs
// lower the critical load), unstable, the lifted length growing. switch_branch = false keeps the
// flat path instead, through the bifurcation, unstable above it.
TEST_CASE("a heavy free-free member: the bifurcation at its bilateral critical load, then a descending branch",
          "[beam_column]") {
  const std::string text =
      std::string("\n") + test::beam_text("2.0", "1.0e7", "\"free\"", "\"free\"") + R"(modulus = 1.0e6
[[loads]]
kind = "uniform"
value = 1.0e4
case = "dead"
[[loads]]
kind = "axial"
value = 1.0e5
case = "live"
[trace]
lambda_max = 6.0
max_amplitude = 0.02
)";
  const scene::Scene scene = scene::parse_scene(text, "heavy_free_member.toml");
  const double critical = closed_form::free_free_bilateral_critical(2.0, 1.0e7, 1.0e6);
  REQUIRE(critical < 1.0e6 * 4.0 / 12.0);  // below the rigid rotation's Rayleigh quotient
  auto bifurcation_load = [&](const TraceResult& result) {
    for (const auto& event : result.events)
      if (event.kind == EventKind::bifurcation) return event.load_factor * 1.0e5;
    FAIL("no bifurcation: " << result.summary.message);
    return 0.0;
  };
  const TraceResult result = test::trace_fe(scene, options_for(scene, 64));
  const TraceResult coarse = test::trace_fe(scene, options_for(scene, 32));
  INFO(result.summary.message);
  REQUIRE(result.summary.termination == continuation::TraceTermination::completed);
  const double n64 = bifurcation_load(result), n32 = bifurcation_load(coarse);
  INFO(std::setprecision(12) << "bifurcation: 32 el. " << n32 << ", 64 el. " << n64 << ", closed form " << critical);
  CHECK(std::abs(n64 - critical) <= std::abs(n32 - n64));
  CHECK(std::abs(n64 - critical) < 1e-6 * critical);
  // Flat and stable below it; after it the lambda falls, the amplitude and lifted length grow.
  const double lambda_c = n64 / 1.0e5;
  bool reached = false, descending = false;
  double previous_lambda = lambda_c, previous_lifted = 0.0;
  for (const auto& step : result.steps) {
    CAPTURE(step.load_factor, step.amplitude, step.lifted_length);
    if (!reached && step.load_factor < lambda_c - 1e-9) {
      CHECK(step.lifted_length == 0.0);
      if (step.load_factor > 0.0) CHECK(step.stability == continuation::Stability::stable);
      continue;
    }
    reached = true;
    if (!descending && std::abs(step.load_factor - lambda_c) <= 1e-9) continue;  // the tilting branch
    descending = true;
    CHECK(step.load_factor <= previous_lambda);
    CHECK(step.lifted_length >= previous_lifted - 1e-12);
    CHECK(step.stability == continuation::Stability::unstable);
    previous_lambda = step.load_factor, previous_lifted = step.lifted_length;
  }
  CHECK(descending);
  CHECK(result.steps.back().load_factor < lambda_c - 0.1);
  CHECK(result.steps.back().amplitude == Approx(0.02).epsilon(1e-6));

  TraceOptions stay = options_for(scene, 64);
  stay.switch_branch = false;
  const TraceResult flat = test::trace_fe(scene, stay);
  INFO(flat.summary.message);
  REQUIRE(flat.summary.termination == continuation::TraceTermination::completed);
  CHECK(bifurcation_load(flat) == Approx(n64).epsilon(1e-9));
  CHECK(flat.steps.back().load_factor == 6.0);
  for (const auto& step : flat.steps) {
    CHECK(step.lifted_length == 0.0);
    if (step.load_factor > lambda_c + 1e-6) CHECK(step.stability == continuation::Stability::unstable);
  }
}

TEST_CASE(
    "the perfect pipeline: the fold at the bilateral critical load, bifurcations where the set's tangent is singular",
    "[beam_column]") {
  // Without the hump the straight member in full contact is a bilateral beam-column up to
  // 2 sqrt(K EI) = 12.00 MN (lambda = 12.0 for a long member; the clamped ends of the 200 m member
  // add a little). On the descending branch the lifted span's antisymmetric mode crosses zero on
  // one contact set after another: the symmetric path passes through (the load has no part
  // along it) and each crossing is a bifurcation, checked here by the inertia of the tangent on
  // that step's set on either side, on a member discretised with N as a dead load.
  scene::Scene scene = upheaval();
  scene.initial_shape = {};
  TraceOptions options = options_for(scene, 200);
  options.arc_length.lambda_max = 14.0;
  options.max_amplitude = 0.1;
  // Bifurcations are seen where a set's count differs between a step's ends: pairs 0.4 apart in
  // lambda on this branch (a rise and its fall within one step) need steps this short (the
  // default is a quarter of the load range, 3.5).
  options.arc_length.max_step = 0.25;
  options.arc_length.initial_step = std::min(options.arc_length.initial_step, 0.25);
  const TraceResult result = test::trace_fe(scene, options);
  INFO(result.summary.message);
  REQUIRE(result.summary.termination == continuation::TraceTermination::completed);
  const double critical = 2.0 * std::sqrt(2.0e5 * 1.8011e8) / 1e6;
  double highest = 0.0;
  for (const auto& step : result.steps) highest = std::max(highest, step.load_factor);
  CHECK(highest / critical == Approx(1.0).epsilon(5e-3));
  CHECK(limit_load_factor(result) == highest);
  int bifurcations = 0;
  for (const auto& event : result.events) {
    if (event.kind != EventKind::bifurcation) continue;
    ++bifurcations;
    const auto nearest = std::min_element(result.steps.begin(), result.steps.end(), [&](const auto& a, const auto& b) {
      return std::abs(a.load_factor - event.load_factor) < std::abs(b.load_factor - event.load_factor);
    });
    REQUIRE(std::abs(nearest->load_factor - event.load_factor) <= 1e-9);
    const std::vector<bool> set = continuation::fe_contact_set(*nearest);
    auto negative = [&](double lambda) {
      const model::MemberModel model = model::make_member_model(with_dead_axial(scene, lambda));
      return contact::check_tangent(fe::discretise(model, 200), set).negative_eigenvalues;
    };
    INFO("bifurcation at lambda " << event.load_factor);
    CHECK(negative(event.load_factor - 1e-6) != negative(event.load_factor + 1e-6));
  }
  CHECK(bifurcations >= 1);
}

// The closed-form localized buckle of the perfect member (verification/closed_form, independent of
// the FE code) whose crown stands `uplift` above the ground: bisection on its half-length, along
// which the uplift grows.
closed_form::LocalizedBuckle buckle_with_uplift(double modulus, double bending_stiffness, double weight,
                                                double uplift) {
  double lo = 1.0, hi = 150.0;
  REQUIRE(closed_form::localized_buckle(modulus, bending_stiffness, weight, lo).uplift < uplift);
  REQUIRE(closed_form::localized_buckle(modulus, bending_stiffness, weight, hi).uplift > uplift);
  for (int i = 0; i < 80; ++i) {
    const double mid = 0.5 * (lo + hi);
    (closed_form::localized_buckle(modulus, bending_stiffness, weight, mid).uplift < uplift ? lo : hi) = mid;
  }
  return closed_form::localized_buckle(modulus, bending_stiffness, weight, 0.5 * (lo + hi));
}

TEST_CASE("the perfect pipeline's descending branch is the closed-form localized buckle", "[beam_column][slow]") {
  // Without the hump the path leaves the straight state at the bilateral critical load (the
  // clamped ends' boundary layer is the only imperfection) and follows the localized buckle down.
  // Far from the ends (beta L = 25.8) that branch is the infinite member's, known in closed form
  // (P at a given crown uplift, the uplift being the paths' amplitude): each step from an uplift of
  // 0.2 m on is compared with it. The FE error at 400 elements is estimated from 200: it must be
  // below the 200-element error (convergence) and below the change from 200 to 400 elements
  // (an error estimate that holds for any order p >= 1: e_400 <= |N_200 - N_400| / (2^p - 1)).
  scene::Scene scene = upheaval();
  scene.initial_shape = {};
  const double modulus = 2.0e5, bending_stiffness = 1.8011e8, weight = 3000.0;
  const auto branch_error = [&](int elements, double uplift) {
    TraceOptions options = options_for(scene, elements);
    options.arc_length.lambda_max = 14.0;
    options.max_amplitude = uplift;
    const TraceResult result = test::trace_fe(scene, options);
    INFO(result.summary.message);
    REQUIRE(result.summary.termination == continuation::TraceTermination::completed);
    const continuation::TraceStep& last = result.steps.back();
    REQUIRE(last.amplitude == Approx(uplift).epsilon(1e-6));
    const closed_form::LocalizedBuckle exact = buckle_with_uplift(modulus, bending_stiffness, weight, last.amplitude);
    REQUIRE(exact.status == closed_form::BuckleStatus::found);
    // The lifted zone of the closed form is 2a; the path's lifted length comes from its nodes'
    // signs and cubic roots: the same within an element or so.
    CHECK(std::abs(last.lifted_length - 2.0 * exact.half_length) < 2.0 * 200.0 / elements);
    return std::pair{last.axial_force, exact.axial_force};
  };
  for (double uplift : {0.25, 1.0}) {
    const auto [n200, p] = branch_error(200, uplift);
    const auto [n400, p_again] = branch_error(400, uplift);
    const double e200 = std::abs(n200 - p) / p, e400 = std::abs(n400 - p) / p, change = std::abs(n200 - n400) / p;
    INFO("uplift " << uplift << " m: N 200 " << n200 << ", 400 " << n400 << ", closed form " << p << "; errors " << e200
                   << ", " << e400 << ", change " << change);
    CHECK(e400 < e200);
    CHECK(e400 <= change);
  }
}

TEST_CASE("the exact FE path reports amplitude and lifted length", "[beam_column]") {
  // A simply supported beam pressed on its foundation and lifted at its left end by a live end
  // moment: without an axial force the exact path runs, with axial_force 0 and stability unknown;
  // its amplitude is the largest -w (sampled finely: no more than the sampled maximum's error
  // above that) and its lifted length is the member's length less the contact regions'.
  const std::string text = std::string("\n") + test::beam_text("1.0", "1.0") + R"(modulus = 1.0e4
[[loads]]
kind = "uniform"
value = 100.0
case = "dead"
[[loads]]
kind = "moment"
at = 0.0
value = 1.0
case = "live"
[trace]
lambda_max = 3.0
)";
  const scene::Scene scene = scene::parse_scene(text, "end_moment.toml");
  TraceOptions options = options_for(scene, 100);
  options.sample_points.clear();
  for (int i = 0; i <= 1000; ++i) options.sample_points.push_back(i / 1000.0);
  const TraceResult result = test::trace_fe(scene, options);
  INFO(result.summary.message);
  REQUIRE(result.summary.termination == continuation::TraceTermination::completed);
  int lifted_steps = 0;
  for (const auto& step : result.steps) {
    CHECK(step.axial_force == 0.0);
    CHECK(step.stability == continuation::Stability::unknown);
    double lowest = 0.0;
    for (double w : step.deflection) lowest = std::min(lowest, w);
    double contact = 0.0;
    for (const auto& region : step.contact_regions) contact += region.end - region.begin;
    INFO("lambda " << step.load_factor);
    CHECK(step.amplitude >= -lowest - 1e-15);
    // Samples 1e-3 apart on a lift-off zone of width a miss its peak by about amplitude
    // (1e-3 / a)^2 (w'' ~ amplitude / a^2 there); 4 times that is the bound.
    if (step.lifted_length > 0.0)
      CHECK(step.amplitude <= -lowest * (1.0 + 4.0 * std::pow(1e-3 / step.lifted_length, 2)) + 1e-15);
    CHECK(step.lifted_length == Approx(1.0 - contact).margin(1e-6));
    lifted_steps += step.amplitude > 0.0;
  }
  CHECK(lifted_steps >= 2);
}

// Settled supports under a live axial force (issue 37, item 5): the settlement's load N K_g u_f is
// N(lambda) K_g u_f, its live part proportional to lambda (fe/discretisation.hpp splits it by
// case). The natural model of an infinite pipeline: a long heavy member whose clamped ends sit at
// the settled level q / K.
namespace {

scene::Scene settled_upheaval(bool imperfect) {
  scene::Scene s = upheaval();
  const double settled = 3000.0 / 2.0e5;  // q / K
  s.supports.left_detail.settlement = settled;
  s.supports.right_detail.settlement = settled;
  if (!imperfect) s.initial_shape = {};
  return s;
}

}  // namespace

TEST_CASE("settled supports under a live axial force: a straight member stays at q / K for every N", "[beam_column]") {
  // Closed form: w = q / K, r = q everywhere is an equilibrium under any N (a uniform w has no
  // slope, so N K_g w = 0) and meets the clamped, settled ends; the FE space holds it exactly, so
  // every step must show it to round-off. A settlement load frozen at N(1) (as before) leaves
  // (N(lambda) - N(1)) K_g u_f unbalanced at the ends: at lambda = 0.5 that moved w there by
  // 1e-3 of q / K.
  const scene::Scene scene = settled_upheaval(false);
  TraceOptions options = options_for(scene, 100);
  options.arc_length.lambda_max = 3.0;
  options.max_amplitude.reset();
  const TraceResult result = test::trace_fe(scene, options);
  INFO(result.summary.message);
  REQUIRE(result.summary.termination == continuation::TraceTermination::completed);
  CHECK(result.events.empty());
  for (const auto& step : result.steps) {
    INFO("lambda " << step.load_factor);
    for (std::size_t i = 0; i < step.deflection.size(); ++i) {
      CHECK(step.deflection[i] == Approx(0.015).epsilon(1e-9));
      CHECK(step.reaction[i] == Approx(3000.0).epsilon(1e-9));
    }
    CHECK(step.axial_force == Approx(1e6 * step.load_factor).epsilon(1e-14));
  }
}

TEST_CASE("settled supports under a live axial force: the trace agrees with solves at fixed N", "[beam_column]") {
  // The imperfect upheaval buckle with its ends settled at q / K, traced through its lift-off, and
  // every step against the contact solve of the same scene with N(lambda) as a dead load (its
  // settlement load then N(lambda) K_g u_f by construction). The fixed-N solves are certified to
  // 1e-8 of their terms; the path's states are exact for their sets: they agree to 1e-7 of the
  // largest deflection.
  const scene::Scene scene = settled_upheaval(true);
  const int elements = 200;
  TraceOptions options = options_for(scene, elements);
  options.arc_length.lambda_max = 5.5;  // below the limit point (5.84 unsettled)
  options.max_amplitude.reset();
  const TraceResult result = test::trace_fe(scene, options);
  INFO(result.summary.message);
  REQUIRE(result.summary.termination == continuation::TraceTermination::completed);
  int compared = 0;
  for (const auto& step : result.steps) {
    if (step.load_factor == 0.0) continue;
    INFO("lambda " << step.load_factor);
    const model::MemberModel model = model::make_member_model(with_dead_axial(scene, step.load_factor));
    const fe::Discretisation d = fe::discretise(model, elements);
    const contact::ContactSolution solved = fixed_n_solve(scene, step.load_factor, elements);
    REQUIRE(solved.summary.is_usable());
    const std::vector<double> w = sampled(model, d, solved.displacement, options.sample_points);
    CHECK(largest_difference(w, step.deflection) < 1e-7 * largest(w));
    ++compared;
  }
  CHECK(compared >= 4);
  // The settled ends carry the member at q / K: at the ends w = 0.015 exactly.
  CHECK(result.steps.back().deflection.front() == Approx(0.015).epsilon(1e-12));
  CHECK(result.steps.back().deflection.back() == Approx(0.015).epsilon(1e-12));
}

TEST_CASE("upheaval buckle: the states at requested loads on both branches", "[beam_column]") {
  // report_at = 5 (lift-off at 4.93, the limit point at 5.84, the path down to 2.7): the path passes
  // N = 5 MN twice, stable on the way up and unstable on the descending branch, a state on each.
  // The stable one is the contact solve of the scene at that N (exact fixed-set states against a
  // solve certified to 1e-8: 1e-7 of the largest deflection); the unstable one is the buckle
  // grown further (more lifted, a larger crest moment), which a solve from zero cannot find.
  const scene::Scene scene = upheaval();
  const int elements = 200;
  TraceOptions options = options_for(scene, elements);
  options.report_at = {5.0};
  const TraceResult result = test::trace_fe(scene, options);
  INFO(result.summary.message);
  REQUIRE(result.summary.is_usable());
  std::vector<const continuation::TraceStep*> requested;
  for (const auto& step : result.steps)
    if (step.requested) requested.push_back(&step);
  REQUIRE(requested.size() == 2);
  for (const continuation::TraceStep* step : requested) CHECK(step->load_factor == 5.0);
  const continuation::TraceStep &up = *requested[0], &down = *requested[1];
  CHECK(up.stability == continuation::Stability::stable);
  CHECK(down.stability == continuation::Stability::unstable);
  CHECK(down.lifted_length > up.lifted_length);
  REQUIRE(up.design.has_value());
  REQUIRE(down.design.has_value());
  CHECK(std::abs(down.design->moment_min.value) > std::abs(up.design->moment_min.value));
  // Recorded in order along the path: between its neighbours in lambda.
  for (const continuation::TraceStep* step : requested) {
    const auto i = static_cast<std::size_t>(step - result.steps.data());
    REQUIRE(i > 0);
    REQUIRE(i + 1 < result.steps.size());
    const double before = result.steps[i - 1].load_factor, after = result.steps[i + 1].load_factor;
    CHECK((before - 5.0) * (after - 5.0) < 0.0);
  }
  const model::MemberModel model = model::make_member_model(with_dead_axial(scene, 5.0));
  const fe::Discretisation d = fe::discretise(model, elements);
  const contact::ContactSolution solved = fixed_n_solve(scene, 5.0, elements);
  REQUIRE(solved.summary.is_usable());
  const std::vector<double> w = sampled(model, d, solved.displacement, options.sample_points);
  CHECK(largest_difference(w, up.deflection) < 1e-7 * largest(w));
  CHECK(largest_difference(w, down.deflection) > 0.1 * largest(w));
}
