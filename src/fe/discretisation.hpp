#pragma once
// The discrete structure-foundation system of one member on one mesh:
//   K u + C^T r = F_dead + lambda F_live,   gap = T r - C u + c >= 0,  r >= 0,  r.gap = 0
// with c = ground_gap, the ground's distance below the axis (a constant offset, not scaled by lambda).
// with u the structural dofs left free by the supports ("equations") and r the nodal foundation
// reactions (one per node of the foundation's extent). Everything is nondimensional
// (member_model.hpp) and sparse; dense matrices are built only by the LCP formulations.
//
// Rigid-body motions the supports leave free are analysed here, once:
//  - a motion the foundation cannot see either (the rotation of an arch on rollers about its
//    centre moves no point radially) is a true mechanism: if the loads do work on it there is
//    no equilibrium (InputError naming the supports); otherwise one dof is fixed as a gauge,
//    which changes no strain, force or deflection;
//  - a motion only the foundation resists (a free-free beam) leaves K singular: the primal LCP
//    handles it, the dual form is refused (structure_is_stable() == false).

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <algorithm>
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "fe/element.hpp"
#include "fe/foundation_element.hpp"
#include "fe/mesh.hpp"
#include "model/member_model.hpp"

namespace liftoff::fe {

using SparseMatrix = Eigen::SparseMatrix<double>;

enum class DofRole { deflection, slope, tangential };

class Discretisation {
 public:
  model::StructureKind kind = model::StructureKind::beam;
  Mesh mesh;
  std::vector<int> equation_of_dof;  // -1: fixed by a support or the gauge
  int equations = 0;
  // The mesh node of each reaction unknown, non-decreasing: one per node of the foundation's
  // elements, but two where the reaction jumps (MemberModel::reaction_jumps: k or g steps there)
  // and the foundation acts on both elements: the left element's (its half of the hat, the left
  // k and g) then the right element's, each with its own row of T, C, c and its own
  // complementarity. One nodal value cannot follow a jump of k (w - g): w would converge like h.
  std::vector<int> reaction_nodes;
  // The reactions at element e's two ends (-1 where no node has one): the last reaction of its
  // first node and the first of its second node.
  std::array<int, 2> element_reactions(int element) const;
  // Whether reaction i shares its node with another (a jump).
  bool reaction_is_split(int i) const {
    return (i > 0 && reaction_nodes[i - 1] == reaction_nodes[i]) ||
           (i + 1 < reactions() && reaction_nodes[i + 1] == reaction_nodes[i]);
  }
  SparseMatrix stiffness;    // K: equations x equations
  SparseMatrix coupling;     // C: reactions x equations
  SparseMatrix flexibility;  // T: reactions x reactions
  // c: reactions. The ground gap g(s) (MemberModel::ground_gap) tested by the reactions' shapes,
  // c_i = integral of Hb_i g ds over the foundation's elements (as C u is of Hb_i w), so that
  // gap = T r - C u + c is the discrete r/k - (w - g): contact where w >= g, r = k (w - g).
  // Integrated exactly (g is linear within elements). Zero without a gap. Every consumer of T and
  // C must add it: the LCPs' q, the fixed-set system's right-hand side, the gaps reported.
  Eigen::VectorXd ground_gap;
  // The same stiffness in mixed (Hellinger-Reissner) form, K = G^T H^-1 G exactly, with element
  // stress resultants as extra unknowns (beam_element.hpp, arch_element.hpp): the saddle-point
  // system built on G and H has a condition number growing like N^2 where K's grows like N^4,
  // which is what lets contact::ActiveSetSystem solve meshes of 1e6 elements to round-off.
  SparseMatrix stress_coupling;  // G: stresses x equations (see the three blocks below)
  Eigen::VectorXd compliance;    // H, diagonal: one per stress unknown
  int stresses_per_element = 0;
  // The stresses are three blocks, each with an offset function:
  //  - stresses_per_element per element, in element order (element_stresses() of them);
  //  - the bilinear foundation's Winkler block (MemberModel::tension_modulus K_t > 0): on each
  //    element of winkler_elements, in order, foundation_element::winkler_points stresses
  //    sigma_q = K_t W_q w(xi_q) (foundation_element.hpp), so that G^T H^-1 G holds the stiffness
  //    integral of K_t N_w^T N_w that `stiffness` holds too; its load K_t g is in dead_load;
  //  - one per spring of an elastic support, in `springs`' order. A spring is a stress like any
  //    other: its row of G reads the displacement it stretches (w; arches u and w separately; the
  //    rotation), its compliance is 1/stiffness, so K = G^T H^-1 G still holds exactly and the
  //    spring's force is its stress.
  std::vector<int> winkler_elements;
  struct SpringRow {
    int node = 0;                            // mesh node of the support
    DofRole role = DofRole::deflection;      // deflection, tangential (arch u) or slope (the rotation)
    std::vector<std::pair<int, double>> on;  // (dof, coefficient): the functional, on every dof
    double stiffness = 0.0;                  // nondimensional
    double settlement = 0.0;                 // the far end's displacement (deflection rows only)
  };
  std::vector<SpringRow> springs;
  int element_stresses() const { return stresses_per_element * mesh.elements(); }
  // The first Winkler stress of winkler_elements[i]; spring i's stress.
  int winkler_stress(int i) const { return element_stresses() + foundation_element::winkler_points * i; }
  int spring_stress(int i) const { return winkler_stress(static_cast<int>(winkler_elements.size())) + i; }
  // Settlements: the displacement the supports prescribe on every dof (0 but at settled
  // supports' w). The equations' unknowns are u - prescribed; the dead load carries -K u_f and a
  // settled spring's k delta; under an axial force N = N_dead + lambda N_live, +N K_g u_f split
  // by case (N_dead K_g u_f dead, N_live K_g u_f live), so that F(lambda) holds it at every lambda.
  Eigen::VectorXd prescribed;
  // Which elements the foundation acts on (the member's extent, or the contact elements of a
  // limit-fitted solve), and the rigid motions the supports leave free, on the equations
  // (columns; the kernel of K, empty when the structure is stable). free_rigid_motions is computed
  // once, from the exact motions (member_rigid_motions), not from K: users share it rather than
  // recompute it (continuation/models/member_kinematics.cpp orthonormalises it).
  std::vector<bool> foundation_on_element;
  // The foundation's tensionless part under each element at its two nodes (linear between them;
  // 0 in a void and beyond the foundation), whether or not the foundation acts on it in this
  // discretisation: k, or for a bilinear foundation k - K_t (MemberModel::contact_k_at), the
  // k of C, T and the contact conditions. element_tension_k: K_t there (constant; 0 in a
  // void and without a tension modulus). The reaction is K_t (w - g) + (k - K_t) max(w - g, 0).
  struct ElementK {
    double begin = 0.0, end = 0.0;
    double at(double xi) const { return (1.0 - xi) * begin + xi * end; }  // exact at both ends
    bool present() const { return begin > 0.0; }
  };
  std::vector<ElementK> element_k;
  std::vector<double> element_tension_k;
  Eigen::MatrixXd free_rigid_motions;
  // The member's in-plane rigid motions on every dof, whatever the supports (rigid_motions()).
  Eigen::MatrixXd member_rigid_motions;
  Eigen::VectorXd dead_load;  // equations
  Eigen::VectorXd live_load;
  // Beams under a compressive axial force N (MemberModel::axial_force; second-order theory):
  // `stiffness` is K(N) = K - N K_g with N = axial_force, the force at the solve's load factor 1
  // (dead + live), from K and geometric_stiffness, K_g on the equations (empty without N),
  // assembled once in the element loop (a caller following N along a path, as
  // continuation/models/member_kinematics.cpp does, forms K - N K_g the same way); and
  // the mixed form above stays that of K alone (contact::ActiveSetSystem adds -N K_g to its
  // displacement block). The initial shape w0 enters as the load N integral of N_w'^T w0'
  // (= N K_g w0 for w0 in the Hermite space; exact for the piecewise linear w0), split dead and
  // live by the axial force's cases; initial_shape_load is that integral (per unit N).
  // K(N) may be indefinite: only contact::solve_contact's stability check says whether an answer
  // is a stable equilibrium.
  double axial_force = 0.0;
  SparseMatrix geometric_stiffness;
  Eigen::VectorXd initial_shape_load;
  bool has_axial_force() const { return axial_force != 0.0; }
  double k = 0.0;  // the largest k (model::MemberModel::k)
  bool tensionless = true;
  bool foundation_outside = false;  // arches: w > 0 outward (arch_element.hpp)
  // Rigid motions only the foundation resists; non-empty means K is singular.
  int unstable_rigid_motions = 0;
  std::string stability_note;  // in words, for messages
  std::string gauge_note;      // what gauge was fixed, if any
  // The member of a uniform mesh made by discretise(model, elements), so that a solver can
  // build coarser meshes of it (the fast solver's start, contact/active_set_solver.hpp); null on
  // a given mesh or foundation.
  std::shared_ptr<const model::MemberModel> uniform_member;

  int dofs() const { return static_cast<int>(equation_of_dof.size()); }
  int reactions() const { return static_cast<int>(reaction_nodes.size()); }
  int stresses() const { return static_cast<int>(compliance.size()); }
  bool has_ground_gap() const { return ground_gap.size() > 0 && ground_gap.lpNorm<Eigen::Infinity>() > 0.0; }
  // T r - C u + c: the discrete gap of an answer (u on the equations).
  Eigen::VectorXd gap_of(const Eigen::VectorXd& reaction, const Eigen::VectorXd& displacement) const {
    Eigen::VectorXd gap = flexibility * reaction - coupling * displacement;
    if (ground_gap.size() == gap.size()) gap += ground_gap;
    return gap;
  }
  // The foundation's reaction on element e at a point where w - g = w_minus_g: the tensionless
  // part's max(w - g, 0) where the foundation acts on e, plus the Winkler part's K_t (w - g).
  // xi: where in the element (0 at its first node, 1 at its second).
  double reaction_in(int e, double xi, double w_minus_g) const {
    return (foundation_on_element[e] ? element_k[e].at(xi) * std::max(w_minus_g, 0.0) : 0.0) +
           element_tension_k[e] * w_minus_g;
  }
  bool structure_is_stable() const { return unstable_rigid_motions == 0; }
  Eigen::VectorXd load(double load_factor) const { return dead_load + load_factor * live_load; }
  // Values on the equations -> values on every dof (fixed dofs 0): loads, corrections, directions.
  Eigen::VectorXd expand(const Eigen::VectorXd& on_equations) const;
  // A displacement on the equations -> on every dof, the settled supports' w included.
  Eigen::VectorXd expand_displacement(const Eigen::VectorXd& on_equations) const;
  // Its inverse: a displacement on every dof -> on the equations, less what the supports prescribe.
  Eigen::VectorXd on_equations(const Eigen::VectorXd& displacement) const;

  // Dof numbering. Beam: node j has (w, w') at 2j, 2j+1. Arch: node j has (u, w, w') at
  // 6j..6j+2 and element j's interior u at 6j+3..6j+5.
  int deflection_dof(int node) const;
  int slope_dof(int node) const;
  int tangential_dof(int node) const;  // arch only
  // Global dofs of an element in the element's local order (beam_element / arch_element).
  std::vector<int> element_dofs(int element) const;
  DofRole role_of_dof(int dof) const;
  double position_of_dof(int dof) const;
};

// discretise runs one verb per stage (deal.II step-3's make_grid, setup_system,
// assemble_system), each a function in discretisation.cpp:
//  1. lay_out: the member on the mesh: the foundation under each element, the reaction
//     unknowns, the springs;
//  2. assemble: the element loop on every dof (element.hpp's beam or arch element, the Winkler
//     part, the foundation's C and T, the loads), then the settlements as loads;
//  3. number_dofs, the dof map: supports, the member's rigid motions (once) and those left free,
//     mechanisms, the gauge, the equations; it reads the assembly, since the loads decide whether
//     a free motion is a mechanism or a gauge;
//  4. restrict_to_equations: K, C, T, G, H and the loads on the equations.
// Throws InputError for a mechanism the loads drive (see above).
Discretisation discretise(const model::MemberModel& model, int elements);
// The same on a given mesh (it must have a node at every mesh_breakpoints(model) point), with the
// foundation on the flagged elements only (empty: on the member's foundation pieces; a flag on
// an element in a void is ignored); reaction nodes are the nodes of those elements. Limit-fitted solves put the
// foundation on whole contact elements this way.
Discretisation discretise(const model::MemberModel& model, Mesh mesh, std::vector<bool> foundation_on_element = {});

// The member's structural elements through the element seam (element.hpp), with their global
// dofs in each element's local order: one beam or arch element per mesh element, a Winkler
// element on each of winkler_elements (on the element's first four dofs, the Hermite dofs of w),
// a linear element k a a^T per spring (on its `on` dofs); beam-columns under an axial force. Their
// tangents at load factor 1 summed on the equations are `stiffness` (to round-off: the sums run in
// another order); a SparseAssembler
// (sparse_assembler.hpp) built on them re-assembles it in place.
struct StructuralElements {
  std::vector<std::unique_ptr<const Element>> elements;
  std::vector<std::vector<int>> dofs;
};
StructuralElements structural_elements(const model::MemberModel& model, const Discretisation& d);

// The in-plane rigid motions of the member, on every dof (columns), whatever the supports:
// beams translation and rotation, arches two translations and the rotation about the centre.
Eigen::MatrixXd rigid_motions(const model::MemberModel& model, const Discretisation& d);

}  // namespace liftoff::fe
