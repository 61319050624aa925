// The fixed-contact-set system: with the contact set Lemke found, one sparse solve reproduces
// Lemke's answer; with every node in contact it is the bilateral foundation.

#include "contact/active_set_system.hpp"

#include <catch2/catch.hpp>

#include "closed_form/beam_on_foundation.hpp"
#include "model/from_scene.hpp"
#include "support/scenes.hpp"
#include "support/solve.hpp"

using namespace liftoff;

namespace {

std::vector<bool> contact_set_of(const contact::ContactSolution& s) {
  std::vector<bool> in_contact(s.reaction.size());
  for (Eigen::Index i = 0; i < s.reaction.size(); ++i) in_contact[i] = s.reaction[i] > 0.0;
  return in_contact;
}

}  // namespace

TEST_CASE("the contact set found by Lemke gives Lemke's answer in one sparse solve") {
  for (const char* name : {"seed_beam_end_moments", "seed_beam_end_moments_central_load", "seed_arch_pinned",
                           "seed_arch_roller", "seed_arch_clamped"}) {
    CAPTURE(name);
    const auto lemke = test::solve(test::shipped_scene(name), contact::Method::dual, 80);
    contact::ActiveSetSystem system(lemke.discretisation);
    REQUIRE(system.factorise(contact_set_of(lemke.solution)));
    const auto state = system.solve(lemke.discretisation.load(1.0));
    CHECK(state.residual < 1e-12);
    CHECK(test::relative_difference(lemke.discretisation.expand(state.displacement), lemke.solution.displacement) <
          1e-8);
    // The complement of the contact set has a non-negative gap: the answer is a contact solution.
    CHECK(state.gap.minCoeff() > -1e-10 * state.gap.cwiseAbs().maxCoeff());
  }
}

TEST_CASE("a free-free beam is held by its contact set, and left floating without one") {
  auto scene = test::beam_scene(10.0, 1.0, scene::EndSupport::free, scene::EndSupport::free, 100.0);
  scene.loads.push_back(test::uniform_load(0.0, 10.0, 1.0));
  const auto model = model::make_member_model(scene);
  const auto d = fe::discretise(model, 40);
  contact::ActiveSetSystem system(d);
  REQUIRE(system.factorise(std::vector<bool>(d.reactions(), true)));
  const auto state = system.solve(d.load(1.0));
  // Uniform load on a free-free beam in full contact: uniform settlement q/K, no bending.
  const double settlement = 1.0 / (100.0 / std::pow(10.0, 4)) / 10.0;  // q/K in units of L
  for (int node = 0; node < static_cast<int>(d.mesh.nodes.size()); ++node)
    CHECK(state.displacement[d.equation_of_dof[d.deflection_dof(node)]] == Approx(settlement).epsilon(1e-10));
  std::vector<bool> one_node(d.reactions(), false);
  one_node[d.reactions() / 2] = true;  // one spring cannot hold a beam against rotation
  CHECK_FALSE(system.factorise(one_node));
  CHECK_FALSE(system.factorise(std::vector<bool>(d.reactions(), false)));
}

TEST_CASE("the mixed form solves fine meshes to round-off: bilateral seed beam against Hetenyi's closed form",
          "[contact][round-off]") {
  auto s = test::shipped_scene("seed_beam_end_moments");
  s.foundation.tensionless = false;
  const model::MemberModel model = model::make_member_model(s);
  closed_form::BeamProblem p;
  p.foundation_modulus = model.k;
  p.left = p.right = closed_form::EndCondition::pinned;
  for (const auto& l : model.loads) p.moments.push_back({l.at, l.value});
  const auto exact = closed_form::solve_bilateral(p);
  auto nodal_error = [&](int n) {
    const fe::Discretisation d = fe::discretise(model, n);
    contact::ActiveSetSystem system(d);
    REQUIRE(system.factorise(std::vector<bool>(d.reactions(), true)));
    const auto state = system.solve(d.load(1.0));
    const Eigen::VectorXd all = d.expand(state.displacement);
    double error = 0.0, scale = 0.0;
    for (int node = 0; node <= n; ++node) {
      error = std::max(error, std::abs(all[d.deflection_dof(node)] - exact.deflection(d.mesh.nodes[node])));
      scale = std::max(scale, std::abs(exact.deflection(d.mesh.nodes[node])));
    }
    return std::pair{error / scale, system.data_error(state, d.load(1.0))};
  };
  // Discretisation error ~ C h^4, C from 100 elements (8.7e-8 there); the rest is round-off,
  // bounded by the mixed system's own Skeel estimate (data_error, a worst case). The K form of
  // the same equations was off by 2.7e-9 at 1e4 and 8e-8 at 3e4 elements (eps cond(K) ~ N^4),
  // this one by 1.2e-15 at both (verification/bench/accuracy_bench.cpp roundoff).
  const double c = nodal_error(100).first * std::pow(100.0, 4);
  for (int n : {10000, 30000}) {
    const auto [error, round_off] = nodal_error(n);
    CAPTURE(n, error, round_off);
    CHECK(error <= c * std::pow(n, -4.0) + 10.0 * round_off);
    CHECK(round_off < 1e-11);  // eps N^2 would be 2e-7 at 3e4: the bound is far below it
    CHECK(error < 1e-13);
  }
}

TEST_CASE("a system reassembled on its discretisation, discretised again, is the system built on it afresh") {
  const model::MemberModel model = model::make_member_model(test::shipped_scene("seed_beam_end_moments_central_load"));
  fe::Discretisation d = fe::discretise(model, 60);
  contact::ActiveSetSystem reused(d);
  REQUIRE(reused.factorise(std::vector<bool>(d.reactions(), true)));
  reused.solve(d.load(1.0));
  // Another mesh (other sizes) and another set: the same object, assembled again.
  for (int elements : {90, 60}) {
    CAPTURE(elements);
    d = fe::discretise(model, elements);
    reused.reassemble();
    std::vector<bool> in_contact(d.reactions(), true);
    for (int i = 0; i < d.reactions() / 4; ++i) in_contact[i] = false;
    contact::ActiveSetSystem fresh(d);
    REQUIRE(fresh.factorise(in_contact));
    REQUIRE(reused.factorise(in_contact));
    CHECK(reused.size() == fresh.size());
    const auto a = reused.solve(d.load(1.0)), b = fresh.solve(d.load(1.0));
    // The same data and the same operations: identical answers, bit for bit.
    CHECK(a.displacement == b.displacement);
    CHECK(a.reaction == b.reaction);
  }
}
