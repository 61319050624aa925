#include "post/fields.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "fe/arch_element.hpp"
#include "fe/shape_functions.hpp"

namespace liftoff::post {

using model::StructureKind;

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
  // The element's own two reactions (at a node where the reaction jumps, its side's).
  if (d.reactions() == 0 || !d.foundation_on_element[element]) return 0.0;
  const auto [first, second] = d.element_reactions(element);
  const Eigen::Vector2d shape = fe::reaction_shape(xi);
  return shape[0] * reaction[first] + shape[1] * reaction[second];
}

Fields sample_fields(const model::MemberModel& model, const fe::Discretisation& d,
                     const contact::ContactSolution& solution, int samples_per_element, double load_factor) {
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
  double kappa = 0.0;  // the element's imposed curvature (curvature ranges end at nodes)
  // Beams under an axial force N: V = -w''' - N (w' + w0'), the force normal to the undeformed
  // axis (w0' the initial shape's chord over the element, as post/design.cpp's statics take it).
  const double axial_force = arch ? 0.0 : model.axial_force(load_factor);
  double initial_slope = 0.0;
  // With the foundation outside, w > 0 is outward: the inward displacement is -w (arch_element.hpp),
  // and rotation, moment, shear and normal force keep their physical meaning.
  const double in = fe::arch_element::inward_sign(d.foundation_outside);
  auto add = [&](int element, double xi) {
    const LocalState x = evaluate_on(d, solution.displacement, element, dofs, xi);
    // An element's end is its next node exactly (the jump's two samples share their s).
    f.s.push_back(xi == 1.0 ? d.mesh.nodes[element + 1] : d.mesh.nodes[element] + xi * d.mesh.element_size(element));
    f.w.push_back(x.w);
    f.rotation.push_back(arch ? -(x.u + in * x.dw) : -x.dw);
    f.bending_moment.push_back(arch ? -(x.du + in * x.d2w) : -(x.d2w + kappa));
    f.shear_force.push_back(arch ? -(x.d2u + in * x.d3w) : -x.d3w - axial_force * (x.dw + initial_slope));
    // The total: the LCP's reaction plus a bilinear foundation's Winkler part K_t (w - g).
    const double winkler =
        d.element_tension_k[element] == 0.0 ? 0.0 : d.element_tension_k[element] * (x.w - model.ground_gap(f.s.back()));
    f.reaction.push_back(reaction_at(d, solution.reaction, element, xi) + winkler);
    if (arch) {
      f.u.push_back(x.u);
      f.normal_force.push_back(model.membrane_stiffness * (x.du - in * x.w));
    }
  };
  // Where the reaction jumps (two reactions at a node) the diagram gets both values at that s:
  // the left element's end, then the right element's start.
  std::vector<char> jumps(d.mesh.nodes.size(), 0);
  for (int i = 0; i + 1 < d.reactions(); ++i)
    if (d.reaction_nodes[i] == d.reaction_nodes[i + 1]) jumps[d.reaction_nodes[i]] = 1;
  for (int e = 0; e < elements; ++e) {
    if (e > 0 && jumps[e]) {
      dofs = d.element_dofs(e - 1);
      add(e - 1, 1.0);
    }
    dofs = d.element_dofs(e);  // once per element, not per sample
    kappa = model::imposed_curvature(model.loads, d.mesh.nodes[e] + 0.5 * d.mesh.element_size(e), load_factor);
    initial_slope =
        (model.initial_shape(d.mesh.nodes[e + 1]) - model.initial_shape(d.mesh.nodes[e])) / d.mesh.element_size(e);
    for (int i = 0; i < samples_per_element; ++i) add(e, static_cast<double>(i) / samples_per_element);
  }
  add(elements - 1, 1.0);
  return f;
}

void add_von_karman_membrane(const model::MemberModel& model, const fe::Discretisation& d,
                             const std::vector<double>& element_normal_force, Fields& fields) {
  if (d.kind == StructureKind::arch) {
    for (std::size_t i = 0; i < fields.s.size(); ++i)
      fields.normal_force[i] += 0.5 * model.membrane_stiffness * fields.rotation[i] * fields.rotation[i];
    return;
  }
  fields.normal_force.clear();
  for (double s : fields.s) fields.normal_force.push_back(element_normal_force[d.mesh.element_containing(s)]);
  fields.u.clear();
}

FieldTable user_fields(const model::MemberModel& model, const Fields& fields) {
  const model::Scales& scales = model.scales;
  const auto scaled = [](const std::vector<double>& values, double factor) {
    std::vector<double> out(values.size());
    std::transform(values.begin(), values.end(), out.begin(), [&](double v) { return v * factor; });
    return out;
  };
  FieldTable t;
  t.coordinate.resize(fields.s.size());
  std::transform(fields.s.begin(), fields.s.end(), t.coordinate.begin(),
                 [&](double s) { return model.user_from_s(s); });
  t.w = scaled(fields.w, scales.displacement());
  t.u = scaled(fields.u, scales.displacement());
  t.rotation = fields.rotation;
  t.bending_moment = scaled(fields.bending_moment, scales.moment());
  t.shear_force = scaled(fields.shear_force, scales.force());
  t.normal_force = scaled(fields.normal_force, scales.force());
  t.reaction = scaled(fields.reaction, scales.force_per_length());
  return t;
}

DeflectionExtremes deflection_extremes(const fe::Discretisation& d, const Eigen::VectorXd& displacement,
                                       const model::MemberModel* ground) {
  DeflectionExtremes x;
  for (int e = 0; e < d.mesh.elements(); ++e) {
    const double h = d.mesh.element_size(e);
    const std::vector<int> dofs = d.element_dofs(e);  // w dofs first (see evaluate)
    const Eigen::Vector4d w_dofs(displacement[dofs[0]], displacement[dofs[1]], displacement[dofs[2]],
                                 displacement[dofs[3]]);
    auto w = [&](double xi) { return fe::hermite_cubic(xi, h).value.dot(w_dofs); };
    // The ground gap g, linear on the element (0 without one): the reaction is k (w - g).
    const double g0 = ground ? ground->ground_gap_in(d.mesh.nodes[e], h, 0.0) : 0.0,
                 g1 = ground ? ground->ground_gap_in(d.mesh.nodes[e], h, 1.0) : 0.0, gs = (g1 - g0) / h;
    auto pressing = [&](double xi) { return w(xi) - ((1.0 - xi) * g0 + xi * g1); };
    // w'(xi) = a xi^2 + b xi + c, from its values at 0, 1/2, 1 (exact for a quadratic); the zeros
    // of w' - shift (shift = g' for w - g).
    const double d0 = fe::hermite_cubic(0.0, h).d1.dot(w_dofs), dm = fe::hermite_cubic(0.5, h).d1.dot(w_dofs),
                 d1 = fe::hermite_cubic(1.0, h).d1.dot(w_dofs);
    const double a = 2.0 * (d0 + d1) - 4.0 * dm, b = 4.0 * dm - 3.0 * d0 - d1;
    auto stationary = [&](double shift) {
      const double c = d0 - shift;
      std::array<double, 4> candidates{0.0, 1.0, -1.0, -1.0};
      const double scale = std::abs(a) + std::abs(b) + std::abs(c);
      if (std::abs(a) > 1e-14 * scale) {
        const double disc = b * b - 4.0 * a * c;
        if (disc >= 0.0) {  // the stable pair of roots
          const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
          candidates[2] = q / a;
          if (q != 0.0) candidates[3] = c / q;
        }
      } else if (b != 0.0) {
        candidates[2] = -c / b;
      }
      return candidates;
    };
    const std::array<double, 4> candidates = stationary(0.0);
    for (double xi : candidates) {
      if (!(xi >= 0.0 && xi <= 1.0)) continue;
      const double value = w(xi), s = d.mesh.nodes[e] + xi * h;
      if (value > x.w_max) x.w_max = value, x.s_at_w_max = s;
      if (value < x.w_min) x.w_min = value, x.s_at_w_min = s;
    }
    // The reaction k max(w - g, 0) where the foundation acts, plus the bilinear foundation's
    // K_t (w - g) (Discretisation::reaction_in).
    const fe::Discretisation::ElementK& k = d.element_k[e];
    const std::array<double, 4> pressing_candidates = gs == 0.0 ? candidates : stationary(gs);
    for (double xi : pressing_candidates)
      if (xi >= 0.0 && xi <= 1.0)
        x.contact_reaction_max = std::max(x.contact_reaction_max, d.reaction_in(e, xi, pressing(xi)));
    // k linear on the element: k (w - g) is a quartic whose maximum moves off w - g's. Newton on
    // (k (w - g))' = 0 from w - g's candidates and the middle (k the whole modulus, the bilinear
    // foundation's K_t included: where w > g the reaction is k (w - g)); every point kept is a
    // value of the reaction, so the result never exceeds the true maximum and reaches it when
    // Newton does.
    if (d.foundation_on_element[e] && k.begin != k.end) {
      const double dk = k.end - k.begin;  // per unit xi
      auto k_at = [&](double xi) { return k.at(xi) + d.element_tension_k[e]; };
      for (double xi : {pressing_candidates[2], pressing_candidates[3], 0.5}) {
        if (!(xi >= 0.0 && xi <= 1.0)) continue;
        for (int step = 0; step < 12; ++step) {
          const fe::HermiteCubic n = fe::hermite_cubic(xi, h);
          const double px = h * (n.d1.dot(w_dofs) - gs), pxx = h * h * n.d2.dot(w_dofs);
          const double g = dk * pressing(xi) + k_at(xi) * px, dg = 2.0 * dk * px + k_at(xi) * pxx;
          if (dg == 0.0) break;
          xi = std::clamp(xi - g / dg, 0.0, 1.0);
        }
        x.contact_reaction_max = std::max(x.contact_reaction_max, d.reaction_in(e, xi, pressing(xi)));
      }
    }
  }
  return x;
}

}  // namespace liftoff::post
