// The foundation element's flexibility with k linear on the element, against an independent
// quadrature and against closed forms of its sums.
#include "fe/foundation_element.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "fe/shape_functions.hpp"

using namespace liftoff::fe;

namespace {

constexpr double eps = std::numeric_limits<double>::epsilon();

// integral over [0, h] of phi phi^T / k, k linear from ka to kb: Gauss-Legendre's five points
// on pieces graded geometrically in k, over each of which k changes by 0.1 % at most: the pole
// of 1/k lies 2000 half-widths away, so the rule's error (Bernstein ellipse bound) is far below
// eps, and the sum of its 5 n positive terms adds at most 5 n eps relative (recursive summation).
Eigen::Matrix2d reference(double h, double ka, double kb) {
  const int pieces = std::max(1, static_cast<int>(std::ceil(std::abs(std::log(kb / ka)) / std::log(1.001))));
  Eigen::Matrix2d m = Eigen::Matrix2d::Zero();
  double x0 = 0.0;
  for (int p = 1; p <= pieces; ++p) {
    const double x1 = p == pieces ? 1.0 : (ka * std::pow(kb / ka, double(p) / pieces) - ka) / (kb - ka);
    for (const GaussPoint& g : gauss5) {
      const double xi = x0 + g.xi * (x1 - x0);
      const Eigen::Vector2d phi = reaction_shape(xi);
      m += (g.weight * (x1 - x0) * h / ((1.0 - xi) * ka + xi * kb)) * phi * phi.transpose();
    }
    x0 = x1;
  }
  return m;
}

}  // namespace

TEST_CASE("foundation flexibility with k linear on the element is its exact integral", "[fe][foundation]") {
  const double h = GENERATE(1.0, 0.013);
  // Ratios either side of the series/logarithm switch (k_end / k_begin = 1.5 and 0.5), tiny
  // variations (the series' domain, where the logarithms would cancel), and steep ones.
  const double ratio = GENERATE(1.0 + 1e-12, 1.0 + 1e-6, 1.01, 1.5, 1.5 * (1 + 1e-9), 0.5, 0.5 * (1 - 1e-9), 3.0,
                                1.0 / 3.0, 1e3, 1e-3, 1e8);
  const double ka = 2.7e4, kb = ka * ratio;
  CAPTURE(h, ratio);
  const Eigen::Matrix2d t = foundation_element::flexibility(h, ka, kb);
  const Eigen::Matrix2d expected = reference(h, ka, kb);
  const int pieces = static_cast<int>(std::ceil(std::abs(std::log(ratio)) / std::log(1.001))) + 1;
  // The closed form's few operations (each subtraction losing a factor 5 at most) and the
  // reference's summation: every entry is positive, so relative to itself.
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) CHECK(std::abs(t(i, j) - expected(i, j)) <= (64 + 5 * pieces) * eps * expected(i, j));
  CHECK(t(0, 1) == t(1, 0));
  // The sum of all entries is the integral of 1/k: h log(kb/ka) / (kb - ka) (log1p of the
  // relative change where that is small: a few eps either way).
  const double change = (kb - ka) / ka;
  const double integral = h * (std::abs(change) < 0.5 ? std::log1p(change) : std::log(kb / ka)) / (kb - ka);
  CHECK(std::abs(t.sum() - integral) <= 64 * eps * integral);
  // The reversed element is the mirrored matrix (xi -> 1 - xi).
  const Eigen::Matrix2d reversed = foundation_element::flexibility(h, kb, ka);
  CHECK(std::abs(reversed(0, 0) - t(1, 1)) <= 64 * eps * t(1, 1));
  CHECK(std::abs(reversed(1, 1) - t(0, 0)) <= 64 * eps * t(0, 0));
  CHECK(std::abs(reversed(0, 1) - t(0, 1)) <= 64 * eps * t(0, 1));
}

TEST_CASE("foundation flexibility tends to the constant form as the ends' k meet", "[fe][foundation]") {
  const double h = 0.2, k = 1e4;
  const Eigen::Matrix2d constant = foundation_element::flexibility(h, k);
  CHECK(foundation_element::flexibility(h, k, k) == constant);
  // d T / d k_end is O(h / k^2): a relative change delta of k_end moves T by less than delta |T|.
  for (double delta : {1e-15, 1e-10, 1e-5}) {
    CAPTURE(delta);
    const Eigen::Matrix2d t = foundation_element::flexibility(h, k, k * (1 + delta));
    CHECK((t - constant).cwiseAbs().maxCoeff() <= (delta + 64 * eps) * constant.maxCoeff());
  }
}
