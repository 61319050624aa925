// Mesh breakpoints, and the analysis of rigid motions the supports leave free.
#include "fe/discretisation.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <limits>

#include "core/error.hpp"
#include "fe/mesh.hpp"
#include "model/from_scene.hpp"
#include "support/scenes.hpp"

using namespace liftoff;
using scene::EndSupport;

TEST_CASE("the mesh has a node at every load, support and foundation end", "[fe][mesh]") {
  scene::Scene s = test::beam_scene(2.0, 1.0, EndSupport::pinned, EndSupport::free, 1e3);
  s.foundation.from = 0.3;
  s.supports.interior = {1.1};
  s.loads = {test::point_force(0.77, 1.0), test::uniform_load(1.5, 1.9, 1.0)};
  const model::MemberModel model = model::make_member_model(s);
  const fe::Mesh mesh = fe::make_mesh(model, 20);
  CHECK(mesh.elements() == 20);
  for (double x : {0.0, 0.3, 0.77, 1.1, 1.5, 1.9, 2.0}) {
    CAPTURE(x);
    CHECK(mesh.node_at(model.s_from_user(x)) >= 0);
  }
  // A uniform request stays uniform when the breakpoints fall on it.
  const fe::Mesh uniform = fe::make_mesh(
      model::make_member_model(test::beam_scene(1.0, 1.0, EndSupport::pinned, EndSupport::pinned, 1.0)), 8);
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
  const model::MemberModel model = model::make_member_model(s);
  const fe::Mesh mesh = fe::make_mesh(model, 10);
  std::vector<bool> foundation(10, false);
  for (int e : {2, 3, 7}) foundation[e] = true;
  const fe::Discretisation d = fe::discretise(model, mesh, foundation);
  CHECK(d.reaction_nodes == std::vector<int>{2, 3, 4, 7, 8});
  // The foundation's flexibility is that of three elements: T sums to 3 h / k.
  CHECK(Eigen::MatrixXd(d.flexibility).sum() == Approx(3 * 0.1 / model.k).epsilon(1e-12));
  // The mixed form carries K exactly: G^T H^-1 G = K to round-off.
  const Eigen::MatrixXd g(d.stress_coupling);
  const Eigen::MatrixXd k = g.transpose() * d.compliance.cwiseInverse().asDiagonal() * g;
  CHECK((k - Eigen::MatrixXd(d.stiffness)).norm() <= 1e-12 * Eigen::MatrixXd(d.stiffness).norm());
}

namespace {

// An independent assembly: each element's matrices computed for it alone, summed by Eigen's
// setFromTriplets in element order (what discretise did before it computed them once per run of
// equal sizes and compressed the columns itself).
fe::SparseMatrix reference_matrix(int rows, int cols, const std::vector<Eigen::Triplet<double>>& triplets) {
  fe::SparseMatrix m(rows, cols);
  m.setFromTriplets(triplets.begin(), triplets.end());
  m.makeCompressed();
  return m;
}

void check_identical(const fe::SparseMatrix& a, const fe::SparseMatrix& b) {
  REQUIRE(a.rows() == b.rows());
  REQUIRE(a.cols() == b.cols());
  REQUIRE(a.nonZeros() == b.nonZeros());
  for (int c = 0; c <= a.cols(); ++c) REQUIRE(a.outerIndexPtr()[c] == b.outerIndexPtr()[c]);
  for (Eigen::Index p = 0; p < a.nonZeros(); ++p) {
    CAPTURE(p);
    REQUIRE(a.innerIndexPtr()[p] == b.innerIndexPtr()[p]);
    REQUIRE(a.valuePtr()[p] == b.valuePtr()[p]);  // bit for bit
  }
}

}  // namespace

TEST_CASE("K and C are the sums of per-element matrices in element order, bit for bit", "[fe][assembly]") {
  scene::Scene s = test::beam_scene(2.0, 1.0, EndSupport::pinned, EndSupport::free, 1e3);
  s.foundation.from = 0.3;
  s.loads = {test::point_force(0.77, 1.0)};  // segments of three different element sizes
  const model::MemberModel model = model::make_member_model(s);
  const fe::Mesh mesh = fe::make_mesh(model, 23);
  std::vector<bool> foundation(mesh.elements(), false);
  for (int e = 0; e < mesh.elements(); ++e)
    foundation[e] = mesh.nodes[e] + 0.5 * mesh.element_size(e) > model.foundation_begin && e % 5 != 2;
  const fe::Discretisation d = fe::discretise(model, mesh, foundation);
  const fe::StructuralElements elements = fe::structural_elements(model, d);
  std::vector<Eigen::Triplet<double>> k, c;
  for (int e = 0; e < mesh.elements(); ++e) {
    const auto* element = dynamic_cast<const fe::LinearElement*>(elements.elements[e].get());
    REQUIRE(element != nullptr);
    const std::vector<int>& dofs = elements.dofs[e];
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) {
        const int row = d.equation_of_dof[dofs[i]], col = d.equation_of_dof[dofs[j]];
        if (row >= 0 && col >= 0) k.emplace_back(row, col, element->stiffness()(i, j));
      }
    if (!d.foundation_on_element[e]) continue;
    const Eigen::Matrix<double, 2, 4> coupling = fe::foundation_element::coupling(mesh.element_size(e));
    const std::array<int, 2> r = d.element_reactions(e);
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 4; ++j)
        if (d.equation_of_dof[dofs[j]] >= 0) c.emplace_back(r[i], d.equation_of_dof[dofs[j]], coupling(i, j));
  }
  check_identical(d.stiffness, reference_matrix(d.equations, d.equations, k));
  check_identical(d.coupling, reference_matrix(d.reactions(), d.equations, c));
}

TEST_CASE("rigid motions: which structures need the foundation to stand", "[fe][stability]") {
  auto unstable = [](EndSupport left, EndSupport right, std::vector<double> interior = {}) {
    scene::Scene s = test::beam_scene(1.0, 1.0, left, right, 1e3);
    s.supports.interior = std::move(interior);
    s.loads = {test::point_force(0.5, 1.0)};
    return fe::discretise(model::make_member_model(s), 10).unstable_rigid_motions;
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
    return fe::discretise(model::make_member_model(s), 20);
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

TEST_CASE("the ground gap vector is the integral of Hb^T g, exact for a piecewise linear g", "[fe][issue12][gap]") {
  // L = 2 and a gap table with a step at x = 0.5 (a trench wall) and a point at 1.25.
  scene::Scene s = test::beam_scene(2.0, 1.0, EndSupport::pinned, EndSupport::pinned, 1e3);
  s.foundation.gap_at = {0.0, 0.5, 0.5, 1.25, 2.0};
  s.foundation.gap_value = {0.0, 1e-3, -1e-3, 3e-3, 3e-3};
  s.loads = {test::point_force(1.0, 1.0)};
  const model::MemberModel model = model::make_member_model(s);
  for (double x : {0.5, 1.25}) CHECK(fe::make_mesh(model, 7).node_at(model.s_from_user(x)) >= 0);
  const fe::Discretisation d = fe::discretise(model, 7);
  REQUIRE(d.ground_gap.size() == d.reactions());

  // By hand, in user units, piece by piece: int g dx and int g x dx of a linear g on [a, b] are
  // (b - a)(ga + gb)/2 and (b - a)/6 (ga (2a + b) + gb (a + 2b)). The reactions' shapes sum to
  // 1 and interpolate s exactly, so sum c_i = int g ds and sum c_i s_i = int g s ds, with
  // g/L and x/L the nondimensional g and s (c carries L^-2 and L^-3 against the user's).
  const double pieces[][4] = {{0.0, 0.5, 0.0, 1e-3}, {0.5, 1.25, -1e-3, 3e-3}, {1.25, 2.0, 3e-3, 3e-3}};
  double integral = 0.0, moment = 0.0;
  for (const auto& [a, b, ga, gb] : pieces) {
    integral += (b - a) * (ga + gb) / 2;
    moment += (b - a) / 6 * (ga * (2 * a + b) + gb * (a + 2 * b));
  }
  double sum = 0.0, first = 0.0;
  for (int i = 0; i < d.reactions(); ++i) {
    sum += d.ground_gap[i];
    first += d.ground_gap[i] * d.mesh.nodes[d.reaction_nodes[i]];
  }
  // Both are sums of a few terms of size ~1e-4: a relative round-off of a few eps.
  CHECK(sum == Approx(integral / 4.0).epsilon(1e-13));
  CHECK(first == Approx(moment / 8.0).epsilon(1e-13));

  // A uniform g is tested as C tests a uniform w: c = k T 1 g (T = int Hb^T Hb / k).
  s.foundation.gap_at = {1.0};
  s.foundation.gap_value = {2e-3};
  const model::MemberModel flat = model::make_member_model(s);
  const fe::Discretisation u = fe::discretise(flat, 9);
  const Eigen::VectorXd expected = flat.k * (u.flexibility * Eigen::VectorXd::Ones(u.reactions())) * (2e-3 / 2.0);
  CHECK((u.ground_gap - expected).lpNorm<Eigen::Infinity>() <= 1e-15 * expected.lpNorm<Eigen::Infinity>() * 10);
  // No gap: c = 0.
  s.foundation.gap_at.clear();
  s.foundation.gap_value.clear();
  CHECK(fe::discretise(model::make_member_model(s), 9).ground_gap.isZero(0.0));
}

TEST_CASE("two reactions at a node where k or the ground gap steps, one where neither does", "[fe][issue12][jump]") {
  // L = 1, EI = 1: k = 1000 on [0, 0.4], 4000 on [0.4, 0.7], 4000 on [0.7, 0.8] (no step at 0.7),
  // a void on [0.8, 0.9], 1000 on [0.9, 1]; the gap steps at 0.2 (and is continuous at 0.5).
  scene::Scene s = test::beam_scene(1.0, 1.0, EndSupport::free, EndSupport::free, 1.0);
  s.foundation.k.reset();
  s.foundation.segments = {{0.0, 0.4, 1000.0, std::nullopt},
                           {0.4, 0.7, 4000.0, std::nullopt},
                           {0.7, 0.8, 4000.0, std::nullopt},
                           {0.9, 1.0, 1000.0, std::nullopt}};
  s.foundation.gap_at = {0.2, 0.2, 0.5};
  s.foundation.gap_value = {0.0, 1e-3, 2e-3};
  s.loads = {test::point_force(0.5, 1.0)};
  const model::MemberModel model = model::make_member_model(s);
  CHECK(model.reaction_jumps() == std::vector<double>{0.2, 0.4});
  const fe::Discretisation d = fe::discretise(model, 20);  // h = 0.05: nodes 4 (0.2), 8 (0.4), 14, 16, 18
  const int step = d.mesh.node_at(0.2), soils = d.mesh.node_at(0.4);
  REQUIRE(step == 4);
  REQUIRE(soils == 8);
  // Nodes 0..16 and 18..20, with 4 and 8 twice: left reaction first, each element's own.
  std::vector<int> expected;
  for (int node = 0; node <= 20; ++node) {
    if (node == 17) continue;
    expected.push_back(node);
    if (node == step || node == soils) expected.push_back(node);
  }
  CHECK(d.reaction_nodes == expected);
  // Reactions 4, 5 at the step's node, 9, 10 at the soils' node.
  CHECK(d.element_reactions(3) == std::array<int, 2>{3, 4});
  CHECK(d.element_reactions(4) == std::array<int, 2>{5, 6});
  CHECK(d.element_reactions(7) == std::array<int, 2>{8, 9});
  CHECK(d.element_reactions(8) == std::array<int, 2>{10, 11});
  for (int i : {4, 5, 9, 10}) CHECK(d.reaction_is_split(i));
  CHECK_FALSE(d.reaction_is_split(3));
  CHECK_FALSE(d.reaction_is_split(6));
  // Each half takes its element's rows alone: T of one element end (h / (3 k), its side's k),
  // no coupling between the two halves, C the element's w-shape integral (h / 2 for a uniform w),
  // and c its side's gap (a uniform w of 1 - g: the left half sees g = 0, the right g = 1e-3).
  const Eigen::MatrixXd t(d.flexibility);
  const double h = 0.05;
  CHECK(t(9, 9) == Approx(h / 3.0 / 1000.0).epsilon(1e-14));
  CHECK(t(10, 10) == Approx(h / 3.0 / 4000.0).epsilon(1e-14));
  CHECK(t(9, 10) == 0.0);
  CHECK(t(8, 9) == Approx(h / 6.0 / 1000.0).epsilon(1e-14));
  CHECK(t(10, 11) == Approx(h / 6.0 / 4000.0).epsilon(1e-14));
  Eigen::VectorXd translation = Eigen::VectorXd::Zero(d.dofs());
  for (int node = 0; node <= 20; ++node) translation[d.deflection_dof(node)] = 1.0;
  Eigen::VectorXd on_equations(d.equations);
  for (int dof = 0; dof < d.dofs(); ++dof)
    if (d.equation_of_dof[dof] >= 0) on_equations[d.equation_of_dof[dof]] = translation[dof];
  const Eigen::VectorXd c_w = d.coupling * on_equations;
  for (int i : {4, 5, 9, 10}) CHECK(c_w[i] == Approx(h / 2.0).epsilon(1e-14));
  CHECK(c_w[3] == Approx(h).epsilon(1e-14));
  CHECK(d.ground_gap[4] == 0.0);
  // The right element of the step: g from 1e-3 at 0.2 to 1e-3 + 1e-3/6 at 0.25, by the half hat.
  CHECK(d.ground_gap[5] == Approx(h / 6.0 * (2 * 1e-3 + (1e-3 + 1e-3 / 6.0))).epsilon(1e-13));
  // A foundation on one side of a jump only (a limit-fitted solve's contact ending there): one.
  std::vector<bool> left_only(20, true);
  for (int e = 8; e < 20; ++e) left_only[e] = false;
  const fe::Discretisation fitted = fe::discretise(model, fe::make_mesh(model, 20), left_only);
  CHECK(fitted.reaction_nodes.back() == soils);
  CHECK(std::count(fitted.reaction_nodes.begin(), fitted.reaction_nodes.end(), soils) == 1);
}

namespace {
// A beam (or the seed arch) with elastic supports set in code: k_s, k_r nondimensional (L = EI = 1).
scene::Scene spring_beam(double left_k, double left_rotational, double interior_k) {
  scene::Scene s = test::beam_scene(1.0, 1.0, EndSupport::free, EndSupport::pinned, 1e3);
  s.supports.left_detail = {true, left_k, left_rotational, 0.0};
  if (interior_k > 0) s.supports.interior_springs.push_back({0.4, {true, interior_k, 0.0, 0.0}});
  s.loads = {test::point_force(0.5, 1.0)};
  return s;
}
}  // namespace

TEST_CASE("springs: one more stress each, so K = G^T H^-1 G still holds; K gains k a a^T", "[fe][springs]") {
  const fe::Discretisation plain = fe::discretise(model::make_member_model(spring_beam(0, 0, 0)), 10);
  scene::Scene arch_scene = test::shipped_scene("seed_arch_pinned");
  arch_scene.supports.left = EndSupport::free;
  arch_scene.supports.left_detail = {true, 30.0, 7.0, 0.0};
  for (const scene::Scene& s : {spring_beam(250.0, 40.0, 90.0), arch_scene}) {
    const fe::Discretisation d = fe::discretise(model::make_member_model(s), 10);
    const bool arch = d.kind == model::StructureKind::arch;
    // Beam: translational and rotational at the left, translational inside; arch: u, w and rotation.
    CHECK(d.springs.size() == 3u);
    CHECK(d.stresses() == d.element_stresses() + 3);
    const Eigen::MatrixXd g(d.stress_coupling);
    const Eigen::MatrixXd k = g.transpose() * d.compliance.cwiseInverse().asDiagonal() * g;
    CHECK((k - Eigen::MatrixXd(d.stiffness)).norm() <= 1e-12 * Eigen::MatrixXd(d.stiffness).norm());
    if (arch) continue;
    // Against the beam without springs, with the left end's w free in both (the same equations):
    // K - K_plain = k_s e_w e_w^T + k_r e_w' e_w'^T + k_i e_w(0.4) e_w(0.4)^T, exactly.
    REQUIRE(d.equations == plain.equations);
    Eigen::MatrixXd difference = Eigen::MatrixXd(d.stiffness) - Eigen::MatrixXd(plain.stiffness);
    const int w0 = d.equation_of_dof[d.deflection_dof(0)], slope0 = d.equation_of_dof[d.slope_dof(0)];
    const int w4 = d.equation_of_dof[d.deflection_dof(d.mesh.node_at(0.4))];
    // Exact but for the rounding of sums of K's entries (~12/h^3): a few ulps of the largest.
    const double round_off =
        64 * std::numeric_limits<double>::epsilon() * Eigen::MatrixXd(plain.stiffness).cwiseAbs().maxCoeff();
    CHECK(std::abs(difference(w0, w0) - 250.0) <= round_off);
    CHECK(std::abs(difference(slope0, slope0) - 40.0) <= round_off);
    CHECK(std::abs(difference(w4, w4) - 90.0) <= round_off);
    difference(w0, w0) = difference(slope0, slope0) = difference(w4, w4) = 0.0;
    CHECK(difference.cwiseAbs().maxCoeff() <= round_off);
  }
}

TEST_CASE("springs restrain rigid motions: a free-free beam on end springs is stable", "[fe][springs][stability]") {
  scene::Scene s = test::beam_scene(1.0, 1.0, EndSupport::free, EndSupport::free, 1e3);
  s.loads = {test::point_force(0.5, 1.0)};
  auto unstable = [&](const scene::Scene& scene) {
    return fe::discretise(model::make_member_model(scene), 10).unstable_rigid_motions;
  };
  CHECK(unstable(s) == 2);
  s.supports.left_detail = {true, 10.0, 0.0, 0.0};
  CHECK(unstable(s) == 1);  // the rotation about the left end
  s.supports.right_detail = {true, 10.0, 0.0, 0.0};
  CHECK(unstable(s) == 0);
  s.supports.right_detail = {};
  s.supports.left_detail = {true, 10.0, 5.0, 0.0};  // translational and rotational at one end
  CHECK(unstable(s) == 0);

  // A mechanism stays a mechanism: an arch on rollers driven round its centre by a tangential
  // force is refused; a spring at an interior point resists that rotation (it stretches along u).
  scene::Scene arch = test::shipped_scene("seed_arch_pinned");
  arch.supports.left = arch.supports.right = EndSupport::roller;
  scene::Load push = test::point_force(5.0, 1.0);
  push.direction = scene::LoadDirection::tangential;
  arch.loads = {push};
  CHECK_THROWS_AS(fe::discretise(model::make_member_model(arch), 20), MechanismError);
  arch.supports.interior_springs.push_back({10.0, {true, 3.0, 0.0, 0.0}});
  const fe::Discretisation held = fe::discretise(model::make_member_model(arch), 20);
  CHECK(held.unstable_rigid_motions == 0);
  CHECK(held.gauge_note.empty());
}

TEST_CASE("settlements: w = delta on the settled dof, the dead load -K u_f moves the member with it",
          "[fe][settlement]") {
  // Both ends of a clamped beam settle by delta: the exact answer is the rigid translation
  // w = delta, w' = 0, whatever the mesh (the foundation is not in K).
  const double delta = 0.0125;
  scene::Scene s = test::beam_scene(1.0, 1.0, EndSupport::clamped, EndSupport::clamped, 1e3);
  s.supports.left_detail.settlement = s.supports.right_detail.settlement = delta;
  const fe::Discretisation d = fe::discretise(model::make_member_model(s), 16);
  const int left_w = d.deflection_dof(0);
  CHECK(d.equation_of_dof[left_w] < 0);
  const Eigen::VectorXd v = Eigen::MatrixXd(d.stiffness).ldlt().solve(d.load(1.0));
  const Eigen::VectorXd u = d.expand_displacement(v);
  CHECK(u[left_w] == delta);        // prescribed, exactly
  CHECK(d.expand(v)[left_w] == 0);  // expand is for loads and corrections: fixed dofs 0
  // K's condition ~ N^4 = 6.6e4 at 16 elements: 1e-10 relative covers the solve's round-off.
  for (int node = 0; node <= d.mesh.elements(); ++node) {
    CHECK(u[d.deflection_dof(node)] == Approx(delta).epsilon(1e-10));
    CHECK(std::abs(u[d.slope_dof(node)]) <= 1e-10 * delta);
  }
  // The foundation reaches the settled ends: its gap carries -C u_f (as a ground gap would).
  REQUIRE(d.ground_gap.size() == d.reactions());
  CHECK(d.ground_gap[0] < 0.0);                   // pushed into the ground at the end
  CHECK(d.ground_gap[d.reactions() / 2] == 0.0);  // the middle node's shapes do not reach the ends
}

TEST_CASE("bilinear foundation: the Winkler part K_t is in K and in its mixed form", "[fe][issue12][tension]") {
  // k = 1e3 on 0.2..1 of a pinned-free beam, K_t = 400: C and T carry k - K_t, K carries K_t.
  scene::Scene s = test::beam_scene(1.0, 1.0, EndSupport::pinned, EndSupport::free, 1e3);
  s.foundation.from = 0.2;
  s.loads = {test::point_force(0.5, 1.0)};
  const fe::Discretisation plain = fe::discretise(model::make_member_model(s), 10);
  s.foundation.tension_k = 400.0;
  const model::MemberModel model = model::make_member_model(s);
  REQUIRE(model.tensionless);
  const fe::Discretisation d = fe::discretise(model, 10);
  // Element 0..1 lie off the foundation: no Winkler stresses there.
  CHECK(d.winkler_elements == std::vector<int>{2, 3, 4, 5, 6, 7, 8, 9});
  CHECK(d.stresses() == d.stresses_per_element * 10 + fe::foundation_element::winkler_points * 8);
  CHECK(d.element_k[5].begin == 600.0);
  CHECK(d.element_k[5].end == 600.0);
  CHECK(d.element_tension_k[5] == 400.0);
  // T is that of k - K_t: it sums to 0.8 / 600.
  CHECK(Eigen::MatrixXd(d.flexibility).sum() == Approx(0.8 / 600.0).epsilon(1e-12));
  // K - K_plain applied to w = 1 is the force K_t integral N_w: summing its w rows gives K_t 0.8.
  const Eigen::MatrixXd added = Eigen::MatrixXd(d.stiffness) - Eigen::MatrixXd(plain.stiffness);
  Eigen::VectorXd translation = Eigen::VectorXd::Zero(d.dofs());
  for (int node = 0; node <= 10; ++node) translation[d.deflection_dof(node)] = 1.0;
  Eigen::VectorXd on_equations(d.equations);
  for (int dof = 0; dof < d.dofs(); ++dof)
    if (d.equation_of_dof[dof] >= 0) on_equations[d.equation_of_dof[dof]] = translation[dof];
  // (The pinned end's w row is not an equation: the translation's force there is left out, and
  // it is 0 since element 0 is off the foundation.)
  CHECK(on_equations.dot(added * on_equations) == Approx(400.0 * 0.8).epsilon(1e-12));
  // The mixed form carries K with the Winkler block exactly: G^T H^-1 G = K to round-off.
  const Eigen::MatrixXd g(d.stress_coupling);
  const Eigen::MatrixXd k = g.transpose() * d.compliance.cwiseInverse().asDiagonal() * g;
  CHECK((k - Eigen::MatrixXd(d.stiffness)).norm() <= 1e-12 * Eigen::MatrixXd(d.stiffness).norm());
  // K_t resists the pinned-free beam's rotation about its pin: K is regular now.
  CHECK(plain.unstable_rigid_motions == 1);
  CHECK(d.unstable_rigid_motions == 0);
  // K_t = k: the bilateral foundation.
  s.foundation.tension_k = 1e3;
  CHECK_FALSE(model::make_member_model(s).tensionless);
  CHECK(model::make_member_model(s).tension_k == 0.0);
}

TEST_CASE("rigid motions are computed once: the member's, and those the supports leave free", "[fe][stability]") {
  // A free-free beam, a beam on one pin and a free arch: the shared motions are the member's
  // rigid motions, and the free ones (on the equations) are motions K does not strain.
  scene::Scene free_free = test::beam_scene(1.0, 1.0, EndSupport::free, EndSupport::free, 1e3);
  free_free.loads = {test::point_force(0.5, 1.0)};
  scene::Scene pinned_free = free_free;
  pinned_free.supports.left = EndSupport::pinned;
  scene::Scene arch = test::shipped_scene("seed_arch_pinned");
  arch.supports.left = arch.supports.right = EndSupport::free;
  for (const scene::Scene& s : {free_free, pinned_free, arch}) {
    const model::MemberModel model = model::make_member_model(s);
    const fe::Discretisation d = fe::discretise(model, 20);
    CAPTURE(d.kind == model::StructureKind::arch, d.unstable_rigid_motions);
    CHECK(d.member_rigid_motions == fe::rigid_motions(model, d));
    const Eigen::MatrixXd& z = d.free_rigid_motions;
    REQUIRE(z.rows() == d.equations);
    REQUIRE(z.cols() == d.unstable_rigid_motions);
    REQUIRE(z.cols() > 0);
    // Beams: K z = 0 but for the round-off of rows summing up to ~12 terms of size |K|max |z|max.
    // Arches: the motions' cos and sin are interpolated by the element's polynomials, whose error
    // strains it slightly (1.6e-13 relative at 20 elements): the 1e-8 relative test member_kinematics.cpp
    // applies before it uses them.
    const double scale = Eigen::MatrixXd(d.stiffness).cwiseAbs().maxCoeff() * z.cwiseAbs().maxCoeff();
    const double allowed =
        d.kind == model::StructureKind::beam ? 64 * std::numeric_limits<double>::epsilon() * scale : 1e-8 * scale;
    CHECK((d.stiffness * z).cwiseAbs().maxCoeff() <= allowed);
    // On the equations they are the member's motions: expanded, each is a combination of those.
    Eigen::MatrixXd expanded(d.dofs(), z.cols());
    for (int m = 0; m < z.cols(); ++m) expanded.col(m) = d.expand(z.col(m));
    const Eigen::MatrixXd& modes = d.member_rigid_motions;
    const Eigen::MatrixXd fit = modes.colPivHouseholderQr().solve(expanded);
    CHECK((modes * fit - expanded).cwiseAbs().maxCoeff() <= 1e-12 * expanded.cwiseAbs().maxCoeff());
  }
  CHECK(fe::discretise(model::make_member_model(pinned_free), 20).free_rigid_motions.cols() == 1);
}

TEST_CASE("an axial force makes the stiffness K - N K_g and an initial shape the load N integral of N' w0'",
          "[fe][axial]") {
  // A pinned-clamped beam, L = 2, EI = 1.5; N L^2/EI dead 3, live 2 (K(N) at lambda = 1: N = 5).
  scene::Scene s = test::beam_scene(2.0, 1.5, EndSupport::pinned, EndSupport::clamped, 100.0);
  s.loads = {test::uniform_load(0.0, 2.0, 1.0)};
  const fe::Discretisation first = fe::discretise(model::make_member_model(s), 12);
  scene::Load dead, live;
  dead.kind = live.kind = scene::LoadKind::axial;
  dead.value = 3.0 * 1.5 / 4.0;
  dead.load_case = scene::LoadCase::dead;
  live.value = 2.0 * 1.5 / 4.0;
  s.loads.push_back(dead);
  s.loads.push_back(live);
  // A triangle: w0 = 0.02 at x = 1 (node 6 of 12), 0 at the ends; in units of L: slopes +-0.02.
  s.initial_shape.at = {0.0, 1.0, 2.0};
  s.initial_shape.value = {0.0, 0.02, 0.0};
  const model::MemberModel model = model::make_member_model(s);
  CHECK(model.axial_dead == Approx(3.0).epsilon(1e-15));
  CHECK(model.axial_live == Approx(2.0).epsilon(1e-15));
  const fe::Discretisation d = fe::discretise(model, 12);
  REQUIRE(d.has_axial_force());
  CHECK(d.axial_force == Approx(5.0).epsilon(1e-15));
  const Eigen::MatrixXd expected = Eigen::MatrixXd(first.stiffness) - 5.0 * Eigen::MatrixXd(d.geometric_stiffness);
  CHECK((Eigen::MatrixXd(d.stiffness) - expected).cwiseAbs().maxCoeff() <= 1e-12 * expected.cwiseAbs().maxCoeff());
  // integral of N' w0' = sum over pieces of w0' [N]: at the kink's w the slopes' jump, 0.02 - (-0.02)
  // = 0.04; nothing anywhere else (interior nodes cancel, the ends' w are fixed).
  REQUIRE(d.initial_shape_load.size() == d.equations);
  const int kink = d.equation_of_dof[d.deflection_dof(6)];
  for (int eq = 0; eq < d.equations; ++eq)
    CHECK(d.initial_shape_load[eq] == Approx(eq == kink ? 0.04 : 0.0).margin(1e-15));
  // By case: N_dead times it in the dead load, N_live in the live load.
  CHECK((d.dead_load - first.dead_load - 3.0 * d.initial_shape_load).cwiseAbs().maxCoeff() <= 1e-15);
  CHECK((d.live_load - first.live_load - 2.0 * d.initial_shape_load).cwiseAbs().maxCoeff() <= 1e-15);
}
