#pragma once
// The closed-form problem of an FE member model (nondimensional, as the FE model sees it), for the
// tests and benchmarks that compare liftoff's beams with the exact solution. Header-only, so that
// liftoff_closed_form itself stays independent of liftoff's code.

#include "closed_form/beam_on_foundation.hpp"
#include "closed_form/scene_problem.hpp"
#include "model/member_model.hpp"

namespace liftoff::closed_form {

inline EndCondition end_condition_of(model::EndSupport e) {
  return e == model::EndSupport::clamped ? EndCondition::clamped
         : e == model::EndSupport::free  ? EndCondition::free
                                         : EndCondition::pinned;
}

inline BeamProblem problem_of(const model::MemberModel& model) {
  BeamProblem p;
  p.length = model.length();
  p.foundation_modulus = model.k;
  p.left = end_condition_of(model.left);
  p.right = end_condition_of(model.right);
  for (const auto& l : model.loads) {  // positions from the member's begin
    if (l.kind == model::LoadKind::sine)
      throw std::invalid_argument("closed_form::problem_of: a sine load, which the reference does not carry");
    if (l.kind == model::LoadKind::force) p.forces.push_back({l.at - model.s_begin, l.value});
    if (l.kind == model::LoadKind::moment) p.moments.push_back({l.at - model.s_begin, l.value});
    if (l.kind == model::LoadKind::uniform && l.slope == 0.0)
      p.uniform_loads.push_back({l.from - model.s_begin, l.to - model.s_begin, l.value});
    if (l.kind == model::LoadKind::uniform && l.slope != 0.0)  // a piece of a distributed table
      p.distributed_loads.push_back(
          {l.from - model.s_begin, l.to - model.s_begin, l.value, l.value + l.slope * (l.to - l.from)});
  }
  for (std::size_t i = 0; i < model.ground_gap_at.size(); ++i) {  // the ground gap, a table in s
    p.gap.at.push_back(model.ground_gap_at[i] - model.s_begin);
    p.gap.value.push_back(model.ground_gap_value[i]);
  }
  p.tension_modulus = model.tension_k;  // the bilinear foundation's K_t (0: tensionless)
  return p;
}

}  // namespace liftoff::closed_form
