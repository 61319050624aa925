// liftoff against the classical results for beams on a tensionless foundation
// (beta = (K/4EI)^(1/4)), with tolerances from each method's own error estimate.
#include <catch2/catch.hpp>
#include <cstdio>

#include "app/solve_command.hpp"
#include "support/scenes.hpp"

using namespace liftoff;
using scene::EndSupport;
using scene::Method;

namespace {

constexpr double pi = 3.14159265358979323846;

// A free-free unit beam (EI = 1) with beta L given: k = K L^4/EI = 4 (beta L)^4.
scene::Scene free_beam(double beta_l) {
  return test::beam_scene(1.0, 1.0, EndSupport::free, EndSupport::free, 4 * std::pow(beta_l, 4));
}

io::SolveReport solve(const scene::Scene& s, Method method, int elements, std::optional<int> modes = {}) {
  app::SolveRequest request;
  request.method = method;
  request.elements = elements;
  request.modes = modes;
  const io::SolveReport r = app::solve_scene(s, request);
  REQUIRE(r.usable);
  return r;
}

double contact_length(const io::SolveReport& r) {
  double length = 0.0;
  for (const auto& region : r.contact_regions) length += region.length();
  return length;
}

// The FE value on 2n elements and its error estimate from n and 2n elements (limits converge
// at h^2: the error of the finer is about a third of the difference).
struct Estimate {
  double value, error;
};
template <typename Quantity>
Estimate fe_estimate(const scene::Scene& s, int n, Quantity quantity) {
  const double coarse = quantity(solve(s, Method::primal, n)), fine = quantity(solve(s, Method::primal, 2 * n));
  return {fine, std::abs(fine - coarse) / 3.0};
}

}  // namespace

TEST_CASE("classical: a free-free beam under a central load stays in full contact iff beta L <= pi",
          "[verification][classical]") {
  for (double beta_l : {2.5, 3.1}) {
    scene::Scene s = free_beam(beta_l);
    s.loads = {test::point_force(0.5, 1.0)};
    const io::SolveReport r = solve(s, Method::primal, 60);
    CAPTURE(beta_l);
    REQUIRE(r.contact_regions.size() == 1);
    CHECK(r.contact_regions[0].begin == 0.0);
    CHECK(r.contact_regions[0].end == 1.0);
  }
  // Beyond pi the contact length is pi / beta, whatever the load.
  for (double beta_l : {6.0, 10.0})
    for (double load : {1.0, 250.0}) {
      scene::Scene s = free_beam(beta_l);
      s.loads = {test::point_force(0.5, load)};
      const Estimate fe = fe_estimate(s, 100, contact_length);
      const io::SolveReport ritz = solve(s, Method::ritz, 100);
      const double exact = pi / beta_l;
      std::printf(
          "free-free beta L = %4.1f, P = %5.1f: contact length FE %.8f (+- %.1e), Ritz %.8f (%d modes), "
          "exact pi/beta %.8f\n",
          beta_l, load, fe.value, fe.error, contact_length(ritz), ritz.modes, exact);
      CAPTURE(beta_l, load);
      CHECK(std::abs(fe.value - exact) <= 3 * fe.error + 1e-12);
      CHECK(std::abs(contact_length(ritz) - exact) <= 3 * ritz.estimated_limit_error + 1e-9);
    }
}

TEST_CASE("classical: a long beam under a point load loses contact at beta a = pi/2", "[verification][classical]") {
  // Not the 3 pi/4 of the bilateral solution's first zero.
  const double beta_l = 40.0;
  scene::Scene s = free_beam(beta_l);
  s.loads = {test::point_force(0.5, 1.0)};
  auto half_length_beta = [&](const io::SolveReport& r) { return contact_length(r) / 2 * beta_l; };
  const Estimate fe = fe_estimate(s, 100, half_length_beta);
  s.ritz.mode_tolerance = 1e-5;  // beta L = 40 needs many modes: settle to 1e-5 L (limit error estimate)
  const io::SolveReport ritz = solve(s, Method::ritz, 200);
  const double ritz_value = half_length_beta(ritz), ritz_error = ritz.estimated_limit_error * beta_l;
  std::printf("long beam: beta a = %.8f (FE, +- %.1e), %.8f (Ritz, %d modes, +- %.1e), pi/2 = %.8f\n", fe.value,
              fe.error, ritz_value, ritz.modes, ritz_error, pi / 2);
  CHECK(std::abs(fe.value - pi / 2) <= 3 * fe.error);
  CHECK(std::abs(ritz_value - pi / 2) <= 3 * ritz_error + 1e-9);
}

TEST_CASE("classical: weight plus a point load: lift-off starts at beta x = pi when P beta / q = 2 e^pi",
          "[verification][classical]") {
  const double beta_l = 40.0, beta = beta_l, q = 1.0;
  const double critical = 2 * std::exp(pi) * q / beta;
  for (double factor : {0.97, 1.03}) {
    scene::Scene s = free_beam(beta_l);
    s.loads = {test::uniform_load(0.0, 1.0, q, scene::LoadCase::dead), test::point_force(0.5, factor * critical)};
    for (Method m : {Method::primal, Method::ritz}) {
      const io::SolveReport r = solve(s, m, 200, 128);
      CAPTURE(factor, r.method);
      if (factor < 1) {
        CHECK(r.contact_regions.size() == 1);  // still in full contact
      } else {
        // Two lift-off zones open symmetrically, centred near beta |x - 1/2| = pi.
        REQUIRE(r.contact_regions.size() == 3);
        const double centre = 0.5 * (r.contact_regions[0].end + r.contact_regions[1].begin);
        CHECK(beta * std::abs(centre - 0.5) == Approx(pi).epsilon(0.02));
      }
    }
  }
}
