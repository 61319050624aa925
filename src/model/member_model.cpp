#include "model/member_model.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.hpp"

namespace liftoff::model {

namespace {
constexpr double degrees = std::numbers::pi / 180.0;
}

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
  return {{foundation_begin, foundation_end, foundation_modulus}};
}

double FoundationPiece::modulus_at(double s) const {
  if (!end_modulus) return modulus;
  const double t = std::clamp((s - begin) / (end - begin), 0.0, 1.0);
  return (1.0 - t) * modulus + t * *end_modulus;
}

double MemberModel::foundation_modulus_at(double s) const {
  for (const FoundationPiece& piece : pieces())
    if (s >= piece.begin && s <= piece.end) return piece.modulus_at(s);
  return 0.0;
}

std::pair<double, double> MemberModel::foundation_modulus_on(double a, double b) const {
  const double middle = 0.5 * (a + b);
  for (const FoundationPiece& piece : pieces())
    if (middle >= piece.begin && middle <= piece.end) return {piece.modulus_at(a), piece.modulus_at(b)};
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
    if (all[i].end == all[i + 1].begin && all[i].modulus_at(all[i].end) != all[i + 1].modulus)
      jumps.push_back(all[i].end);
  for (std::size_t i = 0; i + 1 < ground_gap_at.size(); ++i)
    if (ground_gap_at[i] == ground_gap_at[i + 1] && ground_gap_value[i] != ground_gap_value[i + 1])
      jumps.push_back(ground_gap_at[i]);
  std::sort(jumps.begin(), jumps.end());
  jumps.erase(std::unique(jumps.begin(), jumps.end()), jumps.end());
  return jumps;
}

double MemberModel::ground_gap(double s) const {
  if (ground_gap_at.empty()) return 0.0;
  if (s < ground_gap_at.front()) return ground_gap_value.front();
  if (s >= ground_gap_at.back()) return ground_gap_value.back();
  const auto upper = std::upper_bound(ground_gap_at.begin(), ground_gap_at.end(), s);
  const std::size_t j = static_cast<std::size_t>(upper - ground_gap_at.begin()), i = j - 1;
  const double t = (s - ground_gap_at[i]) / (ground_gap_at[j] - ground_gap_at[i]);
  return ground_gap_value[i] + t * (ground_gap_value[j] - ground_gap_value[i]);
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

MemberModel make_member_model(const scene::Scene& scene) {
  const auto& structure = scene.structure;
  MemberModel model;
  model.kind = structure.kind;
  model.scales.bending_stiffness = structure.bending_stiffness;
  if (structure.kind == StructureKind::beam) {
    model.scales.length = structure.length;
    model.s_begin = 0.0;
    model.s_end = 1.0;
  } else {
    model.scales.length = structure.radius;
    model.s_begin = -structure.half_angle_deg * degrees;
    model.s_end = structure.half_angle_deg * degrees;
    model.membrane_stiffness =
        structure.axial_stiffness.value_or(0.0) * structure.radius * structure.radius / structure.bending_stiffness;
  }
  const Scales& scales = model.scales;

  model.left = scene.supports.left;
  model.right = scene.supports.right;
  for (double position : scene.supports.interior) model.point_supports.push_back(model.s_from_user(position));
  // Springs: k_s l^3/EI, k_r l/EI; settlements in l.
  const double length = scales.length, ei = scales.bending_stiffness;
  auto spring_at = [&](double s, const scene::SupportDetail& detail) {
    return SupportSpring{s, detail.stiffness * length * length * length / ei, detail.rotational_stiffness * length / ei,
                         detail.settlement / length};
  };
  if (scene.supports.left_detail.spring) model.springs.push_back(spring_at(model.s_begin, scene.supports.left_detail));
  for (const scene::InteriorSpring& point : scene.supports.interior_springs)
    model.springs.push_back(spring_at(model.s_from_user(point.at), point.detail));
  if (scene.supports.right_detail.spring) model.springs.push_back(spring_at(model.s_end, scene.supports.right_detail));
  if (!scene.supports.left_detail.spring) model.left_settlement = scene.supports.left_detail.settlement / length;
  if (!scene.supports.right_detail.spring) model.right_settlement = scene.supports.right_detail.settlement / length;
  for (double settlement : scene.supports.interior_settlement) model.point_settlements.push_back(settlement / length);

  const auto& foundation = scene.foundation;
  const double modulus_scale = scales.bending_stiffness / std::pow(scales.length, 4);
  // The one-piece form is the one-segment case.
  const std::vector<scene::FoundationSegment> segments =
      foundation.stiffness_parameter || foundation.modulus || foundation.segments.empty()
          ? std::vector<scene::FoundationSegment>{{foundation.from, foundation.to, foundation.stiffness_parameter,
                                                   foundation.modulus}}
          : foundation.segments;
  for (const scene::FoundationSegment& segment : segments) {
    FoundationPiece piece;
    piece.begin = model.s_from_user(segment.from);
    piece.end = model.s_from_user(segment.to);
    piece.modulus = segment.stiffness_parameter ? *segment.stiffness_parameter : *segment.modulus / modulus_scale;
    if (segment.at_to)
      piece.end_modulus = segment.stiffness_parameter ? *segment.at_to : *segment.at_to / modulus_scale;
    // Abutting pieces share their end exactly (the reader made the user's values equal).
    if (!model.foundation_pieces.empty() && segment.from == segments[model.foundation_pieces.size() - 1].to)
      piece.begin = model.foundation_pieces.back().end;
    model.foundation_pieces.push_back(piece);
    model.foundation_modulus = std::max(model.foundation_modulus, piece.largest_modulus());
  }
  model.tensionless = foundation.tensionless;
  model.foundation_outside = structure.kind == StructureKind::arch && foundation.side == scene::FoundationSide::outside;
  model.foundation_begin = model.s_from_user(foundation.from);
  model.foundation_end = model.s_from_user(foundation.to);
  for (std::size_t i = 0; i < foundation.gap_at.size(); ++i) {
    model.ground_gap_at.push_back(model.s_from_user(foundation.gap_at[i]));
    model.ground_gap_value.push_back(foundation.gap_value[i] / scales.displacement());
  }
  if (foundation.tension_modulus)
    model.tension_modulus = *foundation.tension_modulus / modulus_scale;
  else if (foundation.tension_stiffness_parameter)
    model.tension_modulus = *foundation.tension_stiffness_parameter;
  // K_t = K_c on every piece: the reaction is K_c (w - g) everywhere, the bilateral foundation.
  if (model.tension_modulus > 0.0 &&
      std::all_of(model.foundation_pieces.begin(), model.foundation_pieces.end(), [&](const FoundationPiece& piece) {
        return piece.is_constant() && piece.modulus == model.tension_modulus;
      })) {
    model.tensionless = false;
    model.tension_modulus = 0.0;
  }

  for (const auto& load : scene.loads) {
    if (load.kind == LoadKind::distributed) {
      for (std::size_t i = 0; i + 1 < load.table_at.size(); ++i) {
        if (!(load.table_at[i + 1] > load.table_at[i])) continue;  // a step
        MemberLoad piece;
        piece.kind = LoadKind::uniform;
        piece.load_case = load.load_case;
        piece.direction = load.direction;
        piece.per = load.per;
        piece.from = model.s_from_user(load.table_at[i]);
        piece.to = model.s_from_user(load.table_at[i + 1]);
        piece.value = load.table_value[i] / scales.force_per_length();
        piece.slope =
            (load.table_value[i + 1] - load.table_value[i]) / scales.force_per_length() / (piece.to - piece.from);
        model.loads.push_back(piece);
      }
      continue;
    }
    MemberLoad member_load;
    member_load.kind = load.kind;
    member_load.load_case = load.load_case;
    member_load.direction = load.direction;
    member_load.per = load.per;
    member_load.at = model.s_from_user(load.at);
    member_load.from = model.s_from_user(load.from);
    member_load.to = model.s_from_user(load.to);
    switch (load.kind) {
      case LoadKind::force:
        member_load.value = load.value / scales.force();
        break;
      case LoadKind::moment:
        member_load.value = load.value / scales.moment();
        break;
      case LoadKind::uniform:
        member_load.value = load.value / scales.force_per_length();
        break;
      case LoadKind::curvature:  // 1/length -> per unit of the length scale
        member_load.value = load.value * scales.length;
        break;
      case LoadKind::distributed:  // made into uniform pieces above
        break;
    }
    model.loads.push_back(member_load);
  }
  return model;
}

}  // namespace liftoff::model
