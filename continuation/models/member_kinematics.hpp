#pragma once
// The kinematics of an FE member on its path (continuation/models/fe_member.hpp): what differs
// between the linear, the second-order (beam-column) and the von Karman member, and nothing else.
// FeMemberPath follows every one of them through the same saddle system on its contact sets.
//
// A kinematics gives the member's unknowns x (the first `equations` of them the displacement on
// the discretisation's equations, then its own: a von Karman member's free axial displacements),
// f(x, lambda) = f_int(x, lambda) - F(lambda), its tangent df/dx and its lambda-derivative:
//   linear:        f = K x - F_dead - lambda F_live                       (one factorisation a set)
//   second order:  f = K(N(lambda)) x - F(lambda),  N = N_dead + lambda N_live, K(N) = K - N K_g,
//                  F(lambda) with the settled supports' load N(lambda) K_g u_f (proportional to
//                  lambda's part of N: settled supports under a live axial force are traced)
//   von Karman:    f = f_int(x) - F_dead - lambda F_live (contact/von_karman_solve.hpp)
// and the certificate of a state in the user's terms, the axial force a step records, the start
// (the contact solve at lambda_min) and the policies only one kinematics needs:
//  - event naming: the contact topology of the element cubics (events.hpp) for the linear and
//    second-order members, as their exact paths always named them; the node set's pieces for the
//    von Karman member (fe_member.hpp says why);
//  - weakly active nodes (second order): at a state where nodes touch with neither reaction nor
//    gap the set's tangent is not the second variation: the cone's critical load
//    (stability/critical_load.hpp) decides, and its spring set is the set a bifurcated branch
//    leaves on;
//  - a member only the foundation holds (linear): held only while compressive reactions balance
//    the loads on its free rigid motions; the load beyond which they cannot (the lift-off load)
//    is found exactly once, and the path ends there (no_equilibrium).
//
// Conditioning: the linear and second-order members take the mixed form's unknowns x = (u, m)
// (the element stress resultants beside the displacement, contact/active_set_system.hpp): the
// primal saddle matrix's condition grows like N^4 and left 3.8e-6 (relative) in the footing
// trace's final deflection at 200 elements; the mixed one's grows like N^2 (round-off). The
// primal K_t is kept for the inertia (stiffness()): an LDL^T of the mixed matrix meets its zero
// block.

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <cmath>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "certify/certificate.hpp"
#include "contact/method.hpp"
#include "continuation/result.hpp"
#include "fe/discretisation.hpp"
#include "model/member_model.hpp"
#include "stability/critical_load.hpp"

namespace liftoff::contact {
class VonKarmanSystem;
}

namespace liftoff::continuation {

enum class EventNaming { nodes, cubics };

// A state's contact set as the start found it: x on the unknowns, the reactions per node, the set.
struct KinematicsStart {
  Eigen::VectorXd x;
  Eigen::VectorXd reaction;
  std::vector<bool> in_contact;
  bool no_equilibrium = false;                          // the contact solver found none (else a failure)
  int contact_solves = 0;                               // full contact solves made
  contact::Method method = contact::Method::automatic;  // the formulation the last one used
  std::string why;                                      // when x is empty
};

// The cone's verdict at a state with weakly active nodes.
struct ConeVerdict {
  bool stable = false;
  bool known = false;
  std::vector<bool> springs;  // the cone's spring set (the nodes that push in along its mode)
};

class MemberKinematics {
 public:
  using VectorXd = Eigen::VectorXd;
  using SparseMatrix = Eigen::SparseMatrix<double>;
  MemberKinematics(const model::MemberModel& member, int elements);
  virtual ~MemberKinematics() = default;

  const model::MemberModel& member() const { return member_; }
  const fe::Discretisation& discretisation() const { return d_; }
  virtual int unknowns() const { return d_.equations; }
  // The tangent stiffness on the displacement alone (the primal K_t, whose inertia on a set is the
  // state's stability): the tangent itself unless the unknowns hold more (a mixed form's stresses).
  virtual SparseMatrix stiffness(const VectorXd& x, double lambda) const { return tangent(x, lambda); }
  // Every state is stable (a linear member: its potential is convex): no stability is computed.
  virtual bool convex() const { return false; }
  // The typical size of each unknown for a deflection w_ref (the corrector's residual scale), and
  // the metric's weight of each (a step's length: the root mean square of the displacement's
  // change over w_ref).
  virtual VectorXd typical(double w_ref) const { return VectorXd::Constant(unknowns(), w_ref); }
  virtual VectorXd metric(double w_ref) const {
    return VectorXd::Constant(unknowns(), 1.0 / (std::sqrt(static_cast<double>(unknowns())) * w_ref));
  }
  // f(x, lambda) (false if not finite), df/dx, df/dlambda.
  virtual bool force(const VectorXd& x, double lambda, VectorXd& f) const = 0;
  virtual SparseMatrix tangent(const VectorXd& x, double lambda) const = 0;
  virtual VectorXd lambda_derivative(const VectorXd& x, double lambda) const = 0;
  // F(lambda) on the unknowns (the loads' size, for an uncertified state's weights).
  virtual VectorXd load(double lambda) const = 0;
  // The compressive axial force a step records (user force units; a von Karman member's mean).
  virtual double axial_force(const VectorXd& x, double lambda) const = 0;
  // The state's certificate (certify/certificate.hpp) from its fields: x and the nodal reactions.
  // sign_floor: the path's accuracy of the contact signs (see fe_member.cpp).
  virtual certify::Certificate certificate(const VectorXd& x, const VectorXd& reaction, double lambda,
                                           double sign_floor) const = 0;
  // The whole state of a recorded step (step_state.hpp: fields at every node, design values, the
  // support reactions of `certificate`, the one the path certified the state with; null where the
  // states are not certified).
  virtual void record_state(TraceStep& step, const VectorXd& x, const VectorXd& reaction, double lambda,
                            const certify::Certificate* certificate) const = 0;
  // The contact solve at lambda (the path's start).
  virtual KinematicsStart solve(double lambda, contact::Method method) const = 0;
  virtual EventNaming naming() const { return EventNaming::cubics; }
  // The deflection the path's metric and sign units take as typical (0: from the start's state).
  virtual double reference_deflection() const { return 0.0; }
  // A state of this kinematics is re-solved exactly at a resumed step's lambda on its set (linear
  // in x at fixed lambda): a trace resumes.
  virtual bool resumable() const { return true; }
  // f is linear in x at fixed lambda and its tangent well conditioned: the corrector's Newton step
  // is exact to round-off and a state needs no polishing (fe_member.cpp, refine).
  virtual bool linear_in_state() const { return false; }
  // The corrections that polish a state are measured by the certificate's backward error (the
  // primal residual's); false: by the kinematics' own residual (a mixed form's, finer).
  virtual bool measured_by_certificate() const { return true; }
  // The branch bifurcating from the path is straight at fixed lambda (second-order theory: the
  // tangent is linear in the unknowns and the load has no part along the critical mode).
  virtual bool straight_bifurcated_branch() const { return false; }
  // Its states are certified (false under a live-load seam).
  virtual bool certified() const { return true; }
  // Weakly active nodes (nullopt: the set's inertia decides).
  virtual std::optional<ConeVerdict> cone(const std::vector<stability::NodeContact>& /*contact*/,
                                          double /*lambda*/) const {
    return std::nullopt;
  }
  // A member only the foundation holds: the load factor between from and to beyond which no
  // equilibrium exists (nullopt: none in that range, or the member is held by supports).
  virtual std::optional<double> lift_off_load(double /*from*/, double /*to*/, double /*tolerance*/) const {
    return std::nullopt;
  }

 protected:
  const model::MemberModel& member_;
  fe::Discretisation d_;
};

// A live load on a von Karman member's unknowns, built by the caller (a seam for loads the scene
// cannot describe yet, e.g. the sine load q0 sin(pi x / L)): F = lambda * live_load; empty: the
// member's own loads. Its states are not certified (the certificate's balance cannot see it).
using VonKarmanLiveLoad = std::function<Eigen::VectorXd(const fe::Discretisation&, const contact::VonKarmanSystem&)>;

// The kinematics of `member` (its theory and axial force decide) on `elements` equal elements;
// `live_load` for a von Karman member only.
std::unique_ptr<MemberKinematics> make_kinematics(const model::MemberModel& member, int elements,
                                                  const VonKarmanLiveLoad& live_load = {});

}  // namespace liftoff::continuation
