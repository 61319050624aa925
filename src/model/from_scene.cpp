#include "model/from_scene.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace liftoff::model {

namespace {
constexpr double degrees = std::numbers::pi / 180.0;
}

StructureKind to_model(scene::StructureKind kind) {
  return kind == scene::StructureKind::beam ? StructureKind::beam : StructureKind::arch;
}

EndSupport to_model(scene::EndSupport support) {
  switch (support) {
    case scene::EndSupport::pinned:
      return EndSupport::pinned;
    case scene::EndSupport::clamped:
      return EndSupport::clamped;
    case scene::EndSupport::free:
      return EndSupport::free;
    case scene::EndSupport::roller:
      return EndSupport::roller;
  }
  throw std::logic_error("to_model: unknown end support");
}

LoadKind to_model(scene::LoadKind kind) {
  switch (kind) {
    case scene::LoadKind::force:
      return LoadKind::force;
    case scene::LoadKind::moment:
      return LoadKind::moment;
    case scene::LoadKind::uniform:
      return LoadKind::uniform;
    case scene::LoadKind::curvature:
      return LoadKind::curvature;
    case scene::LoadKind::sine:
      return LoadKind::sine;
    case scene::LoadKind::distributed:
    case scene::LoadKind::axial:
    case scene::LoadKind::temperature:
      break;
  }
  throw std::logic_error("to_model: a distributed or axial load has no model kind (uniform pieces, axial force)");
}

Theory to_model(scene::Theory theory) {
  switch (theory) {
    case scene::Theory::linear:
      return Theory::linear;
    case scene::Theory::von_karman:
      return Theory::von_karman;
  }
  throw std::logic_error("to_model: unknown theory");
}

LoadCase to_model(scene::LoadCase load_case) {
  return load_case == scene::LoadCase::dead ? LoadCase::dead : LoadCase::live;
}

LoadDirection to_model(scene::LoadDirection direction) {
  switch (direction) {
    case scene::LoadDirection::radial:
      return LoadDirection::radial;
    case scene::LoadDirection::tangential:
      return LoadDirection::tangential;
    case scene::LoadDirection::vertical:
      return LoadDirection::vertical;
    case scene::LoadDirection::horizontal:
      return LoadDirection::horizontal;
  }
  throw std::logic_error("to_model: unknown load direction");
}

LoadBasis to_model(scene::LoadBasis basis) {
  return basis == scene::LoadBasis::projection ? LoadBasis::projection : LoadBasis::arc;
}

MemberModel make_member_model(const scene::Scene& scene) {
  const auto& structure = scene.structure;
  MemberModel model;
  model.kind = to_model(structure.kind);
  model.theory = to_model(structure.theory);
  model.scales.bending_stiffness = structure.bending_stiffness;
  if (structure.kind == scene::StructureKind::beam) {
    model.scales.length = structure.length;
    model.s_begin = 0.0;
    model.s_end = 1.0;
    // The von Karman beam's membrane stiffness (the reader requires EA there); linear beams have none.
    if (structure.theory == scene::Theory::von_karman)
      model.membrane_stiffness =
          structure.axial_stiffness.value_or(0.0) * structure.length * structure.length / structure.bending_stiffness;
  } else {
    model.scales.length = structure.radius;
    model.s_begin = -structure.half_angle_deg * degrees;
    model.s_end = structure.half_angle_deg * degrees;
    model.membrane_stiffness =
        structure.axial_stiffness.value_or(0.0) * structure.radius * structure.radius / structure.bending_stiffness;
  }
  const Scales& scales = model.scales;

  model.left = to_model(scene.supports.left);
  model.right = to_model(scene.supports.right);
  model.left_axially_restrained = scene.supports.left_axially_restrained;
  model.right_axially_restrained = scene.supports.right_axially_restrained;
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
      foundation.k || foundation.modulus || foundation.segments.empty()
          ? std::vector<scene::FoundationSegment>{{foundation.from, foundation.to, foundation.k, foundation.modulus}}
          : foundation.segments;
  for (const scene::FoundationSegment& segment : segments) {
    FoundationPiece piece;
    piece.begin = model.s_from_user(segment.from);
    piece.end = model.s_from_user(segment.to);
    piece.k = segment.k ? *segment.k : *segment.modulus / modulus_scale;
    if (segment.at_to) piece.end_k = segment.k ? *segment.at_to : *segment.at_to / modulus_scale;
    // Abutting pieces share their end exactly (the reader made the user's values equal).
    if (!model.foundation_pieces.empty() && segment.from == segments[model.foundation_pieces.size() - 1].to)
      piece.begin = model.foundation_pieces.back().end;
    model.foundation_pieces.push_back(piece);
    model.k = std::max(model.k, piece.largest_k());
  }
  model.tensionless = foundation.tensionless;
  model.foundation_outside =
      structure.kind == scene::StructureKind::arch && foundation.side == scene::FoundationSide::outside;
  model.foundation_begin = model.s_from_user(foundation.from);
  model.foundation_end = model.s_from_user(foundation.to);
  for (std::size_t i = 0; i < foundation.gap_at.size(); ++i) {
    model.ground_gap_at.push_back(model.s_from_user(foundation.gap_at[i]));
    model.ground_gap_value.push_back(foundation.gap_value[i] / scales.displacement());
  }
  if (foundation.tension_modulus)
    model.tension_k = *foundation.tension_modulus / modulus_scale;
  else if (foundation.tension_k)
    model.tension_k = *foundation.tension_k;
  // K_t = K_c on every piece: the reaction is K_c (w - g) everywhere, the bilateral foundation.
  if (model.tension_k > 0.0 &&
      std::all_of(model.foundation_pieces.begin(), model.foundation_pieces.end(),
                  [&](const FoundationPiece& piece) { return piece.is_constant() && piece.k == model.tension_k; })) {
    model.tensionless = false;
    model.tension_k = 0.0;
  }

  for (std::size_t i = 0; i < scene.initial_shape.at.size(); ++i) {
    model.initial_shape_at.push_back(model.s_from_user(scene.initial_shape.at[i]));
    model.initial_shape_value.push_back(scene.initial_shape.value[i] / scales.displacement());
  }
  if (scene.initial_shape.shape == "half_sine" || scene.initial_shape.shape == "bump") {
    const double from = model.s_from_user(scene.initial_shape.from);
    model.initial_sine =
        MemberModel::InitialSine{scene.initial_shape.amplitude / scales.displacement(), from,
                                 model.s_from_user(scene.initial_shape.from + scene.initial_shape.length) - from};
  }
  for (const auto& load : scene.loads) {
    if (load.kind == scene::LoadKind::axial || load.kind == scene::LoadKind::temperature) {
      const double force = load.axial_force(structure) / scales.force();
      (load.load_case == scene::LoadCase::dead ? model.axial_dead : model.axial_live) += force;
      continue;
    }
    if (load.kind == scene::LoadKind::distributed) {
      for (std::size_t i = 0; i + 1 < load.table_at.size(); ++i) {
        if (!(load.table_at[i + 1] > load.table_at[i])) continue;  // a step
        MemberLoad piece;
        piece.kind = LoadKind::uniform;
        piece.load_case = to_model(load.load_case);
        piece.direction = to_model(load.direction);
        piece.per = to_model(load.per);
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
    member_load.kind = to_model(load.kind);  // not distributed: that one is handled above
    member_load.load_case = to_model(load.load_case);
    member_load.direction = to_model(load.direction);
    member_load.per = to_model(load.per);
    member_load.at = model.s_from_user(load.at);
    member_load.from = model.s_from_user(load.from);
    member_load.to = model.s_from_user(load.to);
    switch (load.kind) {
      case scene::LoadKind::force:
        member_load.value = load.value / scales.force();
        break;
      case scene::LoadKind::moment:
        member_load.value = load.value / scales.moment();
        break;
      case scene::LoadKind::uniform:
        member_load.value = load.value / scales.force_per_length();
        break;
      case scene::LoadKind::sine:
        member_load.value = load.value / scales.force_per_length();
        member_load.half_waves = load.half_waves;
        break;
      case scene::LoadKind::curvature:  // 1/length -> per unit of the length scale
        member_load.value = load.value * scales.length;
        break;
      case scene::LoadKind::distributed:  // made into uniform pieces above
      case scene::LoadKind::axial:        // the axial force, above
      case scene::LoadKind::temperature:
        break;
    }
    model.loads.push_back(member_load);
  }
  return model;
}

}  // namespace liftoff::model
