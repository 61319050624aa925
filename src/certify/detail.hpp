#pragma once
// What the FE and Ritz certificates share: the tolerances' constants, compensated sums, the
// supports and loads of the member read again from the model, the rigid motions of the balance.
// Internal to liftoff_certify.

#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <limits>
#include <string_view>
#include <vector>

#include "certify/certificate.hpp"

namespace liftoff::certify::detail {

inline constexpr double eps = std::numeric_limits<double>::epsilon();
// A backward-stable solve leaves a row residual of a few eps of the row's terms, and computing
// the residual again sums at most ~20 terms (two arch elements, the foundation, the load):
// 64 eps covers both with room.
inline constexpr double backward_tolerance = 64 * eps;
// Evaluating a field (w from four Hermite dofs, the gap from ten quadrature terms) rounds a few
// times: the least error an answer's pointwise values carry.
inline constexpr double minimum_round_off = 16 * eps;
// Sign conditions may be violated by the answer's round-off: this many times it.
inline constexpr double sign_safety = 8.0;
// Below a thousand ulps neither a round-off nor a discretisation error means anything (the
// element data are rounded at a few ulps; the summary prints eight digits).
inline constexpr double meaningless_error = 1024 * eps;
// A round-off below this fraction of max |w| (or max |r|) is accepted even where the
// discretisation error is smaller (a member the elements represent exactly: a lifted-off beam
// under end moments has a cubic w, and its "discretisation error" is round-off itself): six
// digits, the accuracy the solvers have always promised (contact_solver's acceptable residual
// and refinement error are 1e-6 too). Above it, round-off that exceeds the discretisation error
// means the mesh is finer than double precision can use.
inline constexpr double negligible_error = 1e-6;
// No check passes with a value above this fraction of its terms, whatever its own tolerance: a
// round-off or truncation estimate that large says the answer (and the estimate, made from an
// answer as bad) is noise. The fuzzer's arch with k = 6e16 had an "equilibrium" whose assembly
// rounding was as large as the load, and an imbalance of 100 % within that tolerance.
inline constexpr double largest_certifiable_error = 1e-3;

// Twice-the-working-precision accumulation: Ogita, Rump & Oishi's Dot2 (TwoSum and an FMA
// TwoProduct), so a residual that cancels terms ~N^4 larger than itself keeps its digits.
struct Compensated {
  double sum = 0.0, error = 0.0;
  void add(double x) {
    const double s = sum + x, z = s - sum;
    error += (sum - (s - z)) + (x - z);
    sum = s;
  }
  void add_product(double a, double b) {
    const double p = a * b;
    add(p);
    error += std::fma(a, b, -p);
  }
  double value() const { return sum + error; }
};

inline Check make_check(std::string_view name, double value, double tolerance) {
  Check check;
  check.name = name;
  check.value = value;
  check.tolerance = tolerance;
  return check;
}

// Element -> the reaction unknowns at its two ends, -1 off the foundation: the last reaction of
// its first node and the first of its second (a node where the reaction jumps has two, the left
// element's first: fe/discretisation.hpp).
std::vector<std::array<int, 2>> element_reactions(const fe::Discretisation& d);
// The dofs the end and point supports fix (as fe::discretise fixes them; the gauge is not one).
std::vector<int> supported_dofs(const model::MemberModel& model, const fe::Discretisation& d);
// The applied loads as nodal forces on every dof (work-equivalent, as the assembly computes them).
Eigen::VectorXd applied_nodal_loads(const model::MemberModel& model, const fe::Discretisation& d, double load_factor);
// Support reactions from g, the generalised force each fixed dof's support exerts (in the dof's
// own sense): force = -g_w, moment = -g_slope, tangential = g_u - g_slope (arches; with the
// foundation outside moment = g_slope, tangential = g_u + g_slope).
// `nodes`: the supports' nodes, or (empty) the rigid supports' nodes.
std::vector<SupportReaction> support_reactions(const model::MemberModel& model, const fe::Discretisation& d,
                                               const Eigen::VectorXd& g, const std::vector<bool>& is_supported,
                                               std::vector<int> nodes = {});
// The settled rigid supports (s, delta), read from the model.
std::vector<std::pair<double, double>> settlements(const model::MemberModel& model);

// The rigid motions of the balance, on every dof: beams translation (w = 1) and rotation about
// the begin (w = s - s_begin, w' = 1); arches fe::rigid_motions (x, y, rotation about the centre).
Eigen::MatrixXd balance_modes(const model::MemberModel& model, const fe::Discretisation& d);
std::string_view balance_name(model::StructureKind kind, int mode);
// Continuum rigid motions at s for the Ritz balance: (u, w, w') of mode j (balance_modes' order).
Eigen::Vector3d balance_mode_at(const model::MemberModel& model, int mode, double s);
int balance_mode_count(model::StructureKind kind);

// The resultant figures from the work of the applied loads and of the foundation on each balance
// mode, and the reaction's centroid (s).
void fill_resultants(Certificate& c, const model::MemberModel& model, const std::vector<double>& applied,
                     const std::vector<double>& foundation, double centroid);

// Sets each check's passed, the certificate's passed and its message.
void conclude(Certificate& c, const model::MemberModel& model);

}  // namespace liftoff::certify::detail
