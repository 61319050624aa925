#pragma once
// The seed's arch beyond linear theory (issue 16, item 6): one end condition's arch (a shipped
// seed_arch_*.toml scene) solved at a load factor lambda (the scene's live crown load times
// lambda) by linear theory (the contact solver's `fast` method) and by von Karman theory
// (contact::VonKarmanSystem with the arch's Marguerre/Donnell element), and the figures the
// report compares: the crown deflection w(0), the contact half-angle (the central contact
// region's, located at the roots of the elements' cubics as `liftoff solve` reports it) and the
// crown thrust -N(0) (compression positive). Along a load history the von Karman solve starts
// from the previous answer (its contact set too), so the branch followed is the one connected to
// the unloaded state; `stable` is the inertia test of the answer on its contact set.
//
// This is a study, not the solver: it lives in verification/ and runs liftoff's own code.

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "contact/von_karman_solve.hpp"
#include "fe/discretisation.hpp"
#include "model/member_model.hpp"
#include "scene/scene.hpp"

namespace liftoff::study {

struct ArchFigures {
  bool usable = false;
  std::string message;            // the solver's, when not usable
  double crown_deflection = 0.0;  // w(0) / R (> 0 into the foundation)
  double half_angle_deg = 0.0;    // the contact region around the crown: half its angle
  int contact_regions = 0;
  double crown_thrust = 0.0;   // -N(0) R^2 / EI (compression positive)
  bool stable = true;          // von Karman: S positive definite on the contact set
  double largest_slope = 0.0;  // max |w'| over the nodes (radians): the rotation's size, beta^2 << 1?
};

struct DepartureRow {
  double load_factor = 0.0;
  ArchFigures linear, von_karman;
  // (von Karman - linear) / linear
  double deflection() const { return von_karman.crown_deflection / linear.crown_deflection - 1.0; }
  double half_angle() const { return von_karman.half_angle_deg / linear.half_angle_deg - 1.0; }
  double thrust() const { return von_karman.crown_thrust / linear.crown_thrust - 1.0; }
};

class SeedArchStudy {
 public:
  // scene: an arch scene (its theory is ignored: both are solved); elements even (a crown node).
  SeedArchStudy(const scene::Scene& scene, int elements);
  // Linear figures at lambda: exactly lambda times those at 1 (one contact set for every lambda
  // > 0 under the crown load alone), but solved, not scaled.
  ArchFigures linear(double load_factor) const;
  // Von Karman figures at lambda, from the state `state` (updated; empty: zero) and its set.
  ArchFigures von_karman(double load_factor, contact::VonKarmanResult* state = nullptr) const;
  DepartureRow row(double load_factor, contact::VonKarmanResult* state = nullptr) const {
    DepartureRow r{load_factor, linear(load_factor), von_karman(load_factor, state)};
    return r;
  }
  const model::MemberModel& model() const { return von_karman_model_; }
  int crown_node() const { return crown_node_; }

 private:
  ArchFigures figures(const Eigen::VectorXd& every_dof, double crown_normal_force) const;
  model::MemberModel linear_model_, von_karman_model_;
  fe::Discretisation discretisation_;
  std::unique_ptr<contact::VonKarmanSystem> system_;
  int crown_node_ = 0;
};

// The load factor in [low, high] at which a relative difference (|f(lambda)|, f one of
// DepartureRow's) first reaches `level`, by bisection on the von Karman solve started from the
// answer at `low` (|f(low)| < level <= |f(high)| is required, else NaN). Ends when the bracket is
// below `resolution` (absolute, in lambda): the result is its midpoint, within resolution / 2.
double crossing(const SeedArchStudy& study, double (DepartureRow::*difference)() const, double level, double low,
                double high, double resolution, const contact::VonKarmanResult& state_at_low);

}  // namespace liftoff::study
