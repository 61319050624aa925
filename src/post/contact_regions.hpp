#pragma once
// Contact regions: the parts of the foundation's extent where the member presses into it
// (w > g, the ground gap; g = 0 without one), as intervals of s whose ends are located inside elements, at the roots of
// the element's cubic deflection, not snapped to nodes. A bilateral foundation is in contact over its whole extent. No
// region spans a void between foundation pieces.

#include <Eigen/Dense>
#include <vector>

#include "core/contact_region.hpp"
#include "fe/discretisation.hpp"
#include "model/member_model.hpp"

namespace liftoff::post {

// The regions in contact (in_contact true), in s, in order.
std::vector<ContactRegion> contact_regions(const model::MemberModel& model, const fe::Discretisation& d,
                                           const Eigen::VectorXd& displacement);

}  // namespace liftoff::post
