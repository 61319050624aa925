// Mesh breakpoints, and the analysis of rigid motions the supports leave free.
#include "fe/discretisation.hpp"

#include <catch2/catch.hpp>

#include "core/error.hpp"
#include "fe/mesh.hpp"
#include "support/scenes.hpp"

using namespace liftoff;
using scene::EndSupport;

TEST_CASE("the mesh has a node at every load, support and foundation end", "[fe][mesh]") {
  scene::Scene s = test::beam_scene(2.0, 1.0, EndSupport::pinned, EndSupport::free, 1e3);
  s.foundation.from = 0.3;
  s.supports.interior = {1.1};
  s.loads = {test::point_force(0.77, 1.0), test::uniform_load(1.5, 1.9, 1.0)};
  const fe::MemberModel model = fe::make_member_model(s);
  const fe::Mesh mesh = fe::make_mesh(model, 20);
  CHECK(mesh.elements() == 20);
  for (double x : {0.0, 0.3, 0.77, 1.1, 1.5, 1.9, 2.0}) {
    CAPTURE(x);
    CHECK(mesh.node_at(model.s_from_user(x)) >= 0);
  }
  // A uniform request stays uniform when the breakpoints fall on it.
  const fe::Mesh uniform =
      fe::make_mesh(fe::make_member_model(test::beam_scene(1.0, 1.0, EndSupport::pinned, EndSupport::pinned, 1.0)), 8);
  for (int e = 0; e < 8; ++e) CHECK(uniform.element_size(e) == Approx(0.125).epsilon(1e-14));
  // Fewer elements than segments: one per segment.
  CHECK(fe::make_mesh(model, 1).elements() == 6);
  // Every element of a segment has the same stored size, bit for bit (identical element
  // matrices), and the sizes add up to the segment's length to round-off.
  const std::vector<double> points = fe::mesh_breakpoints(model);
  for (std::size_t i = 0; i + 1 < points.size(); ++i) {
    const int first = mesh.node_at(points[i]), last = mesh.node_at(points[i + 1]);
    double sum = 0.0;
    for (int e = first; e < last; ++e) {
      CHECK(mesh.element_size(e) == mesh.element_size(first));
      sum += mesh.element_size(e);
    }
    CHECK(sum == Approx(points[i + 1] - points[i]).epsilon(1e-14));
  }
}

TEST_CASE("a foundation on chosen elements: reaction nodes are those elements' nodes", "[fe][mesh]") {
  scene::Scene s = test::beam_scene(1.0, 1.0, EndSupport::pinned, EndSupport::pinned, 1e3);
  s.loads = {test::point_force(0.5, 1.0)};
  const fe::MemberModel model = fe::make_member_model(s);
  const fe::Mesh mesh = fe::make_mesh(model, 10);
  std::vector<bool> foundation(10, false);
  for (int e : {2, 3, 7}) foundation[e] = true;
  const fe::Discretisation d = fe::discretise(model, mesh, foundation);
  CHECK(d.reaction_nodes == std::vector<int>{2, 3, 4, 7, 8});
  // The foundation's flexibility is that of three elements: T sums to 3 h / k.
  CHECK(Eigen::MatrixXd(d.flexibility).sum() == Approx(3 * 0.1 / model.foundation_modulus).epsilon(1e-12));
  // The mixed form carries K exactly: G^T H^-1 G = K to round-off.
  const Eigen::MatrixXd g(d.stress_coupling);
  const Eigen::MatrixXd k = g.transpose() * d.compliance.cwiseInverse().asDiagonal() * g;
  CHECK((k - Eigen::MatrixXd(d.stiffness)).norm() <= 1e-12 * Eigen::MatrixXd(d.stiffness).norm());
}

TEST_CASE("rigid motions: which structures need the foundation to stand", "[fe][stability]") {
  auto unstable = [](EndSupport left, EndSupport right, std::vector<double> interior = {}) {
    scene::Scene s = test::beam_scene(1.0, 1.0, left, right, 1e3);
    s.supports.interior = std::move(interior);
    s.loads = {test::point_force(0.5, 1.0)};
    return fe::discretise(fe::make_member_model(s), 10).unstable_rigid_motions;
  };
  CHECK(unstable(EndSupport::free, EndSupport::free) == 2);
  CHECK(unstable(EndSupport::pinned, EndSupport::free) == 1);
  CHECK(unstable(EndSupport::clamped, EndSupport::free) == 0);
  CHECK(unstable(EndSupport::pinned, EndSupport::pinned) == 0);
  CHECK(unstable(EndSupport::free, EndSupport::free, {0.3, 0.7}) == 0);
  CHECK(unstable(EndSupport::free, EndSupport::free, {0.3}) == 1);

  // Arches: pinned and clamped ends are stable; rollers leave the rotation about the centre,
  // which nothing resists and which is gauged; free ends leave two motions the foundation sees.
  auto arch = [](EndSupport ends) {
    scene::Scene s = test::shipped_scene("seed_arch_pinned");
    s.supports.left = s.supports.right = ends;
    return fe::discretise(fe::make_member_model(s), 20);
  };
  CHECK(arch(EndSupport::pinned).unstable_rigid_motions == 0);
  CHECK(arch(EndSupport::clamped).unstable_rigid_motions == 0);
  CHECK(arch(EndSupport::pinned).gauge_note.empty());
  const fe::Discretisation rollers = arch(EndSupport::roller);
  CHECK(rollers.unstable_rigid_motions == 0);
  CHECK_FALSE(rollers.gauge_note.empty());
  const fe::Discretisation free_ends = arch(EndSupport::free);
  CHECK(free_ends.unstable_rigid_motions == 2);
  CHECK_FALSE(free_ends.gauge_note.empty());
}
