#pragma once
// The whole state of a recorded step of a load path (TraceStep::fields, design, supports), in the
// user's units, as `liftoff solve` reports the same scene at the same lambda (the linear FE path:
// the live loads scaled by lambda; a beam-column: its axial force N(lambda) as a dead load).
//
// - Fields at every mesh node (FE) or at the elements + 1 points of a uniform grid (Ritz; solve's
//   Ritz fields hold them, every samples_per_element-th): coordinate (x, or theta in degrees), w,
//   rotation, bending moment M, shear force V, normal force N, reaction, gap, and u where the member
//   has an axial unknown (arches; von Karman beams on the FE mesh). Signs as solve's
//   (post/user_tables.hpp): w > 0 into the foundation, M sagging positive, N tension positive
//   (on a beam-column -N(lambda) all along; 0 on a beam without axial force), reaction compression
//   positive; gap = g - w where the member has lifted off the ground over the foundation (g the
//   ground gap, 0 without one), 0 in contact and off the foundation (uplift's measure, design.hpp).
//   A node where a value jumps gets the value right of it (V and M of a beam by statics at a point
//   force or support, as solve's samples there), the member's last node the value left of it; where
//   the reaction jumps (a node with two reactions), the larger (as solve's node table).
// - Design values exactly as solve's (io::SolveReport::design): FE beams by the statics of the free
//   body with the certificate's support reactions (post::recover_beam_statics: V and M at the nodes
//   are the statics' too); arches and von Karman members from their fields sampled as solve samples
//   them (samples_per_element per element), extremes at the samples; Ritz linear beams without an
//   axial force by the Ritz statics on solve's samples; none for other Ritz members (solve gives
//   none: its statics would be first order).
// - Support reactions: the certificate's (FE: the one the path certified the step with, not
//   recomputed; Ritz: certify::ritz_support_reactions, the certificate's own without its
//   half-modes solve), in the user's units.
// Cost: O(elements) per step (Ritz: O(samples x modes)), no solve.

#include <Eigen/Dense>

#include "certify/certificate.hpp"
#include "continuation/result.hpp"
#include "fe/discretisation.hpp"
#include "model/member_model.hpp"
#include "ritz/ritz_model.hpp"

namespace liftoff::continuation {

// An FE state (the linear path and beam-columns): displacement on every dof, reaction per reaction
// node, at load factor lambda, and the certificate the path certified it with.
void record_fe_state(TraceStep& step, const model::MemberModel& model, const fe::Discretisation& d, double lambda,
                     const Eigen::VectorXd& displacement, const Eigen::VectorXd& reaction,
                     const certify::Certificate& certificate);

// A von Karman FE state, as its certificate reads it (certify::VonKarmanAnswer: u at every node and
// the elements' normal forces beside w and the reactions); `certificate` null where the path does
// not certify its states (a live load the member model does not describe): no support reactions.
void record_von_karman_state(TraceStep& step, const model::MemberModel& model, const fe::Discretisation& d,
                             double lambda, const certify::VonKarmanAnswer& answer,
                             const certify::Certificate* certificate);

// A Ritz state: the unknowns x of `ritz` at lambda; `elements` is TraceOptions::elements (solve's
// Ritz samples are samples_per_element x elements + 1).
void record_ritz_state(TraceStep& step, const model::MemberModel& member, const ritz::RitzModel& ritz,
                       const Eigen::VectorXd& x, double lambda, int elements);

}  // namespace liftoff::continuation
