// Tests of src/contact/stability.* and of the contact solvers under a compressive axial force
// (second-order theory, fe/discretisation.hpp): the beam-column against its exact Fourier series,
// the methods against each other, and the refusal of unstable equilibria.
#include "contact/stability.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "certify/certificate.hpp"
#include "core/error.hpp"
#include "support/scenes.hpp"
#include "support/solve.hpp"

using namespace liftoff;
using contact::Method;
using scene::EndSupport;

namespace {

constexpr double pi = std::numbers::pi;

scene::Load axial_load(double value, scene::LoadCase c = scene::LoadCase::dead) {
  scene::Load l;
  l.kind = scene::LoadKind::axial;
  l.value = value;
  l.load_case = c;
  l.case_name = c == scene::LoadCase::dead ? "dead" : "live";
  return l;
}

// The half-sine initial shape of amplitude a on [0, L], as the reader samples it.
scene::InitialShape half_sine(double length, double amplitude) {
  scene::InitialShape shape;
  shape.shape = "half_sine";
  for (int i = 0; i <= scene::initial_shape_samples; ++i) {
    const double t = static_cast<double>(i) / scene::initial_shape_samples;
    shape.at.push_back(t * length);
    shape.value.push_back(i == 0 || i == scene::initial_shape_samples ? 0.0 : amplitude * std::sin(pi * t));
  }
  return shape;
}

// w(L/2) of EI w'''' + P w'' + K w = q on a pinned strut of length L (bilateral foundation): the
// Fourier sine series, sum over odd n of 4 q / (n pi (EI a^4 - P a^2 + K)) sin(n pi / 2), a = n pi / L.
// Terms fall like n^-5: 20000 of them leave below 1e-19 of the sum.
double beam_column_midspan(double length, double ei, double p, double k, double q) {
  double sum = 0.0;
  for (int n = 39999; n >= 1; n -= 2) {  // smallest first
    const double a = n * pi / length;
    const double sign = (n / 2) % 2 == 0 ? 1.0 : -1.0;
    sum += 4.0 * q / (n * pi * (ei * a * a * a * a - p * a * a + k)) * sign;
  }
  return sum;
}

double midspan(const test::Solved& s) {
  const int node = s.discretisation.mesh.node_at(0.5 * (s.model.s_begin + s.model.s_end));
  REQUIRE(node >= 0);
  return s.solution.displacement[s.discretisation.deflection_dof(node)] * s.model.scales.length;
}

certify::Certificate certify_solved(const test::Solved& s) {
  return certify::certify(s.model, s.discretisation, s.solution, certify::CertifyOptions{});
}

}  // namespace

TEST_CASE("bilateral pinned beam-column at half its critical load converges to the Fourier series",
          "[contact][axial]") {
  // L = 2, EI = 3, K L^4/EI = 100; P = 0.5 pi^2 EI/L^2 (the strut's Euler load without foundation).
  const double length = 2.0, ei = 3.0, k = 100.0, q = 1.5;
  const double p = 0.5 * pi * pi * ei / (length * length);
  scene::Scene s = test::beam_scene(length, ei, EndSupport::pinned, EndSupport::pinned, k, /*tensionless=*/false);
  s.loads = {test::uniform_load(0.0, length, q), axial_load(p)};
  const double exact = beam_column_midspan(length, ei, p, k * ei / std::pow(length, 4), q);
  // Second order matters here: the first-order answer is off by far more than the FE error.
  CHECK(std::abs(beam_column_midspan(length, ei, 0.0, k * ei / std::pow(length, 4), q) - exact) > 0.1 * exact);

  std::vector<double> h, error;
  for (int n : {4, 8, 16, 32}) {
    const test::Solved fe = test::solve(s, Method::fast, n);
    REQUIRE(fe.solution.summary.is_usable());
    h.push_back(1.0 / n);
    error.push_back(std::abs(midspan(fe) - exact) / exact);
    if (n == 32) {
      const certify::Certificate c = certify_solved(fe);
      CAPTURE(c.message);
      CHECK(c.passed);
    }
  }
  const double order = test::observed_order(h, error);
  std::printf("bilateral beam-column, P = 0.5 P_E: midspan error %.2e at 32 elements, observed order %.2f\n",
              error.back(), order);
  CAPTURE(order, error);
  // Hermite cubics with the consistent K_g: nodal values converge like h^4.
  CHECK(order > 3.8);
  CHECK(error.back() < 1e-6);
}

TEST_CASE("tensionless heavy beam-column below its limit: dual, primal and fast agree", "[contact][axial]") {
  // Pinned strut on a tensionless foundation, its weight pressing it down, an upward point force
  // lifting part of it off; P = 0.6 pi^2 EI/L^2, below the strut's own Euler load (so K(P) is
  // positive definite and the dual form applies).
  const double length = 1.0, ei = 1.0;
  scene::Scene s = test::beam_scene(length, ei, EndSupport::pinned, EndSupport::pinned, 2000.0);
  s.loads = {test::uniform_load(0.0, length, 1.0), test::point_force(0.3, -0.6), axial_load(0.6 * pi * pi)};
  s.initial_shape = half_sine(length, -1e-3);
  const test::Solved fast = test::solve(s, Method::fast, 60);
  const test::Solved dual = test::solve(s, Method::dual, 60);
  const test::Solved primal = test::solve(s, Method::primal, 60);
  for (const test::Solved* one : {&fast, &dual, &primal}) {
    CAPTURE(one->solution.summary.message);
    REQUIRE(one->solution.summary.is_usable());
    const certify::Certificate c = certify_solved(*one);
    CAPTURE(c.message);
    CHECK(c.passed);
  }
  // Some of it lifts off, some stays in contact.
  int lifted = 0;
  for (int i = 0; i < fast.discretisation.reactions(); ++i) lifted += fast.solution.reaction[i] == 0.0;
  CHECK(lifted > 5);
  CHECK(lifted < fast.discretisation.reactions() - 5);
  const double dual_gap = test::relative_difference(dual.solution.displacement, fast.solution.displacement);
  const double primal_gap = test::relative_difference(primal.solution.displacement, fast.solution.displacement);
  std::printf("tensionless beam-column: dual vs fast %.1e, primal vs fast %.1e\n", dual_gap, primal_gap);
  CHECK(dual_gap < 1e-10);
  CHECK(primal_gap < 1e-10);
}

TEST_CASE("a weightless strut on a tensionless foundation beyond the Euler load is refused", "[contact][axial]") {
  // It gets no help from the foundation: it buckles away from it at pi^2 EI/L^2 for any k. With an
  // upward imperfection and P = 1.2 pi^2 EI/L^2 no stable equilibrium exists.
  const double length = 1.0, ei = 1.0;
  scene::Scene s = test::beam_scene(length, ei, EndSupport::pinned, EndSupport::pinned, 1000.0);
  s.loads = {axial_load(1.2 * pi * pi)};
  s.initial_shape = half_sine(length, -1e-2);
  for (const Method method : {Method::fast, Method::primal}) {
    const test::Solved fe = test::solve(s, method, 40);
    CAPTURE(contact::to_string(method), fe.solution.summary.message);
    CHECK_FALSE(fe.solution.summary.is_usable());
    CHECK((fe.solution.summary.termination == contact::ContactTermination::unstable_equilibrium ||
           fe.solution.summary.termination == contact::ContactTermination::no_equilibrium));
  }
  CHECK_THROWS_WITH(test::solve(s, Method::dual, 40),
                    Catch::Matchers::Contains("exceeds the critical load") && Catch::Matchers::Contains("primal"));
}

TEST_CASE("the tangent check reads the inertia on the contact set", "[contact][axial]") {
  const double length = 1.0, ei = 1.0, k = 1000.0;
  scene::Scene s = test::beam_scene(length, ei, EndSupport::pinned, EndSupport::pinned, k);
  // Between the strut's Euler load pi^2 and the first bilateral critical load pi^2 + k/pi^2.
  s.loads = {axial_load(3.0 * pi * pi)};
  const model::MemberModel model = model::make_member_model(s);
  const fe::Discretisation d = fe::discretise(model, 40);
  CHECK_FALSE(contact::is_positive_definite(d.stiffness));
  const contact::StabilityCheck all = contact::check_tangent(d, std::vector<bool>(d.reactions(), true));
  CHECK(all.positive_definite);
  const contact::StabilityCheck none = contact::check_tangent(d, std::vector<bool>(d.reactions(), false));
  CHECK_FALSE(none.positive_definite);
  CHECK(none.negative_eigenvalues == 1);  // 3 pi^2 is below the second Euler load 4 pi^2
  CHECK_THAT(none.message, Catch::Matchers::Contains("1 negative eigenvalue"));
}

TEST_CASE("an initial shape without an axial force changes nothing", "[contact][axial]") {
  scene::Scene s = test::beam_scene(1.0, 1.0, EndSupport::pinned, EndSupport::free, 500.0);
  s.loads = {test::uniform_load(0.0, 1.0, 1.0), test::point_force(0.9, -0.3)};
  const test::Solved straight = test::solve(s, Method::fast, 50);
  s.initial_shape = half_sine(1.0, 0.05);
  const test::Solved imperfect = test::solve(s, Method::fast, 50);
  CAPTURE(straight.solution.summary.message);
  REQUIRE(straight.solution.summary.is_usable());
  REQUIRE(imperfect.solution.summary.is_usable());
  CHECK(imperfect.solution.displacement == straight.solution.displacement);  // identical, not close
  CHECK(imperfect.solution.reaction == straight.solution.reaction);
}
