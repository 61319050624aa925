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
