#pragma once
// The foundation's scale in the user's units, and the warnings it calls for.
//
// Beam: K is the foundation modulus (force per length per length), beta = (K / 4 EI)^(1/4) the
// reciprocal of the decay length of w ~ exp(-beta x) cos(beta x), and k = K L^4/EI = 4 (beta L)^4
// the nondimensional modulus the numerics see (model/member_model.hpp). beta L classes the member
// (Hetenyi): below pi/4 practically rigid, above pi the ends do not feel each other.
// Arch: k = K R^4/EI, and the matching figures are beta R = (k/4)^(1/4) (the decay per radian)
// and beta S = beta R * 2 gamma, S = 2 gamma R the arch's length. Why the same beta: with the arc
// coordinate x = R theta the arch's bending equation is the straight beam's EI w'''' + K w = q plus
// curvature terms (EI/R^2 w'', EA coupling through u) whose weight relative to K is of order
// 1/(beta R)^2, small on any foundation stiff enough to matter; beta is a scale, not a solution.
// With segments or a linear modulus every figure has a least and a largest value (the foundation
// pieces' ends); the characteristic length 1/beta is the shortest, the stiffest piece's.

#include <string>
#include <vector>

#include "model/member_model.hpp"
#include "scene/scene.hpp"

namespace liftoff::post {

struct ScaleFigures {
  bool arch = false;
  double length_scale = 0.0;   // L or R (user length)
  double member_length = 0.0;  // L, or the arch's length 2 gamma R
  // Least and largest over the foundation (every piece's ends).
  double k_min = 0.0, k_max = 0.0;                      // nondimensional K l^4/EI
  double K_min = 0.0, K_max = 0.0;                      // force per length per length
  double beta_min = 0.0, beta_max = 0.0;                // 1 / length
  double beta_length_min = 0.0, beta_length_max = 0.0;  // beta L (arch: beta S)
  double beta_radius_min = 0.0, beta_radius_max = 0.0;  // arches: beta R
  // FE: the largest beta h over the elements under the foundation (each element's own beta and
  // size h) and that element's h (user length); -1 without a mesh (Ritz).
  double beta_h = -1.0;
  double element_size = -1.0;
  int elements = -1;

  bool varies() const { return k_min != k_max; }
  double characteristic_length() const { return 1.0 / beta_max; }  // the shortest 1/beta
};

// The figures of the model's foundation; `mesh_nodes` (s, ascending) adds beta h (empty: none).
ScaleFigures scale_figures(const model::MemberModel& model, const std::vector<double>& mesh_nodes = {});

// Thresholds of the warnings (src/scene/README.md, "Scale and warnings").
inline constexpr double rigid_beta_length = 0.1;      // beta L below: practically rigid
inline constexpr double long_beta_length = 20.0;      // beta L above: suspicious if k looks like K
inline constexpr double unresolved_beta_h = 1.0;      // beta h above: the mesh misses 1/beta
inline constexpr double least_real_modulus = 1e3;     // N/m^2: soft soil under a narrow member
inline constexpr double largest_real_modulus = 1e11;  // N/m^2: rock under a wide one
inline constexpr double max_gyration_ratio = 4.0;     // sqrt(EI/EA) above L/4 (R/4): no section
inline constexpr double max_deflection_ratio = 10.0;  // |w| above L/10: no linear model
inline constexpr double soft_modulus = 1e6;           // N/m^2: soft clay under a narrow member, or softer

// One line each: a nondimensional modulus that reads like a dimensional one (or the reverse), a
// modulus outside any real bed's (only when [units] names a system), a practically rigid member,
// a mesh that does not resolve 1/beta.
// Slips of units are named where a plain number in a sibling unit (N m^2 in a kN-m scene) would
// make an implausible figure ordinary: "FILE: key 'structure.EI': EI = 5.4e+08 looks like N m^2
// in a kN-m scene: 1000x". Also a radius of gyration sqrt(EI/EA) above l/4 (only with [units]).
// Numbers written with their unit (Scene::given_with_unit) are never suspected.
std::vector<std::string> scale_warnings(const scene::Scene& scene, const model::MemberModel& model,
                                        const ScaleFigures& figures);

// With [units] stated: the answer's largest |w| (w_extreme) above the member's length / 10, with
// the slip of a plain modulus below soft_modulus that would explain it (w taken as 1/K).
std::vector<std::string> deflection_warnings(const scene::Scene& scene, const ScaleFigures& figures, double w_extreme);

}  // namespace liftoff::post
