// Issue 12's loads against independent references: the curling slab strip (an imposed
// curvature) against the closed form and the closed form's end-moment problem, and a
// trapezoidal (distributed) load against the closed form. Tolerances come from each method's
// own error estimate or from the discretisation order, as said at each check.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>

#include "app/solve_command.hpp"
#include "certify/certificate.hpp"
#include "closed_form/beam_on_foundation.hpp"
#include "closed_form/member_problem.hpp"
#include "model/from_scene.hpp"
#include "post/fields.hpp"
#include "support/scenes.hpp"
#include "support/solve.hpp"

using namespace liftoff;
using scene::EndSupport;
using scene::Method;

namespace {

io::SolveReport solve(const scene::Scene& s, Method method, std::optional<double> tolerance = {}) {
  app::SolveRequest request;
  request.method = method;
  request.tolerance = tolerance;
  io::SolveReport r = app::solve_scene(s, request);
  REQUIRE(r.usable);
  REQUIRE(r.certified());
  return r;
}

// The curling strip's figures from the scene itself (user units).
struct Curling {
  double L, EI, K, q, kappa, M0, beta, Lambda, c, rise;
};
Curling curling_figures(const scene::Scene& s) {
  Curling f{};
  f.L = s.structure.length;
  f.EI = s.structure.bending_stiffness;
  f.K = *s.foundation.modulus;
  for (const auto& l : s.loads) {
    if (l.kind == scene::LoadKind::uniform) f.q = l.value;
    if (l.kind == scene::LoadKind::curvature) f.kappa = l.value;
  }
  f.M0 = f.EI * f.kappa;
  f.beta = std::pow(f.K / (4 * f.EI), 0.25);
  f.Lambda = 2 * f.beta * f.beta * f.M0 / f.q;
  f.c = (std::sqrt(f.Lambda) - 1) / f.beta;
  f.rise = f.q / f.K * (f.Lambda * f.Lambda - 1) / 2;
  return f;
}

// The same strip with end moments M0 in place of the curvature (closed form, user units): the
// curvature over [0, L] is work-equivalent to -M0 at x = 0 and +M0 at x = L (counterclockwise).
closed_form::BeamProblem end_moment_problem(const Curling& f) {
  closed_form::BeamProblem p;
  p.length = f.L;
  p.bending_stiffness = f.EI;
  p.foundation_modulus = f.K;
  p.left = p.right = closed_form::EndCondition::free;
  p.uniform_loads.push_back({0.0, f.L, f.q});
  p.moments = {{0.0, -f.M0}, {f.L, f.M0}};
  return p;
}

}  // namespace

TEST_CASE("curling slab strip: the issue's closed form, the end-moment problem, FE fast and fitted",
          "[verification][issue12][curvature]") {
  const scene::Scene s = test::shipped_scene("engineering/curling_slab_strip");
  const Curling f = curling_figures(s);
  REQUIRE(f.Lambda > 1);  // the scene is meant to lift off

  // 1. The closed form (finite strip, end moments) against the semi-infinite formulas:
  //    they differ by the other edge's influence, e^(-beta (L - 2c)) ~ 1e-6 here; 1e-5 allowed.
  const closed_form::TensionlessResult exact = closed_form::solve_tensionless_auto(end_moment_problem(f));
  REQUIRE(exact.status == closed_form::TensionlessStatus::converged);
  REQUIRE(exact.contact.size() == 1);
  const double far = std::exp(-f.beta * (f.L - 2 * f.c));
  std::printf("curling: c = %.6f m (formula %.6f), rise %.6e m (formula %.6e), e^-beta(L-2c) = %.1e\n",
              exact.contact[0].start, f.c, -exact.solution.deflection(0.0), f.rise, far);
  CHECK(std::abs(exact.contact[0].start - f.c) <= 10 * far * f.L);
  CHECK(std::abs(f.L - exact.contact[0].end - f.c) <= 10 * far * f.L);
  CHECK(std::abs(-exact.solution.deflection(0.0) - f.rise) <= 10 * far * f.rise);

  // 2. FE fast on the scene's mesh: the contact limits fall within an element of the exact ones
  //    (P1 reactions resolve a limit to its element), the edge rise within the h^2 error of the
  //    limits (relative (beta h)^2, x 10 for the constant).
  const io::SolveReport fast = solve(s, Method::fast);
  const double h = f.L / fast.elements;
  REQUIRE(fast.contact_regions.size() == 1);
  CHECK(std::abs(fast.contact_regions[0].begin - exact.contact[0].start) <= h);
  CHECK(std::abs(fast.contact_regions[0].end - exact.contact[0].end) <= h);
  CHECK(std::abs(-fast.w_min - f.rise) <= 10 * std::pow(f.beta * h, 2) * f.rise);

  // 3. The tolerance path (limit-fitted): within its own estimates of the limits and w.
  const double tolerance = 1e-7;
  const io::SolveReport fitted = solve(s, Method::fast, tolerance);
  REQUIRE(fitted.contact_regions.size() == 1);
  std::printf("curling fitted: limits %.9f %.9f (exact %.9f %.9f), w_min %.9e (exact %.9e), estimates %.1e %.1e\n",
              fitted.contact_regions[0].begin, fitted.contact_regions[0].end, exact.contact[0].start,
              exact.contact[0].end, fitted.w_min, exact.solution.deflection(0.0), fitted.estimated_limit_error,
              fitted.estimated_w_error);
  CHECK(std::abs(fitted.contact_regions[0].begin - exact.contact[0].start) <= tolerance * f.L);
  CHECK(std::abs(fitted.contact_regions[0].end - exact.contact[0].end) <= tolerance * f.L);
  CHECK(std::abs(fitted.w_min - exact.solution.deflection(0.0)) <= 2 * tolerance * f.rise);

  // 4. The moment reported is the elastic one: zero at the free edges, -M0 (hogging) where the
  //    strip lies flat, i.e. the end-moment problem's moment less M0 everywhere. The fields are
  //    cubic w'' per element, exact to h^2 of the curvature's scale M0.
  const auto& x = fast.fields.coordinate;
  const auto& moment = fast.fields.bending_moment;
  REQUIRE(x.size() == moment.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i)
    worst = std::max(worst, std::abs(moment[i] - (exact.solution.bending_moment(x[i]) - f.M0)));
  std::printf("curling: elastic moment at the edges %.3e and %.3e N m, middle %.6e (-M0 = %.6e), worst %.2e\n",
              moment.front(), moment.back(), moment[moment.size() / 2], -f.M0, worst);
  CHECK(worst <= 10 * std::pow(f.beta * h, 2) * f.M0);
  CHECK(std::abs(moment.front()) <= 10 * std::pow(f.beta * h, 2) * f.M0);
  // In the middle the edges' disturbance has decayed like e^(-beta (L/2 - c)) (Hetenyi; x 10
  // for the amplitude): the restrained moment -M0 of a flat slab.
  CHECK(std::abs(moment[moment.size() / 2] + f.M0) <= 10 * std::exp(-f.beta * (f.L / 2 - f.c)) * f.M0);
}

TEST_CASE("an imposed curvature: the same nodal loads as end moments EI kappa", "[fe][issue12][curvature]") {
  // A free strip with curvature over all of it and one with end moments -M0, +M0 have the same
  // load vector (the interior nodes cancel exactly), so the same answer to round-off.
  scene::Scene a = test::beam_scene(1.0, 1.0, EndSupport::free, EndSupport::free, 4 * std::pow(6.0, 4));
  a.loads = {test::uniform_load(0.0, 1.0, 10.0)};
  scene::Scene b = a;
  scene::Load curvature;
  curvature.kind = scene::LoadKind::curvature;
  curvature.value = 2.0;
  curvature.from = 0.0;
  curvature.to = 1.0;
  a.loads.push_back(curvature);
  b.loads.push_back(test::point_moment(0.0, -2.0));
  b.loads.push_back(test::point_moment(1.0, 2.0));
  const test::Solved with_curvature = test::solve(a, contact::Method::fast, 64);
  const test::Solved with_moments = test::solve(b, contact::Method::fast, 64);
  CHECK((with_curvature.discretisation.live_load - with_moments.discretisation.live_load).lpNorm<Eigen::Infinity>() <=
        1e-15 * 2.0);
  CHECK(test::relative_difference(with_curvature.solution.displacement, with_moments.solution.displacement) < 1e-12);
  // value > 0 lifts the ends (w < 0 there).
  CHECK(with_curvature.solution.displacement[0] < 0.0);
}

TEST_CASE("a trapezoidal distributed load against the closed form", "[verification][issue12][distributed]") {
  // beta L = 5, clamped-free, tensionless: a soil-pressure-like profile with a step.
  scene::Scene s = test::beam_scene(4.0, 2.0, EndSupport::clamped, EndSupport::free, 4 * std::pow(5.0, 4));
  scene::Load q;
  q.kind = scene::LoadKind::distributed;
  q.table_at = {0.0, 1.0, 2.5, 2.5, 4.0};
  q.table_value = {0.0, 3.0, 1.0, -0.5, 2.0};
  s.loads = {q, test::point_force(3.6, -2.0)};  // lifts the free end: one contact region
  const model::MemberModel model = model::make_member_model(s);
  const closed_form::BeamProblem problem = closed_form::problem_of(model);
  const closed_form::TensionlessResult exact = closed_form::solve_tensionless_auto(problem);
  REQUIRE(exact.status == closed_form::TensionlessStatus::converged);

  const io::SolveReport fitted = solve(s, Method::fast, 1e-8);
  REQUIRE(fitted.contact_regions.size() == exact.contact.size());
  for (std::size_t i = 0; i < exact.contact.size(); ++i) {
    CAPTURE(i);
    CHECK(std::abs(fitted.contact_regions[i].begin / 4.0 - exact.contact[i].start) <= 1e-8);
    CHECK(std::abs(fitted.contact_regions[i].end / 4.0 - exact.contact[i].end) <= 1e-8);
  }
  // The certificate's applied force is the table's integral (trapezoids) plus the point force.
  const double integral = 0.5 * 1.0 * 3.0 + 0.5 * 1.5 * (3.0 + 1.0) + 0.5 * 1.5 * (-0.5 + 2.0) - 2.0;
  CHECK(fitted.certificate_figures.applied_force == Approx(integral).epsilon(1e-12));  // a few roundings of the scales
  // Dual and fast agree on the scene's mesh to round-off (one discrete problem).
  const test::Solved dual = test::solve(s, contact::Method::dual, 200),
                     fast = test::solve(s, contact::Method::fast, 200);
  CHECK(test::relative_difference(dual.solution.displacement, fast.solution.displacement) < 1e-9);
}
