#pragma once
// The member in nondimensional form, the only form the numerics see.
//
// Scales: the length scale is L for beams and R for arches, the stiffness scale is EI. So the
// member coordinate s is x/L in [0, 1] for beams and theta (radians) in [-gamma, gamma] for
// arches; displacements come out in units of the length scale; the foundation k K becomes
// k = K l^4/EI; a force P becomes P l^2/EI, a moment M l/EI, a distributed load q l^3/EI.
// Results therefore do not depend on the user's units, and `Scales` converts back. A scene
// becomes a MemberModel in one place, model/from_scene.hpp.
//
// Names: `k` is always the nondimensional stiffness parameter K l^4/EI (the scene's key
// `nondimensional_k`, the outputs' "k"); `k` is only ever the dimensional K (force per length
// per length), which the numerics never see.

#include <algorithm>
#include <optional>
#include <string_view>
#include <utility>
#include <vector>

namespace liftoff::model {

// The model's own vocabulary, converted from the scene's once (model/from_scene.hpp), so the
// numerics do not depend on the input-file layer.
enum class StructureKind { beam, arch };
// Beam ends: pinned (w = 0), clamped (w = w' = 0), free.
// Arch ends: pinned (u = w = 0), roller (w = 0), clamped (u = w = rotation = 0), free.
enum class EndSupport { pinned, clamped, free, roller };
std::string_view to_string(EndSupport);  // the scene's word for it, for messages
// Kinematics ([structure] theory): linear (first order, or second order under a given axial
// force), or von Karman (moderate rotations: membrane strain u' + w0' w' + w'^2/2 coupled to
// bending, fe/von_karman_element.hpp; issue 16).
enum class Theory { linear, von_karman };
std::string_view to_string(Theory);  // the scene's word for it
// No table load here: a scene's distributed load arrives as uniform (linear) pieces.
// curvature: an imposed free (thermal) curvature, an initial strain rather than a force.
// sine: value sin(half_waves pi (s - from) / (to - from)) on [from, to], a force per length (beams
// only; the scene reader refuses it on arches and fe/arch_loads.hpp would too).
enum class LoadKind { force, moment, uniform, curvature, sine };
// Arches only: along what a load's value acts. radial: toward the foundation; tangential and
// horizontal: toward increasing theta / to the right; vertical: downward.
enum class LoadDirection { radial, tangential, vertical, horizontal };
// The scene's word for it (the key `direction`'s value), for messages.
std::string_view to_string(LoadDirection);
// Arches, vertical uniform loads: per unit arc length or per unit horizontal projection.
enum class LoadBasis { arc, projection };
// Live loads are scaled by the load factor lambda; dead loads are not.
enum class LoadCase { live, dead };

struct Scales {
  double length = 1.0;             // L or R
  double bending_stiffness = 1.0;  // EI
  double displacement() const { return length; }
  double force() const { return bending_stiffness / (length * length); }
  double moment() const { return bending_stiffness / length; }
  double force_per_length() const { return bending_stiffness / (length * length * length); }
};

// One load on the member. A scene's `distributed` table becomes one `uniform` load per interval
// of the table, linear from `value` at `from` with `slope` per unit s (steps are where two
// pieces meet), so every consumer of loads integrates linear pieces and never sees a table.
// A `curvature` load is an imposed free curvature kappa_T over [from, to] (value = kappa_T l):
// an initial strain, the elastic curvature being w'' + value there (beams only).
struct MemberLoad {
  LoadKind kind = LoadKind::force;
  double at = 0.0;     // s
  double value = 0.0;  // nondimensional; uniform: the intensity at `from`
  double slope = 0.0;  // uniform: d(intensity)/ds (0 for a scene's uniform load)
  double from = 0.0;   // s, uniform and curvature loads
  double to = 0.0;
  LoadCase load_case = LoadCase::live;
  LoadDirection direction = LoadDirection::radial;  // arches (fe/arch_loads.hpp)
  LoadBasis per = LoadBasis::arc;
  int half_waves = 1;  // sine: n >= 1

  // A force per length on [from, to] (uniform or sine), as opposed to a point action or a curvature.
  bool is_distributed_force() const { return kind == LoadKind::uniform || kind == LoadKind::sine; }
  // Whether the load acts on [from, to] (distributed forces and curvatures) rather than at `at`.
  bool has_extent() const { return is_distributed_force() || kind == LoadKind::curvature; }
  // sine: the wavenumber n pi / (to - from) of its sine.
  double wavenumber() const;
  // The force per length at s in [from, to]: a uniform load's linear intensity, or a sine's.
  double intensity(double s) const;
  // Exact integrals of a distributed force over [a, b] (clipped to [from, to]): its resultant
  // int q ds, and int (x - s) q(s) ds, the moment about x of the load on [a, b] (closed forms of
  // the linear and the sine intensity; for the sine, 1 - cos and t - sin t by their half-angle and
  // series forms where they would cancel).
  double resultant(double a, double b) const;
  double moment_about(double x, double a, double b) const;
};

// A quadrature rule over [a, b] for int q(s) p(s) ds with q a distributed force and p a
// polynomial of degree <= 3 (a Hermite cubic): exact for a uniform (linear) load (Gauss, 5
// points); for a sine, 8-point Gauss on pieces of at most a quarter wave, whose error bound
// (k h)^16 (8!)^4 / (17 (16!)^3) with k h <= pi/2 is below 1e-19 of the integral's scale: the
// error is round-off. Points (s, weight) with the weight already multiplied by the length.
struct LoadQuadraturePoint {
  double s = 0.0;
  double weight = 0.0;
};
std::vector<LoadQuadraturePoint> load_quadrature(const MemberLoad& load, double a, double b);

// The imposed curvature (nondimensional) at s: the sum of the curvature loads covering s, with
// the case's factor (dead 1, live load_factor). Breakpoints are nodes, so s inside an element
// is never on a range's end.
double imposed_curvature(const std::vector<MemberLoad>& loads, double s, double load_factor);

// One piece of the foundation in member terms: [begin, end] in s, stiffness parameter k = K l^4/EI,
// constant or linear from `k` at begin to `end_k` at end.
struct FoundationPiece {
  double begin = 0.0;
  double end = 0.0;
  double k = 0.0;                 // at begin; everywhere when constant
  std::optional<double> end_k{};  // linear: k at end
  bool is_constant() const { return !end_k; }
  // k at s in [begin, end]: linear between the ends, exact at both.
  double k_at(double s) const;
  double largest_k() const { return end_k ? std::max(k, *end_k) : k; }
};

// An elastic support at s: a translational spring of stiffness k_s l^3/EI on w (arches: on u and
// w alike), a rotational one of k_r l/EI on the rotation, the translational spring's far end
// displaced by `settlement` (in l) along w (fe/discretisation.hpp says how each enters).
struct SupportSpring {
  double s = 0.0;
  double stiffness = 0.0;
  double rotational_stiffness = 0.0;
  double settlement = 0.0;
};

struct MemberModel {
  StructureKind kind = StructureKind::beam;
  double s_begin = 0.0;
  double s_end = 1.0;
  double membrane_stiffness = 0.0;  // arches: EA R^2 / EI; beams under von Karman: EA l^2 / EI
  Theory theory = Theory::linear;
  // Beams under von Karman: whether each end's axial displacement is held (u = 0; the scene's
  // support key axial = "restrained" | "free", restrained by default at pinned and clamped ends,
  // free at free ends). Not read under linear theory.
  bool left_axially_restrained = true;
  bool right_axially_restrained = true;
  EndSupport left = EndSupport::pinned;
  EndSupport right = EndSupport::pinned;
  std::vector<double> point_supports;  // s
  // Settlements of the rigid supports (in l): w = settlement there instead of 0. point_settlements
  // is parallel to point_supports, or empty when none settles.
  double left_settlement = 0.0;
  double right_settlement = 0.0;
  std::vector<double> point_settlements;
  // Elastic supports ([supports] kind = "spring"), ends and interior points, sorted by s.
  std::vector<SupportSpring> springs;
  // The foundation: pieces sorted, disjoint (they may abut), with voids between them allowed.
  // foundation_begin..foundation_end spans them all; k is the largest k (the
  // scale of the foundation's decay length), the only k when there is one constant piece.
  std::vector<FoundationPiece> foundation_pieces;
  double k = 0.0;  // the foundation's stiffness parameter K l^4/EI (the largest piece's)
  bool tensionless = true;
  double foundation_begin = 0.0;  // s
  double foundation_end = 1.0;
  // Arches: the foundation lies outside (around the extrados), so w > 0 is outward.
  bool foundation_outside = false;
  std::vector<MemberLoad> loads;
  Scales scales;
  // The ground's distance g below the unloaded axis (radial for arches), nondimensional (over
  // the length scale), piecewise linear in s between these points: s non-decreasing, a repeated
  // s is a step, g constant beyond the ends. Empty: g = 0. Contact where w >= g.
  std::vector<double> ground_gap_at;
  std::vector<double> ground_gap_value;
  // The bilinear foundation's k in tension (the scene's "tension_modulus" or "tension_nondimensional_k"), <= every
  // piece's k; the reaction is k max(w - g, 0) + tension_k min(w - g, 0)
  //   = tension_k (w - g) + (k - tension_k) max(w - g, 0):
  // a bilateral (Winkler) foundation of parameter tension_k on every piece plus the tensionless
  // one of parameter k - tension_k (contact_k_at). 0 for a bilateral or plain tensionless
  // foundation (make_member_model makes tension_k = every piece's k a bilateral foundation).
  double tension_k = 0.0;
  // Beams: the compressive axial force N l^2/EI (positive compresses) per case, constant along
  // the member, N = axial_dead + lambda axial_live (second-order theory, fe/element.hpp's
  // BeamColumnElement). Both 0: first-order theory, as without axial loads.
  double axial_dead = 0.0;
  double axial_live = 0.0;
  // Beams: the stress-free initial shape w0 (over the length scale, positive toward the
  // foundation), piecewise linear in s through these points (s increasing), constant beyond the
  // ends. Empty: straight. The unknowns are v = w - w0 and the ground
  // follows w0 (the gap g is measured from it), so w0 enters the equations only through the axial
  // force: the load N K_g w0 (fe/discretisation.hpp).
  std::vector<double> initial_shape_at;
  std::vector<double> initial_shape_value;
  // A named initial shape ({ shape = "half_sine" } or "bump") kept exact as well:
  // w0 = amplitude sin(pi (s - from) / length) on [from, from + length], 0 elsewhere (over the
  // length scale, s). The table above samples it (scene.hpp's initial_shape_samples per half-wave)
  // for the linear paths, where w0 enters only through the axial load; the von Karman models read
  // this one (initial_slope), whose membrane strain w0' w' needs w0' itself, not a second-order copy.
  struct InitialSine {
    double amplitude = 0.0;
    double from = 0.0;
    double length = 1.0;
  };
  std::optional<InitialSine> initial_sine;

  // N at the load factor lambda.
  double axial_force(double load_factor) const { return axial_dead + load_factor * axial_live; }
  bool has_axial_force() const { return axial_dead != 0.0 || axial_live != 0.0; }
  bool has_initial_shape() const { return !initial_shape_at.empty(); }
  // w0 at s (0 without an initial shape); at a step, the value to its right. The table's.
  double initial_shape(double s) const;
  // w0' at s: initial_sine's exact slope when there is one (at the sine's ends, the slope to the
  // right), else the table's (its segment to the right of s; 0 beyond the ends or without one).
  double initial_slope(double s) const;

  // User coordinate (x, or theta in degrees) <-> member coordinate s.
  double s_from_user(double position) const;
  double user_from_s(double s) const;
  double length() const { return s_end - s_begin; }
  // k of the piece containing s (ends included; at two pieces' common end the first's), 0 in a
  // void or beyond the foundation. At element middles it decides whether the foundation is
  // under the element (piece ends are mesh nodes, never middles).
  double k_at(double s) const;
  // k at a and b of the piece under the interval [a, b] (the one containing its middle; its k is
  // linear there), {0, 0} in a void or beyond the foundation. An element's k at its two nodes.
  std::pair<double, double> k_on(double a, double b) const;
  // The bilinear foundation's parts at s: the Winkler part's k (tension_k on a piece, 0 in a
  // void) and the tensionless part's k - tension_k (the contact conditions' k).
  double tension_k_at(double s) const { return k_at(s) > 0.0 ? tension_k : 0.0; }
  double contact_k_at(double s) const { return k_at(s) - tension_k_at(s); }
  bool has_tension_k() const { return tension_k > 0.0; }
  // Where the reaction k (w - g) may jump inside the foundation (sorted, s): the common end of two
  // abutting pieces whose k differ there, and a step of the gap table (a repeated position with
  // two values). Read from the data, never from nearby numbers: the FE puts two reactions there.
  std::vector<double> reaction_jumps() const;
  // The stretches of foundation without a void: unions of abutting pieces, in order.
  std::vector<std::pair<double, double>> foundation_stretches() const;
  // Whether s is the end of a stretch (the foundation stops there; within round-off).
  bool is_foundation_edge(double s) const;
  // The Ritz model and the trace paths model one piece of constant k.
  bool foundation_is_one_piece() const { return foundation_pieces.size() == 1; }
  bool k_is_constant() const {
    return std::all_of(foundation_pieces.begin(), foundation_pieces.end(),
                       [](const FoundationPiece& p) { return p.is_constant(); });
  }
  // Whether a support is elastic or settles: the Ritz model and the Ritz trace path refuse these.
  bool has_springs() const { return !springs.empty(); }
  bool has_settlements() const;
  // foundation_pieces, or for a model built in code without them (tests, references) the one
  // piece foundation_begin..foundation_end of parameter k.
  std::vector<FoundationPiece> pieces() const;
  bool has_ground_gap() const { return !ground_gap_at.empty(); }
  // g at s (0 without a gap). At a step's position: the value to its right. Called inside
  // elements, where g is linear (the table's points are mesh breakpoints).
  double ground_gap(double s) const;
  // g at xi in [0, 1] of the element [a, a + h], the element's own linear g (at a step on one
  // of its ends: that end's value from this element's side).
  double ground_gap_in(double a, double h, double xi) const {
    const double quarter = ground_gap(a + 0.25 * h), three_quarters = ground_gap(a + 0.75 * h);
    return quarter + (xi - 0.25) * 2.0 * (three_quarters - quarter);
  }
};

}  // namespace liftoff::model
