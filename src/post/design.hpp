#pragma once
// Design values of an answer (nondimensional): shear and bending moment recovered from the
// statics of the free body, and the extremes engineers check first.
//
// Beams (FE answers): V(s) and M(s) are the resultant force and moment of everything acting on
// the member from its begin up to s: the applied loads (dead + load_factor live), the
// foundation's reaction field of the discrete model (the P1 reaction of the contact conditions,
// one-sided at a jump, plus a bilinear foundation's K_t (w - g)), and the point forces and
// couples of the supports (`supports`, as the certificate computes them). Signs as in
// fields.hpp: V = dM/ds, M sagging positive; a force toward the foundation (P) makes V jump by
// -P, a support force pushing the member away (R) by +R, a counterclockwise couple C makes M jump
// by -C. Within an element every distributed force is a polynomial of degree <= 3, so V and M
// are integrated exactly (degree <= 5): at a free end they are zero to round-off when the answer
// is in equilibrium, and the closure, V and M past the member's end, says how well it is.
// Unlike -w''' per element, this V is the statics of the answer, not a derivative of its cubics.
// Second order (a beam under a compressive axial force N, MemberModel::axial_force): V stays the
// force normal to the undeformed axis, -w''' - N (w + w0)' (the supports' forces from the
// certificate, whose balance counts N's nodal forces), and M gains the axial force's moment at
// the deflected shape, M(s) = M(begin) + integral of V + N (y(s) - y(begin)), y = w + w0 the
// axis' offset from the straight line (M = -w'' still); M's extremes are where M' = V + N y'
// vanishes. w0 is taken linear on each element (exact when its table's points are nodes).
//
// Extremes: M's largest and smallest exactly (element ends and the zeros of V inside elements,
// a quartic's roots bracketed between the zeros of its derivatives); |V|'s largest (element
// ends and the zeros of the distributed force); the reaction's largest (ends and its stationary
// points); the largest uplift: the open gap g - w between the member and the ground surface
// where the member has lifted off (w < g) over the foundation's extent (without a ground gap,
// -w): what separates the member from the soil, not its upward displacement from the unloaded
// axis. No lift-off: uplift 0 with no position.
//
// Ritz beams: the same statics with the Ritz reaction integrated by quadrature (below).
// Arches: from sampled fields (design_from_samples), M and V as fields.hpp recovers them,
// extremes at the samples only.

#include <Eigen/Dense>
#include <functional>
#include <optional>
#include <vector>

#include "contact/contact_solver.hpp"
#include "fe/discretisation.hpp"
#include "model/member_model.hpp"
#include "post/fields.hpp"
#include "post/user_tables.hpp"

namespace liftoff::post {

// A support's action on the member (nondimensional, certify::SupportReaction's signs).
struct PointReaction {
  double s = 0.0;
  double force = 0.0;   // pushes the member away from the foundation
  double moment = 0.0;  // counterclockwise
};

struct Extreme {
  double value = 0.0;
  std::optional<double> s;  // where; none when there is no such point (no uplift)
};

struct DesignValues {
  Extreme moment_max, moment_min, shear_max_abs, pressure_max, uplift_max;
  // What is left past the member's end when V and M are integrated from its begin, relative to
  // the sum of the magnitudes of the forces (and moments) integrated: round-off for an answer in
  // equilibrium. -1 when not computed (samples).
  double shear_closure = -1.0, moment_closure = -1.0;
  bool from_statics = false;  // false: extremes at samples only
};

// V and M by statics at every sample of `fields` (fields.s as sample_fields makes them, with
// xi = 0 taken on the right of a node's jumps and an element's end on its left), replacing
// fields.shear_force and fields.bending_moment; returns the design values. Beams only.
DesignValues recover_beam_statics(const model::MemberModel& model, const fe::Discretisation& d,
                                  const contact::ContactSolution& solution, const std::vector<PointReaction>& supports,
                                  double load_factor, Fields* fields);

// Beams whose reaction is a function of s (the Ritz model's k w on its contact pieces): the
// same statics with the reaction integrated by Gauss-Legendre's five points between
// consecutive breakpoints (the samples, loads, supports, load ranges' and foundation pieces'
// ends, and `reaction_breaks`: the contact limits, where the reaction has a kink). M's extremes
// at the breakpoints and where V changes sign between them (bisection); |V| and the reaction's
// at the breakpoints. Replaces fields.shear_force and bending_moment (a sample at a point
// load's position takes the value right of it, the member's end the value left of its own).
DesignValues recover_beam_statics(const model::MemberModel& model, const std::function<double(double)>& reaction,
                                  const std::vector<double>& reaction_breaks,
                                  const std::vector<PointReaction>& supports, double load_factor, Fields& fields);

// Design values from sampled fields (arches): extremes at the samples.
DesignValues design_from_samples(const model::MemberModel& model, const Fields& fields);

// The design values in the user's units (user_tables.hpp).
DesignTable user_design(const DesignValues& design, const model::MemberModel& model);

}  // namespace liftoff::post
