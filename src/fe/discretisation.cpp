#include "fe/discretisation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <tuple>

#include "core/error.hpp"
#include "fe/arch_element.hpp"
#include "fe/arch_loads.hpp"
#include "fe/beam_element.hpp"
#include "fe/element.hpp"
#include "fe/foundation_element.hpp"
#include "fe/shape_functions.hpp"

namespace liftoff::fe {

using Triplets = std::vector<Eigen::Triplet<double>>;

// ---- dof numbering ---------------------------------------------------------------------------

int Discretisation::deflection_dof(int node) const {
  return kind == model::StructureKind::beam ? 2 * node : 6 * node + 1;
}
int Discretisation::slope_dof(int node) const {
  return kind == model::StructureKind::beam ? 2 * node + 1 : 6 * node + 2;
}
int Discretisation::tangential_dof(int node) const { return 6 * node; }

std::array<int, 2> Discretisation::element_reactions(int element) const {
  std::array<int, 2> ends{-1, -1};
  const auto last = std::upper_bound(reaction_nodes.begin(), reaction_nodes.end(), element);
  if (last != reaction_nodes.begin() && *(last - 1) == element)
    ends[0] = static_cast<int>(last - reaction_nodes.begin()) - 1;
  if (last != reaction_nodes.end() && *last == element + 1) ends[1] = static_cast<int>(last - reaction_nodes.begin());
  return ends;
}

std::vector<int> Discretisation::element_dofs(int e) const {
  if (kind == model::StructureKind::beam) return {2 * e, 2 * e + 1, 2 * e + 2, 2 * e + 3};
  return {6 * e + 1, 6 * e + 2, 6 * e + 7, 6 * e + 8, 6 * e, 6 * e + 3, 6 * e + 4, 6 * e + 5, 6 * e + 6};
}

DofRole Discretisation::role_of_dof(int dof) const {
  if (kind == model::StructureKind::beam) return dof % 2 == 0 ? DofRole::deflection : DofRole::slope;
  switch (dof % 6) {
    case 1:
      return DofRole::deflection;
    case 2:
      return DofRole::slope;
    default:
      return DofRole::tangential;
  }
}

double Discretisation::position_of_dof(int dof) const {
  if (kind == model::StructureKind::beam) return mesh.nodes[dof / 2];
  const int block = dof / 6, offset = dof % 6;
  if (offset < 3) return mesh.nodes[block];
  const double h = mesh.element_size(block);
  return mesh.nodes[block] + h * quartic_nodes[offset - 2];
}

Eigen::VectorXd Discretisation::expand(const Eigen::VectorXd& on_equations) const {
  Eigen::VectorXd all = Eigen::VectorXd::Zero(dofs());
  for (int dof = 0; dof < dofs(); ++dof)
    if (equation_of_dof[dof] >= 0) all[dof] = on_equations[equation_of_dof[dof]];
  return all;
}

Eigen::VectorXd Discretisation::expand_displacement(const Eigen::VectorXd& on_equations) const {
  Eigen::VectorXd all = expand(on_equations);
  if (prescribed.size() == all.size()) all += prescribed;
  return all;
}

Eigen::VectorXd Discretisation::on_equations(const Eigen::VectorXd& displacement) const {
  Eigen::VectorXd x = Eigen::VectorXd::Zero(equations);
  for (int dof = 0; dof < dofs(); ++dof)
    if (const int eq = equation_of_dof[dof]; eq >= 0)
      x[eq] = displacement[dof] - (prescribed.size() == dofs() ? prescribed[dof] : 0.0);
  return x;
}

namespace {

int dof_count(model::StructureKind kind, int elements) {
  return kind == model::StructureKind::beam ? 2 * (elements + 1) : 6 * elements + 3;
}

// Dofs fixed by the end and point supports.
std::vector<int> supported_dofs(const model::MemberModel& model, const Discretisation& d) {
  std::vector<int> fixed;
  auto fix_end = [&](int node, model::EndSupport support) {
    const bool arch = model.kind == model::StructureKind::arch;
    switch (support) {
      case model::EndSupport::free:
        break;
      case model::EndSupport::roller:
        fixed.push_back(d.deflection_dof(node));
        break;
      case model::EndSupport::pinned:
        fixed.push_back(d.deflection_dof(node));
        if (arch) fixed.push_back(d.tangential_dof(node));
        break;
      case model::EndSupport::clamped:
        fixed.push_back(d.deflection_dof(node));
        fixed.push_back(d.slope_dof(node));
        if (arch) fixed.push_back(d.tangential_dof(node));
        break;
    }
  };
  fix_end(0, model.left);
  fix_end(d.mesh.elements(), model.right);
  for (double s : model.point_supports) fixed.push_back(d.deflection_dof(d.mesh.node_at(s)));
  return fixed;
}

// The rows of G of the elastic supports, one per spring (a support with both kinds has two; an
// arch's translational spring two, on u and on w).
std::vector<Discretisation::SpringRow> spring_rows(const model::MemberModel& model, const Discretisation& d) {
  std::vector<Discretisation::SpringRow> rows;
  const bool arch = model.kind == model::StructureKind::arch;
  for (const model::SupportSpring& spring : model.springs) {
    const int node = d.mesh.node_at(spring.s);
    if (node < 0) throw std::invalid_argument("discretise: the mesh lacks a node at an elastic support");
    if (spring.stiffness > 0.0) {
      rows.push_back({node, DofRole::deflection, {{d.deflection_dof(node), 1.0}}, spring.stiffness, spring.settlement});
      if (arch) rows.push_back({node, DofRole::tangential, {{d.tangential_dof(node), 1.0}}, spring.stiffness, 0.0});
    }
    if (spring.rotational_stiffness > 0.0) {
      // The rotation a counterclockwise moment works on: -w' (beams), -(u + w') (arches; -(u - w')
      // with the foundation outside), as the assembly's moment loads read it.
      Discretisation::SpringRow row{node, DofRole::slope, {}, spring.rotational_stiffness, 0.0};
      row.on.emplace_back(d.slope_dof(node), arch ? -arch_element::inward_sign(model.foundation_outside) : -1.0);
      if (arch) row.on.emplace_back(d.tangential_dof(node), -1.0);
      rows.push_back(row);
    }
  }
  return rows;
}

// The displacement the settled supports prescribe, on every dof.
Eigen::VectorXd prescribed_displacement(const model::MemberModel& model, const Discretisation& d) {
  Eigen::VectorXd u = Eigen::VectorXd::Zero(d.dofs());
  if (model.left != model::EndSupport::free) u[d.deflection_dof(0)] = model.left_settlement;
  if (model.right != model::EndSupport::free) u[d.deflection_dof(d.mesh.elements())] = model.right_settlement;
  for (std::size_t i = 0; i < model.point_settlements.size() && i < model.point_supports.size(); ++i)
    u[d.deflection_dof(d.mesh.node_at(model.point_supports[i]))] = model.point_settlements[i];
  return u;
}

}  // namespace

Eigen::MatrixXd rigid_motions(const model::MemberModel& model, const Discretisation& d) {
  const int n = d.dofs();
  const double middle = 0.5 * (model.s_begin + model.s_end);
  if (model.kind == model::StructureKind::beam) {
    Eigen::MatrixXd modes = Eigen::MatrixXd::Zero(n, 2);
    for (int dof = 0; dof < n; ++dof) {
      const double s = d.position_of_dof(dof);
      const bool slope = d.role_of_dof(dof) == DofRole::slope;
      modes(dof, 0) = slope ? 0.0 : 1.0;         // translation
      modes(dof, 1) = slope ? 1.0 : s - middle;  // rotation about the middle
    }
    return modes;
  }
  // Arch: horizontal and vertical translation, rotation about the centre of curvature (w and w'
  // change sign with the foundation outside: w > 0 is outward there).
  Eigen::MatrixXd modes = Eigen::MatrixXd::Zero(n, 3);
  const double in = arch_element::inward_sign(d.foundation_outside);
  for (int dof = 0; dof < n; ++dof) {
    const double t = d.position_of_dof(dof), c = std::cos(t), s = std::sin(t);
    switch (d.role_of_dof(dof)) {
      case DofRole::tangential:
        modes.row(dof) << c, -s, 1.0;
        break;
      case DofRole::deflection:
        modes.row(dof) << -in * s, -in * c, 0.0;
        break;
      case DofRole::slope:
        modes.row(dof) << -in * c, in * s, 0.0;
        break;
    }
  }
  return modes;
}

namespace {

Eigen::MatrixXd kernel(const Eigen::MatrixXd& a, int columns) {
  if (a.rows() == 0) return Eigen::MatrixXd::Identity(columns, columns);
  Eigen::FullPivLU<Eigen::MatrixXd> lu(a);
  lu.setThreshold(1e-10);
  if (lu.rank() == columns) return Eigen::MatrixXd(columns, 0);
  return lu.kernel();
}

// The beam or arch element of length h (element.hpp).
std::unique_ptr<const LinearElement> member_element(const model::MemberModel& model, double h) {
  if (model.kind == model::StructureKind::beam) return std::make_unique<const BeamElement>(h);
  return std::make_unique<const ArchElement>(h, model.membrane_stiffness, model.foundation_outside);
}

struct Assembly {
  Triplets stiffness, coupling, flexibility, stress_coupling;
  Triplets geometric;             // K_g, beams with an axial force only
  Eigen::VectorXd initial_shape;  // integral of N_w'^T w0' on every dof (an axial force only)
  Eigen::VectorXd ground_gap;     // reactions
  Eigen::VectorXd compliance;
  Eigen::VectorXd dead_load, live_load;  // on every dof
};

Assembly assemble(const model::MemberModel& model, const Discretisation& d) {
  Assembly a;
  const int n = d.dofs();
  a.dead_load = Eigen::VectorXd::Zero(n);
  a.live_load = Eigen::VectorXd::Zero(n);
  const Mesh& mesh = d.mesh;
  const bool beam = model.kind == model::StructureKind::beam;
  const int spe = d.stresses_per_element;
  const int winkler_count = static_cast<int>(d.winkler_elements.size());
  a.compliance.resize(d.spring_stress(static_cast<int>(d.springs.size())));
  int winkler_index = 0;  // into d.winkler_elements, which is in element order
  a.ground_gap = Eigen::VectorXd::Zero(d.reactions());

  const bool axial = beam && model.has_axial_force();
  if (axial) a.initial_shape = Eigen::VectorXd::Zero(n);
  // The element matrices depend on h alone: computed once per run of equal sizes (a segment of a
  // mesh is uniform), the same numbers as per element.
  double cached_h = std::numeric_limits<double>::quiet_NaN();
  std::unique_ptr<const LinearElement> element;
  Eigen::MatrixXd g;
  Eigen::VectorXd element_compliance;
  Eigen::Matrix<double, 2, 4> foundation_coupling;
  for (int e = 0; e < mesh.elements(); ++e) {
    const double h = mesh.element_size(e);
    const double middle = mesh.nodes[e] + 0.5 * h;
    const std::vector<int> dofs = d.element_dofs(e);
    if (axial) {
      const Eigen::Matrix4d kg = beam_element::geometric_stiffness(h);
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) a.geometric.emplace_back(dofs[i], dofs[j], kg(i, j));
      // integral of N'^T w0' over the element: w0' is constant on each piece of the table, and the
      // integral of N' over a piece is N at its ends.
      const std::vector<double>& at = model.initial_shape_at;
      const std::vector<double>& w0 = model.initial_shape_value;
      Eigen::Vector4d load = Eigen::Vector4d::Zero();
      for (std::size_t i = 0; i + 1 < at.size(); ++i) {
        const double lo = std::max(at[i], mesh.nodes[e]), hi = std::min(at[i + 1], mesh.nodes[e + 1]);
        if (!(hi > lo)) continue;
        const double slope = (w0[i + 1] - w0[i]) / (at[i + 1] - at[i]);
        load += slope *
                (hermite_cubic((hi - mesh.nodes[e]) / h, h).value - hermite_cubic((lo - mesh.nodes[e]) / h, h).value);
      }
      for (int j = 0; j < 4; ++j) a.initial_shape[dofs[j]] += load[j];
    }
    if (!(h == cached_h)) {
      cached_h = h;
      element = member_element(model, h);
      g = beam ? Eigen::MatrixXd(beam_element::stress_coupling(h))
               : Eigen::MatrixXd(arch_element::stress_coupling(h, model.foundation_outside));
      element_compliance = beam ? Eigen::VectorXd(beam_element::compliance(h))
                                : Eigen::VectorXd(arch_element::compliance(h, model.membrane_stiffness));
      foundation_coupling = foundation_element::coupling(h);
    }
    const Eigen::MatrixXd& k = element->stiffness();
    for (int i = 0; i < k.rows(); ++i)
      for (int j = 0; j < k.cols(); ++j) a.stiffness.emplace_back(dofs[i], dofs[j], k(i, j));
    a.compliance.segment(static_cast<Eigen::Index>(spe) * e, spe) = element_compliance;
    for (int i = 0; i < g.rows(); ++i)
      for (int j = 0; j < g.cols(); ++j)
        if (g(i, j) != 0.0) a.stress_coupling.emplace_back(spe * e + i, dofs[j], g(i, j));

    // The first four local dofs are the Hermite dofs of w for both element kinds.
    if (winkler_index < winkler_count && d.winkler_elements[winkler_index] == e) {
      // The bilinear foundation's Winkler part K_t (w - g): its stiffness K_t N_w^T N_w both in K
      // and as Gauss-point stresses in G, H (foundation_element.hpp), its load K_t g N_w dead.
      const double kt = d.element_tension_k[e];
      const int first = d.winkler_stress(winkler_index++);
      for (int q = 0; q < foundation_element::winkler_points; ++q) {
        const auto& point = foundation_element::winkler_rule[q];
        const Eigen::Vector4d n_w = hermite_cubic(point.xi, h).value;
        const double weight = point.weight * h;
        a.compliance[first + q] = 1.0 / (kt * weight);
        for (int i = 0; i < 4; ++i) {
          if (n_w[i] != 0.0) a.stress_coupling.emplace_back(first + q, dofs[i], n_w[i]);
          for (int j = 0; j < 4; ++j) a.stiffness.emplace_back(dofs[i], dofs[j], kt * weight * n_w[i] * n_w[j]);
        }
      }
      if (model.has_ground_gap()) {
        Eigen::Vector4d load = Eigen::Vector4d::Zero();
        for (const auto& point : foundation_element::winkler_rule)  // g linear, N_w cubic: exact
          load += (kt * point.weight * h * model.ground_gap_in(mesh.nodes[e], h, point.xi)) *
                  hermite_cubic(point.xi, h).value;
        for (int j = 0; j < 4; ++j) a.dead_load[dofs[j]] += load[j];
      }
    }
    if (d.foundation_on_element[e]) {
      const auto& c = foundation_coupling;
      const auto t = foundation_element::flexibility(h, d.element_k[e].begin, d.element_k[e].end);
      const std::array<int, 2> r = d.element_reactions(e);
      for (int i = 0; i < 2; ++i) {
        for (int j = 0; j < 4; ++j) a.coupling.emplace_back(r[i], dofs[j], c(i, j));
        for (int j = 0; j < 2; ++j) a.flexibility.emplace_back(r[i], r[j], t(i, j));
      }
      if (model.has_ground_gap()) {
        // g is linear in the element: its end values from two interior points (a step at a node
        // has each side's value), then integral of Hb^T g = h/6 [2 g0 + g1, g0 + 2 g1].
        const double g0 = model.ground_gap_in(mesh.nodes[e], h, 0.0), g1 = model.ground_gap_in(mesh.nodes[e], h, 1.0);
        a.ground_gap[r[0]] += h / 6.0 * (2.0 * g0 + g1);
        a.ground_gap[r[1]] += h / 6.0 * (g0 + 2.0 * g1);
      }
    }

    for (const model::MemberLoad& load : model.loads) {
      if (middle < load.from || middle > load.to) continue;
      Eigen::VectorXd& target = load.load_case == model::LoadCase::dead ? a.dead_load : a.live_load;
      if (load.kind == model::LoadKind::uniform && !beam) {  // radial or vertical, fe/arch_loads.hpp
        const auto consistent = arch_element_load(mesh.nodes[e], h, load.direction, load.per, model.foundation_outside,
                                                  [&](double s) { return load.intensity(s); });
        for (int j = 0; j < arch_element::dofs; ++j) target[dofs[j]] += consistent[j];
      } else if (load.kind == model::LoadKind::sine && !beam) {
        throw std::logic_error("fe: a sine load on an arch (the scene reader refuses it)");
      } else if (load.is_distributed_force()) {
        // q times cubic shapes: linear q exactly (degree 4, Gauss 5); a sine to round-off
        // (model::load_quadrature).
        Eigen::Vector4d consistent = Eigen::Vector4d::Zero();
        for (const model::LoadQuadraturePoint& g : model::load_quadrature(load, mesh.nodes[e], mesh.nodes[e] + h))
          consistent += (g.weight * load.intensity(g.s)) * hermite_cubic((g.s - mesh.nodes[e]) / h, h).value;
        for (int j = 0; j < 4; ++j) target[dofs[j]] += consistent[j];
      } else if (load.kind == model::LoadKind::curvature) {
        // An initial strain: Pi = 1/2 int (w'' + kappa)^2 gives F = -kappa int N'' = -kappa [N']_0^h,
        // so a range of curvature is a pair of end moments EI kappa (the interior nodes cancel).
        target[dofs[1]] += load.value;
        target[dofs[3]] -= load.value;
      }
    }
  }

  // Springs: K += k a a^T, one more stress (row a of G, compliance 1/k); a settled spring's far
  // end pulls with k delta (a dead load: the ground, not the live load, moves it).
  for (std::size_t i = 0; i < d.springs.size(); ++i) {
    const Discretisation::SpringRow& spring = d.springs[i];
    const int row = d.spring_stress(static_cast<int>(i));
    a.compliance[row] = 1.0 / spring.stiffness;
    for (const auto& [dof, coefficient] : spring.on) {
      a.stress_coupling.emplace_back(row, dof, coefficient);
      a.dead_load[dof] += spring.stiffness * spring.settlement * coefficient;
      for (const auto& [other, other_coefficient] : spring.on)
        a.stiffness.emplace_back(dof, other, spring.stiffness * coefficient * other_coefficient);
    }
  }

  for (const model::MemberLoad& load : model.loads) {
    if (load.has_extent()) continue;
    Eigen::VectorXd& target = load.load_case == model::LoadCase::dead ? a.dead_load : a.live_load;
    const int node = mesh.node_at(load.at);
    if (load.kind == model::LoadKind::force && model.kind == model::StructureKind::arch) {
      const Eigen::Vector2d c = arch_load_components(load.direction, load.per, load.at, model.foundation_outside);
      target[d.deflection_dof(node)] += c[0] * load.value;
      target[d.tangential_dof(node)] += c[1] * load.value;
    } else if (load.kind == model::LoadKind::force) {
      target[d.deflection_dof(node)] += load.value;
    } else {
      // Work of a counterclockwise moment: M * rotation, rotation = -w' (beam), -(u + w') (arch;
      // -(u - w') with the foundation outside).
      target[d.slope_dof(node)] -= arch_element::inward_sign(model.foundation_outside) * load.value;
      if (model.kind == model::StructureKind::arch) target[d.tangential_dof(node)] -= load.value;
    }
  }
  return a;
}

// The triplets are renumbered in place (and dropped where a map gives -1): no second list.
SparseMatrix to_sparse(int rows, int cols, Triplets triplets, const std::vector<int>* row_map,
                       const std::vector<int>* col_map) {
  if (row_map || col_map) {
    std::size_t kept = 0;
    for (const auto& t : triplets) {
      const int i = row_map ? (*row_map)[t.row()] : t.row();
      const int j = col_map ? (*col_map)[t.col()] : t.col();
      if (i >= 0 && j >= 0) triplets[kept++] = Eigen::Triplet<double>(i, j, t.value());
    }
    triplets.resize(kept);
  }
  // Compressed columns by a counting sort on the column, rows sorted stably within each column and
  // duplicates summed in the order they come: setFromTriplets' sums, bit for bit, without its
  // row-major copy and second transposition.
  std::vector<int> start(static_cast<std::size_t>(cols) + 1, 0);
  for (const auto& t : triplets) ++start[t.col() + 1];
  for (int c = 0; c < cols; ++c) start[c + 1] += start[c];
  std::vector<int> row(triplets.size()), next(start.begin(), start.end() - 1);
  std::vector<double> value(triplets.size());
  for (const auto& t : triplets) {
    const int at = next[t.col()]++;
    row[at] = t.row();
    value[at] = t.value();
  }
  int kept = 0;
  std::vector<int> outer(static_cast<std::size_t>(cols) + 1, 0);
  for (int c = 0; c < cols; ++c) {
    const int begin = start[c], end = start[c + 1];
    for (int p = begin + 1; p < end; ++p)  // insertion sort: stable, and a column holds a few entries
      for (int q = p; q > begin && row[q - 1] > row[q]; --q) {
        std::swap(row[q - 1], row[q]);
        std::swap(value[q - 1], value[q]);
      }
    for (int p = begin; p < end; ++p) {
      if (kept > outer[c] && row[p] == row[kept - 1]) {
        value[kept - 1] += value[p];
      } else {
        row[kept] = row[p];
        value[kept++] = value[p];
      }
    }
    outer[c + 1] = kept;
  }
  SparseMatrix m(rows, cols);
  m.resizeNonZeros(kept);
  std::copy(outer.begin(), outer.end(), m.outerIndexPtr());
  std::copy(row.begin(), row.begin() + kept, m.innerIndexPtr());
  std::copy(value.begin(), value.begin() + kept, m.valuePtr());
  return m;
}

std::string describe_rigid_motions(model::StructureKind kind, int count) {
  if (kind == model::StructureKind::beam)
    return count == 2 ? "rigid translation and rotation" : "a rigid rotation about its only support";
  return count == 1 ? "one rigid motion" : fmt::format("{} rigid motions", count);
}

}  // namespace

StructuralElements structural_elements(const model::MemberModel& model, const Discretisation& d) {
  StructuralElements set;
  std::size_t winkler_index = 0;  // winkler_elements is in element order
  for (int e = 0; e < d.mesh.elements(); ++e) {
    const double h = d.mesh.element_size(e);
    std::vector<int> dofs = d.element_dofs(e);
    if (model.kind == model::StructureKind::beam && model.has_axial_force())
      set.elements.push_back(std::make_unique<const BeamColumnElement>(h, model.axial_dead, model.axial_live));
    else
      set.elements.push_back(member_element(model, h));
    set.dofs.push_back(dofs);
    if (winkler_index < d.winkler_elements.size() && d.winkler_elements[winkler_index] == e) {
      ++winkler_index;
      set.elements.push_back(std::make_unique<const WinklerElement>(h, d.element_tension_k[e]));
      dofs.resize(4);
      set.dofs.push_back(std::move(dofs));
    }
  }
  for (const Discretisation::SpringRow& spring : d.springs) {
    const int m = static_cast<int>(spring.on.size());
    Eigen::VectorXd a(m);
    std::vector<int> dofs(m);
    for (int i = 0; i < m; ++i) std::tie(dofs[i], a[i]) = spring.on[i];
    set.elements.push_back(std::make_unique<const LinearElement>(spring.stiffness * a * a.transpose()));
    set.dofs.push_back(std::move(dofs));
  }
  return set;
}

Discretisation discretise(const model::MemberModel& model, int elements) {
  Discretisation d = discretise(model, make_mesh(model, elements));
  d.uniform_member = std::make_shared<const model::MemberModel>(model);
  return d;
}

namespace {

// ---- the stages of discretise, in order ------------------------------------------------------

// Mesh stage: the member on `mesh`: the foundation under each element, the reaction unknowns,
// the springs' rows. No dof is numbered yet (equation_of_dof: every dof, all 0).
Discretisation lay_out(const model::MemberModel& model, Mesh mesh, std::vector<bool> foundation_on_element) {
  Discretisation d;
  d.kind = model.kind;
  d.mesh = std::move(mesh);
  d.k = model.k;
  d.tensionless = model.tensionless;
  d.foundation_outside = model.kind == model::StructureKind::arch && model.foundation_outside;
  d.stresses_per_element = model.kind == model::StructureKind::beam ? beam_element::stresses : arch_element::stresses;
  const int elements = d.mesh.elements();
  d.equation_of_dof.assign(dof_count(model.kind, elements), 0);
  for (double s : mesh_breakpoints(model))
    if (d.mesh.node_at(s) < 0) throw std::invalid_argument("discretise: the mesh lacks a node at a breakpoint");

  d.element_k.resize(elements);
  d.element_tension_k.resize(elements);
  for (int e = 0; e < elements; ++e) {
    const auto [begin, end] = model.k_on(d.mesh.nodes[e], d.mesh.nodes[e + 1]);
    // The Winkler part K_t under the element (constant), the tensionless part k - K_t at its ends.
    const double middle = d.mesh.nodes[e] + 0.5 * d.mesh.element_size(e);
    d.element_tension_k[e] = model.tension_k_at(middle);
    d.element_k[e] = {begin - d.element_tension_k[e], end - d.element_tension_k[e]};
    if (d.element_tension_k[e] > 0.0) d.winkler_elements.push_back(e);
  }
  if (foundation_on_element.empty()) foundation_on_element.assign(elements, true);
  if (static_cast<int>(foundation_on_element.size()) != elements)
    throw std::invalid_argument("discretise: one foundation flag per element expected");
  for (int e = 0; e < elements; ++e) foundation_on_element[e] = foundation_on_element[e] && d.element_k[e].present();
  d.foundation_on_element = std::move(foundation_on_element);
  std::vector<bool> jumps(d.mesh.nodes.size(), false);
  for (double s : model.reaction_jumps())
    if (const int node = d.mesh.node_at(s); node >= 0) jumps[node] = true;
  for (int node = 0; node <= elements; ++node) {
    const bool left = node > 0 && d.foundation_on_element[node - 1];
    const bool right = node < elements && d.foundation_on_element[node];
    if (left || right) d.reaction_nodes.push_back(node);
    if (left && right && jumps[node]) d.reaction_nodes.push_back(node);
  }
  d.springs = spring_rows(model, d);
  return d;
}

// Settlements: u = u_f + v with u_f the prescribed w at the settled supports, so K v = F - K u_f
// (a dead load: the ground moves the supports whatever the live load) and the gap is offset
// by -C u_f (added to the ground gap c, not scaled by lambda either).
void apply_settlements(const model::MemberModel& model, Discretisation& d, Assembly& a) {
  d.prescribed = prescribed_displacement(model, d);
  if (d.prescribed.isZero(0.0)) return;
  for (const auto& t : a.stiffness) a.dead_load[t.row()] -= t.value() * d.prescribed[t.col()];
  // K(N) u_f = K u_f - N K_g u_f with N = N_dead + lambda N_live: N K_g u_f is split by the axial
  // force's cases, as the initial shape's load is, so that F_dead + lambda F_live holds it at every
  // lambda (a path in lambda re-forms K(N(lambda)); at lambda = 1 it is N(1) K_g u_f as before).
  for (const auto& t : a.geometric) {
    a.dead_load[t.row()] += model.axial_dead * t.value() * d.prescribed[t.col()];
    a.live_load[t.row()] += model.axial_live * t.value() * d.prescribed[t.col()];
  }
  // Where the foundation reaches a settled support.
  a.ground_gap -= to_sparse(d.reactions(), d.dofs(), a.coupling, nullptr, nullptr) * d.prescribed;
}

// Dof-map stage: supports, the rigid motions they leave free (the member's rigid motions are
// computed here, once, and kept in d.member_rigid_motions for every later user), the mechanisms the loads
// would drive (an error), the gauge, and the numbering of the equations. It reads the assembly on
// every dof: whether a free motion is a mechanism depends on the loads and on C.
void number_dofs(const model::MemberModel& model, Discretisation& d, const Assembly& a) {
  const int n = d.dofs();
  std::vector<int> fixed = supported_dofs(model, d);
  d.member_rigid_motions = rigid_motions(model, d);
  const Eigen::MatrixXd& modes = d.member_rigid_motions;
  // A spring restrains whatever motion stretches it, like a fixed dof.
  auto free_motions = [&](const std::vector<int>& fixed_dofs) {
    Eigen::MatrixXd at_fixed = Eigen::MatrixXd::Zero(fixed_dofs.size() + d.springs.size(), modes.cols());
    for (std::size_t i = 0; i < fixed_dofs.size(); ++i) at_fixed.row(i) = modes.row(fixed_dofs[i]);
    for (std::size_t i = 0; i < d.springs.size(); ++i)
      for (const auto& [dof, coefficient] : d.springs[i].on)
        at_fixed.row(fixed_dofs.size() + i) += coefficient * modes.row(dof);
    return Eigen::MatrixXd(modes * kernel(at_fixed, static_cast<int>(modes.cols())));
  };
  // Rigid motions left free by the supports, split into those the foundation sees and those
  // it cannot (C m = 0).
  const Eigen::MatrixXd motions = free_motions(fixed);
  Eigen::MatrixXd left_free(n, 0);
  if (motions.cols() > 0) {
    const SparseMatrix coupling_all = to_sparse(d.reactions(), n, a.coupling, nullptr, nullptr);
    const Eigen::MatrixXd seen = coupling_all * motions;
    const Eigen::MatrixXd unseen =
        motions * kernel(seen / std::max(1e-300, seen.cwiseAbs().maxCoeff()), static_cast<int>(motions.cols()));
    const double middle = 0.5 * (model.s_begin + model.s_end);
    for (int m = 0; m < unseen.cols(); ++m) {
      const Eigen::VectorXd mode = unseen.col(m) / unseen.col(m).cwiseAbs().maxCoeff();
      for (const Eigen::VectorXd* load : {&a.dead_load, &a.live_load}) {
        if (std::abs(load->dot(mode)) > 1e-10 * std::max(1e-300, load->lpNorm<1>()))
          throw MechanismError(
              "key 'supports': the supports leave the member free to move rigidly in a way the foundation "
              "cannot resist (for an arch on rollers: rotation about its centre of curvature), and the loads "
              "drive that motion, so no equilibrium exists; expected supports that prevent it (e.g. a pinned end)");
      }
      // Gauge: fix the dof that moves most, nearest the middle of the member.
      int gauge = -1;
      for (int dof = 0; dof < n; ++dof) {
        if (std::abs(mode[dof]) < 0.999 || std::find(fixed.begin(), fixed.end(), dof) != fixed.end()) continue;
        if (gauge < 0 || std::abs(d.position_of_dof(dof) - middle) < std::abs(d.position_of_dof(gauge) - middle))
          gauge = dof;
      }
      fixed.push_back(gauge);
      const bool arch = model.kind == model::StructureKind::arch;
      d.gauge_note = fmt::format(
          "{} free to {}, which no support and no foundation resists and the loads do not drive: u = 0 at "
          "{} = {:.6g}{} fixes it and changes no deflection, force or moment",
          arch ? "the arch is" : "the member is", arch ? "rotate rigidly about its centre" : "move rigidly",
          arch ? "theta" : "x", model.user_from_s(d.position_of_dof(gauge)), arch ? " deg" : "");
    }
    left_free = free_motions(fixed);
    if (left_free.cols() > 0 && !d.winkler_elements.empty()) {
      // The Winkler part of a bilinear foundation resists, in K, every motion that moves w on it.
      const SparseMatrix g = to_sparse(static_cast<int>(a.compliance.size()), n, a.stress_coupling, nullptr, nullptr);
      const Eigen::MatrixXd g_m = g * left_free;
      const Eigen::MatrixXd seen_by_winkler = g_m.bottomRows(g_m.rows() - d.element_stresses());
      left_free = left_free * kernel(seen_by_winkler / std::max(1e-300, seen_by_winkler.cwiseAbs().maxCoeff()),
                                     static_cast<int>(left_free.cols()));
    }
    d.unstable_rigid_motions = static_cast<int>(left_free.cols());
    if (!d.structure_is_stable())
      d.stability_note = fmt::format("the supports leave {} that only the foundation resists",
                                     describe_rigid_motions(model.kind, d.unstable_rigid_motions));
  }

  for (int dof : fixed) d.equation_of_dof[dof] = -1;
  for (int dof = 0; dof < n; ++dof)
    if (d.equation_of_dof[dof] >= 0) d.equation_of_dof[dof] = d.equations++;
  d.free_rigid_motions.resize(d.equations, d.unstable_rigid_motions);
  for (int dof = 0; dof < n && d.unstable_rigid_motions > 0; ++dof)
    if (d.equation_of_dof[dof] >= 0) d.free_rigid_motions.row(d.equation_of_dof[dof]) = left_free.row(dof);
}

// Assembly, last part: the matrices and loads on the equations.
void restrict_to_equations(Discretisation& d, Assembly a) {
  d.stiffness = to_sparse(d.equations, d.equations, std::move(a.stiffness), &d.equation_of_dof, &d.equation_of_dof);
  d.coupling = to_sparse(d.reactions(), d.equations, std::move(a.coupling), nullptr, &d.equation_of_dof);
  d.flexibility = to_sparse(d.reactions(), d.reactions(), std::move(a.flexibility), nullptr, nullptr);
  d.stress_coupling = to_sparse(static_cast<int>(a.compliance.size()), d.equations, std::move(a.stress_coupling),
                                nullptr, &d.equation_of_dof);
  d.compliance = std::move(a.compliance);
  d.ground_gap = std::move(a.ground_gap);
  d.dead_load = Eigen::VectorXd::Zero(d.equations);
  d.live_load = Eigen::VectorXd::Zero(d.equations);
  if (a.initial_shape.size() > 0) d.initial_shape_load = Eigen::VectorXd::Zero(d.equations);
  for (int dof = 0; dof < d.dofs(); ++dof) {
    const int eq = d.equation_of_dof[dof];
    if (eq < 0) continue;
    d.dead_load[eq] = a.dead_load[dof];
    d.live_load[eq] = a.live_load[dof];
    if (a.initial_shape.size() > 0) d.initial_shape_load[eq] = a.initial_shape[dof];
  }
  if (!a.geometric.empty())
    d.geometric_stiffness =
        to_sparse(d.equations, d.equations, std::move(a.geometric), &d.equation_of_dof, &d.equation_of_dof);
}

// Second-order theory (beams under an axial force): K(N) = K - N K_g at the solve's load factor 1,
// from the K_g the element loop assembled once (the one the mixed form and the certificate use
// too, so every consumer sees the same K_g), and the initial shape's load N K_g w0 by case.
void apply_axial_force(const model::MemberModel& model, Discretisation& d) {
  if (model.kind != model::StructureKind::beam || !model.has_axial_force()) return;
  d.axial_force = model.axial_force(1.0);
  d.stiffness = SparseMatrix(d.stiffness - d.axial_force * d.geometric_stiffness);
  if (d.initial_shape_load.size() == d.equations) {
    d.dead_load += model.axial_dead * d.initial_shape_load;
    d.live_load += model.axial_live * d.initial_shape_load;
  }
}

}  // namespace

// The stages in order, as deal.II's step-3 runs make_grid, setup_system, assemble_system. The
// element loop runs on every dof before the equations are numbered, because the dof map needs
// the loads and C to tell a mechanism (an error) from a gauge.
Discretisation discretise(const model::MemberModel& model, Mesh mesh, std::vector<bool> foundation_on_element) {
  Discretisation d = lay_out(model, std::move(mesh), std::move(foundation_on_element));
  Assembly a = assemble(model, d);
  apply_settlements(model, d, a);
  number_dofs(model, d, a);
  restrict_to_equations(d, std::move(a));
  apply_axial_force(model, d);
  return d;
}

}  // namespace liftoff::fe
