#include "closed_form/upheaval.hpp"

#include <cmath>

namespace liftoff::closed_form {

namespace {
// tan z = z on (pi, 3 pi / 2): Newton on f(z) = sin z - z cos z (no pole), from 4.5.
double first_root() {
  double z = 4.5;
  for (int i = 0; i < 50; ++i) {
    const double f = std::sin(z) - z * std::cos(z);
    const double df = z * std::sin(z);
    const double step = f / df;
    z -= step;
    if (std::abs(step) <= 1e-16 * z) break;
  }
  return z;
}
}  // namespace

UpheavalMode hobbs_vertical_mode() {
  UpheavalMode mode;
  mode.z = first_root();
  const double z = mode.z;
  mode.load_parameter = 4 * z * z;
  // With q = L = EI = 1: P = 4 z^2, n = 2 z.
  const double p = mode.load_parameter, n = 2 * z;
  const double b = 1.0 / (p * n * n * std::cos(z));
  const double a = -b * std::cos(z) - 1.0 / (8 * p);
  mode.uplift = -(a + b);
  mode.crown_moment = -(-b * n * n + 1.0 / p);
  return mode;
}

double hobbs_vertical_deflection(double x) {
  if (std::abs(x) >= 0.5) return 0.0;
  const UpheavalMode mode = hobbs_vertical_mode();
  const double z = mode.z, p = mode.load_parameter, n = 2 * z;
  const double b = 1.0 / (p * n * n * std::cos(z));
  const double a = -b * std::cos(z) - 1.0 / (8 * p);
  return a + b * std::cos(n * x) + x * x / (2 * p);
}

}  // namespace liftoff::closed_form
