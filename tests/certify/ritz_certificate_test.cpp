// The certificate of Ritz answers: it passes on every shipped scene, its support reactions agree
// with the FE's, and it catches spoilt answers.

#include <catch2/catch.hpp>
#include <filesystem>

#include "certify/certificate.hpp"
#include "post/contact_regions.hpp"
#include "ritz/starting_point.hpp"
#include "support/scenes.hpp"
#include "support/solve.hpp"

using namespace liftoff;
using contact::Method;

namespace {

struct RitzAnswer {
  model::MemberModel model;
  ritz::RitzOptions options;
  ritz::RitzSolution solution;
};

RitzAnswer solve_ritz(const scene::Scene& s, int modes = 0) {
  RitzAnswer a;
  const test::Solved start = test::solve(s, Method::fast, 200);
  a.model = start.model;
  const ritz::StartingPoint point = ritz::starting_point_from_regions(start.regions, a.model);
  a.options.modes = modes > 0 ? modes : s.ritz.modes;
  a.options.mode_tolerance = s.ritz.mode_tolerance * a.model.length();
  a.solution = ritz::solve_ritz(a.model, point.topology, point.limits, a.options);
  return a;
}

const certify::Check& check(const certify::Certificate& c, std::string_view name) {
  const certify::Check* found = c.find(name);
  REQUIRE(found != nullptr);
  return *found;
}

}  // namespace

TEST_CASE("the Ritz certificate passes on every shipped scene", "[certify][ritz]") {
  for (const auto& entry :
       std::filesystem::directory_iterator(std::string(LIFTOFF_SOURCE_DIR) + "/verification/scenes")) {
    // The engineering corpus (a subfolder) has its own test, with the refusals it expects.
    if (!entry.is_regular_file() || entry.path().extension() != ".toml") continue;
    const scene::Scene s = scene::read_scene_file(entry.path());
    CAPTURE(entry.path().filename().string());
    const RitzAnswer a = solve_ritz(s);
    REQUIRE(a.solution.summary.is_usable());
    const certify::Certificate c = certify::certify(a.model, a.solution, a.options);
    CAPTURE(c.message);
    CHECK(c.passed);
  }
}

TEST_CASE("Ritz support reactions are the FE's, within both models' error", "[certify][ritz]") {
  // The clamped arch: every function of the clamped family is even about the end, so the Ritz
  // end shear is zero at every N; the variationally consistent reaction is not.
  const scene::Scene s = test::shipped_scene("seed_arch_clamped");
  const RitzAnswer a = solve_ritz(s, 32);
  REQUIRE(a.solution.summary.is_usable());
  const certify::Certificate ritz = certify::certify(a.model, a.solution, a.options);
  const test::Solved fe = test::solve(s, Method::fast, 200);
  const certify::Certificate finite = certify::certify(fe.model, fe.discretisation, fe.solution);
  REQUIRE(ritz.passed);
  REQUIRE(finite.passed);
  REQUIRE(ritz.support_reactions.size() == 2);
  REQUIRE(finite.support_reactions.size() == 2);
  // Tolerance: each model's own estimate of its error in the fields, relative, on the largest
  // reaction component (the FE's change from half the elements, the Ritz's from half the modes),
  // x 4 as the certificate's balance.
  const double fe_error = check(finite, certify::check_name::round_off).tolerance;
  const double ritz_error = check(ritz, certify::check_name::round_off).tolerance;
  for (int i = 0; i < 2; ++i) {
    const auto& r = ritz.support_reactions[i];
    const auto& f = finite.support_reactions[i];
    const double scale = std::max({std::abs(f.force), std::abs(f.moment), std::abs(f.tangential)});
    CAPTURE(i, r.force, f.force, r.moment, f.moment, r.tangential, f.tangential);
    CHECK(std::abs(f.force) > 1e-3 * scale);  // not zero, as the end shear would be
    for (auto [x, y] : {std::pair{r.force, f.force}, {r.moment, f.moment}, {r.tangential, f.tangential}})
      CHECK(std::abs(x - y) <= 4 * (fe_error + ritz_error) * scale);
  }
}

TEST_CASE("the Ritz certificate catches spoilt answers", "[certify][ritz]") {
  const RitzAnswer good = solve_ritz(test::shipped_scene("seed_beam_end_moments"), 32);
  REQUIRE(good.solution.summary.is_usable());
  REQUIRE(certify::certify(good.model, good.solution, good.options).passed);
  const ritz::RitzModel& model = *good.solution.model;

  SECTION("amplitudes 0.1 % off: the Ritz equations and the balance") {
    RitzAnswer bad = good;
    bad.solution.unknowns.head(model.amplitudes()) *= 1.001;
    const certify::Certificate c = certify::certify(bad.model, bad.solution, bad.options);
    CHECK_FALSE(c.passed);
    CHECK_FALSE(check(c, certify::check_name::backward_error).passed);
  }
  SECTION("a contact limit moved: w is not zero there") {
    RitzAnswer bad = good;
    bad.solution.unknowns[model.limit_offset()] += 1e-3;
    const certify::Certificate c = certify::certify(bad.model, bad.solution, bad.options);
    CHECK_FALSE(c.passed);
    CHECK_FALSE(check(c, certify::check_name::complementarity).passed);
  }
}
