// `liftoff solve` under a sinusoidal load ([[loads]] kind = "sine", issue 16 item 5's load): FE
// (consistent load, convergence study), Ritz, the certificate and the design values against
// closed forms derived here, independent of liftoff.
//
// A simply supported beam (length L, EI) on a bilateral Winkler foundation K under
// q = q0 sin(n pi x / L) over the whole span: w = A sin(n pi x / L) satisfies w = w'' = 0 at both
// ends, and EI w'''' + K w = q gives A (EI (n pi/L)^4 + K) = q0, so
//   w(x) = q0 sin(n pi x/L) / (EI (n pi/L)^4 + K),   M = -EI w'' = EI (n pi/L)^2 w,
//   M_max = q0 EI (n pi/L)^2 / (EI (n pi/L)^4 + K) (sagging, at x = L/2 for n = 1),
//   |V|_max = EI (n pi/L)^3 A at the ends (V = M').
// A load on part of the span, q = q0 sin(m pi (x - a)/(b - a)) on [a, b], is expanded in the
// beam's modes sin(j pi x / L): q_j = (2/L) int_a^b q sin(j pi x/L) dx (product to sum: closed
// form below), w = sum_j q_j sin(j pi x/L) / (EI (j pi/L)^4 + K); q_j = O(1/j^2) (q continuous,
// with kinks at a and b), so the terms left off past J are below
// sum_{j > J} 2 q0 (b - a) / L / (EI (j pi / L)^4) <= 2 q0 (b - a) L^3 / (3 EI pi^4 J^3).

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "app/solve_command.hpp"
#include "certify/certificate.hpp"
#include "scene/scene_reader.hpp"
#include "support/scene_text.hpp"

using namespace liftoff;

namespace {

const double pi = std::acos(-1.0);

// A pinned-pinned beam, L = 2, EI = 3, K = 40 (k = K L^4 / EI = 640/3; beta L = 2.9), and the
// load given as TOML lines.
constexpr double L = 2.0, EI = 3.0, K = 40.0;
scene::Scene beam(const std::string& load, bool tensionless = false) {
  const std::string text = test::beam_text("2.0", "3.0") +
                           "modulus = 40.0\ntensionless = " + std::string(tensionless ? "true" : "false") +
                           "\n[[loads]]\n" + load;
  return scene::parse_scene(text, "sine.toml");
}

io::SolveReport solve(const scene::Scene& s, scene::Method method, int elements = 16, int modes = -1) {
  app::SolveRequest request;
  if (modes > 0) request.modes = modes;
  request.method = method;
  request.elements = elements;
  return app::solve_scene(s, request);
}

// The largest |w_h - w| over the FE nodes (or the Ritz field samples) of a report.
template <class W>
double nodal_error(const io::FieldTable& t, const W& exact) {
  double worst = 0.0;
  for (std::size_t i = 0; i < t.coordinate.size(); ++i)
    worst = std::max(worst, std::abs(t.w[i] - exact(t.coordinate[i])));
  return worst;
}

// q_j of q0 sin(m pi (x - a)/(b - a)) on [a, b]: (2/L) int_a^b sin(c (x - a)) sin(d x) dx with
// c = m pi/(b - a), d = j pi/L, = (1/L) int [cos((c - d) x - c a) - cos((c + d) x - c a)].
double coefficient(double q0, int m, double a, double b, int j) {
  const double c = m * pi / (b - a), d = j * pi / L;
  const auto cos_integral = [&](double omega) {  // int_a^b cos(omega x - c a) dx
    if (std::abs(omega) < 1e-12) return (b - a) * std::cos(omega * a - c * a);
    return (std::sin(omega * b - c * a) - std::sin(omega * a - c * a)) / omega;
  };
  return q0 / L * (cos_integral(c - d) - cos_integral(c + d));
}

}  // namespace

TEST_CASE("sine load: FE nodal w converges to the closed form, Ritz reproduces it", "[app][sine]") {
  const double q0 = 5.0;
  for (int n : {1, 2}) {
    const scene::Scene s = beam("kind = \"sine\"\nvalue = 5.0\nn = " + std::to_string(n) + "\n");
    const double r = n * pi / L, amplitude = q0 / (EI * r * r * r * r + K);
    const auto exact = [&](double x) { return amplitude * std::sin(r * x); };
    std::vector<double> errors;
    for (int elements : {8, 16, 32, 64}) {
      const io::SolveReport fe = solve(s, scene::Method::fast, elements);
      REQUIRE(fe.certified());
      errors.push_back(nodal_error(fe.nodes, exact) / amplitude);
    }
    const double order = std::log2(errors[2] / errors[3]);
    INFO("n = " << n << ", nodal errors / A on 8..64 elements: " << errors[0] << " " << errors[1] << " " << errors[2]
                << " " << errors[3] << ", observed order " << order);
    // Order 4: the Hermite cubics' energy-norm error is O(h^2) (w'' is linear per element) and a
    // nodal value's error is the energy product of that error with the error of the node's Green
    // function, O(h^2) too (without the foundation the nodal values would be exact: the Green
    // function is then a cubic per element). A linear load is exact in the consistent load; the
    // sine's quadrature error is round-off (model::load_quadrature), so nothing lowers the order.
    // Seen: n = 1: 4.6e-5, 2.8e-6, 1.8e-7, 1.1e-8 (order 4.00); n = 2 likewise.
    CHECK(order == Approx(4.0).margin(0.1));
    CHECK(std::log2(errors[1] / errors[2]) == Approx(4.0).margin(0.2));

    const io::SolveReport ritz = solve(s, scene::Method::ritz);
    REQUIRE(ritz.certified());
    CHECK(nodal_error(ritz.fields, exact) <= 1e-13 * amplitude);
  }
}

TEST_CASE("sine load: the design values against the closed form's M_max and |V|_max", "[app][sine]") {
  const double q0 = 5.0, r = pi / L, amplitude = q0 / (EI * r * r * r * r + K);
  const double moment_max = EI * r * r * amplitude, shear_max = EI * r * r * r * amplitude;
  const scene::Scene s = beam("kind = \"sine\"\nvalue = 5.0\n");
  std::vector<double> m_errors, v_errors;
  for (int elements : {16, 32, 64}) {
    const io::SolveReport fe = solve(s, scene::Method::fast, elements);
    REQUIRE(fe.design);
    REQUIRE(fe.design->from_statics);
    m_errors.push_back(std::abs(fe.design->moment_max.value - moment_max) / moment_max);
    v_errors.push_back(std::abs(fe.design->shear_max_abs.value - shear_max) / shear_max);
    // What closes at the far end is the answer's own imbalance (its certificate's balance checks,
    // which grow like the stiffness's condition, h^-3: 8e-16, 2e-14, 2e-13 seen) plus N eps of
    // the integration's rounding (as tests/post/design_test.cpp derives it).
    double balance = 0.0;
    for (const certify::Check& check : fe.certificate->checks)
      if (check.name.find("balance") != std::string::npos) balance = std::max(balance, check.value);
    const double tolerance = 4 * std::max(balance, elements * std::numeric_limits<double>::epsilon());
    CHECK(fe.design->shear_closure <= tolerance);
    CHECK(fe.design->moment_closure <= tolerance);
  }
  INFO("FE M_max errors " << m_errors[0] << " " << m_errors[1] << " " << m_errors[2] << "; |V|_max errors "
                          << v_errors[0] << " " << v_errors[1] << " " << v_errors[2]);
  CHECK(m_errors[2] < 1e-6);
  CHECK(v_errors[2] < 1e-6);
  CHECK(std::log2(m_errors[1] / m_errors[2]) > 1.9);
  const io::SolveReport ritz = solve(s, scene::Method::ritz);
  REQUIRE(ritz.design);
  INFO("Ritz M_max " << ritz.design->moment_max.value << " at " << ritz.design->moment_max.at.value_or(-1)
                     << ", closed form " << moment_max);
  CHECK(std::abs(ritz.design->moment_max.value - moment_max) <= 1e-12 * moment_max);
  CHECK(std::abs(ritz.design->moment_max.at.value() - 0.5 * L) <= 1e-6 * L);
  CHECK(std::abs(ritz.design->shear_max_abs.value - shear_max) <= 1e-12 * shear_max);
}

TEST_CASE("sine load: n = 2 on part of the span against the modal series", "[app][sine]") {
  // q0 = -3 sin(2 pi (x - 0.5)), two half-waves on [0.5, 1.5]; the series to J = 4001 terms.
  const double q0 = -3.0, a = 0.5, b = 1.5;
  const int terms = 4001;
  const auto series = [&](double x) {
    double w = 0.0;
    for (int j = 1; j <= terms; ++j) {
      const double d = j * pi / L;
      w += coefficient(q0, 2, a, b, j) * std::sin(d * x) / (EI * d * d * d * d + K);
    }
    return w;
  };
  const double tail = 2.0 * std::abs(q0) * (b - a) * L * L * L / (3.0 * EI * std::pow(pi, 4) * std::pow(terms, 3));
  const scene::Scene s = beam("kind = \"sine\"\nvalue = -3.0\nn = 2\nfrom = 0.5\nto = 1.5\n");
  // The load's kinks at a and b make the Ritz modes' coefficients decay algebraically: 48 modes
  // (the automatic choice stops earlier, at 3e-4 of max |w|).
  const io::SolveReport ritz = solve(s, scene::Method::ritz, 16, 48);
  REQUIRE(ritz.certified());
  double scale = 0.0;
  for (double x : ritz.fields.coordinate) scale = std::max(scale, std::abs(series(x)));
  const double ritz_error = nodal_error(ritz.fields, series);
  const io::SolveReport fe = solve(s, scene::Method::fast, 64);
  REQUIRE(fe.certified());
  const double fe_error = nodal_error(fe.nodes, series);
  INFO("max |w| " << scale << ", Ritz error " << ritz_error << ", FE (64) nodal error " << fe_error << ", tail "
                  << tail);
  // Seen: Ritz 4e-8, FE 3e-8 of max |w| (FE's order-4 nodal error on 64 elements is 3e-8 for the
  // full-span n = 2 load above); the series' tail is 2e-10 of it.
  CHECK(ritz_error <= 1e-7 * scale);
  CHECK(fe_error <= 1e-7 * scale);
}

TEST_CASE("sine load: a tensionless beam lifts off under two half-waves, certified by FE and Ritz", "[app][sine]") {
  const scene::Scene s = beam("kind = \"sine\"\nvalue = 5.0\nn = 2\n", true);
  const io::SolveReport fe = solve(s, scene::Method::fast, 64);
  REQUIRE(fe.certified());
  REQUIRE(fe.contact_regions.size() >= 1);
  CHECK(fe.design->uplift_max.value > 0.0);
  // The lift-off point has no closed form here: the FE limits on 64 and 256 elements converge
  // toward the Ritz limit (the distance shrinks), Ritz being exact for the load.
  const io::SolveReport ritz = solve(s, scene::Method::ritz, 16, 48);
  REQUIRE(ritz.certified());
  const io::SolveReport fine = solve(s, scene::Method::fast, 256);
  REQUIRE(fine.certified());
  REQUIRE(ritz.contact_regions.size() == fe.contact_regions.size());
  REQUIRE(fine.contact_regions.size() == fe.contact_regions.size());
  const double limit = ritz.contact_regions[0].end;
  INFO("lift-off at x = " << fe.contact_regions[0].end << " (FE 64), " << fine.contact_regions[0].end << " (FE 256), "
                          << limit << " (Ritz)");
  CHECK(ritz.contact_regions[0].begin == 0.0);
  CHECK(std::abs(fine.contact_regions[0].end - limit) < 0.25 * std::abs(fe.contact_regions[0].end - limit));
}
