// TrigPolynomial: exact integrals against high-order Gauss quadrature, derivatives against
// finite differences, continuity as omega -> 0, and the algebra (products, sums, composition,
// antiderivatives) against pointwise evaluation.
#include "ritz/trig_polynomial.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "support/gauss_legendre.hpp"

using namespace liftoff::ritz;

namespace {

constexpr double pi = std::numbers::pi;

// Composite 20-point Gauss with panels short enough that each holds less than one radian of
// the fastest oscillation: the quadrature error is far below round-off.
template <typename F>
double quadrature(F f, double a, double b, double omega) {
  static const liftoff::test::GaussRule rule = liftoff::test::gauss_legendre(20);
  const int panels = std::max(8, static_cast<int>(std::ceil(std::abs(b - a) * omega)) + 8);
  const double h = (b - a) / panels;
  double sum = 0.0;
  for (int p = 0; p < panels; ++p) {
    const double mid = a + (p + 0.5) * h;
    for (std::size_t i = 0; i < rule.x.size(); ++i) sum += rule.w[i] * 0.5 * h * f(mid + 0.5 * h * rule.x[i]);
  }
  return sum;
}

double term_value(const TrigTerm& t, double s) {
  const double trig = t.wave == Wave::cosine ? std::cos(t.omega * s) : std::sin(t.omega * s);
  return t.coefficient * std::pow(s, t.power) * trig;
}

}  // namespace

TEST_CASE("trig polynomial: integrals of single terms agree with Gauss quadrature", "[ritz][trig]") {
  std::mt19937 rng(20080517);
  std::uniform_real_distribution<double> position(-3.0, 3.0), unit(-1.0, 1.0);
  const std::vector<double> omegas = {0.0, 1e-9, 1e-4, 0.05, 0.3, 0.9, 1.7, 3.1, 7.0, 25.0, 120.0, 400.0};
  for (int power = 0; power <= 8; ++power) {
    for (double omega : omegas) {
      for (Wave wave : {Wave::cosine, Wave::sine}) {
        for (int trial = 0; trial < 6; ++trial) {
          double a = position(rng), b = position(rng);
          if (trial == 0) a = 0.0;       // an end at the origin
          if (trial == 1) b = a + 1e-3;  // a short interval
          const TrigTerm term{1.0 + unit(rng), power, omega, wave};
          const double exact = integral(term, a, b);
          const double reference = quadrature([&](double s) { return term_value(term, s); }, a, b, omega);
          // The natural size of the integral: |c| int_0^X s^p ds, X = max(|a|, |b|).
          const double x = std::max(std::abs(a), std::abs(b));
          const double scale = std::abs(term.coefficient) * std::pow(x, power + 1) / (power + 1);
          CAPTURE(power, omega, static_cast<int>(wave), a, b, exact, reference);
          CHECK(std::abs(exact - reference) <= 1e-13 * scale + 1e-300);
        }
      }
    }
  }
}

TEST_CASE("trig polynomial: integrals are continuous as omega -> 0", "[ritz][trig]") {
  // s^p cos(w s) = s^p - w^2 s^(p+2)/2 + ...: |I(w) - I(0)| <= w^2/2 int |s|^(p+2) and
  // |int s^p sin(w s)| <= w int |s|^(p+1); checked on both sides of the series / closed-form switch.
  const double a = -0.4, b = 1.3;
  for (int power = 0; power <= 6; ++power) {
    const double at_zero = integral(TrigTerm{1.0, power, 0.0, Wave::cosine}, a, b);
    auto abs_moment = [&](int q) { return (std::pow(std::abs(a), q + 1) + std::pow(b, q + 1)) / (q + 1); };
    for (double omega = 1.0; omega > 1e-17; omega /= 3.0) {
      const double c = integral(TrigTerm{1.0, power, omega, Wave::cosine}, a, b);
      const double s = integral(TrigTerm{1.0, power, omega, Wave::sine}, a, b);
      CAPTURE(power, omega);
      CHECK(std::abs(c - at_zero) <= 0.5 * omega * omega * abs_moment(power + 2) + 1e-15 * abs_moment(power));
      CHECK(std::abs(s) <= omega * abs_moment(power + 1) + 1e-15 * abs_moment(power));
    }
  }
  // And smooth across the switch: second differences in omega stay tiny.
  for (int power : {0, 3, 6}) {
    for (double omega = 0.2; omega < 8.0; omega += 0.01) {
      const double h = 1e-3;
      auto i = [&](double w) { return integral(TrigTerm{1.0, power, w, Wave::cosine}, a, b); };
      const double second = (i(omega + h) - 2 * i(omega) + i(omega - h)) / (h * h);
      CAPTURE(power, omega, second);
      CHECK(std::abs(second) <= 2.0 * std::pow(1.3, power + 3));  // |d2I/dw2| <= int s^(p+2)
    }
  }
}

TEST_CASE("trig polynomial: derivatives agree with central differences", "[ritz][trig]") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), omega(0.0, 12.0);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<TrigTerm> terms;
    for (int k = 0; k < 6; ++k)
      terms.push_back({unit(rng), k % 4, k == 0 ? 0.0 : omega(rng), k % 2 ? Wave::sine : Wave::cosine});
    const TrigPolynomial f(terms);
    const TrigPolynomial df = f.derivative(), d2f = f.derivative(2), d3f = f.derivative(3);
    for (double s : {-0.8, -0.1, 0.0, 0.37, 0.99}) {
      // Central difference: truncation h^2/6 |f'''| ~ 1e-10 * 12^3, round-off eps |f| / h ~ 1e-11.
      const double h = 1e-5;
      auto fd = [&](const TrigPolynomial& g) { return (g(s + h) - g(s - h)) / (2 * h); };
      CAPTURE(trial, s, f.to_string());
      CHECK(df(s) == Approx(fd(f)).margin(1e-6 * (1 + std::abs(df(s)))));
      CHECK(d2f(s) == Approx(fd(df)).margin(1e-6 * (1 + std::abs(d2f(s)))));
      CHECK(d3f(s) == Approx(fd(d2f)).margin(1e-6 * (1 + std::abs(d3f(s)))));
      CHECK(d2f(s) == Approx(df.derivative()(s)).epsilon(1e-14).margin(1e-12));
    }
  }
}

TEST_CASE("trig polynomial: products, sums, composition and antiderivatives", "[ritz][trig]") {
  const TrigPolynomial f({{0.7, 1, 2.0, Wave::cosine}, {-1.2, 0, 3.5, Wave::sine}, {0.4, 2, 0.0, Wave::cosine}});
  const TrigPolynomial g({{1.1, 0, 2.0, Wave::sine}, {0.3, 1, 5.5, Wave::cosine}, {-2.0, 0, 0.0, Wave::cosine}});
  for (double s : {-1.3, -0.2, 0.0, 0.6, 2.2}) {
    CHECK((f * g)(s) == Approx(f(s) * g(s)).epsilon(1e-13));
    CHECK((f + g)(s) == Approx(f(s) + g(s)).epsilon(1e-13));
    CHECK((f - 2.0 * g)(s) == Approx(f(s) - 2.0 * g(s)).epsilon(1e-13));
    CHECK(f.composed_affine(-0.5, 0.3)(s) == Approx(f(-0.5 * s + 0.3)).epsilon(1e-13));
    CHECK(f.antiderivative().derivative()(s) == Approx(f(s)).epsilon(1e-12));
  }
  CHECK(f.antiderivative()(1.7) - f.antiderivative()(-0.4) == Approx(f.integral(-0.4, 1.7)).epsilon(1e-12));
  CHECK((f - f).is_zero());

  // Like terms merge: sin^2(pi s) = 1/2 - 1/2 cos(2 pi s), two terms; the frequency 0 from
  // pi - pi computed in another order merges with the constant.
  const TrigPolynomial square = TrigPolynomial::sine(pi) * TrigPolynomial::sine(pi);
  REQUIRE(square.terms().size() == 2);
  CHECK(square.terms()[0].omega == 0.0);
  CHECK(square.terms()[0].coefficient == Approx(0.5));
  CHECK(square.terms()[1].omega == Approx(2 * pi));
  CHECK(square.integral(0.0, 1.0) == Approx(0.5).epsilon(1e-15));
  // A phase at a multiple of pi/2 gives one exact term: sin(3 pi s + pi/2) = cos(3 pi s).
  const TrigPolynomial shifted = TrigPolynomial::sine(3 * pi, pi / 2);
  REQUIRE(shifted.terms().size() == 1);
  CHECK(shifted.terms()[0].wave == Wave::cosine);
  // Negative frequencies fold: sin(-2 s) = -sin(2 s).
  const TrigPolynomial folded({{1.0, 0, -2.0, Wave::sine}});
  CHECK(folded.terms()[0].omega == 2.0);
  CHECK(folded.terms()[0].coefficient == -1.0);
  CHECK_THROWS_AS(TrigPolynomial({{1.0, -1, 0.0, Wave::cosine}}), std::invalid_argument);
}

TEST_CASE("trig polynomial: products of basis-like functions integrate exactly at high frequency", "[ritz][trig]") {
  // int_0^1 sin(i pi s) sin(j pi s) ds = delta_ij / 2, up to i, j = 60 (frequencies to 120 pi).
  for (int i = 1; i <= 60; i += 7) {
    for (int j = 1; j <= 60; j += 5) {
      const double value = (TrigPolynomial::sine(i * pi) * TrigPolynomial::sine(j * pi)).integral(0.0, 1.0);
      CHECK(value == Approx(i == j ? 0.5 : 0.0).margin(1e-14));
    }
  }
}

TEST_CASE("trig polynomial: values on a grid agree with pointwise values", "[ritz][trig]") {
  // Rotating the phase from point to point (re-seeded every 32 points) loses a few eps per
  // step of the run to round-off: bound it by 200 eps per unit of |c| X^p, plus the argument
  // rounding of omega s (the grid's s and value()'s s differ by an ulp or so).
  std::mt19937 random(7);
  std::uniform_real_distribution<double> coefficient(-2.0, 2.0), frequency(0.0, 120.0);
  const double a = -1.3, b = 2.1, x = 2.1;
  const int n = 400;
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<TrigTerm> terms;
    double bound = 0.0;
    for (int k = 0; k < 6; ++k) {
      const TrigTerm t{coefficient(random), k % 4, k == 0 ? 0.0 : frequency(random), k % 2 ? Wave::sine : Wave::cosine};
      terms.push_back(t);
      bound += std::abs(t.coefficient) * std::pow(x, t.power) * (200.0 + 10.0 * t.omega * x) * 2.2e-16;
    }
    const TrigPolynomial f(terms);
    const std::vector<double> values = f.values_on_grid(a, b, n);
    REQUIRE(values.size() == n + 1);
    for (int i = 0; i <= n; ++i) CHECK(std::abs(values[i] - f(a + (b - a) * i / n)) <= bound);
  }
}
