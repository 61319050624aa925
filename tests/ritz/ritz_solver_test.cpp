// The Ritz solver end to end: quadratic Newton convergence on the regularised system (and only
// linear on the raw gradient), agreement with fine-mesh FE + LCP on the seed scenes, modal
// convergence, and wrong topologies reported rather than returned.
#include "ritz/ritz_solver.hpp"

#include <catch2/catch.hpp>
#include <cstdio>

#include "app/solve_command.hpp"
#include "model/from_scene.hpp"
#include "nonlinear/newton.hpp"
#include "support/scenes.hpp"

using namespace liftoff;
using scene::Method;

namespace {

io::SolveReport solve(const scene::Scene& s, Method method, std::optional<int> elements = {},
                      std::optional<int> modes = {}) {
  app::SolveRequest request;
  request.method = method;
  request.elements = elements;
  request.modes = modes;
  return app::solve_scene(s, request);
}

// Order of convergence from three successive residuals r0 > r1 > r2.
double order_of(double r0, double r1, double r2) { return std::log(r2 / r1) / std::log(r1 / r0); }

// Relative residuals below this are round-off (the Jacobian's condition number times eps).
constexpr double roundoff_floor = 1e-12;

std::vector<double> above_roundoff(const std::vector<double>& history) {
  std::vector<double> above;
  for (double r : history)
    if (r > roundoff_floor) above.push_back(r);
  return above;
}

// Order from the last three residuals above round-off.
double final_order(const std::vector<double>& history) {
  const std::vector<double> above = above_roundoff(history);
  REQUIRE(above.size() >= 3);
  const std::size_t n = above.size();
  return order_of(above[n - 3], above[n - 2], above[n - 1]);
}

}  // namespace

TEST_CASE("Ritz: Newton converges quadratically on w(t) = 0, linearly on the raw gradient", "[ritz][newton]") {
  // Both from the same start: the converged limits of the second seed beam moved by 0.01 L, the
  // amplitudes minimising the energy for those limits.
  const scene::Scene s = test::shipped_scene("seed_beam_end_moments_central_load");
  const io::SolveReport converged = solve(s, Method::ritz, 50, 16);
  REQUIRE(converged.usable);
  const model::MemberModel member = model::make_member_model(s);
  const ritz::RitzModel model(member, 16, {true, 2});
  Eigen::VectorXd limits(2);
  limits << converged.contact_regions[0].end + 0.01, converged.contact_regions[1].begin - 0.01;
  const Eigen::VectorXd start = *model.minimiser_for_limits(limits, 1.0);

  auto run = [&](bool regularised) {
    Eigen::VectorXd x = start;
    nonlinear::NewtonOptions options;
    options.max_iterations = 12;
    options.globalisation = nonlinear::Globalisation::none;
    // Relative residuals, as the solver uses them: force rows by |F|, limit rows by |W|.
    const int n = model.unknowns(), a = model.amplitudes();
    options.residual_scale = Eigen::VectorXd::Constant(n, 1.0 / model.live_load().lpNorm<Eigen::Infinity>());
    options.residual_scale.tail(n - a).setConstant(1.0 / start.head(a).lpNorm<Eigen::Infinity>());
    return nonlinear::solve_newton(
        [&](const Eigen::VectorXd& y, Eigen::VectorXd& f) {
          if (!model.admissible(y)) return false;
          if (regularised)
            model.residual(y, 1.0, f);
          else
            f = model.gradient(y, 1.0);
          return true;
        },
        [&](const Eigen::VectorXd& y, const Eigen::VectorXd&, Eigen::MatrixXd& j) {
          if (regularised)
            model.jacobian(y, 1.0, j);
          else
            j = model.hessian(y, 1.0);
          return true;
        },
        x, options);
  };

  // The regularised system (w(t_m) = 0 for each limit): quadratic.
  const nonlinear::NewtonSummary quadratic = run(true);
  REQUIRE(quadratic.is_usable());
  std::printf("w(t) = 0 rows, residual history:");
  for (double r : quadratic.residual_history) std::printf(" %.1e", r);
  const double quadratic_order = final_order(quadratic.residual_history);
  std::printf("\n  observed order %.2f\n", quadratic_order);
  // The three-point estimate tends to 2 from below while the constant of r_k+1 = C r_k^2 still
  // varies; a linear method gives 1. And the contraction is quadratic: r_k+1 / r_k^2 stays
  // bounded (it would grow like 1 / r_k for linear convergence).
  CHECK(quadratic_order >= 1.6);
  const std::vector<double> r = above_roundoff(quadratic.residual_history);
  for (std::size_t k = r.size() - 2; k + 1 < r.size(); ++k) CHECK(r[k + 1] / (r[k] * r[k]) < 1e3);

  // The seed's own equations: dPi/dt = +-k/2 w(t)^2 has a double root, so Newton with the
  // exact Hessian (4.5) on the gradient (4.6) only converges linearly.
  const nonlinear::NewtonSummary raw = run(false);
  std::printf("raw gradient (4.6), residual history:");
  for (double r : raw.residual_history) std::printf(" %.1e", r);
  const auto& h = raw.residual_history;
  REQUIRE(h.size() >= 6);
  const double linear_order = order_of(h[h.size() - 3], h[h.size() - 2], h[h.size() - 1]);
  std::printf("\n  observed order %.2f\n", linear_order);
  CHECK(linear_order < 1.3);
  CHECK(raw.residual_history.size() > quadratic.residual_history.size());
}

TEST_CASE("Ritz agrees with fine-mesh FE on every contact limit of the seed scenes", "[ritz][seed]") {
  // Tolerances: 1e-4 L for beams and 1e-3 degree for the arch (the requirement), which is far
  // above both sides' own error estimates: FE at these meshes is within ~1e-5 (the convergence
  // tests), Ritz reports its last change with N.
  const auto [name, elements, tolerance] =
      GENERATE(table<std::string, int, double>({{"seed_beam_end_moments", 400, 1e-4},
                                                {"seed_beam_end_moments_central_load", 400, 1e-4},
                                                {"seed_arch_pinned", 640, 1e-3},
                                                {"seed_arch_roller", 640, 1e-3},
                                                {"seed_arch_clamped", 640, 1e-3}}));
  const scene::Scene s = test::shipped_scene(name);
  const io::SolveReport fe = solve(s, Method::dual, elements);
  const io::SolveReport ritz = solve(s, Method::ritz);
  REQUIRE(fe.usable);
  CAPTURE(name, ritz.message);
  REQUIRE(ritz.usable);
  REQUIRE(fe.contact_regions.size() == ritz.contact_regions.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < fe.contact_regions.size(); ++i)
    worst = std::max({worst, std::abs(fe.contact_regions[i].begin - ritz.contact_regions[i].begin),
                      std::abs(fe.contact_regions[i].end - ritz.contact_regions[i].end)});
  std::printf("%-36s Ritz (%d modes, est. %.1e) vs FE (%d elements): largest limit difference %.2e\n", name.c_str(),
              ritz.modes, ritz.estimated_limit_error, elements, worst);
  CHECK(worst < tolerance);
  CHECK(ritz.estimated_limit_error < tolerance);
}

TEST_CASE("Ritz: a topology that cannot exist is reported, never returned", "[ritz][failure]") {
  // The first seed beam has one contact region at the right end; ask for contact at the left.
  scene::Scene s = test::shipped_scene("seed_beam_end_moments");
  s.ritz.topology = {true, false};
  s.ritz.limits = {0.3};
  const io::SolveReport r = solve(s, Method::ritz, {}, 16);
  CAPTURE(r.termination, r.message);
  CHECK_FALSE(r.usable);
  CHECK_FALSE(r.message.empty());
}
