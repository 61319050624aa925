// Independent closed forms for the buckling of beam-columns on Winkler foundations; see
// beam_column.hpp for the physics and the derivations.
#include "closed_form/beam_column.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <utility>

namespace liftoff::closed_form {

namespace {
const double kPi = std::acos(-1.0);

bool positive(double v) { return std::isfinite(v) && v > 0.0; }

// The lift-off equation at the force P = mu^2 EI: the w' mismatch at x = a after w'' and w''' are
// matched, multiplied by the determinant of that 2 x 2 system (no poles, same roots). Also returns
// B and C2 (when the determinant is not zero).
struct Branch {
  double K, EI, q, a;

  struct Point {
    double value = 0.0, B = 0.0, C2 = 0.0, mu = 0.0, alpha = 0.0, beta = 0.0, C1 = 0.0;
  };

  Point at(double mu) const {
    Point p;
    const double P = mu * mu * EI, omega = std::sqrt(K / EI);
    p.mu = mu;
    p.alpha = std::sqrt(std::max(0.0, 0.5 * (omega - P / (2 * EI))));
    p.beta = std::sqrt(0.5 * (omega + P / (2 * EI)));
    p.C1 = -q / K;
    const double al = p.alpha, be = p.beta, c = std::cos(mu * a), s = std::sin(mu * a);
    // w'' and w''' at x = a, lifted side = contact side, in (B, C2).
    const double m00 = -mu * mu * c, m01 = 2 * al * be, r0 = (al * al - be * be) * p.C1 - q / P;
    const double m10 = mu * mu * mu * s, m11 = -(3 * al * al * be - be * be * be),
                 r1 = p.C1 * (3 * al * be * be - al * al * al);
    const double det = m00 * m11 - m01 * m10;
    const double b_det = r0 * m11 - m01 * r1, c2_det = m00 * r1 - m10 * r0;
    // w'(a): -B mu sin(mu a) + q a / P (lifted) = -alpha C1 + beta C2 (contact).
    p.value = -mu * s * b_det + (q * a / P + al * p.C1) * det - be * c2_det;
    if (det != 0.0) {
      p.B = b_det / det;
      p.C2 = c2_det / det;
    }
    return p;
  }
};

}  // namespace

StrutBuckling bilateral_pinned_strut_critical(double length, double bending_stiffness, double modulus) {
  StrutBuckling best{INFINITY, 0};
  // P(n) = EI a + K / a, a = (n pi / L)^2, is convex in a: stop once it grows.
  for (int n = 1;; ++n) {
    const double a = std::pow(n * kPi / length, 2);
    const double load = bending_stiffness * a + modulus / a;
    if (load >= best.load) break;
    best = {load, n};
  }
  return best;
}

double long_member_critical(double modulus, double bending_stiffness) {
  return 2.0 * std::sqrt(modulus * bending_stiffness);
}

double tensionless_pinned_strut_critical(double length, double bending_stiffness) {
  return kPi * kPi * bending_stiffness / (length * length);
}

namespace {
using Matrix4 = std::array<std::array<double, 4>, 4>;

Matrix4 multiply(const Matrix4& a, const Matrix4& b) {
  Matrix4 c{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k) c[i][j] += a[i][k] * b[k][j];
  return c;
}

// exp(A) by a Taylor series on A / 2^s (norm below 1/2), squared s times.
Matrix4 exponential(const Matrix4& a) {
  double norm = 0.0;
  for (const auto& row : a) {
    double sum = 0.0;
    for (double v : row) sum += std::abs(v);
    norm = std::max(norm, sum);
  }
  int squarings = 0;
  while (norm / std::ldexp(1.0, squarings) > 0.5) ++squarings;
  Matrix4 scaled = a, term{}, result{};
  for (auto& row : scaled)
    for (double& v : row) v = std::ldexp(v, -squarings);
  for (int i = 0; i < 4; ++i) term[i][i] = result[i][i] = 1.0;
  for (int n = 1; n <= 30; ++n) {
    term = multiply(term, scaled);
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) term[i][j] /= n, result[i][j] += term[i][j];
  }
  for (int i = 0; i < squarings; ++i) result = multiply(result, result);
  return result;
}

// The free-end determinant at p = P L^2 / EI for k = K L^4 / EI (x in units of L).
double free_free_determinant(double p, double k) {
  const Matrix4 a{{{0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}, {-k, 0, -p, 0}}};
  const Matrix4 transfer = exponential(a);
  // The solutions free at x = 0: y(0) = (1, 0, 0, 0) and (0, 1, 0, -p) (w'' = 0, w''' + p w' = 0).
  const std::array<std::array<double, 4>, 2> start{{{1, 0, 0, 0}, {0, 1, 0, -p}}};
  // The end conditions at x = 1: w'' and w''' + p w'.
  const std::array<std::array<double, 4>, 2> end{{{0, 0, 1, 0}, {0, p, 0, 1}}};
  double m[2][2] = {};
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) m[i][j] += end[i][r] * transfer[r][c] * start[j][c];
  return m[0][0] * m[1][1] - m[0][1] * m[1][0];
}
}  // namespace

double free_free_bilateral_critical(double length, double bending_stiffness, double modulus) {
  const double k = modulus * std::pow(length, 4) / bending_stiffness;
  if (!(k > 0.0 && k <= 1e4) || !positive(length) || !positive(bending_stiffness)) return std::nan("");
  const double highest = k / 12.0 * (1.0 + 1e-6);
  constexpr int samples = 4000;
  double lo = 0.0, f_lo = free_free_determinant(0.0, k);
  for (int i = 1; i <= samples; ++i) {
    const double hi = highest * i / samples, f_hi = free_free_determinant(hi, k);
    if ((f_lo > 0.0) != (f_hi > 0.0)) {
      double a = lo, b = hi;
      for (int n = 0; n < 200 && b - a > 1e-15 * b; ++n) {
        const double mid = 0.5 * (a + b), f_mid = free_free_determinant(mid, k);
        ((f_mid > 0.0) == (f_lo > 0.0) ? a : b) = mid;
      }
      return 0.5 * (a + b) * bending_stiffness / (length * length);
    }
    lo = hi, f_lo = f_hi;
  }
  return std::nan("");
}

std::string to_string(BuckleStatus status) {
  constexpr std::pair<BuckleStatus, const char*> names[] = {
      {BuckleStatus::found, "found"},
      {BuckleStatus::no_root, "no root"},
      {BuckleStatus::secondary_lift_off, "secondary lift-off"},
      {BuckleStatus::inadmissible, "inadmissible"},
      {BuckleStatus::invalid_input, "invalid input"},
  };
  for (const auto& [value, name] : names)
    if (value == status) return name;
  return "unknown";
}

double LocalizedBuckle::deflection(double x) const {
  x = std::abs(x);
  if (x < half_length) return A + B * std::cos(mu * x) + q * x * x / (2 * axial_force);
  const double s = x - half_length;
  return q / K + std::exp(-alpha * s) * (C1 * std::cos(beta * s) + C2 * std::sin(beta * s));
}

LocalizedBuckle localized_buckle(double modulus, double bending_stiffness, double weight, double half_length) {
  LocalizedBuckle out;
  if (!positive(modulus) || !positive(bending_stiffness) || !positive(weight) || !positive(half_length)) {
    out.message = "localized_buckle: K, EI, q and a must be positive and finite";
    return out;
  }
  const double K = modulus, EI = bending_stiffness, q = weight, a = half_length;
  const Branch branch{K, EI, q, a};
  out.half_length = a;
  out.q = q;
  out.EI = EI;
  out.K = K;
  // Scan mu = sqrt(P / EI) over (0, mu_max), mu_max^2 EI = 2 sqrt(K EI), in steps of mu a <= 0.01
  // (the roots are about pi / a apart), for the least sign change; then bisection to round-off.
  const double mu_max = std::sqrt(2.0 * std::sqrt(K / EI));
  const int n = std::max(2000, static_cast<int>(std::ceil(100.0 * mu_max * a)));
  double lo = 0.0, hi = 0.0, g_lo = 0.0;
  bool bracketed = false;
  double prev_mu = mu_max * 1e-6, prev_g = branch.at(prev_mu).value;
  for (int i = 1; i <= n && !bracketed; ++i) {
    const double mu = i == n ? mu_max * (1.0 - 1e-14) : mu_max * (1e-6 + (1.0 - 1e-6) * i / n);
    const double g = branch.at(mu).value;
    if ((g < 0.0) != (prev_g < 0.0)) {
      lo = prev_mu;
      hi = mu;
      g_lo = prev_g;
      bracketed = true;
    }
    prev_mu = mu;
    prev_g = g;
  }
  if (!bracketed) {
    out.status = BuckleStatus::no_root;
    out.message = "localized_buckle: no root of the lift-off equation below 2 sqrt(K EI)";
    return out;
  }
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    const double g = branch.at(mid).value;
    if ((g < 0.0) == (g_lo < 0.0))
      lo = mid, g_lo = g;
    else
      hi = mid;
  }
  const Branch::Point p = branch.at(0.5 * (lo + hi));
  out.mu = p.mu;
  out.alpha = p.alpha;
  out.beta = p.beta;
  out.axial_force = p.mu * p.mu * EI;
  out.B = p.B;
  out.C1 = p.C1;
  out.C2 = p.C2;
  out.A = -p.B * std::cos(p.mu * a) - q * a * a / (2 * out.axial_force);
  out.uplift = -(out.A + out.B);
  out.amplitude = out.A + out.B - q / K;
  out.crown_moment = -EI * (-out.B * p.mu * p.mu + q / out.axial_force);
  // Sign conditions: w <= 0 lifted, w >= 0 in contact (over 30 decay lengths; at most 2e5 samples).
  const double scale = q / K + std::abs(out.uplift);
  double lifted = 0.0, tail = 0.0;
  for (int i = 0; i <= 2000; ++i) lifted = std::max(lifted, out.deflection(a * i / 2000.0) / scale);
  const double reach = std::min(30.0 / std::max(p.alpha, 1e-300), 1e6 * a);
  const int samples = static_cast<int>(std::min(2e5, std::max(2000.0, 40.0 * p.beta * reach)));
  for (int i = 0; i <= samples; ++i) tail = std::max(tail, -out.deflection(a + reach * i / samples) / scale);
  out.tail_dip = tail;
  out.max_violation = std::max(lifted, tail);
  const double worst = out.max_violation;
  std::ostringstream msg;
  msg << "P = " << out.axial_force << " (" << out.axial_force / long_member_critical(K, EI)
      << " of 2 sqrt(K EI)), uplift " << out.uplift << ", wrong-sign |w| " << worst << " of q/K + uplift";
  out.message = msg.str();
  out.status = lifted > 1e-9 ? BuckleStatus::inadmissible
               : tail > 1e-9 ? BuckleStatus::secondary_lift_off
                             : BuckleStatus::found;
  return out;
}

}  // namespace liftoff::closed_form
