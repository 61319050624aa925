#pragma once
// The scene: one problem as the user wrote it, in the user's units, validated.
//
// A scene is read from TOML by scene_reader.hpp. Positions are in the user's coordinate:
// x from the left end for beams, theta in degrees from the crown for arches (positive toward
// the right end). Sign convention: deflection w > 0 means into the foundation; a force with
// value > 0 pushes the member toward the foundation; a moment with value > 0 turns
// counterclockwise when the member is drawn with x (or theta) increasing to the right and the
// foundation below it.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "scene/units.hpp"

namespace liftoff::scene {

enum class StructureKind { beam, arch };
// Beam ends: pinned (w = 0), clamped (w = w' = 0), free.
// Arch ends: pinned (u = w = 0), roller (w = 0), clamped (u = w = rotation = 0), free.
enum class EndSupport { pinned, clamped, free, roller };
// distributed: piecewise linear force per length from a table; curvature: an imposed free
// (thermal) curvature over from..to, an initial strain rather than a force. Beams only: axial, a
// compressive axial force along the whole member (value > 0 compresses); temperature, a uniform
// temperature rise dT (value) with the expansion coefficient alpha, the compressive force
// N = EA alpha dT of a fully axially restrained member. Both act through second-order theory.
// sine: value sin(half_waves pi (x - from) / (to - from)) on [from, to], force per length like
// uniform (the closed forms' load; beams only).
enum class LoadKind { force, moment, uniform, distributed, curvature, axial, temperature, sine };
// Arches only: along what a load's value acts. radial: toward the foundation (today's); tangential
// and horizontal: toward increasing theta / to the right; vertical: downward (gravity). Uniform
// loads take radial or vertical, point forces any of the four.
enum class LoadDirection { radial, tangential, vertical, horizontal };
// Arches only, vertical uniform loads: the value is per unit arc length (self-weight) or per unit
// horizontal projection (fill, traffic), that is |cos theta| per unit arc.
enum class LoadBasis { arc, projection };
// Arches only: where the foundation lies. inside: under the intrados (today's); outside: around the
// extrados (a buried arch, a culvert). w > 0 is into the foundation either way, so outward when
// outside.
enum class FoundationSide { inside, outside };
// Live loads are scaled by the load factor lambda (1 in `solve`); dead loads are not.
enum class LoadCase { live, dead };
// How the contact problem is solved. dual, primal: FE + LCP (Lemke); fast: FE, the sparse
// active-set solver (contact/active_set_solver.hpp), O(n); automatic: chosen from the scene
// (app/solve_command.hpp says how); ritz: the Ritz model with moving contact limits (Newton);
// all: primal, dual, fast and Ritz side by side.
enum class Method { dual, primal, fast, automatic, ritz, all };
// How `liftoff trace` follows the load history: pseudo-arc-length (through folds) or plain load
// control (lambda stepped directly).
enum class TraceControl { arc_length, load };
// [structure] theory: linear (first order, or second order under a given axial force) or von
// Karman (moderate rotations: the membrane strain u' + w0' w' + w'^2/2 coupled to bending; beams,
// and circular arches in the Marguerre/Donnell form, model/member_model.hpp).
enum class Theory { linear, von_karman };

std::string_view to_string(StructureKind);
std::string_view to_string(EndSupport);
std::string_view to_string(LoadKind);
std::string_view to_string(LoadCase);
std::string_view to_string(LoadDirection);
std::string_view to_string(LoadBasis);
std::string_view to_string(FoundationSide);
std::string_view to_string(Method);
std::string_view to_string(TraceControl);
std::string_view to_string(Theory);
std::optional<StructureKind> parse_structure_kind(std::string_view);
std::optional<EndSupport> parse_end_support(std::string_view);
std::optional<LoadKind> parse_load_kind(std::string_view);
std::optional<LoadCase> parse_load_case(std::string_view);
std::optional<Method> parse_method(std::string_view);  // "auto" -> automatic
std::optional<TraceControl> parse_trace_control(std::string_view);
std::optional<Theory> parse_theory(std::string_view);

struct Structure {
  StructureKind kind = StructureKind::beam;
  double length = 0.0;                    // beam: L
  double radius = 0.0;                    // arch: R
  double half_angle_deg = 0.0;            // arch: gamma, the arch spans -gamma..gamma
  double bending_stiffness = 0.0;         // EI
  std::optional<double> axial_stiffness;  // EA (required for arches and under von Karman)
  Theory theory = Theory::linear;         // key `theory`; von_karman needs EA
};

// The table form of a support (keys kind, stiffness, rotational_stiffness, settlement): springs
// (stiffness: force per length, on w; arches on u and w alike; rotational_stiffness: moment per
// radian) and a settlement (length: the support, or a spring's far end, is displaced to
// w = settlement, > 0 into the foundation). A spring end is otherwise free (its EndSupport is free).
struct SupportDetail {
  bool spring = false;
  double stiffness = 0.0;
  double rotational_stiffness = 0.0;
  double settlement = 0.0;
};
struct InteriorSpring {
  double at = 0.0;  // strictly inside
  SupportDetail detail;
};

struct Supports {
  EndSupport left = EndSupport::pinned;
  EndSupport right = EndSupport::pinned;
  std::vector<double> interior;  // point supports (w = 0) strictly inside, sorted ascending
  // The table forms (all zero for the string form and for plain interior numbers).
  SupportDetail left_detail, right_detail;
  std::vector<double> interior_settlement;       // parallel to interior (empty: none settles)
  std::vector<InteriorSpring> interior_springs;  // elastic point supports, sorted by at
  // Whether each end's axial displacement is held (u = 0): a support table's key
  // axial = "restrained" | "free", beams only, read only under theory = "von_karman". Restrained by default
  // at pinned and clamped ends, free at free and spring ends (a free end cannot be restrained).
  // Under linear theory the defaults, which nothing reads.
  bool left_axially_restrained = true;
  bool right_axially_restrained = true;
};

// One piece of the foundation ([[foundation.segments]]): its extent and its modulus, exactly one
// of nondimensional_k (K l^4/EI; its old name `k` is read with a warning) and modulus (K, force
// per length per length); constant, or linear from
// `from` to `to` when given as [at from, at to].
struct FoundationSegment {
  double from = 0.0;  // user coordinate, from < to
  double to = 0.0;
  std::optional<double> k;        // key "nondimensional_k" (at `from` when linear)
  std::optional<double> modulus;  // key "modulus" (at `from` when linear)
  std::optional<double> at_to{};  // linear: the k or modulus (as given) at `to`
};

struct Foundation {
  // Exactly one of the two is given: nondimensional_k = K L^4/EI (beam) or K R^4/EI (arch), or K
  // itself. Both absent when the foundation is given as segments. (The old name of
  // nondimensional_k, `k`, is read with a warning: engineers call the dimensional K "k".)
  std::optional<double> k;        // key "nondimensional_k"
  std::optional<double> modulus;  // key "modulus", force per length per length
  bool tensionless = true;        // false: conventional bilateral foundation
  double from = 0.0;              // extent of the foundation, user coordinate;
  double to = 0.0;                // the reader fills the member's ends by default
                                  // (with segments: the first from, the last to)
  // [[foundation.segments]]: the pieces, sorted by `from`, disjoint (they may abut), voids
  // between them allowed. Empty for the one-piece form (k or modulus on [from, to]).
  std::vector<FoundationSegment> segments;
  FoundationSide side = FoundationSide::inside;  // arches only (key `side`)
  // The ground's distance g below the member's unloaded axis (key `gap` or `gap_file`), length
  // units, piecewise linear in the user coordinate: positions non-decreasing (a repeated one is a
  // step), g constant beyond the table's ends. Empty: g = 0. Contact where w >= g.
  std::vector<double> gap_at;
  std::vector<double> gap_value;
  std::string gap_file;  // as written (gap_file), empty for an inline table or none
  // The key that gave the gap, for messages ("foundation.gap" or "foundation.gap_file").
  std::string gap_key() const { return gap_file.empty() ? "foundation.gap" : "foundation.gap_file"; }
  // The key that gave the tension modulus, for messages; empty without one.
  std::string tension_key() const {
    return tension_modulus ? "foundation.tension_modulus" : tension_k ? "foundation.tension_nondimensional_k" : "";
  }
  // The bilinear foundation's modulus in tension (keys `tension_modulus` or
  // `tension_nondimensional_k`, old name `tension_k`).
  std::optional<double> tension_modulus;
  std::optional<double> tension_k;
};

struct Load {
  LoadKind kind = LoadKind::force;
  double at = 0.0;     // force and moment: position
  double value = 0.0;  // force, moment, force per unit length (uniform) or curvature kappa_T
  double from = 0.0;   // uniform, curvature, sine: extent; the reader fills the member's ends by default
  double to = 0.0;
  int half_waves = 1;  // sine: n >= 1, the half-waves on [from, to] (key `n`)
  // distributed: q(position) piecewise linear through (table_at[i], table_value[i]); positions
  // non-decreasing (a repeated one is a step), q = 0 outside [table_at.front(), table_at.back()].
  std::vector<double> table_at;
  std::vector<double> table_value;
  LoadCase load_case = LoadCase::live;
  // The load case as written (key `case`): "dead", "live" or a free name ("G", "Q", "W") that
  // [[combinations]] factor. `solve` and `sweep` apply every load once, whatever its case; `trace`
  // takes "dead" and "live" only (a free name is refused there: it has no lambda of its own).
  std::string case_name = "live";
  LoadDirection direction = LoadDirection::radial;  // arches only (key `direction`)
  LoadBasis per = LoadBasis::arc;                   // arches, vertical uniform loads (key `per`)
  double alpha = 0.0;                               // temperature: the expansion coefficient, 1/K
  // axial and temperature: the compressive axial force they make (force units; positive
  // compresses): value, or EA alpha value for a temperature rise. 0 for the other kinds.
  double axial_force(const Structure& structure) const;
};

// [geometry] initial_shape: the stress-free shape w0 of the member, measured like w (length units,
// positive toward the foundation), piecewise linear through (at[i], value[i]) in the user
// coordinate, w0 constant beyond the table's ends. The named shapes are sampled into this table
// by the reader (half_sine: amplitude sin(pi x / L) over the member; bump: amplitude
// sin(pi (x - at + length/2) / length) on at -+ length/2, 0 elsewhere). Empty: a straight member.
struct InitialShape {
  std::vector<double> at;
  std::vector<double> value;
  std::string shape;  // "table", "half_sine" or "bump" as written; empty without one
  // A named shape's sine, kept exact (MemberModel::initial_sine): amplitude sin(pi (x - from) / length) on
  // [from, from + length] (user units). Unused for a table.
  double amplitude = 0.0;
  double from = 0.0;
  double length = 0.0;
  bool empty() const { return at.empty(); }
};
// The samples per half-wave of a named initial shape (piecewise linear between them).
inline constexpr int initial_shape_samples = 256;

// [solve] tolerance: the accuracy wanted for the contact limits, relative to the member's length
// (arches: to the angular span); liftoff then chooses the discretisation (app/solve_command.hpp).
// Below min_tolerance double precision cannot honour it (the limits' Newton round-off is ~1e-14).
inline constexpr double min_tolerance = 1e-13;
inline constexpr double max_tolerance = 0.1;

struct SolveSettings {
  Method method = Method::automatic;  // auto: fast for every FE scene (contact_solver.hpp)
  int elements = 200;
  std::optional<double> tolerance;  // absent: the mesh of `elements` (or Ritz's modes) as given
};

// [ritz]: the Ritz model with moving contact limits.
struct RitzSettings {
  int modes = 0;                 // N; 0 means "auto": increase N until the limits settle
  int max_modes = 256;           // the largest N "auto" tries
  double mode_tolerance = 1e-5;  // "auto": limits settled when they move less than this * length
  // The pieces of the foundation's extent, in order, true = contact; empty means "auto": taken
  // from an FE + LCP solution of the same scene, which also gives the initial limits.
  std::vector<bool> topology;
  std::vector<double> limits;  // initial guesses (user coordinate), one per change of piece
};

// [trace]: the load history F = F_dead + lambda F_live of `liftoff trace` (`solve` ignores it).
struct TraceSettings {
  std::optional<double> lambda_max;  // required by `liftoff trace` (the reader checks > lambda_min)
  double lambda_min = 0.0;
  std::optional<Method> method;  // ritz: the Ritz path; dual/primal/fast/auto: the FE path, with
                                 // that contact solver; all: both, events side by side (FE: auto).
                                 // Absent: [solve] method
  TraceControl control = TraceControl::arc_length;
  // In lambda; min_step <= initial_step <= max_step. Not given: these fractions of the load range
  // lambda_max - lambda_min (the reader scales them), so that a trace takes as many steps on any range.
  double initial_step = 0.05;
  double min_step = 1e-8;
  double max_step = 0.25;
  int max_steps = 10000;
  std::optional<double> monitor;  // w of the load-displacement curve; absent: the first live
                                  // point force, else mid-member
  int samples = 101;              // uniformly spaced points along the member recorded per step
  bool refine = false;            // FE path: also trace with twice the elements and report
                                  // the events' differences as the discretisation error
  // Beam-columns: the trace also ends (completed) at the first step whose buckle amplitude
  // (TraceStep::amplitude, user length) reaches this, on whichever branch (a descending one
  // after a limit point never reaches lambda_max). Absent: no such bound.
  std::optional<double> max_amplitude;
  // Beam-columns: at a bifurcation point where the path loses its stability, follow the
  // bifurcated branch (the member's buckled shape) instead of the now unstable one it was on.
  bool switch_branch = true;
  // The loads at which the whole state is wanted (key report_at): physical loads in the live
  // load's unit where the live case is of one kind, load factors otherwise (app/trace_load.hpp
  // converts them and checks them against [lambda_min, lambda_max]); as written.
  std::vector<double> report_at;
  int report_at_line = 0;  // line of the key report_at, for messages (0: unknown)
  int line = 0;            // line of the [trace] header, for messages (0: unknown)
};

// [compare]: a published result the summary sets the answer beside (the default scene: the seed
// paper's contact angle). Arches only: the half-width of the contact region around the crown.
struct Comparison {
  std::string source;  // where the value comes from, quoted by the summary
  double contact_half_angle_deg = 0.0;
};

// [[combinations]]: a named combination of the load cases with partial factors, e.g. "ULS" with
// G = 1.35, Q = 1.5. A case the combination does not name has factor 0 (it is not in the
// combination); every name must be the case of a load or of [moving]. `liftoff envelope` solves
// each combination as its own problem (contact is nonlinear: never superposed).
struct Combination {
  std::string name;
  std::vector<std::pair<std::string, double>> factors;  // (case, factor >= 0), as written
  double factor_of(std::string_view case_name) const;   // 0 when the case is not named
};

// [moving]: a load group (an axle set, a crane's wheels) at a sequence of lead positions. Each
// load is a point force or moment acting at lead + offset; the group at every position lies on
// the member (the reader checks). `liftoff envelope` solves every position (with every
// combination, when there are any), on top of the scene's [[loads]].
struct MovingLoads {
  std::vector<Load> group;         // kind force or moment; `at` holds the offset from the lead
  std::vector<double> positions;   // lead positions, ascending (from..to by step, or `positions`)
  std::string case_name = "live";  // the group's load case (key `case`), for [[combinations]]
};

struct Scene {
  std::string source_name;  // file path, or "<default scene>"
  std::string text;         // the TOML text, stored in every output so results describe themselves
  Structure structure;
  Supports supports;
  Foundation foundation;
  std::vector<Load> loads;
  InitialShape initial_shape;  // [geometry] initial_shape (beams only)
  SolveSettings solve;
  RitzSettings ritz;
  std::optional<TraceSettings> trace;  // absent when the scene has no [trace] table
  std::optional<Comparison> compare;   // absent when the scene has no [compare] table
  Units units;                         // [units]: labels only (none stated: all empty)
  // What the reader accepted but the user should hear about (an old key name), one line each,
  // "FILE:LINE: key 'PATH': ...": every output carries them (SolveReport::warnings).
  std::vector<std::string> warnings;
  // The keys whose numbers were written with their unit ("loads[0].value"): their units were
  // stated, so no slip of units is suspected in them (post/scale.hpp's warnings).
  std::vector<std::string> given_with_unit;
  std::vector<Combination> combinations;  // [[combinations]] (`liftoff envelope` only)
  std::optional<MovingLoads> moving;      // [moving] (`liftoff envelope` only)

  // Ends of the member in the user's coordinate: [0, L] or [-gamma, gamma] degrees.
  double begin() const;
  double end() const;
};

}  // namespace liftoff::scene
