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

// The answer's evidence, recomputed densely from the discretisation: the mode solves
// (K + K_S - N K_g) phi = 0 at N = dead + lambda_cr live on its spring set S, and meets the cone's
// conditions at the weakly active nodes (dr >= 0 on a spring, dgap >= 0 off one).
void check_mode(const fe::Discretisation& d, const stability::CriticalLoadResult& r) {
  REQUIRE(r.termination == StabilityTermination::critical_load_found);
  const Eigen::MatrixXd c = Eigen::MatrixXd(d.coupling), t = Eigen::MatrixXd(d.flexibility);
  std::vector<int> s;
  for (int i = 0; i < d.reactions(); ++i)
    if (r.spring[i]) s.push_back(i);
  Eigen::MatrixXd c_s(s.size(), d.equations), t_ss(s.size(), s.size());
  for (std::size_t a = 0; a < s.size(); ++a) {
    c_s.row(a) = c.row(s[a]);
    for (std::size_t b = 0; b < s.size(); ++b) t_ss(a, b) = t(s[a], s[b]);
  }
  const Eigen::VectorXd& phi = r.mode;
  Eigen::VectorXd reaction = Eigen::VectorXd::Zero(d.reactions());
  Eigen::MatrixXd k = Eigen::MatrixXd(d.stiffness);
  if (!s.empty()) {
    const Eigen::VectorXd r_s = t_ss.ldlt().solve(c_s * phi);
    for (std::size_t a = 0; a < s.size(); ++a) reaction[s[a]] = r_s[a];
    k += c_s.transpose() * t_ss.ldlt().solve(c_s);
  }
  const Eigen::MatrixXd k_g = Eigen::MatrixXd(stability::geometric_stiffness(d));
  const Eigen::VectorXd k_phi = k * phi;
  // The eigen-residual: the solvers stop at 1e-10 relative (sparse) or round-off (dense).
  CHECK((k_phi - r.critical_axial_force() * (k_g * phi)).norm() <= 1e-9 * k_phi.norm());
  const Eigen::VectorXd gap = t * reaction - c * phi;
  const double reaction_scale = reaction.lpNorm<Eigen::Infinity>(), gap_scale = (c * phi).lpNorm<Eigen::Infinity>();
  for (int i = 0; i < d.reactions(); ++i) {
    if (r.contact[i] != NodeContact::weakly_active) continue;
    CAPTURE(i, reaction[i], gap[i]);
    if (r.spring[i])
      CHECK(reaction[i] >= -1e-9 * reaction_scale);
    else
      CHECK(gap[i] >= -1e-9 * gap_scale);
  }
  CHECK(r.critical_load_factor >= r.lower_bound * (1 - 1e-12));
  CHECK(r.critical_load_factor <= r.upper_bound * (1 + 1e-12));
}

// The largest and smallest deflection of a mode (the slope dofs left out).
std::pair<double, double> deflection_range(const fe::Discretisation& d, const Eigen::VectorXd& mode) {
  double low = 0.0, high = 0.0;
  for (int dof = 0; dof < d.dofs(); ++dof)
    if (d.equation_of_dof[dof] >= 0 && d.role_of_dof(dof) == fe::DofRole::deflection)
      low = std::min(low, mode[d.equation_of_dof[dof]]), high = std::max(high, mode[d.equation_of_dof[dof]]);
  return {low, high};
}

// Dense and sparse agree to the sparse path's stopping test: an eigen-residual rho = 1e-10 puts
// the Rayleigh quotient within about rho^2 times the spectrum's spread, so 1e-9 is generous.
void check_paths_agree(const stability::CriticalLoadResult& dense, const stability::CriticalLoadResult& sparse) {
  REQUIRE(dense.method == EigenMethod::dense);
  REQUIRE(sparse.method == EigenMethod::sparse);
  CHECK(sparse.critical_load_factor == Approx(dense.critical_load_factor).epsilon(1e-9));
  CHECK(sparse.lower_bound == Approx(dense.lower_bound).epsilon(1e-9));
  CHECK(sparse.upper_bound == Approx(dense.upper_bound).epsilon(1e-9));
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

TEST_CASE("stability: pinned strut on a bilateral foundation, min over n of n^2 pi^2 + k/(n^2 pi^2), order 4",
          "[stability]") {
  // k = 0: Euler; k = 1e3: the two-half-wave mode governs (64.81).
  for (double k : {0.0, 1e3}) {
    const double exact = bilateral_strut(k);
    std::vector<double> error;
    for (int n : {4, 8, 16, 32, 64}) {
      const fe::Discretisation d = strut(n, k);
      const auto dense =
          stability::critical_load(d, 0.0, 1.0, every(d, NodeContact::in_contact), with(EigenMethod::dense));
      const auto sparse =
          stability::critical_load(d, 0.0, 1.0, every(d, NodeContact::in_contact), with(EigenMethod::sparse));
      CAPTURE(k, n, dense.critical_load_factor, sparse.critical_load_factor, exact);
      check_mode(d, dense);
      check_mode(d, sparse);
      check_paths_agree(dense, sparse);
      CHECK(std::all_of(dense.spring.begin(), dense.spring.end(), [](bool b) { return b; }));
      CHECK(dense.set_iterations == 1);
      error.push_back(std::abs(dense.critical_load_factor - exact) / exact);
    }
    // Hermite cubics: the eigenvalue's error is O(h^4). The foundation in the mixed form's
    // weighting, C^T T^-1 C (k times the projection of w on the hats), differs from k N^T N by
    // O(h^4) too; at h = 1/4 and 1/8 the two-half-wave mode has two and four elements per
    // half-wave (orders 1.8 and 3.6 there), so the order is asserted from h = 1/16 on.
    for (std::size_t i = 2; i + 1 < error.size(); ++i) {
      const double order = std::log2(error[i] / error[i + 1]);
      CAPTURE(k, i, error[i], error[i + 1], order);
      CHECK(order > 3.8);
      CHECK(order < 4.2);
    }
    CHECK(error.back() < 1e-6);
  }
}

TEST_CASE("stability: dead and live axial forces: N_dead + lambda N_live = N_cr", "[stability]") {
  const fe::Discretisation d = strut(16, 1e3);
  const auto contact = every(d, NodeContact::in_contact);
  const double n_cr = stability::critical_load(d, 0.0, 1.0, contact).critical_load_factor;
  const auto split = stability::critical_load(d, 20.0, 2.0, contact);
  check_mode(d, split);
  CHECK(split.critical_load_factor == Approx((n_cr - 20.0) / 2.0).epsilon(1e-12));
  CHECK(split.critical_axial_force() == Approx(n_cr).epsilon(1e-12));
  for (auto method : {EigenMethod::dense, EigenMethod::sparse}) {
    CAPTURE(stability::to_string(method));
    // Beyond the critical force under the dead load alone: unstable before any live load.
    CHECK(stability::critical_load(d, 1.01 * n_cr, 1.0, contact, with(method)).termination ==
          StabilityTermination::unstable_at_zero);
    // A live tension (or none) never buckles the member.
    CHECK(stability::critical_load(d, 0.5 * n_cr, -1.0, contact, with(method)).termination ==
          StabilityTermination::stable_for_all_factors);
    CHECK(stability::critical_load(d, 0.5 * n_cr, 0.0, contact, with(method)).termination ==
          StabilityTermination::stable_for_all_factors);
  }
}

TEST_CASE("stability: a weightless pinned strut on a tensionless foundation buckles away from it at pi^2, any k",
          "[stability]") {
  // Zero reactions and gaps everywhere: every node weakly active. The Euler mode oriented away
  // from the foundation (w <= 0) compresses no spring, so the foundation adds nothing: pi^2 for
  // every k, while a bilateral foundation (the upper bound, every weak node a spring) gives
  // min_n n^2 pi^2 + k/(n^2 pi^2).
  for (double k : {1e2, 1e4, 1e6}) {
    std::vector<double> error;
    for (int n : {8, 16, 32, 64}) {
      const fe::Discretisation d = strut(n, k);
      const auto weak = every(d, NodeContact::weakly_active);
      const auto dense = stability::critical_load(d, 0.0, 1.0, weak, with(EigenMethod::dense));
      const auto sparse = stability::critical_load(d, 0.0, 1.0, weak, with(EigenMethod::sparse));
      CAPTURE(k, n, dense.brief_report(), sparse.brief_report());
      check_mode(d, dense);
      check_mode(d, sparse);
      check_paths_agree(dense, sparse);
      for (const auto* r : {&dense, &sparse}) {
        CHECK(std::none_of(r->spring.begin(), r->spring.end(), [](bool b) { return b; }));
        const auto [low, high] = deflection_range(d, r->mode);
        CHECK(low == Approx(-1.0).epsilon(1e-12));
        CHECK(high <= 1e-12);
        // The upper bound is the bilateral strut's, to the discretisation's error (h^4 above),
        // where the mesh resolves its waves (k = 1e6 has 10 half-waves: 64 elements do not).
        if (k <= 1e4) CHECK(r->upper_bound == Approx(bilateral_strut(k)).epsilon(n >= 32 ? 1e-4 : 0.2));
      }
      // The same matrices as the bare strut: exactly the k = 0 answer.
      CHECK(dense.critical_load_factor ==
            Approx(stability::critical_load(strut(n, 0.0), 0.0, 1.0, {}, with(EigenMethod::dense)).critical_load_factor)
                .epsilon(1e-13));
      error.push_back((dense.critical_load_factor - pi2) / pi2);
    }
    for (std::size_t i = 0; i + 1 < error.size(); ++i) {
      const double order = std::log2(error[i] / error[i + 1]);
      CAPTURE(k, i, error[i], order);
      CHECK(order > 3.9);
      CHECK(order < 4.1);
    }
  }
}

TEST_CASE("stability: a long bilateral member buckles at 2 sqrt(k)", "[stability]") {
  // k = 1e6 (a member 31.6 characteristic lengths long, (k)^(1/4) = 31.6): the closed form's
  // minimum is at n = 10 half-waves, n^2 pi^2 = 987 near sqrt(k) = 1000, and exceeds 2 sqrt(k) by
  // (x - sqrt k)^2 / x = 0.17 (8.6e-5 relative).
  const double k = 1e6, exact = bilateral_strut(k);
  CHECK(exact >= 2 * std::sqrt(k));
  CHECK(exact == Approx(2 * std::sqrt(k)).epsilon(1e-4));
  std::vector<double> error;
  for (int n : {100, 200, 400}) {
    const fe::Discretisation d = strut(n, k);
    const auto r = stability::critical_load(d, 0.0, 1.0, every(d, NodeContact::in_contact), with(EigenMethod::sparse));
    check_mode(d, r);
    CAPTURE(n, r.brief_report());
    error.push_back(std::abs(r.critical_load_factor - exact) / exact);
    if (n == 100) check_paths_agree(stability::critical_load(d, 0.0, 1.0, r.contact, with(EigenMethod::dense)), r);
  }
  // 10 elements per half-wave at n = 100: in the asymptotic range, measured 3.6e-7, 1.4e-8, 7.4e-10
  // (orders 4.7, 4.2: the O(h^6) term still shows at 10 elements per half-wave).
  for (std::size_t i = 0; i + 1 < error.size(); ++i) {
    const double order = std::log2(error[i] / error[i + 1]);
    CAPTURE(i, error[i], order);
    CHECK(order > 3.8);
    CHECK(order < 5.0);
  }
  CHECK(error.back() < 1e-8);
}

TEST_CASE("stability: a uniformly loaded member in contact everywhere (w = q/k) buckles like the bilateral one",
          "[stability]") {
  // A free-free beam under a uniform load q sinks rigidly, w = q/k, with r = q > 0 at every node;
  // a pinned one is held at its ends, but its reactions stay positive (its end reactions in the
  // mixed form too, where the hat's half-element sees w > 0). Either way every node is in contact
  // and the critical factor is the bilateral foundation's; the pinned one's closed form is
  // min_n n^2 pi^2 + k/(n^2 pi^2).
  for (auto end : {scene::EndSupport::free, scene::EndSupport::pinned}) {
    scene::Scene s = test::beam_scene(1.0, 1.0, end, end, 1e3);
    s.loads.push_back(test::uniform_load(0.0, 1.0, 1.0));
    const fe::Discretisation d = fe::discretise(model::make_member_model(s), 64);
    contact::ContactOptions options;
    options.method = contact::Method::fast;
    const contact::ContactSolution state = contact::solve_contact(d, options);
    REQUIRE(state.summary.is_usable());
    const auto contact = stability::classify_contact(state.reaction, state.gap);
    CHECK(contact == every(d, NodeContact::in_contact));
    const auto r = stability::critical_load(d, 0.0, 1.0, contact);
    check_mode(d, r);
    const auto bilateral = stability::critical_load(d, 0.0, 1.0, every(d, NodeContact::in_contact));
    CHECK(r.critical_load_factor == bilateral.critical_load_factor);
    if (end == scene::EndSupport::pinned)
      CHECK(r.critical_load_factor == Approx(bilateral_strut(1e3)).epsilon(1e-6));  // h^4 above: 6e-9 at 64
  }
}

TEST_CASE("stability: a partly lifted state: the spring set iterates to an admissible fixed point", "[stability]") {
  // In contact on [a, 1 - a], weakly active elsewhere. Where the mode of the fewest springs pushes
  // into the foundation at weak nodes, the set grows until the mode meets every condition.
  int iterated = 0;
  for (double a : {0.3, 0.45, 0.5})
    for (double k : {1e2, 1e3, 1e4}) {
      const fe::Discretisation d = strut(20, k);
      auto contact = every(d, NodeContact::weakly_active);
      for (int i = 0; i < d.reactions(); ++i) {
        const double x = d.mesh.nodes[d.reaction_nodes[i]];
        if (x >= a && x <= 1 - a) contact[i] = NodeContact::in_contact;
      }
      const auto dense = stability::critical_load(d, 0.0, 1.0, contact, with(EigenMethod::dense));
      const auto sparse = stability::critical_load(d, 0.0, 1.0, contact, with(EigenMethod::sparse));
      CAPTURE(a, k, dense.brief_report(), sparse.brief_report());
      check_mode(d, dense);
      check_mode(d, sparse);
      check_paths_agree(dense, sparse);
      iterated += dense.set_iterations > 1;
    }
  CHECK(iterated >= 3);  // measured: 4 of the 9 states need more than one set
}

TEST_CASE("stability: enumeration of the weak springs finds no smaller admissible mode than the fixed point",
          "[stability]") {
  // 10 elements, in contact on [0.4, 0.6]: 8 weak nodes, 256 sets. With one set iteration allowed
  // the solver enumerates them (the answer of a cycle).
  for (double k : {1e3, 1e4}) {
    const fe::Discretisation d = strut(10, k);
    auto contact = every(d, NodeContact::weakly_active);
    for (int i = 0; i < d.reactions(); ++i) {
      const double x = d.mesh.nodes[d.reaction_nodes[i]];
      if (x >= 0.35 && x <= 0.65) contact[i] = NodeContact::in_contact;
    }
    CriticalLoadOptions options = with(EigenMethod::dense);
    const auto fixed = stability::critical_load(d, 0.0, 1.0, contact, options);
    options.max_set_iterations = 1;
    const auto enumerated = stability::critical_load(d, 0.0, 1.0, contact, options);
    CAPTURE(k, fixed.brief_report(), enumerated.brief_report());
    check_mode(d, fixed);
    check_mode(d, enumerated);
    // The first set, the one flip allowed, then every subset.
    if (fixed.set_iterations > 1) CHECK(enumerated.set_iterations == 2 + 256);
    CHECK(enumerated.critical_load_factor <= fixed.critical_load_factor * (1 + 1e-12));
    CHECK(enumerated.critical_load_factor == Approx(fixed.critical_load_factor).epsilon(1e-12));
  }
}

TEST_CASE("stability: the sparse path at 1e4 and 1e5 elements (timing, reported)", "[stability][slow]") {
  for (int n : {10000, 100000}) {
    for (bool weak : {false, true}) {
      const fe::Discretisation d = strut(n, 1e3);
      const auto start = std::chrono::steady_clock::now();
      const auto r =
          stability::critical_load(d, 0.0, 1.0, every(d, weak ? NodeContact::weakly_active : NodeContact::in_contact),
                                   with(EigenMethod::sparse));
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      WARN(n << " elements, " << (weak ? "tensionless weightless" : "bilateral") << ": " << r.brief_report() << ", "
             << r.factorisations << " factorisations, " << seconds << " s");
      REQUIRE(r.termination == StabilityTermination::critical_load_found);
      // The discretisation error is far below round-off here (h^4: 6e-9 at 64 elements); the
      // mixed form's condition grows like N^2, so its round-off is eps N^2 at most (measured:
      // 1e-11 at 1e4 elements, 2.8e-9 at 1e5).
      const double round_off = std::numeric_limits<double>::epsilon() * double(n) * double(n);
      CHECK(r.critical_load_factor == Approx(weak ? pi2 : bilateral_strut(1e3)).epsilon(round_off));
    }
  }
}

TEST_CASE("stability: the cone decides stability under the dead load alone", "[stability]") {
  // A weightless tensionless strut under a dead force between pi^2 and the bilateral strut's
  // critical force: stable were the foundation bilateral, unstable on the cone (it lifts off).
  const fe::Discretisation d = strut(32, 1e3);
  const auto weak = every(d, NodeContact::weakly_active);
  for (auto method : {EigenMethod::dense, EigenMethod::sparse}) {
    CAPTURE(stability::to_string(method));
    const auto lifted = stability::critical_load(d, 2.0 * pi2, 1.0, weak, with(method));
    CHECK(lifted.termination == StabilityTermination::unstable_at_zero);
    const auto [low, high] = deflection_range(d, lifted.mode);
    CHECK(low == Approx(-1.0).epsilon(1e-12));  // the mode it fails in lifts off
    CHECK(high <= 1e-12);
    CHECK(stability::critical_load(d, 2.0 * pi2, 1.0, every(d, NodeContact::in_contact), with(method))
              .critical_load_factor == Approx(bilateral_strut(1e3) - 2.0 * pi2).epsilon(1e-6));
  }
  // A free-free beam with every node lifted: nothing holds its rigid motions.
  const fe::Discretisation free = fe::discretise(
      model::make_member_model(test::beam_scene(1.0, 1.0, scene::EndSupport::free, scene::EndSupport::free, 1e3)), 16);
  for (auto method : {EigenMethod::dense, EigenMethod::sparse}) {
    const auto r = stability::critical_load(free, 0.0, 1.0, every(free, NodeContact::lifted), with(method));
    CHECK(r.termination == StabilityTermination::unstable_at_zero);
    CHECK_FALSE(r.is_usable());
  }
}

TEST_CASE("stability: a discretisation assembled under N (K(N) = K - N K_g) gives the same critical load",
          "[stability]") {
  // fe::discretise puts N K_g into `stiffness` when the member carries an axial force; the
  // critical load of the weightless pinned strut must stay pi^2 whatever N it was assembled
  // under (N counted once, as dead + lambda live here), on both paths.
  const fe::Discretisation bare = strut(32, 1e2);
  for (double force : {0.5 * pi2, 0.9 * pi2, 3.0 * pi2}) {
    scene::Scene s = test::beam_scene(1.0, 1.0, scene::EndSupport::pinned, scene::EndSupport::pinned, 1e2);
    scene::Load load;
    load.kind = scene::LoadKind::axial;
    load.value = force;
    load.load_case = scene::LoadCase::dead;
    s.loads.push_back(load);
    const fe::Discretisation d = fe::discretise(model::make_member_model(s), 32);
    REQUIRE(d.axial_force == Approx(force).epsilon(1e-15));
    for (auto method : {EigenMethod::dense, EigenMethod::sparse}) {
      const auto weak = every(d, NodeContact::weakly_active);
      const auto under = stability::critical_load(d, 0.0, 1.0, weak, with(method));
      const auto reference = stability::critical_load(bare, 0.0, 1.0, weak, with(method));
      CAPTURE(force, stability::to_string(method), under.brief_report(), reference.brief_report());
      REQUIRE(under.termination == StabilityTermination::critical_load_found);
      // K - N K_g + N K_g is K to round-off (N |K_g| eps against pi^2 |K_g|): 1e-12 relative.
      CHECK(under.critical_load_factor == Approx(reference.critical_load_factor).epsilon(1e-12));
      CHECK(under.critical_load_factor == Approx(pi2).epsilon(1e-5));  // h^4 at 32 elements: 1.5e-7
      // The factor on the whole force: N_cr / N.
      const auto on_force = stability::critical_load(d, 0.0, force, weak, with(method));
      CHECK(on_force.critical_load_factor * force == Approx(reference.critical_load_factor).epsilon(1e-12));
      if (method == EigenMethod::dense) CHECK(under.eigen_iterations == 0);
    }
  }
}
