#pragma once
// The FE model's states in the user's terms (fe_member.hpp, member_kinematics.hpp): the TraceStep
// of a state, its certificate, and the contact solve a path starts from.

#include <Eigen/Dense>
#include <stdexcept>
#include <string>
#include <vector>

#include "certify/certificate.hpp"
#include "contact/contact_solver.hpp"
#include "continuation/events.hpp"
#include "continuation/trace.hpp"
#include "fe/discretisation.hpp"
#include "model/member_model.hpp"

namespace liftoff::continuation::fe_states {

// A fixed-set solve whose relative residual exceeds this is not trusted (as contact_solver).
inline constexpr double acceptable_residual = 1e-8;

// The step of the state (displacement on every dof, reaction per reaction node) at lambda on the
// contact set `set`: contact regions, w at the monitor and w and r at the sample points (user
// units), amplitude and lifted length (events.hpp), the set as the step's state (with a tail of
// fe_state_tail zeros, which the FE model fills). Not filled:
// axial_force, stability, iterations.
TraceStep step_of(const model::MemberModel& model, const fe::Discretisation& d, const SpecialPoints& points,
                  const TraceOptions& options, double lambda, const Eigen::VectorXd& displacement,
                  const Eigen::VectorXd& reaction, const std::vector<bool>& set);

// The certificate of the state from its own fields (src/certify: balance with the support
// reactions and K(N) at lambda, the contact inequalities at the nodes, backward error to
// acceptable_residual), returned whether it passes or not; round-off against the discretisation is
// left to the solve of the same mesh (it costs a second solve). Its signs decided no finer than
// max(acceptable_residual, sign_floor) (the engine's FE model: its own accuracy of the signs).
certify::Certificate certificate_of(const model::MemberModel& model, const fe::Discretisation& d, double lambda,
                                    const Eigen::VectorXd& displacement, const Eigen::VectorXd& reaction,
                                    double sign_floor = 0.0);

// The contact solve that gives an FE path its contact set at lambda: the Lemke LCP the trace asks
// for (dual, primal), else the sparse active-set solver (fast, with Lemke as its own fallback).
contact::ContactSolution contact_solve(const fe::Discretisation& d, contact::Method asked, double lambda);

// The contact set of a contact solution: in contact where the reaction, not the gap, is the basic
// (non-zero) one, each relative to its own size (the gap's size is that of its terms, T r and C u:
// in full contact the gaps are round-off).
std::vector<bool> contact_set_of(const fe::Discretisation& d, const contact::ContactSolution& solution);

}  // namespace liftoff::continuation::fe_states
