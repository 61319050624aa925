#pragma once
// The Gauss-Legendre rule of n points on [-1, 1], nodes by Newton's method on P_n (exact to
// round-off), for tests that integrate a reference to round-off. Independent of the library's
// own fixed rules (fe/shape_functions.hpp), so that a test does not check the code with itself.

#include <cmath>
#include <numbers>
#include <vector>

namespace liftoff::test {

struct GaussRule {
  std::vector<double> x, w;  // nodes in (-1, 1), weights (sum 2)
};

inline GaussRule gauss_legendre(int n) {
  GaussRule r;
  for (int i = 1; i <= n; ++i) {
    double x = std::cos(std::numbers::pi * (i - 0.25) / (n + 0.5)), dp = 0.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = x;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (x * p1 - p0) / (x * x - 1.0);
      const double dx = p1 / dp;
      x -= dx;
      if (std::abs(dx) < 1e-16) break;
    }
    r.x.push_back(x);
    r.w.push_back(2.0 / ((1.0 - x * x) * dp * dp));
  }
  return r;
}

}  // namespace liftoff::test
