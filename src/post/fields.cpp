#include "post/fields.hpp"

#include <algorithm>
#include <cmath>

#include "fe/arch_element.hpp"
#include "fe/shape_functions.hpp"

namespace liftoff::post {

using fe::StructureKind;

namespace {

// evaluate() with the element's dofs already gathered (sampling calls it many times per element).
LocalState evaluate_on(const fe::Discretisation& d, const Eigen::VectorXd& displacement, int element,
                       const std::vector<int>& dofs, double xi) {
  const double h = d.mesh.element_size(element);
  const fe::HermiteCubic n = fe::hermite_cubic(xi, h);
  Eigen::Vector4d w_dofs;
  for (int j = 0; j < 4; ++j) w_dofs[j] = displacement[dofs[j]];
  LocalState state;
  state.w = n.value.dot(w_dofs);
  state.dw = n.d1.dot(w_dofs);
  state.d2w = n.d2.dot(w_dofs);
  state.d3w = n.d3.dot(w_dofs);
  if (d.kind == StructureKind::arch) {
    const fe::LagrangeQuartic l = fe::lagrange_quartic(xi, h);
    Eigen::Matrix<double, 5, 1> u_dofs;
    for (int j = 0; j < 5; ++j) u_dofs[j] = displacement[dofs[4 + j]];
    state.u = l.value.dot(u_dofs);
    state.du = l.d1.dot(u_dofs);
    state.d2u = l.d2.dot(u_dofs);
  }
  return state;
}

}  // namespace

LocalState evaluate(const fe::Discretisation& d, const Eigen::VectorXd& displacement, int element, double xi) {
  return evaluate_on(d, displacement, element, d.element_dofs(element), xi);
}

double reaction_at(const fe::Discretisation& d, const Eigen::VectorXd& reaction, int element, double xi) {
  // Reaction nodes are the nodes of the elements the foundation acts on (increasing): its extent,
  // or a limit-fitted solve's contact elements, in several runs.
  if (d.reactions() == 0 || !d.foundation_on_element[element]) return 0.0;
  const auto found = std::lower_bound(d.reaction_nodes.begin(), d.reaction_nodes.end(), element);
  const auto first = static_cast<int>(found - d.reaction_nodes.begin());
  const Eigen::Vector2d shape = fe::reaction_shape(xi);
  return shape[0] * reaction[first] + shape[1] * reaction[first + 1];
}

Fields sample_fields(const fe::MemberModel& model, const fe::Discretisation& d,
                     const contact::ContactSolution& solution, int samples_per_element) {
  Fields f;
  const bool arch = d.kind == StructureKind::arch;
  const int elements = d.mesh.elements();
  const std::size_t samples = static_cast<std::size_t>(elements) * samples_per_element + 1;
  for (std::vector<double>* field : {&f.s, &f.w, &f.rotation, &f.bending_moment, &f.shear_force, &f.reaction})
    field->reserve(samples);
  if (arch) {
    f.u.reserve(samples);
    f.normal_force.reserve(samples);
  }
  std::vector<int> dofs;
  // With the foundation outside, w > 0 is outward: the inward displacement is -w (arch_element.hpp),
  // and rotation, moment, shear and normal force keep their physical meaning.
  const double in = fe::arch_element::inward_sign(d.foundation_outside);
  auto add = [&](int element, double xi) {
    const LocalState x = evaluate_on(d, solution.displacement, element, dofs, xi);
    f.s.push_back(d.mesh.nodes[element] + xi * d.mesh.element_size(element));
    f.w.push_back(x.w);
    f.rotation.push_back(arch ? -(x.u + in * x.dw) : -x.dw);
    f.bending_moment.push_back(arch ? -(x.du + in * x.d2w) : -x.d2w);
    f.shear_force.push_back(arch ? -(x.d2u + in * x.d3w) : -x.d3w);
    f.reaction.push_back(reaction_at(d, solution.reaction, element, xi));
    if (arch) {
      f.u.push_back(x.u);
      f.normal_force.push_back(model.membrane_stiffness * (x.du - in * x.w));
    }
  };
  for (int e = 0; e < elements; ++e) {
    dofs = d.element_dofs(e);  // once per element, not per sample
    for (int i = 0; i < samples_per_element; ++i) add(e, static_cast<double>(i) / samples_per_element);
  }
  add(elements - 1, 1.0);
  return f;
}

DeflectionExtremes deflection_extremes(const fe::Discretisation& d, const Eigen::VectorXd& displacement,
                                       int samples_per_element) {
  DeflectionExtremes x{-INFINITY, 0.0, INFINITY, 0.0};
  const int elements = d.mesh.elements();
  for (int e = 0; e < elements; ++e) {
    const double h = d.mesh.element_size(e);
    const std::vector<int> dofs = d.element_dofs(e);  // w dofs first (see evaluate)
    const Eigen::Vector4d w_dofs(displacement[dofs[0]], displacement[dofs[1]], displacement[dofs[2]],
                                 displacement[dofs[3]]);
    for (int i = 0; i <= samples_per_element; ++i) {
      if (i == samples_per_element && e + 1 < elements) break;  // the end point once, as sample_fields
      const double xi = static_cast<double>(i) / samples_per_element;
      const double w = fe::hermite_cubic(xi, h).value.dot(w_dofs), s = d.mesh.nodes[e] + xi * h;
      if (w >= x.w_max) x.w_max = w, x.s_at_w_max = s;  // the last largest, as std::minmax_element
      if (w < x.w_min) x.w_min = w, x.s_at_w_min = s;
    }
  }
  return x;
}

}  // namespace liftoff::post
