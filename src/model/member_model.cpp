#include "model/member_model.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/enum_names.hpp"
#include "core/error.hpp"

namespace liftoff::model {

namespace {
constexpr double degrees = std::numbers::pi / 180.0;
}

namespace {
constexpr EnumName<EndSupport> end_support_names[] = {
    {EndSupport::pinned, "pinned"},
    {EndSupport::clamped, "clamped"},
    {EndSupport::free, "free"},
    {EndSupport::roller, "roller"},
};
constexpr EnumName<LoadDirection> load_direction_names[] = {
    {LoadDirection::radial, "radial"},
    {LoadDirection::tangential, "tangential"},
    {LoadDirection::vertical, "vertical"},
    {LoadDirection::horizontal, "horizontal"},
};
constexpr EnumName<Theory> theory_names[] = {
    {Theory::linear, "linear"},
    {Theory::von_karman, "von_karman"},
};
}  // namespace

std::string_view to_string(EndSupport support) { return name_in<EndSupport>(end_support_names, support); }
std::string_view to_string(LoadDirection direction) { return name_in<LoadDirection>(load_direction_names, direction); }
std::string_view to_string(Theory theory) { return name_in<Theory>(theory_names, theory); }

double MemberModel::s_from_user(double position) const {
  return kind == StructureKind::beam ? position / scales.length : position * degrees;
}

double MemberModel::user_from_s(double s) const {
  return kind == StructureKind::beam ? s * scales.length : s / degrees;
}

double MemberLoad::wavenumber() const { return half_waves * std::numbers::pi / (to - from); }

double MemberLoad::intensity(double s) const {
  if (kind == LoadKind::sine) return value * std::sin(wavenumber() * (s - from));
  return value + slope * (s - from);
}

namespace {
// sin u - u cos u = sum_{j >= 1} (-1)^(j+1) 2j u^(2j+1) / (2j+1)!, by the series below u = 1,
// where the closed form loses (1/u)^2 of its digits; 12 terms leave < 1e-20 of u^3 / 3.
double sin_minus_u_cos(double u) {
  if (std::abs(u) >= 1.0) return std::sin(u) - u * std::cos(u);
  double term = u, sum = 0.0;  // term = (-1)^j u^(2j+1) / (2j+1)!
  for (int j = 1; j <= 12; ++j) {
    term *= -u * u / ((2.0 * j) * (2.0 * j + 1.0));
    sum -= 2.0 * j * term;
  }
  return sum;
}
}  // namespace

double MemberLoad::resultant(double a, double b) const {
  a = std::max(a, from), b = std::min(b, to);
  if (!(b > a)) return 0.0;
  if (kind != LoadKind::sine) return (b - a) * (value + slope * (0.5 * (a + b) - from));
  // int_a^b sin(k (s - f)) = (cos(k (a - f)) - cos(k (b - f))) / k, as a product of sines.
  const double k = wavenumber();
  return value * 2.0 * std::sin(0.5 * k * (a + b - 2.0 * from)) * std::sin(0.5 * k * (b - a)) / k;
}

double MemberLoad::moment_about(double x, double a, double b) const {
  a = std::max(a, from), b = std::min(b, to);
  if (!(b > a)) return 0.0;
  const double length = b - a;
  if (kind != LoadKind::sine) {
    // int_a^b (b - s)(q_b - slope (b - s)) ds with q_b the intensity at b.
    const double at_b = value + slope * (b - from);
    return (x - b) * resultant(a, b) + at_b * length * length / 2.0 - slope * length * length * length / 3.0;
  }
  // int_a^b (b - s) sin(phi_b - k (b - s)) ds, t = b - s: sin phi_b int t cos kt - cos phi_b int t sin kt,
  // int_0^L t cos kt = (kL sin kL - 2 sin^2(kL/2)) / k^2, int_0^L t sin kt = (sin kL - kL cos kL) / k^2.
  const double k = wavenumber(), phi_b = k * (b - from), u = k * length;
  const double t_cos = (u * std::sin(u) - 2.0 * std::sin(0.5 * u) * std::sin(0.5 * u)) / (k * k);
  const double t_sin = sin_minus_u_cos(u) / (k * k);
  return (x - b) * resultant(a, b) + value * (std::sin(phi_b) * t_cos - std::cos(phi_b) * t_sin);
}

namespace {
// Gauss-Legendre nodes and weights on [0, 1], m points, by Newton on P_m (to round-off).
std::vector<LoadQuadraturePoint> gauss_legendre(int m) {
  std::vector<LoadQuadraturePoint> rule(m);
  for (int i = 0; i < m; ++i) {
    double x = std::cos(std::numbers::pi * (i + 0.75) / (m + 0.5)), dp = 0.0;
    for (int iteration = 0; iteration < 100; ++iteration) {
      double p0 = 1.0, p1 = x;
      for (int j = 2; j <= m; ++j) {
        const double p2 = ((2.0 * j - 1.0) * x * p1 - (j - 1.0) * p0) / j;
        p0 = p1, p1 = p2;
      }
      dp = m * (x * p1 - p0) / (x * x - 1.0);
      const double step = p1 / dp;
      x -= step;
      if (std::abs(step) < 1e-16) break;
    }
    rule[i] = {0.5 * (1.0 - x), 1.0 / ((1.0 - x * x) * dp * dp)};  // weight 2/((1-x^2)P'^2) on [-1,1], halved
  }
  return rule;
}
}  // namespace

std::vector<LoadQuadraturePoint> load_quadrature(const MemberLoad& load, double a, double b) {
  static const std::vector<LoadQuadraturePoint> gauss5 = gauss_legendre(5), gauss8 = gauss_legendre(8);
  a = std::max(a, load.from), b = std::min(b, load.to);
  std::vector<LoadQuadraturePoint> points;
  if (!(b > a)) return points;
  int pieces = 1;
  if (load.kind == LoadKind::sine)
    pieces = std::max(1, static_cast<int>(std::ceil(load.wavenumber() * (b - a) / (0.5 * std::numbers::pi))));
  const auto& rule = load.kind == LoadKind::sine ? gauss8 : gauss5;
  const double h = (b - a) / pieces;
  for (int p = 0; p < pieces; ++p)
    for (const LoadQuadraturePoint& g : rule) points.push_back({a + (p + g.s) * h, g.weight * h});
  return points;
}

double imposed_curvature(const std::vector<MemberLoad>& loads, double s, double load_factor) {
  double kappa = 0.0;
  for (const MemberLoad& load : loads)
    if (load.kind == LoadKind::curvature && s >= load.from && s <= load.to)
      kappa += load.value * (load.load_case == LoadCase::dead ? 1.0 : load_factor);
  return kappa;
}

std::vector<FoundationPiece> MemberModel::pieces() const {
  if (!foundation_pieces.empty()) return foundation_pieces;
  return {{foundation_begin, foundation_end, k}};
}

double FoundationPiece::k_at(double s) const {
  if (!end_k) return k;
  const double t = std::clamp((s - begin) / (end - begin), 0.0, 1.0);
  return (1.0 - t) * k + t * *end_k;
}

double MemberModel::k_at(double s) const {
  for (const FoundationPiece& piece : pieces())
    if (s >= piece.begin && s <= piece.end) return piece.k_at(s);
  return 0.0;
}

std::pair<double, double> MemberModel::k_on(double a, double b) const {
  const double middle = 0.5 * (a + b);
  for (const FoundationPiece& piece : pieces())
    if (middle >= piece.begin && middle <= piece.end) return {piece.k_at(a), piece.k_at(b)};
  return {0.0, 0.0};
}

std::vector<std::pair<double, double>> MemberModel::foundation_stretches() const {
  std::vector<std::pair<double, double>> stretches;
  for (const FoundationPiece& piece : pieces()) {
    if (!stretches.empty() && piece.begin <= stretches.back().second)
      stretches.back().second = piece.end;
    else
      stretches.emplace_back(piece.begin, piece.end);
  }
  return stretches;
}

std::vector<double> MemberModel::reaction_jumps() const {
  std::vector<double> jumps;
  const std::vector<FoundationPiece> all = pieces();
  for (std::size_t i = 0; i + 1 < all.size(); ++i)
    if (all[i].end == all[i + 1].begin && all[i].k_at(all[i].end) != all[i + 1].k) jumps.push_back(all[i].end);
  for (std::size_t i = 0; i + 1 < ground_gap_at.size(); ++i)
    if (ground_gap_at[i] == ground_gap_at[i + 1] && ground_gap_value[i] != ground_gap_value[i + 1])
      jumps.push_back(ground_gap_at[i]);
  std::sort(jumps.begin(), jumps.end());
  jumps.erase(std::unique(jumps.begin(), jumps.end()), jumps.end());
  return jumps;
}

namespace {
// The piecewise linear function through (at, value) at s: constant beyond the ends, at a step
// the value to its right; 0 for an empty table.
double piecewise_linear(const std::vector<double>& at, const std::vector<double>& value, double s) {
  if (at.empty()) return 0.0;
  if (s < at.front()) return value.front();
  if (s >= at.back()) return value.back();
  const auto upper = std::upper_bound(at.begin(), at.end(), s);
  const std::size_t j = static_cast<std::size_t>(upper - at.begin()), i = j - 1;
  const double t = (s - at[i]) / (at[j] - at[i]);
  return value[i] + t * (value[j] - value[i]);
}
}  // namespace

double MemberModel::ground_gap(double s) const { return piecewise_linear(ground_gap_at, ground_gap_value, s); }

double MemberModel::initial_shape(double s) const { return piecewise_linear(initial_shape_at, initial_shape_value, s); }

double MemberModel::initial_slope(double s) const {
  if (initial_sine) {
    const InitialSine& sine = *initial_sine;
    if (s < sine.from || s >= sine.from + sine.length) return 0.0;
    const double wavenumber = std::numbers::pi / sine.length;
    return sine.amplitude * wavenumber * std::cos(wavenumber * (s - sine.from));
  }
  const std::vector<double>& at = initial_shape_at;
  if (at.empty() || s < at.front() || s >= at.back()) return 0.0;
  const auto upper = std::upper_bound(at.begin(), at.end(), s);
  const std::size_t j = static_cast<std::size_t>(upper - at.begin()), i = j - 1;
  return (initial_shape_value[j] - initial_shape_value[i]) / (at[j] - at[i]);
}

bool MemberModel::is_foundation_edge(double s) const {
  const double tol = 1e-12 * length();
  for (const auto& [a, b] : foundation_stretches())
    if (std::abs(s - a) <= tol || std::abs(s - b) <= tol) return true;
  return false;
}

bool MemberModel::has_settlements() const {
  bool any = left_settlement != 0.0 || right_settlement != 0.0;
  for (double settlement : point_settlements) any = any || settlement != 0.0;
  for (const SupportSpring& spring : springs) any = any || spring.settlement != 0.0;
  return any;
}

}  // namespace liftoff::model
