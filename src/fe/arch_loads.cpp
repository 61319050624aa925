#include "fe/arch_loads.hpp"

#include <cmath>

#include "fe/shape_functions.hpp"

namespace liftoff::fe {

Eigen::Vector2d arch_load_components(model::LoadDirection direction, model::LoadBasis per, double theta, bool outside) {
  const double c = std::cos(theta), s = std::sin(theta), inward = outside ? -1.0 : 1.0;
  Eigen::Vector2d along = Eigen::Vector2d::Zero();  // (along the inward normal, along t)
  switch (direction) {
    case model::LoadDirection::radial:
      return {1.0, 0.0};  // toward the foundation, whichever side it is on
    case model::LoadDirection::tangential:
      return {0.0, 1.0};
    case model::LoadDirection::vertical:
      along = {c, s};  // (0, -1) . n = cos theta, (0, -1) . t = sin theta
      if (per == model::LoadBasis::projection) along *= c;
      break;
    case model::LoadDirection::horizontal:
      along = {-s, c};  // (1, 0) . n = -sin theta, (1, 0) . t = cos theta
      break;
  }
  return {inward * along[0], along[1]};
}

Eigen::Matrix<double, 9, 1> arch_element_load(double s0, double h, model::LoadDirection direction, model::LoadBasis per,
                                              bool outside, const std::function<double(double)>& q) {
  Eigen::Matrix<double, 9, 1> f = Eigen::Matrix<double, 9, 1>::Zero();
  for (const GaussPoint& g : gauss5) {
    const double s = s0 + g.xi * h;
    const Eigen::Vector2d c = arch_load_components(direction, per, s, outside) * (g.weight * h * q(s));
    f.head<4>() += c[0] * hermite_cubic(g.xi, h).value;
    f.tail<5>() += c[1] * lagrange_quartic(g.xi, h).value;
  }
  return f;
}

}  // namespace liftoff::fe
