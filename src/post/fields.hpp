#pragma once
// Fields along the member, recovered from a contact solution (nondimensional).
//
// Beams: rotation = -w' (counterclockwise), bending moment M = -(w'' + kappa_T) (sagging
// positive; kappa_T the imposed curvature of curvature loads, so M is the elastic moment and a
// free member curling freely carries none), shear V = dM/ds = -w'''; under a compressive axial
// force N (second-order theory) V = -w''' - N (w + w0)', the force normal to the undeformed axis
// (what balances the foundation's reaction and the loads: dV/ds = r - q), no longer dM/ds. Arches: rotation = -(u +
// w'), M = -(u' + w''), V = dM/ds, normal force N = EA R^2/EI (u' - w) (tension positive). The reaction is the seed's
// linear interpolation of the nodal reactions (compression positive), zero off the foundation.

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <vector>

#include "contact/contact_solver.hpp"
#include "fe/discretisation.hpp"
#include "model/member_model.hpp"
#include "post/user_tables.hpp"

namespace liftoff::post {

// The samples per element `liftoff solve` takes of an FE answer's fields (and of an arch's design
// values), at most max_field_samples points in all (HDF5 and memory stay O(1e7) bytes per field).
inline constexpr int samples_per_element = 16;
inline constexpr int max_field_samples = 2'000'000;
// `wanted` per element on `elements` elements, capped so: what solve samples.
inline int capped_samples_per_element(int elements, int wanted = samples_per_element) {
  return std::max(1, std::min(wanted, max_field_samples / std::max(1, elements)));
}

// w and u with their s-derivatives at a point of an element.
struct LocalState {
  double w = 0, dw = 0, d2w = 0, d3w = 0;
  double u = 0, du = 0, d2u = 0;
};
LocalState evaluate(const fe::Discretisation& d, const Eigen::VectorXd& displacement, int element, double xi);

struct Fields {
  std::vector<double> s;
  std::vector<double> w, rotation, bending_moment, shear_force, reaction;
  std::vector<double> u, normal_force;  // arches only (empty for beams)
};

// samples_per_element >= 1 points per element (xi = i / samples, i = 0..samples-1), plus the end,
// and at a node where the reaction jumps (two reactions) also the left element's end: s repeats there.
// load_factor scales live curvature loads (the solution's lambda).
Fields sample_fields(const model::MemberModel& model, const fe::Discretisation& d,
                     const contact::ContactSolution& solution, int samples_per_element, double load_factor = 1.0);

// The largest and smallest deflection of the discrete answer, each element's cubic maximised
// exactly (at its ends and at the zeros of w', a quadratic): a sampled maximum is off by
// O(h_sample^2) relative to the curvature, which on a fine mesh is far above the discretisation
// error (approach_slab_one_support: 2.3e-9 of max |w| at 100 elements against the closed form,
// sampled). contact_reaction_max: the largest k (w - g) on the elements the foundation acts on
// (g the ground gap of `ground`, 0 when null; k linear on an element: Newton on (k (w - g))' = 0).
struct DeflectionExtremes {
  double w_max = -INFINITY, s_at_w_max = 0, w_min = INFINITY, s_at_w_min = 0, contact_reaction_max = 0;
};
DeflectionExtremes deflection_extremes(const fe::Discretisation& d, const Eigen::VectorXd& displacement,
                                       const model::MemberModel* ground = nullptr);

// Nodal reaction interpolated at s (zero off the foundation).
double reaction_at(const fe::Discretisation& d, const Eigen::VectorXd& reaction, int element, double xi);

// A von Karman answer's membrane force in fields that sample_fields made of it (which knows the
// linear strain only). Arches: N = EA (u' - w + beta^2 / 2) at each sample (the rotation's term
// added to the linear N; fe/arch_von_karman_element.hpp). Beams: the normal force of the element
// each sample is in (`element_normal_force`, constant on an element: tension positive), and no u
// (the element's interior u is condensed out, fe/von_karman_element.hpp: u is known at the nodes).
void add_von_karman_membrane(const model::MemberModel& model, const fe::Discretisation& d,
                             const std::vector<double>& element_normal_force, Fields& fields);

// The fields in the user's units (user_tables.hpp): coordinate, w, u, rotation, M, V, N, reaction.
FieldTable user_fields(const model::MemberModel& model, const Fields& fields);

}  // namespace liftoff::post
