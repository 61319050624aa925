#pragma once
// The Ritz answer's post-processing, beside the FE answer's (fields.hpp, contact_regions.hpp,
// design.hpp): its fields sampled on a uniform grid, its contact regions, and a beam's design
// values by statics. Nondimensional, as the FE ones; io converts to the user's units.

#include <vector>

#include "model/member_model.hpp"
#include "post/contact_regions.hpp"
#include "post/design.hpp"
#include "post/fields.hpp"
#include "ritz/ritz_solver.hpp"

namespace liftoff::post {

// The solution's fields at `samples` >= 2 uniform points of [s_begin, s_end]. Beams: w, its
// rotation, M and V from the modal series' derivatives; arches also u and N. Needs
// solution.model.
Fields sample_fields(const model::MemberModel& model, const ritz::RitzSolution& solution, int samples);
// The same of the state `x` of `ritz` (a load path's step, with no RitzSolution around it).
Fields sample_fields(const model::MemberModel& model, const ritz::RitzModel& ritz, const Eigen::VectorXd& x,
                     int samples);

// The contact pieces of the solution (its model's limits at its unknowns), in order along s;
// empty without a model.
std::vector<ContactRegion> contact_regions(const ritz::RitzSolution& solution);

// Beams: V and M by statics (recover_beam_statics with the Ritz reaction k w, its kinks at the
// contact limits) at `samples` uniform points, with the supports' reactions the certificate
// found; `fields` receives those samples with V and M replaced. The modal series' own
// derivatives do not converge at point loads (on the B70 sleeper |V| 46.9 kN against the
// statics' 70.0 kN).
DesignValues ritz_beam_statics(const model::MemberModel& model, const ritz::RitzSolution& solution,
                               const std::vector<PointReaction>& supports, double load_factor, int samples,
                               Fields& fields);
DesignValues ritz_beam_statics(const model::MemberModel& model, const ritz::RitzModel& ritz, const Eigen::VectorXd& x,
                               const std::vector<PointReaction>& supports, double load_factor, int samples,
                               Fields& fields);

}  // namespace liftoff::post
