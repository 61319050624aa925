// The circular arch under von Karman theory with the foundation (contact/von_karman_solve.hpp,
// arches): the linear arch as the small-load limit, the von Karman beam on the circle segment
// through the same contact solve, tensionless = bilateral below lift-off, the crown deflection's
// order of convergence in h.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <vector>

#include "contact/contact_solver.hpp"
#include "contact/von_karman_solve.hpp"
#include "fe/discretisation.hpp"
#include "model/from_scene.hpp"
#include "post/contact_regions.hpp"
#include "support/scenes.hpp"
#include "support/solve.hpp"

using namespace liftoff;
using contact::VonKarmanOptions;
using contact::VonKarmanResult;
using contact::VonKarmanSystem;
using Eigen::VectorXd;

namespace {

constexpr double degrees = 180.0 / 3.14159265358979323846;

// The seed's arch (R/h = 500, 10 degrees, k = 1e6, crown load) under von Karman theory.
model::MemberModel seed_arch(const std::string& ends) {
  model::MemberModel m = model::make_member_model(test::shipped_scene("seed_arch_" + ends));
  m.theory = model::Theory::von_karman;
  return m;
}

double crown(const fe::Discretisation& d, const VectorXd& every_dof) {
  return every_dof[d.deflection_dof(static_cast<int>(d.mesh.nodes.size()) / 2)];
}

VectorXd every_dof(const fe::Discretisation& d, const VonKarmanResult& r) {
  return d.expand_displacement(r.x.head(d.equations));
}

// The half-angle (degrees) of the contact region around the crown.
double half_angle(const model::MemberModel& m, const fe::Discretisation& d, const VectorXd& displacement) {
  for (const ContactRegion& r : post::contact_regions(m, d, displacement))
    if (r.begin <= 0.0 && r.end >= 0.0) return 0.5 * (r.end - r.begin) * degrees;
  return 0.0;
}

}  // namespace

TEST_CASE("arch von Karman solve: small loads reproduce the linear arch (`fast`) to O(load^2)",
          "[contact][von_karman][arch]") {
  // Relative departure = a lambda + b lambda^2 + ...: over lambda, lambda / 2, lambda / 4 the
  // observed order of the absolute departure, 1 + log2(d(lambda) / d(lambda / 2)), tends to 2 with
  // an error ~ (b / a) lambda / 2 that halves with lambda; the check asks the finer pair's order
  // within 0.05 of 2 and closer than the coarser pair's.
  const std::string ends = GENERATE("pinned", "clamped");
  const model::MemberModel m = seed_arch(ends);
  const fe::Discretisation d = fe::discretise(m, 100);
  const VonKarmanSystem system(m, d);
  std::vector<double> departure;
  for (double lambda : {4e-3, 2e-3, 1e-3}) {
    contact::ContactOptions options;
    options.method = contact::Method::fast;
    options.load_factor = lambda;
    const contact::ContactSolution linear = contact::solve_contact(d, options);
    REQUIRE(linear.summary.is_usable());
    const VonKarmanResult r = system.solve(lambda, VonKarmanOptions{});
    CAPTURE(ends, lambda, r.message);
    REQUIRE(r.is_usable());
    CHECK(r.stable);
    departure.push_back(std::abs(crown(d, every_dof(d, r)) / crown(d, linear.displacement) - 1.0));
  }
  const double coarse = 1.0 + std::log2(departure[0] / departure[1]),
               fine = 1.0 + std::log2(departure[1] / departure[2]);
  CAPTURE(departure, coarse, fine);
  CHECK(departure[0] < 0.01);
  CHECK(std::abs(fine - 2.0) < 0.05);
  CHECK(std::abs(fine - 2.0) < std::abs(coarse - 2.0));
}

TEST_CASE(
    "arch von Karman solve: the seed's pinned arch meets the von Karman beam on its circle segment within "
    "O((rise / span)^2), contact included",
    "[contact][von_karman][arch]") {
  // The seed's arch is shallow: rise / span = (1 - cos 10 deg) / (2 sin 10 deg) = 0.044. The von
  // Karman beam on the chord L = 2 sin(alpha) (units: L), with the initial shape of the circle
  // (w0 = -(height above the chord) / L, a table of 20001 points: its chords' slopes err by
  // O(1e-4^2) in the element integrals), the foundation following it, k L^4, EA R^2/EI L^2, the
  // load P L^2, pinned and axially restrained ends (the arch's pinned u = w = 0). The theories
  // differ by the shallow approximation (directions, arc length against chord, u in the rotation):
  // relative order 16 (rise / span)^2 = 0.031. The linear arch is further off than that at the
  // seed's load (its crown deflection departs by 14 %): this checks that the difference is the
  // geometric nonlinearity, through an independent element and the same contact solve.
  const model::MemberModel arch = seed_arch("pinned");
  const double alpha = arch.s_end, chord = 2.0 * std::sin(alpha), rise = 1.0 - std::cos(alpha);
  const int n = 200;
  const fe::Discretisation da = fe::discretise(arch, n);
  const VonKarmanResult ra = VonKarmanSystem(arch, da).solve(1.0, VonKarmanOptions{});
  REQUIRE(ra.is_usable());

  model::MemberModel beam;
  beam.kind = model::StructureKind::beam;
  beam.theory = model::Theory::von_karman;
  beam.membrane_stiffness = arch.membrane_stiffness * chord * chord;
  beam.k = arch.k * std::pow(chord, 4);
  beam.tensionless = true;
  for (int i = 0; i <= 20000; ++i) {
    const double s = i / 20000.0, x = (s - 0.5) * chord;
    beam.initial_shape_at.push_back(s);
    beam.initial_shape_value.push_back(-(std::sqrt(1.0 - x * x) - std::cos(alpha)) / chord);
  }
  REQUIRE(arch.loads.size() == 1);
  model::MemberLoad force = arch.loads[0];
  force.at = 0.5;
  force.value = arch.loads[0].value * chord * chord;
  beam.loads = {force};
  const fe::Discretisation db = fe::discretise(beam, n);
  const VonKarmanResult rb = VonKarmanSystem(beam, db).solve(1.0, VonKarmanOptions{});
  REQUIRE(rb.is_usable());

  const double w_arch = crown(da, every_dof(da, ra)), w_beam = crown(db, every_dof(db, rb)) * chord;
  const double phi_arch = half_angle(arch, da, every_dof(da, ra));
  double phi_beam = 0.0;
  for (const ContactRegion& r : post::contact_regions(beam, db, every_dof(db, rb)))
    if (r.begin <= 0.5 && r.end >= 0.5) phi_beam = std::asin((r.end - 0.5) * chord) * degrees;
  contact::ContactOptions options;
  options.method = contact::Method::fast;
  model::MemberModel linear_arch = arch;
  linear_arch.theory = model::Theory::linear;
  const contact::ContactSolution linear = contact::solve_contact(fe::discretise(linear_arch, n), options);
  const double w_linear = crown(da, linear.displacement);
  const double bound = 16.0 * std::pow(rise / chord, 2);
  CAPTURE(w_arch, w_beam, w_linear, phi_arch, phi_beam, bound);
  CHECK(std::abs(w_arch / w_beam - 1.0) < bound);
  CHECK(std::abs(phi_arch / phi_beam - 1.0) < bound);
  CHECK(std::abs(w_linear / w_beam - 1.0) > 3.0 * std::abs(w_arch / w_beam - 1.0));
}

TEST_CASE("arch von Karman solve: tensionless is bilateral below lift-off, and differs beyond it",
          "[contact][von_karman][arch]") {
  // The seed's pinned arch under a dead uniform radial pressure into the foundation and a live
  // crown force pulling away from it (lambda = 1: the seed's P): below lift-off (lambda = 0.005)
  // every node is in contact and the tensionless answer is the bilateral one (to the solves'
  // round-off); a larger pull (lambda = 0.1) lifts the crown.
  model::MemberModel tensionless = seed_arch("pinned");
  model::MemberLoad pressure;
  pressure.kind = model::LoadKind::uniform;
  pressure.from = tensionless.s_begin;
  pressure.to = tensionless.s_end;
  pressure.value = 1e3;
  pressure.load_case = model::LoadCase::dead;
  tensionless.loads[0].value = -tensionless.loads[0].value;  // away from the foundation
  tensionless.loads.push_back(pressure);
  model::MemberModel bilateral = tensionless;
  bilateral.tensionless = false;
  const fe::Discretisation dt = fe::discretise(tensionless, 100), db = fe::discretise(bilateral, 100);
  const VonKarmanSystem st(tensionless, dt), sb(bilateral, db);
  const VonKarmanResult small_t = st.solve(0.005, VonKarmanOptions{}), small_b = sb.solve(0.005, VonKarmanOptions{});
  REQUIRE(small_t.is_usable());
  REQUIRE(small_b.is_usable());
  CHECK(std::all_of(small_t.in_contact.begin(), small_t.in_contact.end(), [](bool c) { return c; }));
  CHECK(test::relative_difference(small_t.x, small_b.x) < 1e-10);
  const VonKarmanResult large_t = st.solve(0.1, VonKarmanOptions{}), large_b = sb.solve(0.1, VonKarmanOptions{});
  REQUIRE(large_t.is_usable());
  REQUIRE(large_b.is_usable());
  CHECK(std::count(large_t.in_contact.begin(), large_t.in_contact.end(), false) >= 1);
  CHECK(test::relative_difference(large_t.x, large_b.x) > 1e-3);
  CHECK(large_t.w[50] < 0.0);  // the crown lifted
}

TEST_CASE("arch von Karman solve: the seed arch's crown deflection converges in h at order 2",
          "[contact][von_karman][arch]") {
  // The crown load's kink and the P1 reactions across the moving contact limit give h^2, as for
  // the linear arch (seed_arch_test); a locking element would converge far slower on R/h = 500.
  const std::string ends = GENERATE("pinned", "clamped");
  const model::MemberModel m = seed_arch(ends);
  auto solve = [&](int n) {
    const fe::Discretisation d = fe::discretise(m, n);
    const VonKarmanResult r = VonKarmanSystem(m, d).solve(1.0, VonKarmanOptions{});
    CAPTURE(n, r.message);
    REQUIRE(r.is_usable());
    return crown(d, every_dof(d, r));
  };
  // Against 1600 elements (the refined Newton direction reaches 2000 on this arch; the error
  // estimate there is ~1e-8); the crown is a node on every mesh.
  const double reference = solve(1600);
  std::vector<double> crowns, h, error;
  for (int n : {25, 50, 100, 200, 400}) {
    crowns.push_back(solve(n));
    h.push_back(1.0 / n);
    error.push_back(std::abs(crowns.back() - reference));
  }
  const double order = test::observed_order(h, error);
  CAPTURE(ends, reference, crowns, error, order);
  std::printf("%s: crown error against 1600 elements %.2e %.2e %.2e %.2e %.2e, order %.2f\n", ends.c_str(), error[0],
              error[1], error[2], error[3], error[4], order);
  CHECK(order >= 1.8);
}
