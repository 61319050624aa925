// Stress: the Ritz model started from poor initial contact limits (bunched near one end, or
// near the middle), with the right topology. The contract (src/README.md, Ritz model): an answer is returned only
// if it is a contact solution; a start from which Newton reaches a spurious root of
// w(t_m) = 0 is reported, never returned. So every start must end either in a converged answer
// that passes the checks here (not taken from the solver: the energy's gradient in the
// amplitudes and w(t_m) = 0, the contact inequalities on a grid finer than the solver's, the
// limits against the FE-informed start and, for beams, the exact closed form), or in a refusal
// whose reason the test confirms on the returned iterate. Which starts converge is printed: the
// basin of the right root is narrower than one might hope (see the report).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <catch2/catch.hpp>
#include <cstdio>

#include "app/solve_command.hpp"
#include "closed_form/scene_problem.hpp"
#include "model/from_scene.hpp"
#include "ritz/ritz_solver.hpp"
#include "support/scenes.hpp"

using namespace liftoff;

namespace {

struct PoorStart {
  std::string scene;
  ritz::Topology topology;
  std::vector<double> limits;  // user coordinate
};

// The closed-form contact limits of a shipped beam scene (x / L), from the FE's regions.
std::vector<double> closed_form_limits(const scene::Scene& s, const io::SolveReport& good) {
  const closed_form::BeamProblem p = closed_form::problem_of(s);
  std::vector<closed_form::Interval> guess;
  for (const auto& r : good.contact_regions) guess.push_back({r.begin, r.end});
  const auto exact = closed_form::solve_tensionless(p, guess);
  REQUIRE(exact.status == closed_form::TensionlessStatus::converged);
  return exact.limits;
}

}  // namespace

TEST_CASE("stress: Ritz from poor initial limits reaches the contact solution", "[stress][ritz]") {
  const PoorStart start = GENERATE(
      PoorStart{"seed_beam_end_moments", {false, 1}, {0.01}}, PoorStart{"seed_beam_end_moments", {false, 1}, {0.5}},
      PoorStart{"seed_beam_end_moments", {false, 1}, {0.99}}, PoorStart{"seed_beam_end_moments", {false, 1}, {0.3}},
      PoorStart{"seed_beam_end_moments", {false, 1}, {0.65}},
      PoorStart{"seed_beam_end_moments_central_load", {true, 2}, {0.1, 0.9}},
      PoorStart{"seed_beam_end_moments_central_load", {true, 2}, {0.01, 0.02}},
      PoorStart{"seed_beam_end_moments_central_load", {true, 2}, {0.98, 0.99}},
      PoorStart{"seed_beam_end_moments_central_load", {true, 2}, {0.49, 0.51}},
      PoorStart{"seed_arch_roller", {false, 2}, {-9.9, -9.8}}, PoorStart{"seed_arch_roller", {false, 2}, {-0.1, 0.1}},
      PoorStart{"seed_arch_roller", {false, 2}, {-8.0, 8.0}}, PoorStart{"seed_arch_pinned", {false, 2}, {9.0, 9.5}});
  const scene::Scene s = test::shipped_scene(start.scene);
  const model::MemberModel member = model::make_member_model(s);
  std::vector<double> limits;
  for (double limit : start.limits) limits.push_back(member.s_from_user(limit));

  ritz::RitzOptions options;  // automatic modes, as `liftoff solve --method ritz`
  options.mode_tolerance = s.ritz.mode_tolerance * member.length();
  const ritz::RitzSolution poor = ritz::solve_ritz(member, start.topology, limits, options);
  CAPTURE(start.scene, fmt::format("{}", fmt::join(start.limits, ", ")), poor.summary.message);
  std::printf("Ritz from %s on %s: %s\n", fmt::format("{}", fmt::join(start.limits, ", ")).c_str(), start.scene.c_str(),
              poor.summary.brief_report().c_str());
  REQUIRE(poor.model);
  const ritz::RitzModel& model = *poor.model;
  const Eigen::VectorXd& x = poor.unknowns;
  REQUIRE(x.size() == model.unknowns());

  // Equilibrium of the Ritz model: dPi/dA = K A + k G(t) W - F, relative to |F|; the solver's
  // convergence test is a relative residual of 1e-12 (src/README.md), plus the round-off of forming it
  // (the terms of K A are each up to |K||A|).
  const int a = model.amplitudes();
  const Eigen::VectorXd gradient = model.gradient(x, 1.0).head(a);
  const Eigen::VectorXd load = model.dead_load() + model.live_load();
  const double roundoff = a * 2.2e-16 * (model.stiffness().cwiseAbs() * x.head(a).cwiseAbs()).maxCoeff();
  const bool in_equilibrium = gradient.lpNorm<Eigen::Infinity>() <= 1e-12 * load.lpNorm<Eigen::Infinity>() + roundoff;

  // The inequalities on a grid 4 times finer than the solver's, and w(t_m) = 0.
  const int samples = 20000;
  double w_scale = 0.0;
  for (int i = 0; i <= samples; ++i)
    w_scale = std::max(w_scale, std::abs(model.w(x, member.s_begin + member.length() * i / samples)));
  double worst_violation = 0.0;
  for (const ContactRegion& piece : model.pieces(x))
    for (int i = 0; i <= samples; ++i) {
      const double t = piece.begin + (piece.end - piece.begin) * i / samples;
      const double w = model.w(x, t);
      worst_violation = std::max(worst_violation, (piece.in_contact ? -w : w) / w_scale);
    }
  // w(t_m) relative to the amplitudes' size, as the solver scales its limit rows (|W|_inf).
  const double amplitude_scale = x.head(model.modes()).lpNorm<Eigen::Infinity>();
  double worst_limit_residual = 0.0;
  for (int m = 0; m < model.limits(); ++m)
    worst_limit_residual =
        std::max(worst_limit_residual, std::abs(model.w(x, x[model.limit_offset() + m])) / amplitude_scale);
  CAPTURE(gradient.lpNorm<Eigen::Infinity>() / load.lpNorm<Eigen::Infinity>(), worst_limit_residual, worst_violation);
  std::printf("  checks: dPi/dA %.1e of |F|, w(t) %.1e of |W|, worst wrong-sign w %.1e of max |w|\n",
              gradient.lpNorm<Eigen::Infinity>() / load.lpNorm<Eigen::Infinity>(), worst_limit_residual,
              worst_violation);

  if (!poor.summary.is_usable()) {
    // A refusal must be justified by the iterate it refused.
    if (poor.summary.termination == ritz::RitzTermination::inequalities_violated) {
      CHECK(worst_violation > options.inequality_tolerance);
    } else {
      CHECK((poor.summary.termination == ritz::RitzTermination::newton_failed ||
             poor.summary.termination == ritz::RitzTermination::modes_not_converged));
      CHECK((!in_equilibrium || worst_limit_residual > 1e-12 || worst_violation > options.inequality_tolerance ||
             poor.summary.termination == ritz::RitzTermination::modes_not_converged));
    }
    CHECK_FALSE(poor.summary.message.empty());
    return;
  }
  CHECK(in_equilibrium);
  CHECK(worst_limit_residual <= 1e-12);
  CHECK(worst_violation <= options.inequality_tolerance);

  // The same limits as from the FE-informed start (`liftoff solve --method ritz`), within the
  // two runs' estimated errors (both stop when the limits move less than mode_tolerance).
  app::SolveRequest request;
  request.method = scene::Method::ritz;
  const io::SolveReport good = app::solve_scene(s, request);
  REQUIRE(good.usable);
  std::vector<double> found, expected;
  for (int m = 0; m < model.limits(); ++m) found.push_back(member.user_from_s(x[model.limit_offset() + m]));
  for (const auto& region : good.contact_regions)
    for (double limit : {region.begin, region.end})
      if (limit > s.begin() + 1e-9 && limit < s.end() - 1e-9) expected.push_back(limit);
  REQUIRE(found.size() == expected.size());
  const double to_user = (s.end() - s.begin()) / member.length();  // s -> user units (L or degrees)
  const double tolerance = 3.0 * (poor.summary.estimated_limit_error * to_user + good.estimated_limit_error);
  for (std::size_t i = 0; i < found.size(); ++i) {
    CAPTURE(i, found[i], expected[i], tolerance);
    CHECK(std::abs(found[i] - expected[i]) <= tolerance);
  }
  // Beams: against the exact tensionless solution too.
  if (s.structure.kind == scene::StructureKind::beam) {
    const std::vector<double> exact = closed_form_limits(s, good);
    REQUIRE(exact.size() == found.size());
    for (std::size_t i = 0; i < found.size(); ++i) {
      CAPTURE(i, found[i], exact[i]);
      CHECK(std::abs(found[i] - exact[i]) <= 3.0 * poor.summary.estimated_limit_error * to_user);
    }
  }
}
