#include "stability/critical_load.hpp"

#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <limits>
#include <vector>

#include "contact/contact_solver.hpp"
#include "model/from_scene.hpp"
#include "stability/geometric_stiffness.hpp"
#include "support/scenes.hpp"

using namespace liftoff;
using stability::CriticalLoadOptions;
using stability::EigenMethod;
using stability::NodeContact;
using stability::StabilityTermination;

namespace {

const double pi2 = M_PI * M_PI;

// A weightless pinned strut, EI = L = 1, on a foundation of modulus k (tensionless in the model:
// the contact state passed decides which springs act), n elements.
fe::Discretisation strut(int n, double k, bool tensionless = true) {
  return fe::discretise(model::make_member_model(test::beam_scene(1.0, 1.0, scene::EndSupport::pinned,
                                                                  scene::EndSupport::pinned, k, tensionless)),
                        n);
}

// The pinned strut on a bilateral foundation: w = sin(n pi x) is an exact mode of
// w'''' + P w'' + k w = 0 with w = w'' = 0 at both ends, n^4 pi^4 - P n^2 pi^2 + k = 0, so
// P = n^2 pi^2 + k / (n^2 pi^2), smallest over n. As k grows, the minimum over a continuous
// x = n^2 pi^2 of x + k/x is 2 sqrt(k) at x = sqrt(k): the long member's 2 sqrt(K EI).
double bilateral_strut(double k) {
  double p = std::numeric_limits<double>::infinity();
  for (int waves = 1; waves <= 1000; ++waves) p = std::min(p, waves * waves * pi2 + k / (waves * waves * pi2));
  return p;
}

std::vector<NodeContact> every(const fe::Discretisation& d, NodeContact c) {
  return std::vector<NodeContact>(static_cast<std::size_t>(d.reactions()), c);
}

CriticalLoadOptions with(EigenMethod method) {
  CriticalLoadOptions options;
  options.method = method;
  return options;
}

}  // namespace

TEST_CASE("stability: the geometric stiffness is the elements' N'^T N' on the equations", "[stability]") {
  const fe::Discretisation d = strut(6, 10.0);
  const Eigen::MatrixXd k_g = Eigen::MatrixXd(stability::geometric_stiffness(d));
  REQUIRE(k_g.rows() == d.equations);
  // The integral of w'^2 for w = x (1 - x) (exact in the Hermite space): 1/3.
  Eigen::VectorXd w = Eigen::VectorXd::Zero(d.equations);
  for (int dof = 0; dof < d.dofs(); ++dof) {
    const int eq = d.equation_of_dof[dof];
    if (eq < 0) continue;
    const double x = d.position_of_dof(dof);
    w[eq] = d.role_of_dof(dof) == fe::DofRole::deflection ? x * (1 - x) : 1 - 2 * x;
  }
  CHECK(w.dot(k_g * w) == Approx(1.0 / 3.0).epsilon(1e-14));
  CHECK((k_g - k_g.transpose()).norm() == 0.0);
}

TEST_CASE("stability: enums, options and misuse", "[stability]") {
  for (auto t : {StabilityTermination::critical_load_found, StabilityTermination::stable_for_all_factors,
                 StabilityTermination::unstable_at_zero, StabilityTermination::not_converged})
    CHECK(from_string<StabilityTermination>(stability::to_string(t)) == t);
  for (auto c : {NodeContact::in_contact, NodeContact::lifted, NodeContact::weakly_active})
    CHECK(from_string<NodeContact>(stability::to_string(c)) == c);
  for (auto m : {EigenMethod::automatic, EigenMethod::dense, EigenMethod::sparse})
    CHECK(from_string<EigenMethod>(stability::to_string(m)) == m);
  CriticalLoadOptions bad;
  bad.block_size = 0;
  CHECK_THROWS_AS(bad.validate(), std::invalid_argument);
  const fe::Discretisation d = strut(4, 10.0);
  CHECK_THROWS_AS(stability::critical_load(d, 0.0, 1.0, {NodeContact::lifted}), std::invalid_argument);
  CHECK_THROWS_AS(stability::critical_load(d, 0.0, NAN, every(d, NodeContact::lifted)), std::invalid_argument);
  CHECK_THROWS_AS(stability::classify_contact(Eigen::VectorXd::Zero(2), Eigen::VectorXd::Zero(3)),
                  std::invalid_argument);
  const auto state = stability::classify_contact(Eigen::Vector3d(2.0, 0.0, 0.0), Eigen::Vector3d(0.0, 1e-20, 0.5));
  CHECK(state == std::vector<NodeContact>{NodeContact::in_contact, NodeContact::weakly_active, NodeContact::lifted});
}

TEST_CASE("stability: pinned strut on a bilateral foundation, min over n of n^2 pi^2 + k/(n^2 pi^2)", "[stability]") {
  for (double k : {0.0, 1e3}) {
    const double exact = bilateral_strut(k);
    std::vector<double> error;
    for (int n : {4, 8, 16, 32}) {
      const fe::Discretisation d = strut(n, k);
      const auto dense =
          stability::critical_load(d, 0.0, 1.0, every(d, NodeContact::in_contact), with(EigenMethod::dense));
      const auto sparse =
          stability::critical_load(d, 0.0, 1.0, every(d, NodeContact::in_contact), with(EigenMethod::sparse));
      REQUIRE(dense.termination == StabilityTermination::critical_load_found);
      REQUIRE(sparse.termination == StabilityTermination::critical_load_found);
      WARN("k " << k << " n " << n << " dense " << dense.critical_load_factor << " sparse "
                << sparse.critical_load_factor << " exact " << exact << " it " << sparse.eigen_iterations << " res "
                << sparse.residual);
      error.push_back((dense.critical_load_factor - exact) / exact);
    }
    for (std::size_t i = 0; i + 1 < error.size(); ++i) WARN("order " << std::log2(error[i] / error[i + 1]));
  }
}

TEST_CASE("stability: weightless pinned strut on a tensionless foundation buckles away at pi^2", "[stability]") {
  for (double k : {1e2, 1e4}) {
    std::vector<double> error;
    for (int n : {4, 8, 16, 32}) {
      const fe::Discretisation d = strut(n, k);
      for (auto method : {EigenMethod::dense, EigenMethod::sparse}) {
        const auto r = stability::critical_load(d, 0.0, 1.0, every(d, NodeContact::weakly_active), with(method));
        WARN("k " << k << " n " << n << " " << r.brief_report() << " max mode " << r.mode.maxCoeff() << " min "
                  << r.mode.minCoeff());
        if (method == EigenMethod::dense) error.push_back((r.critical_load_factor - pi2) / pi2);
      }
    }
    for (std::size_t i = 0; i + 1 < error.size(); ++i) WARN("order " << std::log2(error[i] / error[i + 1]));
  }
}
