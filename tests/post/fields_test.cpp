// Fields along the member against the closed-form beam, and contact limits located inside
// elements rather than at nodes.
#include "post/fields.hpp"

#include <catch2/catch.hpp>
#include <cstdio>

#include "closed_form/beam_on_foundation.hpp"
#include "post/contact_regions.hpp"
#include "support/scenes.hpp"
#include "support/solve.hpp"

using namespace liftoff;
using contact::Method;
using scene::EndSupport;

TEST_CASE("moment, shear, rotation and reaction converge to the closed-form beam", "[post]") {
  // Bilateral clamped-free beam, beta L = 4, a point force and a uniform load.
  const double k = 4 * std::pow(4.0, 4);
  scene::Scene s = test::beam_scene(1.0, 1.0, EndSupport::clamped, EndSupport::free, k, false);
  s.loads = {test::point_force(0.7, 1.0), test::uniform_load(0.0, 0.4, 3.0)};
  closed_form::BeamProblem p;
  p.foundation_modulus = k;
  p.left = closed_form::EndCondition::clamped;
  p.right = closed_form::EndCondition::free;
  p.forces = {{0.7, 1.0}};
  p.uniform_loads = {{0.0, 0.4, 3.0}};
  const auto reference = closed_form::solve_bilateral(p);

  struct Errors {
    double moment = 0, shear = 0, rotation = 0, reaction = 0;
  };
  auto errors_at = [&](int n) {
    const test::Solved fe = test::solve(s, Method::dual, n);
    const post::Fields f = post::sample_fields(fe.model, fe.discretisation, fe.solution, 4);
    Errors e;
    for (std::size_t i = 0; i < f.s.size(); ++i) {
      const double x = f.s[i];
      // Sample interior points only: M and V jump at the load, rotation and reaction do not.
      if (std::abs(x - 0.7) < 1e-9 || x == 0.0 || x == 1.0) continue;
      e.moment = std::max(e.moment, std::abs(f.bending_moment[i] - reference.bending_moment(x)));
      e.shear = std::max(e.shear, std::abs(f.shear_force[i] - reference.shear_force(x)));
      e.rotation = std::max(e.rotation, std::abs(f.rotation[i] + reference.slope(x)));
      e.reaction = std::max(e.reaction, std::abs(f.reaction[i] - reference.reaction(x)));
    }
    return e;
  };
  const Errors coarse = errors_at(20), fine = errors_at(80);
  std::printf(
      "field errors 20 -> 80 elements: moment %.1e -> %.1e, shear %.1e -> %.1e, rotation %.1e -> %.1e, reaction %.1e "
      "-> %.1e\n",
      coarse.moment, fine.moment, coarse.shear, fine.shear, coarse.rotation, fine.rotation, coarse.reaction,
      fine.reaction);
  // Expected orders for cubic elements: rotation h^3, moment h^2, shear h^1, and h^2 for the
  // linear reaction. Four times finer must gain at least 4^order / 2 on each.
  CAPTURE(coarse.moment, fine.moment, coarse.shear, fine.shear, coarse.rotation, fine.rotation, coarse.reaction,
          fine.reaction);
  CHECK(fine.rotation < coarse.rotation / 32);
  CHECK(fine.moment < coarse.moment / 8);
  CHECK(fine.shear < coarse.shear / 2);
  CHECK(fine.reaction < coarse.reaction / 8);
}

TEST_CASE("contact limits lie inside elements, at roots of the deflection", "[post]") {
  const scene::Scene s = test::shipped_scene("seed_beam_end_moments_central_load");
  const test::Solved fe = test::solve(s, Method::dual, 30);
  REQUIRE(fe.regions.size() == 2);
  const double limit = fe.regions[0].end;
  const int e = fe.discretisation.mesh.element_containing(limit);
  const double h = fe.discretisation.mesh.element_size(e), xi = (limit - fe.discretisation.mesh.nodes[e]) / h;
  CAPTURE(limit, xi);
  CHECK(xi > 1e-6);  // not snapped to a node
  CHECK(xi < 1 - 1e-6);
  const double w_scale = fe.solution.displacement.lpNorm<Eigen::Infinity>();
  CHECK(std::abs(post::evaluate(fe.discretisation, fe.solution.displacement, e, xi).w) < 1e-12 * w_scale);
  // Every node carrying a reaction lies in a contact region.
  for (int i = 0; i < fe.discretisation.reactions(); ++i) {
    if (fe.solution.reaction[i] <= 0) continue;
    const double node = fe.discretisation.mesh.nodes[fe.discretisation.reaction_nodes[i]];
    bool inside = false;
    for (const auto& r : fe.regions) inside |= node >= r.begin - 1e-12 && node <= r.end + 1e-12;
    CHECK(inside);
  }
}

TEST_CASE("a foundation on part of the member and interior point supports", "[post][fe]") {
  scene::Scene s = test::beam_scene(1.0, 1.0, EndSupport::free, EndSupport::free, 1e4);
  s.foundation.from = 0.2;
  s.foundation.to = 0.9;
  s.supports.interior = {0.1};
  s.loads = {test::point_force(0.5, 1.0), test::point_force(0.95, 0.5)};
  const test::Solved fe = test::solve(s, Method::automatic, 50);
  REQUIRE(fe.solution.summary.is_usable());
  const int support = fe.discretisation.mesh.node_at(0.1);
  REQUIRE(support >= 0);
  CHECK(fe.solution.displacement[fe.discretisation.deflection_dof(support)] == 0.0);
  REQUIRE_FALSE(fe.regions.empty());
  for (const auto& r : fe.regions) {
    CHECK(r.begin >= 0.2 - 1e-12);
    CHECK(r.end <= 0.9 + 1e-12);
  }
  const post::Fields f = post::sample_fields(fe.model, fe.discretisation, fe.solution, 4);
  for (std::size_t i = 0; i < f.s.size(); ++i)
    if (f.s[i] < 0.2 || f.s[i] > 0.9) CHECK(f.reaction[i] == 0.0);
}

TEST_CASE("where the reaction jumps the diagram has both values at one s", "[post][jump]") {
  // The footing on two soils (clay 2e7, sand 8e7 N/m^2 meeting at x = 1.5 m inside the contact
  // region), 60 elements: the sampled reaction repeats s = 1.5 m with the clay's value then the
  // sand's, the two nodal reactions there; every other s is sampled once, in order.
  const test::Solved fe = test::solve(test::shipped_scene("engineering/footing_two_soils"), Method::fast, 60);
  REQUIRE(fe.solution.summary.is_usable());
  const fe::Discretisation& d = fe.discretisation;
  const post::Fields f = post::sample_fields(fe.model, d, fe.solution, 4);
  const double jump = fe.model.s_from_user(1.5);
  const int node = d.mesh.node_at(jump);
  REQUIRE(node >= 0);
  REQUIRE(f.s.size() == static_cast<std::size_t>(4 * d.mesh.elements() + 2));
  int repeats = 0;
  for (std::size_t i = 1; i < f.s.size(); ++i) {
    CHECK(f.s[i] >= f.s[i - 1]);
    if (f.s[i] != f.s[i - 1]) continue;
    ++repeats;
    CHECK(f.s[i] == d.mesh.nodes[node]);
    CHECK(f.reaction[i - 1] == fe.solution.reaction[d.element_reactions(node - 1)[1]]);
    CHECK(f.reaction[i] == fe.solution.reaction[d.element_reactions(node)[0]]);
    CHECK(f.w[i] == f.w[i - 1]);                     // the same point of the member
    CHECK(f.reaction[i] > 3.0 * f.reaction[i - 1]);  // the sand's k is 4 times the clay's, w the same
  }
  CHECK(repeats == 1);
}
