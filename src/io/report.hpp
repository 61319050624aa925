#pragma once
// What a solve produced, in the user's units, ready for the summary, JSON and HDF5.
//
// Coordinates are x (beam, length units) or theta in degrees (arch). Deflection w > 0 is into
// the foundation; u is tangential (toward increasing theta); rotation is counterclockwise;
// bending moment sagging positive; normal force tension positive; reaction (force per unit
// length) compression positive.

#include <array>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "certify/certificate.hpp"
#include "contact/contact_solver.hpp"
#include "core/contact_region.hpp"
#include "core/enum_names.hpp"
#include "fe/discretisation.hpp"
#include "model/member_model.hpp"
#include "post/contact_regions.hpp"
#include "post/design.hpp"
#include "post/fields.hpp"
#include "post/scale.hpp"
#include "ritz/ritz_solver.hpp"
#include "scene/scene.hpp"

namespace liftoff::io {

inline constexpr const char* sign_convention =
    "w > 0 into the foundation; force > 0 toward the foundation; moment and rotation > 0 counterclockwise "
    "(x or theta to the right, foundation below); bending moment sagging positive; normal force tension "
    "positive; reaction compression positive";

// The fields and design values in the user's units: one type for solve's reports and trace steps
// (post/user_tables.hpp).
using post::DesignTable;
using post::DesignValue;
using post::FieldTable;

// Beams under an axial force: the critical load of the state solved (stability/critical_load.hpp),
// on the cone of admissible perturbations of its contact state. critical_load_factor is the
// factor on the whole axial force N (dead + live at lambda = 1) at which this configuration loses
// stability (> 1: stable); critical_axial_force = critical_load_factor N in force units. NaN when
// no critical load was found (stable for every factor under a tension, or not converged).
struct StabilityTable {
  std::string stability;  // "stable", "unstable", or "undetermined" (the eigen solve did not converge)
  double critical_load_factor = std::numeric_limits<double>::quiet_NaN();
  double critical_axial_force = std::numeric_limits<double>::quiet_NaN();
  double lower_bound = std::numeric_limits<double>::quiet_NaN();  // factors: the fewest springs (nodes in contact)
  double upper_bound = std::numeric_limits<double>::quiet_NaN();  // and the most (every weakly active node too)
  std::string method;                                             // "dense" or "sparse"
  std::string termination;                                        // stability::StabilityTermination's name
  std::string message;
  int set_iterations = -1, eigen_iterations = -1;
  double residual = -1.0;
  double time_s = -1.0;
  // Where the cone's answer and the contact solver's inertia check on the contact set
  // (contact/stability.hpp, the refusal test) disagree, in words; empty when they agree.
  std::string warning;
};

// Whether the method ran on the scene, beyond the solver's own termination: refused is a scene
// the method does not take (or a method that threw): no answer, the reason in message, and
// termination reads to_string(SolveOutcome::refused), "refused", in every output.
enum class SolveOutcome { ran, refused };
std::string_view to_string(SolveOutcome);

struct SolveReport {
  std::string scene_name;
  std::string scene_text;
  scene::StructureKind kind = scene::StructureKind::beam;
  std::string coordinate_name;  // "x" or "theta_deg"
  bool tensionless = true;
  bool foundation_outside = false;  // arches: [foundation] side = "outside" (how H and V resolve)
  double k = 0.0;                   // k = K l^4 / EI
  // Beams under an axial force: the acting compressive force N (dead + live at lambda = 1, force
  // units, positive compresses); absent without one.
  std::optional<double> axial_force;
  // The kinematics the answer was solved under ([structure] theory): "linear" or "von_karman".
  std::string theory = "linear";
  // Von Karman beams (empty / absent otherwise): the membrane force N = EA (u' + w0' w' + w'^2/2)
  // of each element (tension positive, force units; constant on an element, uniform along the
  // member in the continuum) at the elements' midpoints (user coordinate); whether the answer is
  // a stable equilibrium on its contact set; the axial displacement u is nodes.u (length units,
  // positive toward increasing x), and the axial reaction at each held end is the support
  // reaction's `horizontal` (along increasing x).
  std::vector<double> membrane_force, membrane_force_at;
  std::optional<bool> stable;
  scene::Units units;  // the scene's [units]: labels for every output
  // The foundation's scale (post/scale.hpp): K, beta, beta L, 1/beta, beta h; absent in a report
  // of a method that did not run.
  std::optional<post::ScaleFigures> scale;
  // The scene reader's warnings (an old key name), then the scale's (post::scale_warnings).
  std::vector<std::string> warnings;

  std::string method;            // the formulation that produced the answer: "dual", "primal", "fast", "ritz"
  std::string method_requested;  // what the user asked for: "auto", "dual", ... (keys --method all, sweeps)
  std::string method_reason;     // why (auto, a fallback), or how the Ritz topology was found
  // The solvers that ran, in order: the formulation, then a fallback after a failed certificate.
  // Empty when none ran (the resultant check's no_equilibrium, a refusal before solving), so a
  // failure's JSON names only these (`method` the last of them, else null).
  std::vector<std::string> methods_run;
  SolveOutcome outcome = SolveOutcome::ran;
  std::string termination;  // the solver's own termination name ("refused" when refused)
  std::string message;      // in words
  bool usable = false;
  double residual = -1.0;  // FE: see contact_solver.hpp; Ritz: final scaled Newton residual
  // FE + LCP (-1 otherwise)
  int elements = -1;
  int pivots = -1;
  int lcp_size = -1;
  int active_set_iterations = -1;  // fast: contact sets tried
  int factorisations = -1;         // fast and bilateral: sparse numeric factorisations
  // Accuracy on demand ([solve] tolerance, --tolerance; -1 / empty otherwise): the tolerance
  // asked for (relative to the length or angular span), the estimates of the answer's errors
  // (FE: the limit-fitted sequence's, contact/fitted_refinement.hpp: w relative to max |w|, the
  // reaction k w relative to its largest) and the elements of each level of the sequence.
  double tolerance = -1.0;
  double estimated_w_error = -1.0;
  double estimated_reaction_error = -1.0;
  double observed_order = -1.0;
  // The smallest tolerance the answer can honour (its round-off floor, relative like the
  // tolerance; FE: contact/fitted_refinement.hpp; Ritz: its measured round-off).
  double round_off_floor = -1.0;
  std::vector<int> refinement_elements;
  bool limit_fitted = false;  // FE: the answer's contact limits are mesh nodes (a limit-fitted solve)
  // Ritz (-1 / empty otherwise)
  int modes = -1;
  int newton_iterations = -1;
  double estimated_limit_error = -1.0;  // user coordinate (also FE with a tolerance)
  std::string topology;
  std::vector<double> amplitudes;
  std::vector<double> residual_history;

  // FE, no_equilibrium from a Lemke ray: the ray as the certificate (contact_solver.hpp,
  // NoEquilibriumCertificate), nondimensional like the LCP it proves infeasible.
  struct RayCertificate {
    std::string formulation;  // "dual" or "primal": the LCP whose ray it is
    std::vector<double> ray;  // dz >= 0, |dz|_inf = 1
    double q_dot_ray = 0.0;   // q^T dz < 0
  };
  std::optional<RayCertificate> no_equilibrium_certificate;

  std::string gauge_note;
  std::optional<scene::Comparison> comparison;  // the scene's [compare]: set beside the answer
  std::vector<ContactRegion> contact_regions;   // user coordinate
  double w_max = 0, at_w_max = 0, w_min = 0, at_w_min = 0;
  double max_reaction = 0;
  double time_s = 0;                        // the whole solve: set-up, solver, post-processing
  FieldTable fields;                        // FE: sampled inside every element; Ritz: on a uniform grid (empty when
                                            // nothing asked for fields: SolveRequest::fields)
  FieldTable nodes;                         // FE only: at the mesh nodes (w, u, rotation, reaction)
  std::optional<DesignTable> design;        // certified answers only
  std::optional<StabilityTable> stability;  // beams under an axial force, FE answers (solved or refused unstable)

  // The answer certificate (certify/certificate.hpp), in the user's units: check positions in the
  // user's coordinate, figures and support reactions converted. Absent when there was no answer.
  std::optional<certify::Certificate> certificate;
  certify::UserFigures certificate_figures;
  bool certified() const { return certificate && certificate->passed; }
};

// Stores the units, the scale figures (beta h from the report's mesh nodes) and every warning.
void attach_scale(SolveReport& report, const scene::Scene& scene, const model::MemberModel& model);

// Stores the certificate in the report, converted to the user's units.
void attach_certificate(SolveReport& report, const certify::Certificate& certificate, const model::MemberModel& model);

// Stores the design values in the report, converted to the user's units.
void attach_design(SolveReport& report, const post::DesignValues& design, const model::MemberModel& model);

// The formulations a contact solve ran, in order: its method, after fast where the contact solver
// fell back from fast to Lemke itself.
std::vector<std::string> methods_run(const contact::ContactSummary& summary);
SolveReport make_report(const scene::Scene& scene, const model::MemberModel& model, const fe::Discretisation& d,
                        const contact::ContactSolution& solution, const post::Fields& fields,
                        const std::vector<ContactRegion>& regions);
SolveReport make_report(const scene::Scene& scene, const model::MemberModel& model, const ritz::RitzSolution& solution,
                        int samples);

// The answer's keys in a solve's JSON that every object carries: null in a report without an
// answer and in the failure object of `liftoff solve --json`.
inline constexpr std::array<const char*, 7> answer_keys = {"contact_regions", "w_max",        "at_w_max", "w_min",
                                                           "at_w_min",        "max_reaction", "residual"};

// An answer's JSON; a report without one (usable false) has null for every answer field
// (contact_regions, the extremes, max_reaction, residual, support_reactions, foundation_resultant,
// amplitudes, membrane_force, u) and `method` null unless a solver ran (src/io/README.md,
// "Failure object").
nlohmann::json to_json(const SolveReport& report);
// The JSON `design` object of a report (and of a trace step): each value with its `at` (null where
// there is no such point), from_statics, and the closure when from statics.
nlohmann::json design_json(const DesignTable& design);
// An arch support's horizontal and vertical reaction from its reaction in the user's units (at:
// theta in degrees); `outside`: [foundation] side = "outside".
certify::HorizontalVertical user_arch_components(const certify::SupportReaction& reaction, bool outside);
// The JSON `support_reactions` array: at, force, moment; arches also tangential, horizontal and
// vertical (certify::arch_components; `outside`: [foundation] side = "outside"), von Karman beams
// horizontal (the axial reaction along +x); spring and settlement where they apply.
nlohmann::json support_reactions_json(const std::vector<certify::SupportReaction>& reactions, bool arch,
                                      bool von_karman, bool outside = false);
// The CSV columns of the design values: moment_max,at_moment_max,moment_min,at_moment_min,
// shear_max_abs,at_shear_max_abs,pressure_max,at_pressure_max,uplift_max,at_uplift_max (the header
// without a trailing comma), and a row's (empty cells without a table; `at` empty where none).
std::string design_csv_header();
std::string design_csv_cells(const DesignTable* design);
// The support reactions in one CSV cell: "at:force:moment" joined by ';'.
std::string support_reactions_csv(const std::vector<certify::SupportReaction>& reactions);
// The JSON `units` object: {"system": ..., "<name>": label} for every label of scene::unit_labels.
nlohmann::json units_json(const scene::Units& units);
// The regions as the files write them: [[begin, end], ...].
nlohmann::json contact_regions_json(const std::vector<ContactRegion>& regions);
std::string text_summary(const SolveReport& report);
// Several methods on one scene, one column each (`--method all`).
std::string side_by_side(const std::vector<SolveReport>& reports);

// One case of a parameter sweep: the values of the swept keys, and a report per method (or the
// one-line error that stopped the case).
struct SweepCase {
  std::vector<double> values;
  std::vector<SolveReport> reports;
  std::string error;
};
// One CSV row per case and method: the swept keys, method (as requested), termination, certified
// (true/false), contact regions ("a..b;c..d"), w_max, w_min, max_reaction, iterations (pivots,
// contact sets or Newton), time_s.
// Then the design values (moment_max, at_moment_max, moment_min, at_moment_min, shear_max_abs,
// at_shear_max_abs, pressure_max, at_pressure_max, uplift_max, at_uplift_max) and the support
// reactions ("at:force:moment" joined by ';'), empty without a certified answer.
std::string sweep_csv(const std::vector<std::string>& keys, const std::vector<SweepCase>& cases);

}  // namespace liftoff::io

namespace liftoff {
// The names' one table is in report.cpp (core/enum_names.hpp).
template <>
std::optional<io::SolveOutcome> from_string(std::string_view);
}  // namespace liftoff
