// The fixed-pattern assembler (fe/sparse_assembler.hpp): one symbolic pattern, values rewritten in
// place, equal to the stiffness discretise assembles from triplets.
#include "fe/sparse_assembler.hpp"

#include <catch2/catch.hpp>
#include <limits>

#include "fe/discretisation.hpp"
#include "model/from_scene.hpp"
#include "model/member_model.hpp"
#include "support/scenes.hpp"

using namespace liftoff;
using scene::EndSupport;

namespace {

constexpr double eps = std::numeric_limits<double>::epsilon();

// Members that use every kind of element: a beam on springs and a bilinear foundation, with
// an interior support; the seed arch with a spring end (u, w and rotation springs).
std::vector<scene::Scene> members() {
  scene::Scene beam = test::beam_scene(1.0, 1.0, EndSupport::free, EndSupport::pinned, 1e3);
  beam.supports.left_detail = {true, 250.0, 40.0, 0.0};
  beam.supports.interior = {0.7};
  beam.supports.interior_springs.push_back({0.4, {true, 90.0, 0.0, 0.0}});
  beam.foundation.from = 0.2;
  beam.foundation.tension_k = 400.0;
  beam.loads = {test::point_force(0.5, 1.0)};
  scene::Scene arch = test::shipped_scene("seed_arch_pinned");
  arch.supports.left = EndSupport::free;
  arch.supports.left_detail = {true, 30.0, 7.0, 0.0};
  return {beam, arch};
}

// The sum of each product's terms, for the round-off allowance of K u.
Eigen::VectorXd abs_product(const fe::SparseMatrix& k, const Eigen::VectorXd& u) {
  return Eigen::MatrixXd(k).cwiseAbs() * u.cwiseAbs();
}

}  // namespace

TEST_CASE("the assembler's K is discretise's K, re-assembled in place", "[fe][assembler]") {
  for (const scene::Scene& s : members()) {
    const model::MemberModel model = model::make_member_model(s);
    const fe::Discretisation d = fe::discretise(model, 12);
    CAPTURE(d.kind == model::StructureKind::arch);
    const fe::StructuralElements set = fe::structural_elements(model, d);
    REQUIRE(set.elements.size() == set.dofs.size());
    // One member element per mesh element, a Winkler element per winkler element, one per spring.
    CHECK(set.elements.size() == d.mesh.elements() + d.winkler_elements.size() + d.springs.size());

    fe::SparseAssembler assembler(set.dofs, d.equation_of_dof);
    CHECK(assembler.equations() == d.equations);
    const Eigen::VectorXd v = Eigen::VectorXd::Random(d.equations);
    assembler.assemble(set.elements, d.expand(v), 0.0);
    const fe::SparseMatrix& k = assembler.tangent();
    // The same coupling, so the same pattern as setFromTriplets gives (structural zeros too).
    CHECK(k.nonZeros() == d.stiffness.nonZeros());
    const double* values = k.valuePtr();
    const int* inner = k.innerIndexPtr();
    const int* outer = k.outerIndexPtr();
    const Eigen::Index nonzeros = k.nonZeros();
    // Sums of up to a dozen contributions per entry, in another order than the triplets':
    // a few ulps of the largest entry.
    const double round_off = 64 * eps * Eigen::MatrixXd(d.stiffness).cwiseAbs().maxCoeff();
    CHECK(Eigen::MatrixXd(k - d.stiffness).cwiseAbs().maxCoeff() <= round_off);
    // f_int = K v, each row to gamma_n |K| |v| (n <= 30 terms).
    const Eigen::VectorXd f = d.stiffness * v;
    CHECK(((assembler.internal_force() - f).cwiseAbs() - 64 * eps * abs_product(d.stiffness, v)).maxCoeff() <= 0.0);

    // Re-assembly at another state: the same arrays, the same count, the current values.
    const Eigen::VectorXd w = Eigen::VectorXd::Random(d.equations) * 1e3;
    assembler.assemble(set.elements, d.expand(w), 2.5);
    CHECK(k.valuePtr() == values);
    CHECK(k.innerIndexPtr() == inner);
    CHECK(k.outerIndexPtr() == outer);
    CHECK(k.nonZeros() == nonzeros);
    CHECK(Eigen::MatrixXd(k - d.stiffness).cwiseAbs().maxCoeff() <= round_off);
    const Eigen::VectorXd g = d.stiffness * w;
    CHECK(((assembler.internal_force() - g).cwiseAbs() - 64 * eps * abs_product(d.stiffness, w)).maxCoeff() <= 0.0);
  }
}

namespace {
// An element whose tangent is its state: K_t = diag(u), so a re-assembly must show the new state.
class StateElement final : public fe::Element {
 public:
  int dofs() const override { return 2; }
  bool is_linear() const override { return false; }
  void evaluate(const fe::ElementState& state, fe::ElementResponse& response) const override {
    response.internal_force = 0.5 * state.displacement.cwiseProduct(state.displacement);
    response.tangent = state.displacement.asDiagonal();
    response.tangent(0, 1) = response.tangent(1, 0) = state.load_factor;
  }
};
}  // namespace

TEST_CASE("the assembler drops fixed dofs, keeps their values in the state, and follows the state", "[fe][assembler]") {
  // Three two-node elements on dofs 0..3; dof 0 fixed.
  std::vector<std::unique_ptr<const fe::Element>> elements;
  for (int e = 0; e < 3; ++e) elements.push_back(std::make_unique<const StateElement>());
  fe::SparseAssembler assembler({{0, 1}, {1, 2}, {2, 3}}, {-1, 0, 1, 2});
  const Eigen::Vector4d u(5.0, 1.0, 2.0, 3.0);
  assembler.assemble(elements, u, 0.5);
  Eigen::Matrix3d expected;
  expected << 1 + 1, 0.5, 0,  //
      0.5, 2 + 2, 0.5,        //
      0, 0.5, 3;
  CHECK(Eigen::MatrixXd(assembler.tangent()) == expected);
  // Dof 1's force gathers both elements' halves of 1^2; dof 0 (fixed, u = 5) is no equation.
  CHECK(assembler.internal_force() == Eigen::Vector3d(1.0, 4.0, 4.5));
  const double* values = assembler.tangent().valuePtr();
  assembler.assemble(elements, Eigen::Vector4d(0.0, -1.0, 0.0, 4.0), 0.0);
  expected << -1 - 1, 0, 0,  //
      0, 0, 0,               //
      0, 0, 4;
  CHECK(assembler.tangent().valuePtr() == values);
  CHECK(Eigen::MatrixXd(assembler.tangent()) == expected);
  CHECK(assembler.tangent().nonZeros() == 7);  // the pattern keeps its structural zeros

  CHECK_THROWS_AS(fe::SparseAssembler({{0, 4}}, {0, 1, 2, 3}), std::invalid_argument);
  CHECK_THROWS_AS(assembler.assemble(elements, Eigen::Vector3d::Zero(), 0.0), std::invalid_argument);
}
