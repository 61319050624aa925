// The contact problem: primal and dual LCPs against each other and against closed forms,
// refusals and outcomes that must be reported, and invariance under units and load scale.
#include <catch2/catch.hpp>
#include <cstdio>

#include "closed_form/scene_problem.hpp"
#include "core/error.hpp"
#include "model/from_scene.hpp"
#include "post/fields.hpp"
#include "support/scenes.hpp"
#include "support/solve.hpp"

using namespace liftoff;
using contact::Method;
using scene::EndSupport;

namespace {

// Largest nodal deflection error against the reference, relative to max |w|.
double deflection_error(const test::Solved& s, const closed_form::BeamSolution& reference) {
  double error = 0.0, scale = 0.0;
  for (int node = 0; node < static_cast<int>(s.discretisation.mesh.nodes.size()); ++node) {
    const double x = s.model.user_from_s(s.discretisation.mesh.nodes[node]);
    const double w = s.solution.displacement[s.discretisation.deflection_dof(node)] * s.model.scales.length;
    error = std::max(error, std::abs(w - reference.deflection(x)));
    scale = std::max(scale, std::abs(reference.deflection(x)));
  }
  return error / scale;
}

}  // namespace

TEST_CASE("bilateral foundation: FE converges to Hetenyi's closed-form beam", "[contact][bilateral]") {
  const EndSupport left = GENERATE(EndSupport::free, EndSupport::pinned);
  const EndSupport right = GENERATE(EndSupport::free, EndSupport::clamped);
  // beta L = 5: neither short nor long; asymmetric loads of every kind.
  scene::Scene s = test::beam_scene(1.0, 1.0, left, right, 4 * std::pow(5.0, 4), /*tensionless=*/false);
  s.loads = {test::point_force(0.3, 1.0), test::point_moment(0.5, 0.2), test::uniform_load(0.6, 0.9, 2.0)};
  const auto reference = closed_form::solve_bilateral(closed_form::problem_of(s));

  std::vector<double> h, error;
  for (int n : {10, 20, 40, 80, 160}) {
    const test::Solved fe = test::solve(s, Method::dual, n);
    REQUIRE(fe.solution.summary.is_usable());
    h.push_back(1.0 / n);
    error.push_back(deflection_error(fe, reference));
  }
  const double order = test::observed_order(h, error);
  std::printf("bilateral %s-%s beam: deflection error %.2e at %d elements, observed order %.2f\n",
              to_string(left).data(), to_string(right).data(), error.back(), 160, order);
  CAPTURE(to_string(left), to_string(right), order, error.back());
  // Nodal deflections of Hermite cubics converge at h^4 for a smooth solution; the seed's
  // mixed foundation (P1 reactions, consistent T) keeps that. Require most of it.
  CHECK(order >= 3.5);
  CHECK(error.back() < 1e-7);
}

TEST_CASE("tensionless seed beams: contact limits converge to the closed form", "[contact][seed]") {
  const std::string name = GENERATE("seed_beam_end_moments", "seed_beam_end_moments_central_load");
  const scene::Scene s = test::shipped_scene(name);
  const closed_form::BeamProblem problem = closed_form::problem_of(s);
  const test::Solved coarse = test::solve(s, Method::dual, 40);
  std::vector<closed_form::Interval> guess;
  for (const auto& r : coarse.regions) guess.push_back({r.begin, r.end});
  const auto reference = closed_form::solve_tensionless(problem, guess);
  REQUIRE(reference.status == closed_form::TensionlessStatus::converged);

  std::vector<double> h, error;
  std::printf("%s: contact limits against the closed form\n", name.c_str());
  for (int n : {25, 50, 100, 200, 400}) {
    const test::Solved fe = test::solve(s, Method::dual, n);
    REQUIRE(fe.regions.size() == reference.contact.size());
    double worst = 0.0;
    for (std::size_t i = 0; i < fe.regions.size(); ++i)
      worst = std::max({worst, std::abs(fe.regions[i].begin - reference.contact[i].start),
                        std::abs(fe.regions[i].end - reference.contact[i].end)});
    h.push_back(1.0 / n);
    error.push_back(worst);
    std::printf("  %4d elements: limit error %.2e L\n", n, worst);
  }
  const double order = test::observed_order(h, error);
  std::printf("  observed order %.2f\n", order);
  CAPTURE(name, order);
  // P1 reactions give h^2 asymptotically; where the limit falls inside its element makes the
  // error oscillate about that trend, so the fitted order is only required to beat 1.5.
  CHECK(order >= 1.5);
  CHECK(error.back() < 1e-5);
}

TEST_CASE("primal and dual LCPs give the same answer on the same mesh", "[contact][lcp]") {
  const auto [name, elements] = GENERATE(table<std::string, int>({{"seed_beam_end_moments", 100},
                                                                  {"seed_beam_end_moments_central_load", 100},
                                                                  {"seed_arch_pinned", 40},
                                                                  {"seed_arch_roller", 40},
                                                                  {"seed_arch_clamped", 40}}));
  const scene::Scene s = test::shipped_scene(name);
  const test::Solved dual = test::solve(s, Method::dual, elements);
  const test::Solved primal = test::solve(s, Method::primal, elements);
  REQUIRE(dual.solution.summary.is_usable());
  REQUIRE(primal.solution.summary.is_usable());
  CAPTURE(name, dual.solution.summary.brief_report(), primal.solution.summary.brief_report());
  // Both are exact solutions of one discrete LCP with a unique solution: they may differ by
  // round-off only; the requirement is 1e-8 relative.
  CHECK(test::relative_difference(dual.solution.displacement, primal.solution.displacement) < 1e-8);
  CHECK(test::relative_difference(dual.solution.reaction, primal.solution.reaction) < 1e-8);
  REQUIRE(dual.regions.size() == primal.regions.size());
  for (std::size_t i = 0; i < dual.regions.size(); ++i) {
    CHECK(dual.regions[i].begin == Approx(primal.regions[i].begin).margin(1e-8));
    CHECK(dual.regions[i].end == Approx(primal.regions[i].end).margin(1e-8));
  }
}

TEST_CASE("a free-free beam: the dual form is refused, the primal solves it", "[contact][lcp]") {
  // beta L = 6 > pi: under a central load the beam lifts off at its ends, with a contact
  // length pi / beta whatever the load (a classical result; the closed form agrees).
  scene::Scene s = test::beam_scene(1.0, 1.0, EndSupport::free, EndSupport::free, 4 * std::pow(6.0, 4));
  s.loads = {test::point_force(0.5, 1.0)};
  REQUIRE_THROWS_AS(test::solve(s, Method::dual, 100), SolverFailure);
  try {
    test::solve(s, Method::dual, 100);
  } catch (const SolverFailure& e) {
    CHECK_THAT(e.what(), Catch::Matchers::Contains("auto") && Catch::Matchers::Contains("fast"));
  }
  const test::Solved automatic = test::solve(s, Method::automatic, 100);
  CHECK(automatic.solution.summary.method == Method::fast);
  REQUIRE(automatic.solution.summary.is_usable());
  REQUIRE(automatic.regions.size() == 1);
  const double length = automatic.regions[0].end - automatic.regions[0].begin;
  // The mesh error of a limit is O(h^2) (see the convergence tests): a few h^2 at h = 0.01.
  CHECK(length == Approx(3.14159265358979 / 6.0).margin(5e-4));
}

TEST_CASE("loads that lift a free beam off entirely: no equilibrium, in words", "[contact][lcp]") {
  scene::Scene s = test::beam_scene(1.0, 1.0, EndSupport::free, EndSupport::free, 1e3);
  s.loads = {test::point_force(0.5, -1.0)};  // pulls the beam away from the foundation
  const test::Solved result = test::solve(s, Method::primal, 20);
  CHECK(result.solution.summary.termination == contact::ContactTermination::no_equilibrium);
  CHECK_THAT(result.solution.summary.message, Catch::Matchers::Contains("no equilibrium"));
}

TEST_CASE("no equilibrium carries Lemke's ray as its certificate, checked here in the LCP's terms",
          "[contact][lcp][certificate]") {
  scene::Scene s = test::beam_scene(1.0, 1.0, EndSupport::free, EndSupport::free, 1e3);
  s.loads = {test::point_force(0.5, -1.0)};  // pulls the beam away from the foundation
  const test::Solved result = test::solve(s, Method::primal, 20);
  REQUIRE(result.solution.summary.termination == contact::ContactTermination::no_equilibrium);
  REQUIRE(result.solution.no_equilibrium_certificate.has_value());
  const contact::NoEquilibriumCertificate& c = *result.solution.no_equilibrium_certificate;
  CHECK(c.formulation == Method::primal);
  const fe::Discretisation& d = result.discretisation;
  const int n = d.equations, m = d.reactions();
  REQUIRE(c.ray.size() == 2 * n + m);
  // The primal LCP as contact_solver.hpp states it, with the loads scaled to unit size.
  const Eigen::MatrixXd k(d.stiffness), cc(d.coupling), t(d.flexibility);
  Eigen::MatrixXd lcp(2 * n + m, 2 * n + m);
  lcp << k, -k, cc.transpose(), -k, k, -cc.transpose(), -cc, cc, t;
  const Eigen::VectorXd load = d.load(1.0) / d.load(1.0).lpNorm<Eigen::Infinity>();
  Eigen::VectorXd q(2 * n + m);
  q << -load, load, Eigen::VectorXd::Zero(m);
  // dz >= 0, |dz|_inf = 1, M^T dz <= 0 and q^T dz < 0, each against the round-off of its terms.
  CHECK(c.ray.minCoeff() >= 0.0);
  CHECK(c.ray.lpNorm<Eigen::Infinity>() == Approx(1.0));
  // Row by row against its terms |M^T| |dz|: Lemke drops column entries below 1e-12 of the
  // largest, and the basis' condition at 20 elements (~1e3) scales that.
  const Eigen::VectorXd terms = lcp.transpose().cwiseAbs() * c.ray;
  const Eigen::VectorXd product = lcp.transpose() * c.ray;
  for (int i = 0; i < product.size(); ++i) CHECK(product[i] <= 1e-9 * terms[i] + 1e-300);
  CHECK(c.q_dot_ray == Approx(q.dot(c.ray)).epsilon(1e-12));
  CHECK(c.q_dot_ray < -1e-3);
  // Its motion du = du+ - du- is one along which the loads do work: the member lifts off.
  const Eigen::VectorXd du = c.ray.head(n) - c.ray.segment(n, n);
  CHECK(load.dot(du) > 1e-3);
  // A solved problem carries none.
  s.loads = {test::point_force(0.5, 1.0)};
  const test::Solved pressed = test::solve(s, Method::primal, 20);
  REQUIRE(pressed.solution.summary.is_usable());
  CHECK_FALSE(pressed.solution.no_equilibrium_certificate.has_value());
}

TEST_CASE("zero load: zero answer, no pivots", "[contact]") {
  const scene::Scene s = test::beam_scene(1.0, 1.0, EndSupport::pinned, EndSupport::pinned, 1e4);
  for (Method m : {Method::dual, Method::primal}) {
    const test::Solved result = test::solve(s, m, 10);
    CHECK(result.solution.summary.is_usable());
    CHECK(result.solution.summary.pivots == 0);
    CHECK(result.solution.displacement.lpNorm<Eigen::Infinity>() == 0.0);
    CHECK(result.regions.empty());
  }
}

TEST_CASE("an arch on rollers: a moment drives its rigid rotation and is refused", "[contact][mechanism]") {
  scene::Scene s = test::shipped_scene("seed_arch_roller");
  s.loads.push_back(test::point_moment(2.0, 0.01));
  CHECK_THROWS_AS(test::solve(s, Method::dual, 40), MechanismError);
  // Without the moment the rotation is gauged at the crown, which is then at rest.
  const test::Solved ok = test::solve(test::shipped_scene("seed_arch_roller"), Method::dual, 40);
  const int crown = ok.discretisation.mesh.node_at(0.0);
  REQUIRE(crown >= 0);
  CHECK(ok.solution.displacement[ok.discretisation.tangential_dof(crown)] == 0.0);
  CHECK_FALSE(ok.discretisation.gauge_note.empty());
}

TEST_CASE("results do not depend on units or on the size of the load", "[contact][scaling]") {
  // Reference: L = 1, EI = 1, k = 1e4, P = 1. The same beam in N and mm: L = 2000 mm,
  // EI = 3e12 N mm^2, K = k EI / L^4, P = 1e6 N (the solution is homogeneous in the load).
  scene::Scene unit = test::beam_scene(1.0, 1.0, EndSupport::pinned, EndSupport::clamped, 1e4);
  unit.loads = {test::point_force(0.3, 1.0), test::uniform_load(0.5, 1.0, -0.5)};
  const double L = 2000.0, EI = 3e12, P = 1e6;
  scene::Scene mm = test::beam_scene(L, EI, EndSupport::pinned, EndSupport::clamped, 0.0);
  mm.foundation.k.reset();
  mm.foundation.modulus = 1e4 * EI / std::pow(L, 4);
  // Nondimensional load P L^2 / EI = 1 in the reference: scale each load by P accordingly.
  const double force_unit = EI / (L * L) * P, distributed_unit = EI / (L * L * L) * P;
  mm.loads = {test::point_force(0.3 * L, 1.0 * force_unit), test::uniform_load(0.5 * L, L, -0.5 * distributed_unit)};

  const test::Solved a = test::solve(unit, Method::dual, 80);
  const test::Solved b = test::solve(mm, Method::dual, 80);
  REQUIRE(a.regions.size() == b.regions.size());
  CHECK(test::relative_difference(a.solution.displacement * P, b.solution.displacement) < 1e-12);
  for (std::size_t i = 0; i < a.regions.size(); ++i) {
    CHECK(a.regions[i].begin == Approx(b.regions[i].begin).margin(1e-12));
    CHECK(a.regions[i].end == Approx(b.regions[i].end).margin(1e-12));
  }
}

TEST_CASE("dead plus lambda times live loads", "[contact][loads]") {
  scene::Scene split = test::beam_scene(1.0, 1.0, EndSupport::free, EndSupport::free, 1e3);
  split.loads = {test::uniform_load(0.0, 1.0, 1.0, scene::LoadCase::dead), test::point_force(0.5, -0.2)};
  scene::Scene combined = split;
  combined.loads = {test::uniform_load(0.0, 1.0, 1.0, scene::LoadCase::dead), test::point_force(0.5, -0.2 * 2.5)};
  const test::Solved a = test::solve(split, Method::primal, 40, 2.5);
  const test::Solved b = test::solve(combined, Method::primal, 40, 1.0);
  CHECK(test::relative_difference(a.solution.displacement, b.solution.displacement) < 1e-10);
}

TEST_CASE("an LCP answer that round-off has spoilt is reported, not returned", "[contact][lcp][slow]") {
  // A free-free beam needs the primal LCP, whose 2n + m unknowns at 400 elements lose the answer
  // to round-off (relative residual ~1e-2): it must come back as a numerical failure.
  const scene::Scene s = scene::read_scene_file(std::string(LIFTOFF_SOURCE_DIR) +
                                                "/verification/dolfinx/scenes/free_free_two_contacts.toml");
  const test::Solved r = test::solve(s, Method::primal, 400);
  CAPTURE(r.solution.summary.residual, r.solution.summary.message);
  CHECK(r.solution.summary.termination == contact::ContactTermination::numerical_failure);
  CHECK(r.solution.summary.residual > 1e-6);
  CHECK_THAT(r.solution.summary.message, Catch::Matchers::Contains("ritz"));
  // The same scene on a coarser mesh is solved, with a residual under the threshold.
  const test::Solved coarse = test::solve(s, Method::primal, 100);
  CHECK(coarse.solution.summary.is_usable());
  CHECK(coarse.solution.summary.residual <= 1e-6);
}

TEST_CASE("ground gap: a hump presses into an unloaded member, every FE method alike", "[contact][issue12][gap]") {
  // Pinned-pinned, no load at all; the ground rises by 1e-3 between the walls at 0.3 and 0.7 (a
  // hump, g < 0). The member must bend away (w < 0) where the hump pushes it.
  scene::Scene s = test::beam_scene(1.0, 1.0, EndSupport::pinned, EndSupport::pinned, 1e4);
  s.foundation.gap_at = {0.3, 0.3, 0.7, 0.7};
  s.foundation.gap_value = {0.0, -1e-3, -1e-3, 0.0};
  const test::Solved fast = test::solve(s, Method::fast, 200);
  REQUIRE(fast.solution.summary.is_usable());
  CHECK(fast.solution.reaction.maxCoeff() > 0.0);  // the hump carries the member: no load, yet reactions
  // Contact only on the hump (the ground elsewhere is at w = 0, below the lifted member): near
  // its walls, like a flat punch, and symmetric (the mesh is: 60, 80, 60 elements).
  REQUIRE(!fast.regions.empty());
  for (const auto& region : fast.regions) {
    CHECK(region.begin >= 0.3 - 1e-12);
    CHECK(region.end <= 0.7 + 1e-12);
  }
  CHECK(fast.regions.front().begin == Approx(1.0 - fast.regions.back().end).margin(1e-9));
  // Where a node presses, the member is above its unloaded axis (w < 0) but not above the hump
  // (w >= g = -1e-3): r = k (w - g) > 0 to the solver's round-off.
  const fe::Discretisation& d = fast.discretisation;
  for (int i = 0; i < d.reactions(); ++i) {
    if (fast.solution.reaction[i] <= 0.0) continue;
    const double w = fast.solution.displacement[d.deflection_dof(d.reaction_nodes[i])];
    CHECK(w < 0.0);
    CHECK(w >= -1e-3 - 1e-15);
  }
  for (Method method : {Method::dual, Method::primal}) {
    const test::Solved other = test::solve(s, method, 200);
    REQUIRE(other.solution.summary.is_usable());
    // The same discrete problem: agreement to the solvers' round-off (residuals ~1e-15; 1e-10
    // leaves room for the LCP's conditioning at 200 elements, cond ~1e8).
    CHECK(test::relative_difference(other.solution.displacement, fast.solution.displacement) <= 1e-10);
  }
  // Without the hump nothing happens.
  s.foundation.gap_at.clear();
  s.foundation.gap_value.clear();
  CHECK(test::solve(s, Method::fast, 200).solution.displacement.isZero(0.0));
}

TEST_CASE("ground gap: a uniform gap under a free member shifts w by exactly g", "[contact][issue12][gap]") {
  // Free-free, so a rigid translation by g costs nothing: with r = k (w - g), w = w0 + g solves
  // the problem exactly if w0 solves it without the gap (bilateral; and tensionless when w0 > 0
  // everywhere, full contact).
  const bool tensionless = GENERATE(false, true);
  scene::Scene s = test::beam_scene(2.0, 3.0, EndSupport::free, EndSupport::free, 500.0, tensionless);
  s.loads = {test::uniform_load(0.0, 2.0, 1.0), test::point_force(1.4, 2.0)};
  const test::Solved plain = test::solve(s, Method::fast, 120);
  const double g = 0.01;  // length units; nondimensional g / L in the dofs
  s.foundation.gap_at = {0.7};
  s.foundation.gap_value = {g};
  const test::Solved shifted = test::solve(s, Method::fast, 120);
  REQUIRE(plain.solution.summary.is_usable());
  REQUIRE(shifted.solution.summary.is_usable());
  const fe::Discretisation& d = shifted.discretisation;
  double worst = 0.0, scale = 0.0;
  for (int node = 0; node <= d.mesh.elements(); ++node) {
    const int dof = d.deflection_dof(node);
    if (tensionless) REQUIRE(plain.solution.displacement[dof] > 0.0);  // full contact without the gap
    worst = std::max(worst, std::abs(shifted.solution.displacement[dof] - plain.solution.displacement[dof] - g / 2.0));
    scale = std::max(scale, std::abs(shifted.solution.displacement[dof]));
  }
  CAPTURE(tensionless, worst, scale);
  // Both answers are refined to round-off (error estimates ~1e-15); 1e-12 of max |w| leaves
  // room for the condition of the free-free system.
  CHECK(worst <= 1e-12 * scale);
  // The reactions do not change: r = k (w - g) = k w0.
  CHECK(test::relative_difference(shifted.solution.reaction, plain.solution.reaction) <= 1e-12);
}

// ---- elastic supports and settlements (issue 12) ----------------------------------------------

TEST_CASE("a very stiff spring tends to the pinned end, with an error ~ 1/k_s", "[contact][springs]") {
  scene::Scene pinned = test::beam_scene(1.0, 1.0, EndSupport::pinned, EndSupport::pinned, 2e3);
  pinned.loads = {test::point_force(0.3, 5.0), test::point_moment(0.7, -2.0)};
  const test::Solved reference = test::solve(pinned, Method::fast, 64);
  auto deflection_error = [&](double stiffness) {
    scene::Scene s = pinned;
    s.supports.left = EndSupport::free;
    s.supports.left_detail = {true, stiffness, 0.0, 0.0};
    const test::Solved solved = test::solve(s, Method::fast, 64);
    REQUIRE(solved.solution.summary.is_usable());
    double error = 0.0;
    for (int node = 0; node <= solved.discretisation.mesh.elements(); ++node) {
      const int w = solved.discretisation.deflection_dof(node);
      error = std::max(error, std::abs(solved.solution.displacement[w] - reference.solution.displacement[w]));
    }
    return error;
  };
  const double e5 = deflection_error(1e5), e7 = deflection_error(1e7), e9 = deflection_error(1e9);
  // The end yields by R/(k_s + k_end), k_end the member's own stiffness at the end: a pinned
  // end of a long beam on the foundation, 2 EI beta^3 (Hetenyi; k = 4 beta^4 EI), ~211 here. The
  // ratios of the errors follow (k_a + k_end)/(k_b + k_end): 1e-2 (1 + 2.1e-3) and 1e-2 (1 + 2e-5).
  // The estimate of k_end holds to ~25 % (lift-off and the finite length beta L = 4.7 change it),
  // i.e. 5e-4 of the first ratio; the solves' round-off (~1e-13 of w) is 1e-4 of e9.
  const double k_end = 2.0 * std::pow(2e3 / 4.0, 0.75);
  CHECK(e5 > 0.0);
  CHECK(e7 / e5 == Approx((1e5 + k_end) / (1e7 + k_end)).epsilon(5e-4));
  CHECK(e9 / e7 == Approx((1e7 + k_end) / (1e9 + k_end)).epsilon(2e-4));
  CHECK(e7 / e5 != Approx(1e-2).epsilon(1e-3));  // the k_end term is really seen
}

TEST_CASE("springs: every FE method gives the same answer", "[contact][springs]") {
  scene::Scene s = test::beam_scene(1.0, 1.0, EndSupport::free, EndSupport::free, 3e3);
  s.supports.left_detail = {true, 200.0, 0.0, 1e-3};
  s.supports.right_detail = {true, 1e3, 5.0, 0.0};
  s.supports.interior_springs.push_back({0.5, {true, 500.0, 0.0, 0.0}});
  s.loads = {test::point_force(0.3, 5.0), test::point_moment(0.7, -2.2)};
  const test::Solved fast = test::solve(s, Method::fast, 100);
  REQUIRE(fast.solution.summary.is_usable());
  for (Method method : {Method::dual, Method::primal}) {
    const test::Solved other = test::solve(s, method, 100);
    REQUIRE(other.solution.summary.is_usable());
    // The same discrete problem: round-off of the dense LCP solves (~1e-12 of max |w| at this size).
    CHECK(test::relative_difference(other.solution.displacement, fast.solution.displacement) < 1e-10);
  }
}

TEST_CASE("a pipeline whose clamped ends settle with the ground by q/K rests on it uniformly, w = q/K",
          "[contact][settlement]") {
  const double k = 1e3, q = 2.0, delta = q / k;  // L = EI = 1: k = K, q nondimensional as given
  scene::Scene s = test::beam_scene(1.0, 1.0, EndSupport::clamped, EndSupport::clamped, k);
  s.supports.left_detail.settlement = s.supports.right_detail.settlement = delta;
  s.loads = {test::uniform_load(0.0, 1.0, q)};
  for (Method method : {Method::fast, Method::dual, Method::primal}) {
    CAPTURE(to_string(method));
    const test::Solved solved = test::solve(s, method, 50);
    REQUIRE(solved.solution.summary.is_usable());
    // The exact answer is in the FE space (w constant): the only error is the solve's round-off,
    // ~ N^2 eps for the mixed form and n eps times growth for Lemke's dense LU: 1e-10 covers both.
    for (int node = 0; node <= solved.discretisation.mesh.elements(); ++node)
      CHECK(std::abs(solved.solution.displacement[solved.discretisation.deflection_dof(node)] - delta) <=
            1e-10 * delta);
    for (int i = 0; i < solved.solution.reaction.size(); ++i)
      CHECK(std::abs(solved.solution.reaction[i] - q) <= 1e-9 * q);
  }
  // Without the settlement the ends hold the pipe up: no longer uniform.
  scene::Scene held = s;
  held.supports.left_detail.settlement = held.supports.right_detail.settlement = 0.0;
  const test::Solved unsettled = test::solve(held, Method::fast, 50);
  CHECK(std::abs(unsettled.solution.displacement[unsettled.discretisation.deflection_dof(25)] - delta) > 1e-3 * delta);
}

TEST_CASE("settled supports are a ground gap's twin: w = v + delta with v over g = -delta", "[contact][settlement]") {
  // Clamped ends settled by delta, a force lifting the middle; its twin has no settlement and the
  // ground at g = -delta. The same discrete problem: w differs by delta, the reactions agree.
  const double delta = 1e-3;
  scene::Scene settled = test::beam_scene(1.0, 1.0, EndSupport::clamped, EndSupport::clamped, 1e4);
  settled.supports.left_detail.settlement = settled.supports.right_detail.settlement = delta;
  settled.loads = {test::point_force(0.5, -40.0)};
  scene::Scene twin = settled;
  twin.supports.left_detail.settlement = twin.supports.right_detail.settlement = 0.0;
  twin.foundation.gap_at = {0.0};
  twin.foundation.gap_value = {-delta};
  for (Method method : {Method::fast, Method::dual, Method::primal}) {
    CAPTURE(to_string(method));
    const test::Solved a = test::solve(settled, method, 80), b = test::solve(twin, method, 80);
    REQUIRE(a.solution.summary.is_usable());
    REQUIRE(b.solution.summary.is_usable());
    const fe::Discretisation& d = a.discretisation;
    double w_difference = 0.0, w_scale = 0.0;
    for (int node = 0; node <= d.mesh.elements(); ++node) {
      const int w = d.deflection_dof(node);
      w_difference = std::max(w_difference, std::abs(a.solution.displacement[w] - b.solution.displacement[w] - delta));
      w_scale = std::max(w_scale, std::abs(a.solution.displacement[w]));
    }
    // Round-off only (K annihilates the translation to round-off, ~N^4 eps relative in K form).
    CHECK(w_difference <= 1e-9 * w_scale);
    CHECK(test::relative_difference(a.solution.reaction, b.solution.reaction) <= 1e-9);
  }
}

namespace {
// A free-free beam, k = 1e4 (kL^4/EI), tension_k = kt (none for kt < 0), loads `loads`.
scene::Scene bilinear_beam(double kt, std::vector<scene::Load> loads) {
  scene::Scene s = test::beam_scene(1.0, 1.0, EndSupport::free, EndSupport::free, 1e4);
  if (kt >= 0.0) s.foundation.tension_k = kt;
  s.loads = std::move(loads);
  return s;
}
// The length of the member where w < 0 (lifted off the ground at the axis), from the nodes.
double lifted_length(const test::Solved& s) {
  const fe::Discretisation& d = s.discretisation;
  double length = 0.0;
  for (int e = 0; e < d.mesh.elements(); ++e)
    if (s.solution.displacement[d.deflection_dof(e)] < 0.0 && s.solution.displacement[d.deflection_dof(e + 1)] < 0.0)
      length += d.mesh.element_size(e);
  return length;
}
}  // namespace

TEST_CASE("bilinear foundation: hand checks, limits K_t = k and K_t -> 0, every FE method",
          "[contact][issue12][tension]") {
  // A uniform load q on a free-free beam presses it down uniformly, w = q/k, whatever K_t: the
  // cubic space holds the constant, so the FE answer is exact to round-off (1e-9 relative: K's
  // condition at 200 elements times eps is ~1e-8 of the solve's scale, refined by fast).
  for (Method m : {Method::fast, Method::primal}) {
    const test::Solved uniform = test::solve(bilinear_beam(3e3, {test::uniform_load(0.0, 1.0, 5.0)}), m, 200);
    REQUIRE(uniform.solution.summary.is_usable());
    const fe::Discretisation& d = uniform.discretisation;
    for (int node = 0; node <= 200; ++node)
      CHECK(uniform.solution.displacement[d.deflection_dof(node)] == Approx(5.0 / 1e4).epsilon(1e-9));
  }
  // Over a uniform gap g (the ground 2e-4 below the axis) the beam settles by g more, w = g + q/k:
  // K_t pulls only with its load K_t g (dead), or it would hold the beam up by K_t g / k.
  {
    scene::Scene trench = bilinear_beam(3e3, {test::uniform_load(0.0, 1.0, 5.0)});
    trench.foundation.gap_at = {0.0, 1.0};
    trench.foundation.gap_value = {2e-4, 2e-4};
    const test::Solved settled = test::solve(trench, Method::fast, 200);
    REQUIRE(settled.solution.summary.is_usable());
    for (int node = 0; node <= 200; ++node)
      CHECK(settled.solution.displacement[settled.discretisation.deflection_dof(node)] ==
            Approx(2e-4 + 5.0 / 1e4).epsilon(1e-9));
  }
  // A central force on a long (kL^4 = 1e4) free-free beam lifts its ends off; K_t holds them
  // down: the lift-off zone shortens as K_t grows, and the three FE methods agree.
  const std::vector<scene::Load> central = {test::point_force(0.5, 100.0)};
  double previous = 2.0;
  for (double kt : {0.0, 1e2, 1e3, 5e3}) {
    CAPTURE(kt);
    const test::Solved fast = test::solve(bilinear_beam(kt, central), Method::fast, 200);
    REQUIRE(fast.solution.summary.is_usable());
    const double lifted = lifted_length(fast);
    CHECK(lifted < previous);
    previous = lifted;
    // Dual is refused on the free-free beam only without K_t (K singular).
    for (Method m :
         kt > 0.0 ? std::vector<Method>{Method::dual, Method::primal} : std::vector<Method>{Method::primal}) {
      const test::Solved other = test::solve(bilinear_beam(kt, central), m, 200);
      REQUIRE(other.solution.summary.is_usable());
      // Lemke's dense solves at 200 elements: round-off well below 1e-8 (as the LCP test above).
      CHECK(test::relative_difference(other.solution.displacement, fast.solution.displacement) < 1e-8);
    }
  }
  CHECK(previous > 0.0);  // still lifted at K_t = k/2

  // K_t = k: the bilateral answer, exactly (the model becomes bilateral).
  scene::Scene bilateral = bilinear_beam(-1.0, central);
  bilateral.foundation.tensionless = false;
  const test::Solved equal = test::solve(bilinear_beam(1e4, central), Method::fast, 200);
  const test::Solved reference = test::solve(bilateral, Method::fast, 200);
  CHECK(test::relative_difference(equal.solution.displacement, reference.solution.displacement) == 0.0);
  // ... and K_t just below k, through the bilinear path: the tensionless part k - K_t = 1e-6 k
  // changes w by O(1e-6) of max |w| (first order in the change of stiffness where w < 0).
  const test::Solved near = test::solve(bilinear_beam(1e4 * (1.0 - 1e-6), central), Method::fast, 200);
  REQUIRE(near.solution.summary.is_usable());
  const double near_difference = test::relative_difference(near.solution.displacement, reference.solution.displacement);
  CHECK(near_difference < 1e-5);
  CHECK(near_difference > 0.0);

  // K_t -> 0: the tensionless answer, the difference first order in K_t (linear: ten times K_t,
  // about ten times the difference, the contact set unchanged).
  const test::Solved tensionless = test::solve(bilinear_beam(-1.0, central), Method::primal, 200);
  const double d1 =
      test::relative_difference(test::solve(bilinear_beam(1e-4, central), Method::fast, 200).solution.displacement,
                                tensionless.solution.displacement);
  const double d2 =
      test::relative_difference(test::solve(bilinear_beam(1e-3, central), Method::fast, 200).solution.displacement,
                                tensionless.solution.displacement);
  CHECK(d1 < 1e-6);
  CHECK(d2 / d1 == Approx(10.0).epsilon(0.05));
}

TEST_CASE("bilinear foundation with springs and a linear modulus: the three stress blocks, every FE method agrees",
          "[contact][issue12][tension][springs]") {
  // The stresses come in three blocks (elements | Winkler | springs, fe/discretisation.hpp) and
  // the linear piece's tensionless part k(s) - K_t is linear too: fast's mixed form must give the
  // K-form methods' answer.
  scene::Scene s = test::beam_scene(1.0, 1.0, EndSupport::free, EndSupport::free, 1.0);
  s.foundation.k.reset();
  s.foundation.segments = {{0.0, 0.6, 3e3, std::nullopt, 1e3}, {0.6, 1.0, 1e3, std::nullopt}};
  s.foundation.tension_k = 400.0;
  s.supports.left_detail = {true, 200.0, 0.0, 0.0};
  s.supports.interior_springs.push_back({0.5, {true, 500.0, 20.0, 0.0}});
  s.loads = {test::point_force(0.3, 5.0), test::point_moment(0.7, -2.2), test::point_force(0.95, -3.0)};
  const model::MemberModel model = model::make_member_model(s);
  REQUIRE(model.has_tension_k());
  const test::Solved fast = test::solve(s, Method::fast, 100);
  REQUIRE(fast.solution.summary.is_usable());
  const fe::Discretisation& d = fast.discretisation;
  REQUIRE(d.springs.size() == 3);  // left w, interior w and rotation
  REQUIRE(d.stresses() == d.spring_stress(3));
  // Both parts are seen: the beam lifts somewhere (K_t pulls) and presses elsewhere.
  const Eigen::VectorXd w = d.expand_displacement(fast.solution.displacement);
  double w_min = 0.0, w_max = 0.0;
  for (int node = 0; node <= d.mesh.elements(); ++node)
    w_min = std::min(w_min, w[d.deflection_dof(node)]), w_max = std::max(w_max, w[d.deflection_dof(node)]);
  CHECK(w_min < 0.0);
  CHECK(w_max > 0.0);
  for (Method method : {Method::dual, Method::primal}) {
    CAPTURE(to_string(method));
    const test::Solved other = test::solve(s, method, 100);
    REQUIRE(other.solution.summary.is_usable());
    // The same discrete problem: round-off of the dense LCP solves (~1e-12 of max |w| at this size).
    CHECK(test::relative_difference(other.solution.displacement, fast.solution.displacement) < 1e-10);
    CHECK(test::relative_difference(other.solution.reaction, fast.solution.reaction) < 1e-10);
  }
}
