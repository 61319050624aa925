#include "fe/element.hpp"

#include <stdexcept>

#include "fe/arch_element.hpp"
#include "fe/beam_element.hpp"
#include "fe/foundation_element.hpp"
#include "fe/shape_functions.hpp"

namespace liftoff::fe {

LinearElement::LinearElement(Eigen::MatrixXd stiffness) : stiffness_(std::move(stiffness)) {
  if (stiffness_.rows() != stiffness_.cols()) throw std::invalid_argument("LinearElement: a square stiffness expected");
}

void LinearElement::evaluate(const ElementState& state, ElementResponse& response) const {
  if (state.displacement.size() != stiffness_.rows())
    throw std::invalid_argument("Element::evaluate: one displacement per local dof expected");
  response.internal_force.noalias() = stiffness_ * state.displacement;
  response.tangent = stiffness_;  // same size after the first call: no allocation
}

BeamElement::BeamElement(double h) : LinearElement(beam_element::stiffness(h)) {}

ArchElement::ArchElement(double h, double membrane_stiffness, bool foundation_outside)
    : LinearElement(arch_element::stiffness(h, membrane_stiffness, foundation_outside)) {}

BeamColumnElement::BeamColumnElement(double h, double axial_dead, double axial_live)
    : bending_(beam_element::stiffness(h)),
      geometric_(beam_element::geometric_stiffness(h)),
      axial_dead_(axial_dead),
      axial_live_(axial_live) {}

void BeamColumnElement::evaluate(const ElementState& state, ElementResponse& response) const {
  if (state.displacement.size() != dofs())
    throw std::invalid_argument("Element::evaluate: one displacement per local dof expected");
  response.tangent = bending_ - axial_force(state.load_factor) * geometric_;
  response.internal_force.noalias() = response.tangent * state.displacement;
}

namespace {
Eigen::Matrix4d winkler_stiffness(double h, double tension_k) {
  Eigen::Matrix4d k = Eigen::Matrix4d::Zero();
  for (const auto& point : foundation_element::winkler_rule) {  // degree 6 <= 7: exact
    const Eigen::Vector4d n_w = hermite_cubic(point.xi, h).value;
    k += (tension_k * point.weight * h) * n_w * n_w.transpose();
  }
  return k;
}
}  // namespace

WinklerElement::WinklerElement(double h, double tension_k) : LinearElement(winkler_stiffness(h, tension_k)) {}

}  // namespace liftoff::fe
