#include "certify/certificate.hpp"

#include <cmath>
#include <stdexcept>

#include "core/require.hpp"

namespace liftoff::certify {

const Check* Certificate::find(std::string_view name) const {
  for (const Check& check : checks)
    if (check.name == name) return &check;
  return nullptr;
}

const Check* Certificate::first_failure() const {
  for (const Check& check : checks)
    if (!check.passed) return &check;
  return nullptr;
}

void CertifyOptions::validate() const {
  require(std::isfinite(load_factor), "CertifyOptions::load_factor", "must be finite");
  require(samples_per_element >= 1, "CertifyOptions::samples_per_element", "must be >= 1");
  require(sign_floor >= 0.0 && sign_floor < 1e-3, "CertifyOptions::sign_floor", "must be in [0, 1e-3)");
  require(backward_tolerance >= 0.0 && backward_tolerance < 1.0, "CertifyOptions::backward_tolerance",
          "must be in [0, 1)");
  require(!std::isnan(discretisation_error), "CertifyOptions::discretisation_error",
          "must be a number (negative: none)");
}

std::vector<SupportReaction> user_support_reactions(const std::vector<SupportReaction>& reactions,
                                                    const model::MemberModel& model) {
  const model::Scales& scales = model.scales;
  std::vector<SupportReaction> out;
  for (const SupportReaction& r : reactions)
    out.push_back({model.user_from_s(r.at), r.force * scales.force(), r.moment * scales.moment(),
                   r.tangential * scales.force(), r.spring, r.settlement * scales.displacement()});
  return out;
}

UserFigures user_figures(const Certificate& c, const model::MemberModel& model) {
  const model::Scales& scales = model.scales;
  UserFigures u;
  u.support_reactions = user_support_reactions(c.support_reactions, model);
  u.foundation_resultant = c.foundation_resultant * scales.force();
  u.foundation_centroid = model.user_from_s(c.foundation_centroid);
  u.applied_force = c.applied_force * scales.force();
  u.applied_moment = c.applied_moment * scales.moment();
  u.foundation_resultant_x = c.foundation_resultant_x * scales.force();
  u.applied_force_x = c.applied_force_x * scales.force();
  return u;
}

}  // namespace liftoff::certify
