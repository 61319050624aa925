#include "fe/von_karman_element.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "fe/beam_element.hpp"
#include "fe/shape_functions.hpp"

namespace liftoff::fe {

namespace von_karman_element {
InitialSlopes sample_initial_slopes(const std::function<double(double)>& initial_slope, double s0, double h) {
  InitialSlopes slopes{};
  for (int q = 0; q < quadrature_points; ++q) slopes[q] = initial_slope(s0 + gauss5[q].xi * h);
  return slopes;
}
}  // namespace von_karman_element

VonKarmanBeamElement::VonKarmanBeamElement(double h, double membrane_stiffness,
                                           von_karman_element::InitialSlopes initial_slopes)
    : h_(h), membrane_stiffness_(membrane_stiffness) {
  if (!(std::isfinite(h) && h > 0.0))
    throw std::invalid_argument("VonKarmanBeamElement: h must be > 0 and finite, got " + std::to_string(h));
  if (!(std::isfinite(membrane_stiffness) && membrane_stiffness > 0.0))
    throw std::invalid_argument("VonKarmanBeamElement: membrane_stiffness (EA L^2 / EI) must be > 0 and finite, got " +
                                std::to_string(membrane_stiffness));
  bending_ = beam_element::stiffness(h);
  geometric_ = beam_element::geometric_stiffness(h);
  initial_coupling_.setZero();
  for (int q = 0; q < von_karman_element::quadrature_points; ++q) {
    if (!std::isfinite(initial_slopes[q]))
      throw std::invalid_argument("VonKarmanBeamElement: initial_slopes[" + std::to_string(q) + "] must be finite");
    initial_coupling_ += (gauss5[q].weight * h * initial_slopes[q]) * hermite_cubic(gauss5[q].xi, h).d1;
  }
}

double VonKarmanBeamElement::membrane_strain(const Eigen::VectorXd& displacement) const {
  if (displacement.size() != dofs())
    throw std::invalid_argument("VonKarmanBeamElement: one displacement per local dof expected");
  const Eigen::Vector4d w = displacement.head<4>();
  // The condensed quintic u (header): eps is the element's mean of u' + w_0' w' + w'^2 / 2.
  return (displacement[5] - displacement[4] + initial_coupling_.dot(w) + 0.5 * w.dot(geometric_ * w)) / h_;
}

double VonKarmanBeamElement::energy(const Eigen::VectorXd& displacement) const {
  const double eps = membrane_strain(displacement);
  const Eigen::Vector4d w = displacement.head<4>();
  return 0.5 * w.dot(bending_ * w) + 0.5 * membrane_stiffness_ * h_ * eps * eps;
}

void VonKarmanBeamElement::evaluate(const ElementState& state, ElementResponse& response) const {
  const double eps = membrane_strain(state.displacement);  // checks the size
  const double normal_force = membrane_stiffness_ * eps;
  const Eigen::Vector4d w = state.displacement.head<4>();
  // h b = d (h eps) / d u_e: the w part a_0 + K_g w, the u part (-1, 1).
  Eigen::Matrix<double, 6, 1> hb;
  hb.head<4>() = initial_coupling_ + geometric_ * w;
  hb[4] = -1.0;
  hb[5] = 1.0;

  response.internal_force.resize(6);
  response.internal_force.head<4>() = bending_ * w;
  response.internal_force.tail<2>().setZero();
  response.internal_force += normal_force * hb;

  // K_t = [K_b + N K_g, 0; 0, 0] + EA h b b^T = ... + (EA / h) (h b)(h b)^T; the scale applied
  // after the outer product, so that K_t is symmetric to the last bit.
  response.tangent.resize(6, 6);
  response.tangent.noalias() = hb * hb.transpose();
  response.tangent *= membrane_stiffness_ / h_;
  response.tangent.topLeftCorner<4, 4>() += bending_ + normal_force * geometric_;
}

}  // namespace liftoff::fe
