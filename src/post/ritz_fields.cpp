#include "post/ritz_fields.hpp"

namespace liftoff::post {

Fields sample_fields(const model::MemberModel& model, const ritz::RitzSolution& solution, int samples) {
  return sample_fields(model, *solution.model, solution.unknowns, samples);
}

Fields sample_fields(const model::MemberModel& model, const ritz::RitzModel& ritz, const Eigen::VectorXd& x,
                     int samples) {
  Fields f;
  const bool arch = ritz.is_arch();
  const std::vector<ContactRegion> pieces = ritz.contact_pieces(x);
  for (int i = 0; i < samples; ++i) {
    const double s = model.s_begin + (model.s_end - model.s_begin) * i / (samples - 1);
    const double dw = ritz.w(x, s, 1), d2w = ritz.w(x, s, 2), d3w = ritz.w(x, s, 3);
    const double u = arch ? ritz.u(x, s) : 0.0, du = arch ? ritz.u(x, s, 1) : 0.0, d2u = arch ? ritz.u(x, s, 2) : 0.0;
    f.s.push_back(s);
    f.w.push_back(ritz.w(x, s));
    f.rotation.push_back(-(u + dw));
    f.bending_moment.push_back(-(du + d2w));
    f.shear_force.push_back(-(d2u + d3w));
    f.reaction.push_back(ritz.reaction(x, s, pieces));
    if (arch) {
      f.u.push_back(u);
      f.normal_force.push_back(model.membrane_stiffness * (du - f.w.back()));
    }
  }
  return f;
}

std::vector<ContactRegion> contact_regions(const ritz::RitzSolution& solution) {
  if (!solution.model) return {};
  return solution.model->contact_pieces(solution.unknowns);
}

DesignValues ritz_beam_statics(const model::MemberModel& model, const ritz::RitzSolution& solution,
                               const std::vector<PointReaction>& supports, double load_factor, int samples,
                               Fields& fields) {
  return ritz_beam_statics(model, *solution.model, solution.unknowns, supports, load_factor, samples, fields);
}

DesignValues ritz_beam_statics(const model::MemberModel& model, const ritz::RitzModel& ritz, const Eigen::VectorXd& x,
                               const std::vector<PointReaction>& supports, double load_factor, int samples,
                               Fields& fields) {
  fields = sample_fields(model, ritz, x, samples);
  const std::vector<ContactRegion> pieces = ritz.contact_pieces(x);
  std::vector<double> limits;
  for (const ContactRegion& region : pieces) limits.insert(limits.end(), {region.begin, region.end});
  return recover_beam_statics(
      model, [&](double s) { return ritz.reaction(x, s, pieces); }, limits, supports, load_factor, fields);
}

}  // namespace liftoff::post
