// The fast contact solver against Lemke, its safeguard, its fallback, its counts, and the
// choice method = auto makes.

#include "contact/active_set_solver.hpp"

#include <Eigen/LU>
#include <catch2/catch.hpp>
#include <limits>
#include <random>

#include "contact/contact_solver.hpp"
#include "core/error.hpp"
#include "model/from_scene.hpp"
#include "support/scenes.hpp"
#include "support/solve.hpp"

using namespace liftoff;
using contact::Method;
using scene::EndSupport;

namespace {

// Lemke's formulation for a discretisation: dual where the structure is stable, else primal.
Method lemke_for(const fe::Discretisation& d) { return d.structure_is_stable() ? Method::dual : Method::primal; }

contact::ContactSolution solve_with(const fe::Discretisation& d, Method method, int max_iterations = 100) {
  contact::ContactOptions options;
  options.method = method;
  options.active_set.max_iterations = max_iterations;
  return contact::solve_contact(d, options);
}

// What an answer computed from K carries (Lemke's dual and primal forms): eps times the condition
// number (1-norm estimate) of the equilibrated fixed-set system [K C_A^T; C_A -T_AA] of its
// contact set. K's condition grows like N^4; the fast solver works on the mixed form of the
// same equations (condition ~N^2) and is far more accurate than this: at 24 elements Lemke's
// answers were 1e-12 to 2e-10 from an extended-precision solve, fast's 1e-14.
double k_form_round_off(const fe::Discretisation& d, const Eigen::VectorXd& reaction) {
  std::vector<int> contact;
  for (int i = 0; i < d.reactions(); ++i)
    if (reaction[i] > 0.0) contact.push_back(i);
  const int n = d.equations, a = static_cast<int>(contact.size());
  const Eigen::MatrixXd k(d.stiffness), c(d.coupling), t(d.flexibility);
  Eigen::MatrixXd system = Eigen::MatrixXd::Zero(n + a, n + a);
  system.topLeftCorner(n, n) = k;
  for (int p = 0; p < a; ++p) {
    system.row(n + p).head(n) = c.row(contact[p]);
    system.col(n + p).head(n) = c.row(contact[p]).transpose();
    for (int q = 0; q < a; ++q) system(n + p, n + q) = -t(contact[p], contact[q]);
  }
  const Eigen::VectorXd s = system.diagonal().cwiseAbs().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd scaled = s.asDiagonal() * system * s.asDiagonal();
  return std::numeric_limits<double>::epsilon() / Eigen::PartialPivLU<Eigen::MatrixXd>(scaled).rcond();
}

// Fast and Lemke agree to the round-off either can carry: Lemke's residual and its K form's
// round-off (above), and the fast answer's own bound when it was asked for (all relative).
void check_same_answer(const contact::ContactSolution& fast, const contact::ContactSolution& lemke,
                       const fe::Discretisation& d) {
  REQUIRE(fast.summary.is_usable());
  REQUIRE(lemke.summary.is_usable());
  const double k_form = k_form_round_off(d, lemke.reaction);
  const double tolerance = 10.0 * std::max({fast.summary.round_off_bound, lemke.summary.residual, k_form, 1e-12});
  CAPTURE(fast.summary.round_off_bound, lemke.summary.residual, k_form);
  CHECK(test::relative_difference(fast.displacement, lemke.displacement) <= tolerance);
  CHECK(test::relative_difference(fast.reaction, lemke.reaction) <= tolerance);
  // The fast answer holds equilibrium and the contact conditions by itself (its residual
  // measures both, relative to the terms involved).
  CHECK(fast.summary.residual <= 1e-12);
}

scene::Scene random_beam(std::mt19937& random) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const EndSupport ends[] = {EndSupport::pinned, EndSupport::clamped, EndSupport::free};
  const double k = std::pow(10.0, -3.0 + 15.0 * unit(random));  // 1e-3 .. 1e12
  auto s = test::beam_scene(1.0, 1.0, ends[random() % 3], ends[random() % 3], k);
  const int loads = 1 + static_cast<int>(random() % 4);
  for (int i = 0; i < loads; ++i) {
    const double value = 2.0 * unit(random) - 0.7;  // mostly into the foundation
    switch (random() % 3) {
      case 0:
        s.loads.push_back(test::point_force(unit(random), value));
        break;
      case 1:
        s.loads.push_back(test::point_moment(unit(random), value));
        break;
      default: {
        const double a = unit(random), b = unit(random);
        s.loads.push_back(test::uniform_load(std::min(a, b), std::max(a, b) + 1e-3, value));
      }
    }
  }
  return s;
}

}  // namespace

TEST_CASE("fast gives Lemke's answer on every shipped scene", "[contact][fast]") {
  for (const char* name : {"seed_beam_end_moments", "seed_beam_end_moments_central_load", "seed_arch_pinned",
                           "seed_arch_roller", "seed_arch_clamped"}) {
    CAPTURE(name);
    const auto scene = test::shipped_scene(name);
    const auto model = model::make_member_model(scene);
    const auto d = fe::discretise(model, scene.solve.elements);
    const auto fast = solve_with(d, Method::fast);
    CHECK(fast.summary.method == Method::fast);
    CHECK(fast.summary.iterations >= 1);
    check_same_answer(fast, solve_with(d, lemke_for(d)), d);
  }
}

TEST_CASE("fast gives Lemke's answer on random beams, free-free included, k from 1e-3 to 1e12", "[contact][fast]") {
  std::mt19937 random(20261122);
  int compared = 0, lifted_off = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const auto scene = random_beam(random);
    CAPTURE(trial, scene::to_string(scene.supports.left), scene::to_string(scene.supports.right), *scene.foundation.k);
    const auto d = fe::discretise(model::make_member_model(scene), 24);
    const auto lemke = solve_with(d, lemke_for(d));
    const auto fast = solve_with(d, Method::fast);
    if (lemke.summary.termination == contact::ContactTermination::no_equilibrium) {
      // Nothing to find: fast cannot hold it either, and Lemke (the fallback) says why.
      CAPTURE(fast.summary.message);
      CHECK(fast.summary.termination == contact::ContactTermination::no_equilibrium);
      ++lifted_off;
      continue;
    }
    check_same_answer(fast, lemke, d);
    ++compared;
  }
  CHECK(compared >= 40);
  INFO("lifted off entirely: " << lifted_off);
}

// Found by a random search over beams (random_beam, 4..33 elements, plain block pivoting):
// a clamped-free beam on a stiff foundation whose contact pattern oscillates along the span.
TEST_CASE("a beam on which plain block pivoting cycles: the safeguarded iteration solves it", "[contact][fast]") {
  auto scene = test::beam_scene(1.0, 1.0, EndSupport::clamped, EndSupport::free, 8687518936.5307198);
  scene.loads.push_back(test::point_force(0.21113115480919778, -0.62458172292233938));
  scene.loads.push_back(test::uniform_load(0.49344248070120228, 0.72114097772403452, 1.133705431883246));
  const auto d = fe::discretise(model::make_member_model(scene), 13);
  const Eigen::VectorXd load = d.load(1.0);

  contact::ActiveSetOptions plain;
  plain.block_retries = -1;
  const auto unsafe = contact::solve_active_set(d, load, plain);
  CHECK(unsafe.summary.termination == contact::ActiveSetTermination::cycling);

  const auto safe = contact::solve_active_set(d, load, {});
  REQUIRE(safe.summary.termination == contact::ActiveSetTermination::solved);
  CHECK(safe.summary.single_steps > 0);  // the safeguard did the work
  check_same_answer(solve_with(d, Method::fast), solve_with(d, Method::dual), d);
}

TEST_CASE("when the fast solver stops, Lemke takes over and the summary says so", "[contact][fast]") {
  const auto scene = test::shipped_scene("seed_beam_end_moments_central_load");
  const auto d = fe::discretise(model::make_member_model(scene), 80);
  const auto fallback = solve_with(d, Method::fast, 1);  // one set: the bilateral one, not the answer
  REQUIRE(fallback.summary.is_usable());
  CHECK(fallback.summary.method == Method::dual);
  CHECK(fallback.summary.iterations == 1);
  CHECK(fallback.summary.pivots > 0);
  CHECK_THAT(fallback.summary.message, Catch::Contains("falling back to dual Lemke"));
  CHECK_THAT(fallback.summary.message, Catch::Contains("iteration_limit"));
  CHECK_THAT(fallback.summary.method_reason, Catch::Contains("fell back to dual Lemke"));
  check_same_answer(solve_with(d, Method::fast), fallback, d);
}

TEST_CASE("a fast solver that stops on a large mesh is reported, not handed to minutes of dense Lemke",
          "[contact][fast]") {
  // 2100 elements: a dual LCP of 2101 unknowns, above max_fallback_lcp (dense Lemke ~ n^3: ~10 s
  // here, ten minutes at max_dense_lcp). One set allowed: fast stops and nothing takes over.
  const auto scene = test::shipped_scene("seed_beam_end_moments_central_load");
  const auto d = fe::discretise(model::make_member_model(scene), 2100);
  REQUIRE(d.reactions() > contact::max_fallback_lcp);
  const auto stopped = solve_with(d, Method::fast, 1);
  CHECK_FALSE(stopped.summary.is_usable());
  CHECK(stopped.summary.pivots <= 0);  // no Lemke pivot (-1: none counted)
  CHECK_THAT(stopped.summary.message, Catch::Contains("too large for the Lemke fallback (limit 2000)"));
}

// The contact limits move by a fraction of the span from the bilateral start, not by a number
// of elements, so the count of contact sets is a property of the problem, not of the mesh.
// (Up to 5000 elements: near 1e4 round-off starts to own the Hermite system, see contact_solver.)
// A limit that lands on a node within round-off may cost one or two more sets.
TEST_CASE("the number of contact sets does not grow with the mesh", "[contact][fast]") {
  for (const char* name : {"seed_beam_end_moments", "seed_beam_end_moments_central_load"}) {
    CAPTURE(name);
    const auto scene = test::shipped_scene(name);
    const auto model = model::make_member_model(scene);
    int coarsest = -1;
    for (int elements : {100, 300, 1000, 3000, 5000}) {
      CAPTURE(elements);
      const auto fast = solve_with(fe::discretise(model, elements), Method::fast);
      REQUIRE(fast.summary.is_usable());
      if (coarsest < 0) coarsest = fast.summary.iterations;
      CHECK(fast.summary.iterations <= coarsest + 2);
      CHECK(fast.summary.factorisations == fast.summary.iterations);  // one per set, none repeated
    }
  }
}

TEST_CASE("a contact set already factorised is not factorised again", "[contact][fast]") {
  const auto d = fe::discretise(model::make_member_model(test::shipped_scene("seed_beam_end_moments")), 40);
  contact::ActiveSetSystem system(d);
  std::vector<bool> in_contact(d.reactions(), true);
  REQUIRE(system.factorise(in_contact));
  REQUIRE(system.factorise(in_contact));
  CHECK(system.factorisations() == 1);
  in_contact[3] = false;
  REQUIRE(system.factorise(in_contact));
  CHECK(system.factorisations() == 2);
}

TEST_CASE("auto: fast for every FE scene, stable or not, small or large", "[contact][auto]") {
  const auto stable = model::make_member_model(test::shipped_scene("seed_beam_end_moments"));
  for (int elements : {20, 200, 2000}) {
    const auto choice = contact::choose_fe_method(fe::discretise(stable, elements));
    CHECK(choice.method == Method::fast);
    CHECK_THAT(choice.reason, Catch::StartsWith("fast:") && Catch::Contains("O(n)") && Catch::Contains("by name"));
  }
  auto free_free = test::beam_scene(1.0, 1.0, EndSupport::free, EndSupport::free, 100.0);
  free_free.loads.push_back(test::point_force(0.5, 1.0));
  const auto unstable = contact::choose_fe_method(fe::discretise(model::make_member_model(free_free), 40));
  CHECK(unstable.method == Method::fast);

  auto bilateral = test::shipped_scene("seed_beam_end_moments");
  bilateral.foundation.tensionless = false;
  const auto choice = contact::choose_fe_method(fe::discretise(model::make_member_model(bilateral), 200));
  CHECK(choice.method == Method::fast);
  CHECK_THAT(choice.reason, Catch::StartsWith("bilateral"));
  // And solve_contact does what it said.
  const auto solved = solve_with(fe::discretise(stable, 200), Method::automatic);
  CHECK(solved.summary.method == Method::fast);
  CHECK(solved.summary.method_reason == contact::choose_fe_method(fe::discretise(stable, 200)).reason);
}

namespace {

// A long member with seven lift-off zones (beta L = 1000, self-weight, uplift forces of five
// times the Hetenyi lift-off force 2 q / beta).
scene::Scene seven_lift_off_zones() {
  const double beta = 1000.0;
  auto s = test::beam_scene(1.0, 1.0, EndSupport::pinned, EndSupport::pinned, 4.0 * std::pow(beta, 4));
  s.loads = {test::uniform_load(0.0, 1.0, 1.0, scene::LoadCase::dead)};
  for (double x : {0.11, 0.23, 0.37, 0.5, 0.61, 0.77, 0.9}) s.loads.push_back(test::point_force(x, -10.0 / beta));
  return s;
}

}  // namespace

TEST_CASE("nested iteration: a coarser mesh's contact set starts this one, same answer in fewer sets here",
          "[contact][fast][nested]") {
  // seven_lift_off_zones: from the bilateral start the limits creep by about a node per block step
  // (11 sets at 1e4 elements); from the contact set of 1000 elements carried over (itself seeded
  // by 100 elements), 2 sets (verification/bench/accuracy_bench.cpp ratio).
  const auto model = model::make_member_model(seven_lift_off_zones());
  const auto d = fe::discretise(model, 10000);
  const auto plain = contact::solve_active_set(d, d.load(1.0), {});
  const auto nested = contact::solve_active_set_nested(model, d, 1.0, {});
  REQUIRE(plain.summary.is_usable());
  REQUIRE(nested.result.summary.is_usable());
  CHECK(nested.levels == 3);  // 100 -> 1000 -> 1e4 elements
  CHECK(nested.result.in_contact == plain.in_contact);
  CHECK(test::relative_difference(nested.result.state.displacement, plain.state.displacement) < 1e-12);
  CAPTURE(plain.summary.iterations, nested.result.summary.iterations, nested.coarse_sets);
  CHECK(nested.result.summary.iterations <= 3);
  CHECK(nested.result.summary.iterations < plain.summary.iterations);
}

TEST_CASE("fast through solve_contact: a large uniform mesh starts from a coarser mesh's set, same answer",
          "[contact][fast][nested]") {
  // The long member of the test above: discretise(model, N) keeps the member, so solve_contact
  // (as `liftoff solve`) takes the nested start without being asked; a mesh it did not make
  // (fitted limits, a given mesh) has no member and starts from the bilateral set.
  const auto model = model::make_member_model(seven_lift_off_zones());
  const auto d = fe::discretise(model, 10000);
  REQUIRE(d.uniform_member);
  const auto fast = solve_with(d, Method::fast);
  const auto plain = contact::solve_active_set(d, d.load(1.0), {});
  REQUIRE(fast.summary.is_usable());
  REQUIRE(plain.summary.is_usable());
  CAPTURE(fast.summary.message, plain.summary.iterations);
  CHECK_THAT(fast.summary.message, Catch::Contains("coarser mesh"));
  CHECK(fast.summary.iterations <= 3);
  CHECK(fast.summary.iterations < plain.summary.iterations);
  // Both are the same contact set's answer refined to round-off (as the test above).
  CHECK(test::relative_difference(fast.displacement, d.expand(plain.state.displacement)) < 1e-12);
  CHECK(test::relative_difference(fast.reaction, plain.state.reaction) < 1e-12);
  // A mesh not made by discretise(model, N) has no member to coarsen.
  CHECK_FALSE(fe::discretise(model, fe::make_mesh(model, 100)).uniform_member);
}

TEST_CASE("a coarse set is not refined to round-off, and a seeded first set's clear signs are read unrefined",
          "[contact][fast][nested]") {
  // seven_lift_off_zones at 1e4 elements: the coarse set of 1000 elements, and a fine first set
  // seeded by 100 elements.
  const auto model = model::make_member_model(seven_lift_off_zones());
  const auto coarse = fe::discretise(model, 1000);
  const auto d = fe::discretise(model, 10000);
  const auto refined = contact::solve_active_set(coarse, coarse.load(1.0), {});
  contact::ActiveSetOptions seed_options;
  seed_options.refine_answer = false;
  seed_options.intermediate_error = 1e-6;
  const auto seed = contact::solve_active_set(coarse, coarse.load(1.0), seed_options);
  REQUIRE(refined.summary.is_usable());
  REQUIRE(seed.summary.is_usable());
  // The same set; its answer left at the intermediate accuracy, no residual computed.
  CHECK(seed.in_contact == refined.in_contact);
  CHECK(seed.state.error_estimate <= 1e-6);
  CHECK(seed.state.error_estimate > refined.state.error_estimate);
  CHECK(seed.state.residual == -1.0);

  // The fine mesh from the set a coarse answer suggests: the first set read unrefined gives the
  // same answer (the set found is refined and checked), in no more sets. The 1000 elements' set is
  // the answer here (the test below), so the seed is the set of 100 elements, which is not.
  const auto plain = contact::solve_active_set(d, d.load(1.0), {});
  const auto start = contact::coarse_start(model, d, 1.0, {}, contact::NestedOptions{100, 100, 0.1});
  REQUIRE(start.levels == 2);
  contact::ActiveSetOptions unrefined_options;
  unrefined_options.unrefined_first_set = true;
  const auto usual = contact::solve_active_set(d, d.load(1.0), {}, start.initial, d.ground_gap);
  const auto unrefined = contact::solve_active_set(d, d.load(1.0), unrefined_options, start.initial, d.ground_gap);
  REQUIRE(usual.summary.is_usable());
  REQUIRE(unrefined.summary.is_usable());
  CAPTURE(usual.summary.iterations, unrefined.summary.iterations, usual.summary.infeasible_history,
          unrefined.summary.infeasible_history);
  CHECK(unrefined.in_contact == plain.in_contact);
  CHECK(test::relative_difference(unrefined.state.displacement, plain.state.displacement) < 1e-12);
  CHECK(test::relative_difference(unrefined.state.reaction, plain.state.reaction) < 1e-12);
  CHECK(unrefined.summary.iterations <= usual.summary.iterations);
  CHECK(unrefined.summary.iterations >= 2);  // the seed was not the answer: the unrefined read was used
}

TEST_CASE("a carried seed's nodes held at the gap by a support take the coarse answer's status there",
          "[contact][fast][nested]") {
  // seven_lift_off_zones is pinned at both ends on the ground: w = g = 0 there exactly, and the
  // fine answer has both end nodes in contact (their neighbours press). Read as w > g they were
  // seeded lifted off, which cost a whole second set on the fine mesh; with the coarse answer's own
  // status there the 1000 elements' set is the fine answer itself: one set.
  const auto model = model::make_member_model(seven_lift_off_zones());
  const auto d = fe::discretise(model, 10000);
  const auto plain = contact::solve_active_set(d, d.load(1.0), {});
  REQUIRE(plain.summary.is_usable());
  REQUIRE(plain.in_contact.front());
  REQUIRE(plain.in_contact.back());
  const auto start = contact::coarse_start(model, d, 1.0, {}, contact::NestedOptions{10, 1000, 0.1});
  REQUIRE(start.levels == 2);
  CHECK(start.initial.front());
  CHECK(start.initial.back());
  CHECK(start.initial == plain.in_contact);
  const auto nested = contact::solve_active_set_nested(model, d, 1.0, {});
  REQUIRE(nested.result.summary.is_usable());
  CAPTURE(nested.result.summary.infeasible_history);
  CHECK(nested.result.summary.iterations == 1);
  CHECK(nested.result.in_contact == plain.in_contact);
  CHECK(test::relative_difference(nested.result.state.displacement, plain.state.displacement) < 1e-12);
}

TEST_CASE("a carried seed's clamped end takes the coarse answer's status: one set on a settled pipeline",
          "[contact][fast][nested]") {
  // pipeline_settled_ends (400 elements, seeded by 100): the right end is clamped on the ground
  // (w = g = 0 there). The mean of w - g beside it, from the coarse cubic, gave the wrong status and
  // a second set; the coarse answer's own status there is the fine answer's.
  const auto scene = test::shipped_scene("engineering/pipeline_settled_ends");
  const auto d = fe::discretise(model::make_member_model(scene), scene.solve.elements);
  const auto fast = solve_with(d, Method::fast);
  REQUIRE(fast.summary.is_usable());
  CAPTURE(fast.summary.message);
  CHECK_THAT(fast.summary.message, Catch::Contains("coarser mesh"));
  CHECK(fast.summary.iterations == 1);
}
