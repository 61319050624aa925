// The certificate of an FE + LCP answer (certificate.hpp says what each check means).

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "certify/certificate.hpp"
#include "certify/detail.hpp"
#include "fe/arch_element.hpp"
#include "fe/arch_von_karman_element.hpp"
#include "fe/beam_element.hpp"
#include "fe/shape_functions.hpp"
#include "fe/von_karman_element.hpp"
#include "linalg/banded_lu.hpp"

namespace liftoff::certify {

using Eigen::VectorXd;
using fe::Discretisation;
using model::MemberModel;
using model::StructureKind;

namespace {

using detail::eps;

// ---- the answer's nodal forces, from the element equations ------------------------------------

// The foundation's k under the element at its two nodes (linear between), from the member (not
// the discretisation's copy): 0 in a void between foundation pieces and beyond the foundation.
// For a bilinear foundation the tensionless part's k - K_t (the contact conditions' modulus), and
// K_t (constant) its Winkler part's.
double tension_k_under(const MemberModel& model, const fe::Mesh& mesh, int element) {
  return model.tension_k_at(mesh.nodes[element] + 0.5 * mesh.element_size(element));
}
std::pair<double, double> k_under(const MemberModel& model, const fe::Mesh& mesh, int element) {
  const auto [begin, end] = model.k_on(mesh.nodes[element], mesh.nodes[element + 1]);
  const double kt = tension_k_under(model, mesh, element);
  return {begin - kt, end - kt};
}

// Whether the element lies on a piece of the foundation (as the assembly decides by default).
bool in_foundation_extent(const MemberModel& model, const fe::Mesh& mesh, int element) {
  return k_under(model, mesh, element).first > 0.0;
}

// The integral over the element of phi_a phi_b / k(s) (phi the P1 reaction shapes, k linear from
// k_a to k_b), by Gauss-Legendre's five points on pieces over which k changes by at most 2 %
// (graded geometrically in k; one piece when k is constant, where the rule is exact): on each,
// 1/k's pole lies beyond 100 half-widths, and Gauss's error bound on the Bernstein ellipse
// rho = 50 (Trefethen, ATAP, thm 19.3) is below 1e-16 of the integrand's size. A bound of its
// own, not the solver's logarithms (fe/foundation_element.hpp).
Eigen::Matrix2d reaction_compliance(double h, double k_a, double k_b) {
  const int pieces = k_a == k_b ? 1 : static_cast<int>(std::ceil(std::abs(std::log(k_b / k_a)) / std::log(1.02)));
  Eigen::Matrix2d m = Eigen::Matrix2d::Zero();
  double xi_begin = 0.0;
  for (int p = 1; p <= pieces; ++p) {
    // k at the piece's end is k_a (k_b/k_a)^(p/pieces).
    const double xi_end = p == pieces ? 1.0 : (k_a * std::pow(k_b / k_a, double(p) / pieces) - k_a) / (k_b - k_a);
    for (const fe::GaussPoint& g : fe::gauss5) {
      const double xi = xi_begin + g.xi * (xi_end - xi_begin), k = (1.0 - xi) * k_a + xi * k_b;
      const Eigen::Vector2d phi = fe::reaction_shape(xi);
      m += (g.weight * (xi_end - xi_begin) * h / k) * phi * phi.transpose();
    }
    xi_begin = xi_end;
  }
  return m;
}

// Whether the foundation acts on the element in this discretisation: its extent, or, for a
// limit-fitted answer (contact/fitted_limits.hpp), the contact elements only.
bool on_foundation(const Discretisation& d, int element) { return d.foundation_on_element[element]; }

// A limit-fitted discretisation: an element of the foundation's extent without foundation (a
// lift-off element); its contact limits are nodes.
bool is_limit_fitted(const MemberModel& model, const Discretisation& d) {
  for (int e = 0; e < d.mesh.elements(); ++e)
    if (in_foundation_extent(model, d.mesh, e) && !on_foundation(d, e)) return true;
  return false;
}

// Per dof: the element forces K_e u_e summed, the foundation's nodal forces (integral of N_w
// times the P1 reaction, plus for a bilinear foundation the Winkler part's K_t (w - g) on every
// element of the foundation, with g from the model), the applied nodal loads, and the
// magnitude of the terms each row sums (|K||u| + |C^T||r| + |F|). Per reaction node: the
// weighted gap integral of phi_i (r/k - w),
// and the magnitude of its terms.
struct NodalForces {
  VectorXd internal, foundation, applied, magnitude;
  VectorXd springs;  // the elastic supports' forces k (a.u - delta) a, read from the model
  // Beams under an axial force N (second-order theory): its nodal forces, -N integral of N_w'^T
  // (w' + w0'), w0 the initial shape, both read from the model (0 without N). On a rigid rotation
  // they are the moment of N at the displaced ends, which the balance counts like a load.
  VectorXd axial;
  VectorXd gap, gap_terms;
  // Per dof on the equations: the assembled K u minus the element-wise sum of K_e u_e, both
  // compensated: what the rounding of the assembled entries does to this u (0 on fixed dofs).
  VectorXd assembly_defect;
};

// w0' at s strictly inside a piece of the initial shape's table (0 beyond it or without one).
double initial_slope(const MemberModel& model, double s) {
  const std::vector<double>& at = model.initial_shape_at;
  for (std::size_t i = 0; i + 1 < at.size(); ++i)
    if (s > at[i] && s < at[i + 1])
      return (model.initial_shape_value[i + 1] - model.initial_shape_value[i]) / (at[i + 1] - at[i]);
  return 0.0;
}

NodalForces nodal_forces(const MemberModel& model, const Discretisation& d, const VectorXd& u, const VectorXd& r,
                         double load_factor) {
  const int n = d.dofs(), elements = d.mesh.elements();
  NodalForces f;
  f.internal = f.foundation = f.magnitude = f.axial = VectorXd::Zero(n);
  f.gap = f.gap_terms = VectorXd::Zero(d.reactions());
  f.applied = detail::applied_nodal_loads(model, d, load_factor);
  f.magnitude = f.applied.cwiseAbs();
  const std::vector<std::array<int, 2>> reaction_of_node = detail::element_reactions(d);
  const bool arch = d.kind == StructureKind::arch;
  // N in K(N) at this load factor, and N of the initial shape's load (the same sum by cases).
  const double axial_force = arch ? 0.0 : model.axial_force(load_factor);
  const double axial_load = model.has_initial_shape() ? axial_force : 0.0;
  std::vector<detail::Compensated> defect(n);
  std::vector<int> dof_of_equation(d.equations);
  for (int dof = 0; dof < n; ++dof)
    if (d.equation_of_dof[dof] >= 0) dof_of_equation[d.equation_of_dof[dof]] = dof;
  for (int col = 0; col < d.equations; ++col)
    for (fe::SparseMatrix::InnerIterator it(d.stiffness, col); it; ++it)
      defect[dof_of_equation[it.row()]].add_product(it.value(), u[dof_of_equation[col]]);
  for (int e = 0; e < elements; ++e) {
    const double h = d.mesh.element_size(e);
    const std::vector<int> dofs = d.element_dofs(e);
    VectorXd ue(dofs.size());
    for (std::size_t j = 0; j < dofs.size(); ++j) ue[j] = u[dofs[j]];
    const Eigen::MatrixXd ke =
        arch ? Eigen::MatrixXd(fe::arch_element::stiffness(h, model.membrane_stiffness, model.foundation_outside))
             : Eigen::MatrixXd(fe::beam_element::stiffness(h));
    const VectorXd fe_forces = ke * ue, fe_magnitude = ke.cwiseAbs() * ue.cwiseAbs();
    for (std::size_t j = 0; j < dofs.size(); ++j) {
      f.internal[dofs[j]] += fe_forces[j];
      f.magnitude[dofs[j]] += fe_magnitude[j];
      if (d.equation_of_dof[dofs[j]] >= 0)
        for (std::size_t i = 0; i < dofs.size(); ++i)
          if (d.equation_of_dof[dofs[i]] >= 0) defect[dofs[j]].add_product(-ke(j, i), ue[i]);
    }
    if (axial_force != 0.0) {
      // -N integral of N_w' (w' + w0') by Gauss quadrature on each piece of w0 (w0' constant
      // there): exact, the integrand is at most quadratic.
      std::vector<double> breaks{d.mesh.nodes[e], d.mesh.nodes[e + 1]};
      for (double at : model.initial_shape_at)
        if (at > breaks.front() && at < breaks.back()) breaks.insert(breaks.end() - 1, at);
      for (std::size_t p = 0; p + 1 < breaks.size(); ++p) {
        const double a = breaks[p], b = breaks[p + 1], w0_slope = initial_slope(model, 0.5 * (a + b));
        for (const fe::GaussPoint& g : fe::gauss5) {
          const double xi = (a - d.mesh.nodes[e] + g.xi * (b - a)) / h, weight = g.weight * (b - a);
          const Eigen::Vector4d slope = fe::hermite_cubic(xi, h).d1;
          double w_slope = 0.0, abs_slope = 0.0;
          for (int j = 0; j < 4; ++j) w_slope += slope[j] * ue[j], abs_slope += std::abs(slope[j] * ue[j]);
          for (int j = 0; j < 4; ++j) {
            f.axial[dofs[j]] -= weight * axial_force * slope[j] * w_slope + weight * axial_load * slope[j] * w0_slope;
            f.magnitude[dofs[j]] +=
                weight * std::abs(slope[j]) * (std::abs(axial_force) * abs_slope + std::abs(axial_load * w0_slope));
            // K holds -N K_g (fe/discretisation.hpp): off the assembly defect.
            if (d.equation_of_dof[dofs[j]] >= 0)
              for (int i = 0; i < 4; ++i)
                if (d.equation_of_dof[dofs[i]] >= 0)
                  defect[dofs[j]].add_product(weight * axial_force * slope[j] * slope[i], ue[i]);
          }
        }
      }
    }
    if (const double kt = tension_k_under(model, d.mesh, e); kt > 0.0) {
      for (const fe::GaussPoint& g : fe::gauss5) {  // exact: cubic x cubic, cubic x linear
        const Eigen::Vector4d shape = fe::hermite_cubic(g.xi, h).value;
        const double weight = g.weight * h, g_here = model.ground_gap(d.mesh.nodes[e] + g.xi * h);
        double w_here = 0.0, abs_w = 0.0;
        for (int j = 0; j < 4; ++j) w_here += shape[j] * ue[j], abs_w += std::abs(shape[j] * ue[j]);
        for (int j = 0; j < 4; ++j) {
          f.foundation[dofs[j]] += weight * shape[j] * kt * (w_here - g_here);
          f.magnitude[dofs[j]] += weight * std::abs(shape[j]) * kt * (abs_w + std::abs(g_here));
          // K holds K_t's stiffness too (fe/discretisation.hpp): off the assembly defect.
          if (d.equation_of_dof[dofs[j]] >= 0)
            for (int i = 0; i < 4; ++i)
              if (d.equation_of_dof[dofs[i]] >= 0)
                defect[dofs[j]].add_product(-weight * kt * shape[j] * shape[i], ue[i]);
        }
      }
    }
    if (!on_foundation(d, e)) continue;
    const auto [ra, rb] = reaction_of_node[e];
    if (ra < 0 || rb < 0) continue;
    // No foundation under the element in the member (a void): a reaction there acts on nothing,
    // so it adds no force and the balance shows it.
    const auto [k_a, k_b] = k_under(model, d.mesh, e);
    if (k_a == 0.0) continue;
    for (const fe::GaussPoint& g : fe::gauss5) {  // exact: cubic x linear
      const fe::HermiteCubic shape = fe::hermite_cubic(g.xi, h);
      const Eigen::Vector2d phi = fe::reaction_shape(g.xi);
      const double weight = g.weight * h, r_here = phi[0] * r[ra] + phi[1] * r[rb];
      const double abs_r = phi[0] * std::abs(r[ra]) + phi[1] * std::abs(r[rb]);
      double w_here = 0.0, abs_w = 0.0;
      for (int j = 0; j < 4; ++j) {
        w_here += shape.value[j] * ue[j];
        abs_w += std::abs(shape.value[j] * ue[j]);
        f.foundation[dofs[j]] += weight * shape.value[j] * r_here;
        f.magnitude[dofs[j]] += weight * std::abs(shape.value[j]) * abs_r;
      }
      // The ground gap g from the model (the user's table), not from the discretisation's c.
      const double g_here = model.ground_gap(d.mesh.nodes[e] + g.xi * h);
      for (int a = 0; a < 2; ++a) {
        const int i = a == 0 ? ra : rb;
        f.gap[i] += weight * phi[a] * (g_here - w_here);
        f.gap_terms[i] += weight * phi[a] * (abs_w + std::abs(g_here));
      }
    }
    // The r/k(s) part, k(s) the member's modulus (linear on the element).
    const Eigen::Matrix2d compliance = reaction_compliance(h, k_a, k_b);
    const Eigen::Vector2d r_e(r[ra], r[rb]), gap = compliance * r_e, terms = compliance * r_e.cwiseAbs();
    f.gap[ra] += gap[0];
    f.gap[rb] += gap[1];
    f.gap_terms[ra] += terms[0];
    f.gap_terms[rb] += terms[1];
  }
  // Elastic supports, from the model: a translational spring on w (arches u and w), a rotational
  // one on the rotation -w' (arches -(u + w'), outside -(u - w')); a settled spring's far end at delta.
  f.springs = VectorXd::Zero(n);
  for (const model::SupportSpring& spring : model.springs) {
    const int node = d.mesh.node_at(spring.s);
    if (node < 0) continue;
    const int w = d.deflection_dof(node), slope = d.slope_dof(node), t = arch ? d.tangential_dof(node) : -1;
    f.springs[w] += spring.stiffness * (u[w] - spring.settlement);
    f.magnitude[w] += spring.stiffness * (std::abs(u[w]) + std::abs(spring.settlement));
    if (arch) {
      f.springs[t] += spring.stiffness * u[t];
      f.magnitude[t] += spring.stiffness * std::abs(u[t]);
    }
    if (spring.rotational_stiffness > 0.0) {
      const double slope_factor = arch && model.foundation_outside ? 1.0 : -1.0;
      const double rotation = slope_factor * u[slope] - (arch ? u[t] : 0.0);
      const double abs_rotation = std::abs(u[slope]) + (arch ? std::abs(u[t]) : 0.0);
      f.springs[slope] += spring.rotational_stiffness * rotation * slope_factor;
      f.magnitude[slope] += spring.rotational_stiffness * abs_rotation;
      if (arch) {
        f.springs[t] -= spring.rotational_stiffness * rotation;
        f.magnitude[t] += spring.rotational_stiffness * abs_rotation;
      }
    }
  }
  f.assembly_defect = VectorXd::Zero(n);
  for (int dof = 0; dof < n; ++dof) f.assembly_defect[dof] = defect[dof].value();
  return f;
}

// ---- balance -----------------------------------------------------------------------------------

// Balance on each rigid motion (certificate.hpp), and the resultant figures: the applied loads,
// the support reactions (the residual at the supported dofs), the foundation, the springs and
// `moment_terms`, nodal forces counted like a load (a given axial force's, or a von Karman
// membrane's: on the rotation, the moment of N at the displaced ends). rows: the row residual
// relative to its terms that a sound answer may leave.
void check_balance(Certificate& c, const MemberModel& model, const Discretisation& d, const NodalForces& f,
                   const VectorXd& moment_terms, const VectorXd& residual, const std::vector<bool>& is_supported,
                   const VectorXd& r_given, double rows) {
  const Eigen::MatrixXd modes = detail::balance_modes(model, d);
  std::vector<double> applied(modes.cols()), foundation(modes.cols());
  for (int j = 0; j < modes.cols(); ++j) {
    const VectorXd m = modes.col(j);
    double a = 0, a_abs = 0, phi = 0, phi_abs = 0, g = 0, g_abs = 0, internal = 0, bound = 0, assembly = 0;
    double springs = 0, springs_abs = 0;  // the elastic supports, like g but from the model
    double moment = 0, moment_abs = 0;    // the axial (membrane) force's moment at the displaced ends
    for (int dof = 0; dof < d.dofs(); ++dof) {
      assembly += m[dof] * f.assembly_defect[dof];
      a += m[dof] * f.applied[dof];
      a_abs += std::abs(m[dof] * f.applied[dof]);
      phi += m[dof] * f.foundation[dof];
      phi_abs += std::abs(m[dof] * f.foundation[dof]);
      springs += m[dof] * f.springs[dof];
      springs_abs += std::abs(m[dof] * f.springs[dof]);
      moment += m[dof] * moment_terms[dof];
      moment_abs += std::abs(m[dof] * moment_terms[dof]);
      internal += m[dof] * f.internal[dof];
      bound += m[dof] * m[dof] * f.magnitude[dof] * f.magnitude[dof];
      if (is_supported[dof]) {
        g += m[dof] * residual[dof];
        g_abs += std::abs(m[dof] * residual[dof]);
      }
    }
    applied[j] = a;
    foundation[j] = phi;
    // a + g - phi = internal - (the free rows' residuals, rigid-weighted); internal is zero in
    // exact arithmetic for beams (K_e annihilates the exact rigid motions), O(h^4) for arches.
    // An answer that solves the assembled equations exactly still leaves the assembly's
    // rounding, m.(K u - sum K_e u_e), computed above for this u (x 2). A backward-stable solver
    // adds its rows' residuals at a few eps each (`rows`, whatever the method: the balance is
    // physics, and primal's looser Wilkinson bound would allow a 0.6 % imbalance on the footing);
    // of random sign, they add up like a random walk: 4 times their 2-norm (the probabilistic
    // round-off bound, Higham and Mary, SIAM J. Sci. Comput. 41, 2019), not their sum, which on a
    // fine mesh is 1e10 times the load and would hide a 3.5 % imbalance. (A motion no term works
    // on, like an arch's rotation on rollers, balances trivially.)
    const double scale = a_abs + g_abs + phi_abs + springs_abs + moment_abs;
    const double consistency = d.kind == StructureKind::arch ? std::abs(internal) : 0.0;
    const double tolerance = 2 * std::abs(assembly) + 4 * rows * std::sqrt(bound) + rows * scale + consistency;
    c.checks.push_back(scale > 0
                           ? detail::make_check(detail::balance_name(d.kind, j),
                                                std::abs(a + g - phi - springs - moment) / scale, tolerance / scale)
                           : detail::make_check(detail::balance_name(d.kind, j), 0.0, rows));
  }
  double integral = 0.0, moment = 0.0;  // of the P1 reaction: integral of r and of r s
  const std::vector<std::array<int, 2>> reactions = detail::element_reactions(d);
  for (int e = 0; e < d.mesh.elements(); ++e) {
    const auto [ra, rb] = reactions[e];
    if (!on_foundation(d, e) || ra < 0 || rb < 0) continue;
    const double h = d.mesh.element_size(e), sa = d.mesh.nodes[e], sb = d.mesh.nodes[e + 1];
    integral += 0.5 * h * (r_given[ra] + r_given[rb]);
    moment += h / 6.0 * (r_given[ra] * (2 * sa + sb) + r_given[rb] * (sa + 2 * sb));
  }
  detail::fill_resultants(c, model, applied, foundation, integral != 0.0 ? moment / integral : 0.0);
}

// ---- round-off, measured ----------------------------------------------------------------------

// The error round-off left in (u, r), measured: one correction A^-1 (b - A x) on the answer's
// own contact-set system in the mixed (Hellinger-Reissner) form of the element equations, with
// the element stress resultants m = H^-1 G u as extra unknowns (K = G^T H^-1 G exactly,
// fe/discretisation.hpp; A: the nodes with r > 0, bilateral: all):
//   [ 0    G^T  C_A^T ] [ u   ]   [ F ]
//   [ G   -H    0     ] [ m   ] = [ 0 ]
//   [ C_A  0   -T_AA  ] [ r_A ]   [ 0 ],
// with m computed from the answer's u (each stress's G u in twice the working precision, over
// H), the residual b - A x computed in twice the working precision (compensated), and the
// correction solved once (banded LU, partial pivoting, on the symmetrically equilibrated A): one
// digit of it is enough. Why the mixed form: its data are exact data of a nearby mesh (G's
// entries are integers and +-2/h, unassembled, H is diagonal: beam_element.hpp), and its
// condition grows like N^2. The stiffness form's data are not: K_e's entries (12/h^3, 6/h^2,
// ...) are rounded independently, so the rounded K_e annihilates the rigid motions only to
// round-off, and the exact answer of the rounded K differs from that of the element by eps
// times K's condition, N^4: measured against it, the mixed solve's limit-fitted answer of
// seed_beam_end_moments at 2048 elements showed a "round-off" of 3.5e-10 of max |w| (2.5e-11 at
// 1024) while its nodal error against the closed form is 1e-15. An answer solved in the
// stiffness form carries exactly that error, and this measures it: seed_beam_end_moments at
// 3200 elements solved by a sparse LU of the assembled K form, 1.6e-4 of max |w| from the
// closed form, is measured at that (tests/certify/fe_certificate_test.cpp). Not measured: the
// rounding of C and T (assembled sums of two elements' entries, benign: they are well
// conditioned) and of G and H themselves (the nearby mesh).
struct RoundOff {
  bool measured = false;
  double w = 0.0, r = 0.0;  // the correction, relative to max |w| (deflection dofs) and max |r|
  VectorXd correction_u;    // every dof
  VectorXd correction_r;
  std::string why_not;
};

// The symmetric equilibration of A: S with every row of S A S at most 1 in magnitude, near 1
// (a few sweeps of Ruiz's scaling), so that pivoting compares like with like.
VectorXd symmetric_scaling(const fe::SparseMatrix& a) {
  const int size = static_cast<int>(a.rows());
  VectorXd s = VectorXd::Ones(size), row_max(size);
  for (int sweep = 0; sweep < 8; ++sweep) {
    row_max.setZero();
    for (int col = 0; col < a.outerSize(); ++col)
      for (fe::SparseMatrix::InnerIterator it(a, col); it; ++it)
        row_max[it.row()] = std::max(row_max[it.row()], std::abs(s[it.row()] * it.value() * s[col]));
    for (int i = 0; i < size; ++i)
      if (row_max[i] > 0) s[i] /= std::sqrt(row_max[i]);
  }
  return s;
}

// A bandwidth-reducing order of a structurally symmetric matrix (Cuthill-McKee: breadth first
// from a pseudo-peripheral unknown, neighbours by increasing degree): order[k] is the k-th unknown.
std::vector<int> banded_order(const fe::SparseMatrix& a) {
  const int size = static_cast<int>(a.rows());
  const int* starts = a.outerIndexPtr();
  const int* rows = a.innerIndexPtr();
  auto degree = [&](int v) { return starts[v + 1] - starts[v]; };
  std::vector<int> order;
  order.reserve(size);
  std::vector<int> neighbours;
  auto sweep = [&](int root, std::vector<char>& seen) {  // appends root's component to order
    std::size_t head = order.size();
    order.push_back(root);
    seen[root] = 1;
    while (head < order.size()) {
      const int v = order[head++];
      neighbours.clear();
      for (int p = starts[v]; p < starts[v + 1]; ++p)
        if (!seen[rows[p]]) {
          seen[rows[p]] = 1;
          neighbours.push_back(rows[p]);
        }
      std::stable_sort(neighbours.begin(), neighbours.end(), [&](int x, int y) { return degree(x) < degree(y); });
      order.insert(order.end(), neighbours.begin(), neighbours.end());
    }
  };
  std::vector<char> seen(size, 0);
  for (int start = 0; start < size; ++start) {
    if (seen[start]) continue;
    // The last unknown reached from `start` lies at the far end of its chain: start there.
    const std::size_t first = order.size();
    sweep(start, seen);
    const int root = order.back();
    for (std::size_t k = first; k < order.size(); ++k) seen[order[k]] = 0;
    order.resize(first);
    sweep(root, seen);
  }
  return order;
}

RoundOff measure_round_off(const Discretisation& d, const VectorXd& u_all, const VectorXd& r, const VectorXd& load) {
  RoundOff out;
  const int n = d.equations, ns = d.stresses(), m = d.reactions();
  if (ns == 0 || d.stress_coupling.rows() != ns || d.stress_coupling.cols() != n) {
    out.why_not = "the discretisation carries no mixed form of its stiffness";
    return out;
  }
  std::vector<int> slot_of_reaction(m, -1);
  int size = n + ns;
  for (int i = 0; i < m; ++i)
    if (!d.tensionless || r[i] > 0) slot_of_reaction[i] = size++;
  VectorXd u = VectorXd::Zero(n);
  for (int dof = 0; dof < d.dofs(); ++dof)
    if (d.equation_of_dof[dof] >= 0) u[d.equation_of_dof[dof]] = u_all[dof];

  // G as rows of stresses (row-major access through its transpose).
  const fe::SparseMatrix g_t = d.stress_coupling.transpose();  // equations x stresses, columns = stresses
  // The answer's stresses m = H^-1 G u, G u compensated.
  VectorXd stress(ns);
  for (int k = 0; k < ns; ++k) {
    detail::Compensated gu;
    for (fe::SparseMatrix::InnerIterator it(g_t, k); it; ++it) gu.add_product(it.value(), u[it.row()]);
    stress[k] = gu.value() / d.compliance[k];
  }

  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(2 * d.stress_coupling.nonZeros() + ns + 2 * d.coupling.nonZeros() + d.flexibility.nonZeros());
  for (int col = 0; col < n; ++col)
    for (fe::SparseMatrix::InnerIterator it(d.stress_coupling, col); it; ++it) {
      triplets.emplace_back(n + it.row(), col, it.value());
      triplets.emplace_back(col, n + it.row(), it.value());
    }
  for (int k = 0; k < ns; ++k) triplets.emplace_back(n + k, n + k, -d.compliance[k]);
  // Under an axial force N the displacement block is -N K_g (fe/discretisation.hpp).
  if (d.has_axial_force())
    for (int col = 0; col < n; ++col)
      for (fe::SparseMatrix::InnerIterator it(d.geometric_stiffness, col); it; ++it)
        triplets.emplace_back(it.row(), col, -d.axial_force * it.value());
  for (int col = 0; col < n; ++col)
    for (fe::SparseMatrix::InnerIterator it(d.coupling, col); it; ++it) {
      const int slot = slot_of_reaction[it.row()];
      if (slot < 0) continue;
      triplets.emplace_back(slot, col, it.value());
      triplets.emplace_back(col, slot, it.value());
    }
  for (int col = 0; col < m; ++col)
    for (fe::SparseMatrix::InnerIterator it(d.flexibility, col); it; ++it) {
      const int i = slot_of_reaction[it.row()], j = slot_of_reaction[col];
      if (i >= 0 && j >= 0) triplets.emplace_back(i, j, -it.value());
    }
  fe::SparseMatrix a(size, size);
  a.setFromTriplets(triplets.begin(), triplets.end());
  a.makeCompressed();

  // The residual b - A x, compensated; the reactions of lifted nodes (r_i != 0 off A is part of
  // the answer) enter the equilibrium rows through C^T r.
  std::vector<detail::Compensated> sums(size);
  for (int row = 0; row < n; ++row) sums[row].add(load[row]);
  for (int col = 0; col < n; ++col)
    for (fe::SparseMatrix::InnerIterator it(d.stress_coupling, col); it; ++it) {
      sums[col].add_product(-it.value(), stress[it.row()]);  // F - G^T m
      sums[n + it.row()].add_product(-it.value(), u[col]);   // H m - G u
    }
  for (int k = 0; k < ns; ++k) sums[n + k].add_product(d.compliance[k], stress[k]);
  if (d.has_axial_force())
    for (int col = 0; col < n; ++col)
      for (fe::SparseMatrix::InnerIterator it(d.geometric_stiffness, col); it; ++it)
        sums[it.row()].add_product(d.axial_force * it.value(), u[col]);  // F - (-N K_g u)
  for (int col = 0; col < n; ++col)
    for (fe::SparseMatrix::InnerIterator it(d.coupling, col); it; ++it) {
      const int slot = slot_of_reaction[it.row()];
      sums[col].add_product(-it.value(), r[it.row()]);
      if (slot >= 0) sums[slot].add_product(-it.value(), u[col]);
    }
  for (int col = 0; col < m; ++col)
    for (fe::SparseMatrix::InnerIterator it(d.flexibility, col); it; ++it) {
      const int slot = slot_of_reaction[it.row()];
      if (slot >= 0) sums[slot].add_product(it.value(), r[col]);
    }
  // A contact row reads C u - T r = c (the ground gap, Discretisation::ground_gap).
  for (int i = 0; i < m && d.ground_gap.size() == m; ++i)
    if (slot_of_reaction[i] >= 0) sums[slot_of_reaction[i]].add(d.ground_gap[i]);
  VectorXd rhs(size);
  for (int row = 0; row < size; ++row) rhs[row] = sums[row].value();

  const VectorXd scaling = symmetric_scaling(a);
  // The system is a chain along the member: numbered by a Cuthill-McKee sweep it is banded with a
  // bandwidth independent of the mesh, and a banded LU with partial pivoting solves it in O(n) (a
  // general sparse LU's set-up, mostly zeroing its workspace, was a third of a 1e-8 tolerance run
  // on small meshes). Its own numbering, not the solver's: an independent factorisation.
  const std::vector<int> order = banded_order(a);
  std::vector<int> position(size);
  for (int k = 0; k < size; ++k) position[order[k]] = k;
  int band = 0;
  for (int col = 0; col < size; ++col)
    for (fe::SparseMatrix::InnerIterator it(a, col); it; ++it)
      band = std::max(band, std::abs(position[it.row()] - position[col]));
  linalg::BandedLu lu;
  lu.set_structure(size, band, band);
  for (int col = 0; col < size; ++col)
    for (fe::SparseMatrix::InnerIterator it(a, col); it; ++it)
      lu.set(position[it.row()], position[col], scaling[it.row()] * it.value() * scaling[col]);
  if (!lu.factorise()) {
    out.why_not = "the answer's contact set leaves the member free to move (its system is singular)";
    return out;
  }
  VectorXd permuted(size);
  for (int k = 0; k < size; ++k) permuted[position[k]] = scaling[k] * rhs[k];
  lu.solve(permuted.data());
  VectorXd correction(size);
  for (int k = 0; k < size; ++k) correction[k] = scaling[k] * permuted[position[k]];
  if (!correction.allFinite()) {
    out.why_not = "the answer's contact-set system could not be solved";
    return out;
  }
  out.correction_u = d.expand(correction.head(n));
  out.correction_r = VectorXd::Zero(m);
  double r_change = 0.0;
  for (int i = 0; i < m; ++i)
    if (slot_of_reaction[i] >= 0) {
      out.correction_r[i] = correction[slot_of_reaction[i]];
      r_change = std::max(r_change, std::abs(out.correction_r[i]));
    }
  double w_scale = 0.0, w_change = 0.0;
  for (int node = 0; node < static_cast<int>(d.mesh.nodes.size()); ++node) {
    const int dof = d.deflection_dof(node);
    w_scale = std::max(w_scale, std::abs(u_all[dof]));
    w_change = std::max(w_change, std::abs(out.correction_u[dof]));
  }
  const double r_scale = m > 0 ? r.cwiseAbs().maxCoeff() : 0.0;
  auto relative = [](double value, double scale) { return scale > 0 ? value / scale : 0.0; };
  out.w = relative(w_change, w_scale);
  out.r = relative(r_change, r_scale);
  out.measured = true;
  return out;
}

// ---- pointwise fields -------------------------------------------------------------------------

double w_in(const Discretisation& d, const VectorXd& u, int e, double xi) {
  const std::vector<int> dofs = d.element_dofs(e);
  const Eigen::Vector4d w_dofs(u[dofs[0]], u[dofs[1]], u[dofs[2]], u[dofs[3]]);
  return fe::hermite_cubic(xi, d.mesh.element_size(e)).value.dot(w_dofs);
}

double r_in(const MemberModel& /*model*/, const Discretisation& d,
            const std::vector<std::array<int, 2>>& reaction_of_node, const VectorXd& r, int e, double xi) {
  if (!on_foundation(d, e)) return 0.0;
  const auto [ra, rb] = reaction_of_node[e];
  if (ra < 0 || rb < 0) return 0.0;
  const Eigen::Vector2d phi = fe::reaction_shape(xi);
  return phi[0] * r[ra] + phi[1] * r[rb];
}

// The discretisation error of (w, r), estimated by the change from a solve on half the elements
// (fast, corrected for its round-off like the answer): max over the answer's sample points,
// relative to max |w| and max |r|. Empty when that solve fails.
struct DiscretisationError {
  bool estimated = false;
  double w = 0.0, r = 0.0;
  int elements = 0;
  std::string why_not;
};

DiscretisationError estimate_discretisation_error(const MemberModel& model, const Discretisation& d, const VectorXd& u,
                                                  const VectorXd& r, double load_factor, int samples) {
  DiscretisationError out;
  const int coarse_elements = std::max(1, d.mesh.elements() / 2);
  Discretisation coarse;
  contact::ContactSolution reference;
  try {
    coarse = fe::discretise(model, coarse_elements);
    contact::ContactOptions options;
    options.method = contact::Method::fast;
    options.load_factor = load_factor;
    reference = contact::solve_contact(coarse, options);
  } catch (const std::exception& e) {
    out.why_not = e.what();
    return out;
  }
  out.elements = coarse.mesh.elements();
  if (!reference.summary.is_usable()) {
    out.why_not = "the half-mesh reference solve failed: " + reference.summary.message;
    return out;
  }
  VectorXd u2 = reference.displacement, r2 = reference.reaction;
  const RoundOff polish = measure_round_off(coarse, u2, r2, coarse.load(load_factor));
  if (polish.measured) {
    u2 += polish.correction_u;
    r2 += polish.correction_r;
  }
  const std::vector<std::array<int, 2>> reactions_fine = detail::element_reactions(d),
                                        reactions_coarse = detail::element_reactions(coarse);
  double w_scale = 0.0, r_scale = 0.0, w_change = 0.0, r_change = 0.0;
  for (int e = 0; e < d.mesh.elements(); ++e)
    for (int i = 0; i <= samples; ++i) {
      const double xi = static_cast<double>(i) / samples, s = d.mesh.nodes[e] + xi * d.mesh.element_size(e);
      const int ec = coarse.mesh.element_containing(s);
      const double xc = std::clamp((s - coarse.mesh.nodes[ec]) / coarse.mesh.element_size(ec), 0.0, 1.0);
      const double w = w_in(d, u, e, xi), rf = r_in(model, d, reactions_fine, r, e, xi);
      w_scale = std::max(w_scale, std::abs(w));
      r_scale = std::max(r_scale, std::abs(rf));
      w_change = std::max(w_change, std::abs(w - w_in(coarse, u2, ec, xc)));
      r_change = std::max(r_change, std::abs(rf - r_in(model, coarse, reactions_coarse, r2, ec, xc)));
    }
  out.w = w_scale > 0 ? w_change / w_scale : 0.0;
  out.r = r_scale > 0 ? r_change / r_scale : 0.0;
  out.estimated = true;
  return out;
}

}  // namespace

Certificate certify(const MemberModel& model, const Discretisation& d, const contact::ContactSolution& solution,
                    const CertifyOptions& options) {
  options.validate();
  Certificate c;
  const VectorXd& u_given = solution.displacement;
  const VectorXd& r_given = solution.reaction;
  if (u_given.size() != d.dofs() || r_given.size() != d.reactions() || !u_given.allFinite() || !r_given.allFinite()) {
    c.message = "no answer to certify: the displacements or reactions are missing or not finite";
    return c;
  }
  const double lambda = options.load_factor;
  const NodalForces f = nodal_forces(model, d, u_given, r_given, lambda);
  const VectorXd residual = f.internal + f.axial + f.foundation + f.springs - f.applied;
  const std::vector<int> supported = detail::supported_dofs(model, d);
  std::vector<bool> is_supported(d.dofs(), false);
  for (int dof : supported) is_supported[dof] = true;

  // The backward error a sound answer may have: a backward-stable solve leaves a few eps (64 eps,
  // detail.hpp): fast and the bilateral solve refine, dual Lemke takes u from a sparse LDL^T solve
  // with its final reactions. Primal Lemke takes u and r from a dense LU of its final basis, of
  // the LCP's size n_L = 2 n + m: Wilkinson's bound n_L eps times the growth factor, 8 allowed.
  // (Primal's answers on the seed arches: 1.3e-12 at n_L = 2600; its wrong footing: 2.2e-8.)
  const int lcp_unknowns = 2 * d.equations + d.reactions();
  const double backward_tolerance =
      options.backward_tolerance > 0.0
          ? options.backward_tolerance
          : std::max(detail::backward_tolerance,
                     solution.summary.method == contact::Method::primal ? 8.0 * lcp_unknowns * detail::eps : 0.0);

  // backward_error: every row of the equations. (A gauge's row, like a support's, carries the
  // rigid-weighted sum of the others' residuals; the balance checks it.)
  {
    Check check = detail::make_check(check_name::backward_error, 0.0, backward_tolerance);
    for (int dof = 0; dof < d.dofs(); ++dof) {
      if (d.equation_of_dof[dof] < 0 || f.magnitude[dof] == 0.0) continue;
      const double value = std::abs(residual[dof]) / f.magnitude[dof];
      if (value > check.value) {
        check.value = value;
        check.at = d.position_of_dof(dof);
      }
    }
    c.checks.push_back(check);
  }

  // Support reactions: the residual at the dofs the supports fix (g, in the dofs' own sense).
  c.support_reactions = detail::support_reactions(model, d, residual, is_supported);
  // Settled supports: w = delta there, exactly (the solvers put it there; an answer that dropped
  // the settlement has w = 0). Elastic supports: their springs' forces, as a support's, by s.
  {
    Check check = detail::make_check(check_name::settlement, 0.0, detail::minimum_round_off);
    const double scale = std::max(u_given.cwiseAbs().maxCoeff(), 1e-300);
    for (const auto& [s, settlement] : detail::settlements(model)) {
      const int node = d.mesh.node_at(s);
      if (node < 0) continue;
      const double value = std::abs(u_given[d.deflection_dof(node)] - settlement) / scale;
      if (value > check.value) {
        check.value = value;
        check.at = s;
      }
      for (SupportReaction& reaction : c.support_reactions)
        if (reaction.at == d.mesh.nodes[node]) reaction.settlement = settlement;
    }
    if (model.has_settlements()) c.checks.push_back(check);
    std::vector<bool> is_spring(d.dofs(), false);
    for (const model::SupportSpring& spring : model.springs) {
      const int node = d.mesh.node_at(spring.s);
      if (node < 0) continue;
      is_spring[d.deflection_dof(node)] = is_spring[d.slope_dof(node)] = true;
      if (d.kind == StructureKind::arch) is_spring[d.tangential_dof(node)] = true;
      const VectorXd on_member = -f.springs;  // the force the springs exert, in the dofs' sense
      std::vector<SupportReaction> one = detail::support_reactions(model, d, on_member, is_spring, {node});
      for (SupportReaction& reaction : one) {
        reaction.spring = true;
        reaction.settlement = spring.settlement;
        c.support_reactions.push_back(reaction);
      }
      std::fill(is_spring.begin(), is_spring.end(), false);
    }
    std::stable_sort(c.support_reactions.begin(), c.support_reactions.end(),
                     [](const SupportReaction& a, const SupportReaction& b) { return a.at < b.at; });
  }

  check_balance(c, model, d, f, f.axial, residual, is_supported, r_given, detail::backward_tolerance);

  // Round-off of the answer, measured (needed by the sign tolerances too).
  // The sign conditions allow the round-off a sound answer may carry: the measured one as far as
  // its backward error passes (scaled down by how far it does not: an answer spoilt beyond
  // round-off cannot excuse its own sign errors).
  const RoundOff round_off = measure_round_off(d, u_given, r_given, d.load(lambda));
  const double backward = c.find(check_name::backward_error)->value;
  const double sound = std::min(1.0, backward_tolerance / std::max(backward, 1e-300));
  const double answer_error = round_off.measured
                                  ? std::max({sound * round_off.w, sound * round_off.r, detail::minimum_round_off})
                                  : detail::minimum_round_off;
  const double sign_tolerance = detail::sign_safety * std::max(answer_error, options.sign_floor);

  // Contact conditions: discrete (nodal, weighted) and pointwise.
  const std::vector<std::array<int, 2>> reaction_of_node = detail::element_reactions(d);
  const int m = d.reactions();
  const double r_scale = m > 0 ? r_given.cwiseAbs().maxCoeff() : 0.0;
  if (d.tensionless) {
    Check sign = detail::make_check(check_name::reaction_sign, 0.0, sign_tolerance);
    Check penetration = detail::make_check(check_name::penetration, 0.0, sign_tolerance);
    Check separation = detail::make_check(check_name::separation, 0.0, sign_tolerance);
    Check complementarity = detail::make_check(check_name::complementarity, 0.0, sign_tolerance);
    auto worse = [](Check& check, double value, double s) {
      if (value > check.value) {
        check.value = value;
        check.at = s;
      }
    };
    // A limit-fitted answer's limits are nodes: w = 0 there (complementarity, below), and its P1
    // reaction there, the L2 projection of k w onto the contact elements' P1 functions, is an
    // O(h^2) artefact of either sign (the continuum reaction k w vanishes at the limit): the
    // sign of the reaction is checked pointwise by separation instead (w >= 0 on contact
    // elements). The same holds at a support on a contact element, where w is held at 0, on any
    // answer: a fitted one whose contact covers the whole member (no limit, so it looks
    // node-based) solved that support's reaction bilaterally (a clamped end in contact).
    // A fitted limit at a step of the ground gap (a trench wall) has w - g of either sign on each
    // side (>= 0 on the contact side, <= 0 beyond): checked pointwise like any other point.
    const bool fitted = is_limit_fitted(model, d);
    std::vector<char> limit_node(d.mesh.nodes.size(), 0), w_held_at_zero(d.mesh.nodes.size(), 0);
    double g_scale = 0.0;
    for (double g : model.ground_gap_value) g_scale = std::max(g_scale, std::abs(g));
    auto gap_steps_at = [&](int e) {  // between elements e and e + 1
      const double left = model.ground_gap_in(d.mesh.nodes[e], d.mesh.element_size(e), 1.0),
                   right = model.ground_gap_in(d.mesh.nodes[e + 1], d.mesh.element_size(e + 1), 0.0);
      return std::abs(left - right) > 1e-9 * g_scale;
    };
    if (fitted)
      for (int e = 0; e + 1 < d.mesh.elements(); ++e)
        if (on_foundation(d, e) != on_foundation(d, e + 1) && in_foundation_extent(model, d.mesh, e) &&
            in_foundation_extent(model, d.mesh, e + 1) && !gap_steps_at(e))
          limit_node[e + 1] = 1;
    for (std::size_t node = 0; node < d.mesh.nodes.size(); ++node)
      w_held_at_zero[node] = d.equation_of_dof[d.deflection_dof(static_cast<int>(node))] < 0;
    // A fitted answer's reactions are solved bilaterally on its contact elements: at a node on a
    // translational spring the spring holds w (to its force over its stiffness, 0 as the
    // stiffness grows: a stiff spring is a held end), and the P1 reaction there carries the same
    // artefact of either sign; separation checks w - g >= 0 pointwise on those elements.
    if (fitted)
      for (const model::SupportSpring& spring : model.springs)
        if (const int node = d.mesh.node_at(spring.s); node >= 0 && spring.stiffness > 0.0) w_held_at_zero[node] = 1;
    // Each node's gap against its own terms; or (global_scale) against the largest node's. Never
    // against less than the terms it would have at the member's largest |w|: the round-off of u
    // is relative to max |w|, so a node where w is small (near a pinned end, where the ground
    // meets the member) carries the same absolute round-off in its gap as any other.
    const double gap_floor = options.global_scale && m > 0 ? f.gap_terms.maxCoeff() : 0.0;
    double w_largest = 0.0;
    for (std::size_t node = 0; node < d.mesh.nodes.size(); ++node)
      w_largest = std::max(w_largest, std::abs(u_given[d.deflection_dof(static_cast<int>(node))]));
    for (int i = 0; i < m; ++i) {
      const int node = d.reaction_nodes[i];
      const double s = d.mesh.nodes[node];
      const double relative_r = r_scale > 0 ? r_given[i] / r_scale : 0.0;
      double support = 0.0;  // the integral of the node's reaction function phi_i
      if (node > 0 && on_foundation(d, node - 1) && reaction_of_node[node - 1][1] == i)
        support += 0.5 * d.mesh.element_size(node - 1);
      if (node < d.mesh.elements() && on_foundation(d, node) && reaction_of_node[node][0] == i)
        support += 0.5 * d.mesh.element_size(node);
      const double gap_terms = std::max({f.gap_terms[i], gap_floor, support * w_largest});
      const double relative_gap = gap_terms > 0 ? f.gap[i] / gap_terms : 0.0;
      if (!limit_node[d.reaction_nodes[i]] && !w_held_at_zero[d.reaction_nodes[i]]) worse(sign, -relative_r, s);
      worse(penetration, -relative_gap, s);
      worse(complementarity, std::min(std::abs(relative_r), std::abs(relative_gap)), s);
    }
    // Pointwise, every element on the foundation, on w - g (contact where w >= g, lifted where
    // w < g). Limit elements: w - g changes sign in the element or in a neighbour, or its nodes
    // differ in contact.
    const int elements = d.mesh.elements(), samples = options.samples_per_element;
    std::vector<char> sign_change(elements, 0), limit(elements, 0);
    double w_scale = 0.0;
    std::vector<double> w_samples(static_cast<std::size_t>(elements) * (samples + 1));
    for (int e = 0; e < elements; ++e) {
      bool positive = false, negative = false;
      for (int i = 0; i <= samples; ++i) {
        const double xi = static_cast<double>(i) / samples;
        const double g = model.ground_gap_in(d.mesh.nodes[e], d.mesh.element_size(e), xi);
        const double w = w_in(d, u_given, e, xi) - g;
        w_samples[static_cast<std::size_t>(e) * (samples + 1) + i] = w;
        w_scale = std::max({w_scale, std::abs(w), std::abs(g)});
        positive |= w > 0;
        negative |= w < 0;
      }
      sign_change[e] = positive && negative;
    }
    for (int e = 0; e < elements && !fitted; ++e) {  // a fitted answer has no limit elements
      const auto [ra, rb] = reaction_of_node[e];
      const bool mixed = ra >= 0 && rb >= 0 && ((r_given[ra] > 0) != (r_given[rb] > 0));
      limit[e] = sign_change[e] || mixed || (e > 0 && sign_change[e - 1]) || (e + 1 < elements && sign_change[e + 1]);
    }
    double inside_limits = -1.0;
    for (int e = 0; e < elements; ++e) {
      if (!options.pointwise || !in_foundation_extent(model, d.mesh, e) || w_scale == 0.0) continue;
      if (!fitted && !on_foundation(d, e)) continue;
      for (int i = 0; i <= samples; ++i) {
        const double xi = static_cast<double>(i) / samples, s = d.mesh.nodes[e] + xi * d.mesh.element_size(e);
        const double w = w_samples[static_cast<std::size_t>(e) * (samples + 1) + i] / w_scale;
        // Fitted: contact elements press (w >= 0), lift-off elements do not (w <= 0).
        const bool pressed = fitted ? on_foundation(d, e) : r_in(model, d, reaction_of_node, r_given, e, xi) > 0;
        const double into = pressed ? std::max(0.0, -w) : std::max(0.0, w);  // separation : penetration
        if (fitted && limit_node[e + (i == samples ? 1 : 0)] && (i == 0 || i == samples)) {
          worse(complementarity, std::abs(w), s);  // w = 0 at a fitted limit
          continue;
        }
        if (limit[e]) {
          inside_limits = std::max(inside_limits, into);
          continue;
        }
        worse(pressed ? separation : penetration, into, s);
      }
    }
    c.limit_element_defect = inside_limits;
    for (Check* check : {&sign, &penetration, &separation, &complementarity}) c.checks.push_back(*check);
  } else {
    // Bilateral: the weighted gap vanishes at every node.
    Check gap = detail::make_check(check_name::complementarity, 0.0, sign_tolerance);
    for (int i = 0; i < m; ++i) {
      const double value = f.gap_terms[i] > 0 ? std::abs(f.gap[i]) / f.gap_terms[i] : 0.0;
      if (value > gap.value) {
        gap.value = value;
        gap.at = d.mesh.nodes[d.reaction_nodes[i]];
      }
    }
    c.checks.push_back(gap);
  }

  // round_off against the discretisation error.
  if (options.round_off) {
    Check check = detail::make_check(check_name::round_off, NAN, NAN);
    if (!round_off.measured) {
      check.value = INFINITY;
      check.tolerance = 0.0;
      c.checks.push_back(check);
      c.round_off_note = "round-off could not be measured: " + round_off.why_not;
    } else {
      // Both answers corrected for their round-off: the change is the discretisation's alone.
      DiscretisationError disc;
      if (options.discretisation_error >= 0.0) {
        disc.estimated = true;
        disc.w = disc.r = options.discretisation_error;
      } else {
        disc = estimate_discretisation_error(model, d, u_given + round_off.correction_u,
                                             r_given + round_off.correction_r, lambda, options.samples_per_element);
      }
      // Without the reference, the a priori O(h^2) of the contact limits stands in for it.
      const double h = 1.0 / d.mesh.elements();
      const double disc_w = disc.estimated ? disc.w : h * h, disc_r = disc.estimated ? disc.r : h * h;
      const double floor = detail::negligible_error;
      const double ratio_w = round_off.w / std::max(disc_w, floor), ratio_r = round_off.r / std::max(disc_r, floor);
      const bool by_w = ratio_w >= ratio_r || r_scale == 0.0;
      check.value = by_w ? round_off.w : round_off.r;
      check.tolerance = std::max(by_w ? disc_w : disc_r, floor);
      c.round_off_note =
          fmt::format("round-off {:.1e} of max |{}| against a discretisation error of {:.1e} ({})", check.value,
                      by_w ? "w" : "r", check.tolerance,
                      !disc.estimated                       ? "a priori h^2: " + disc.why_not
                      : options.discretisation_error >= 0.0 ? std::string("the solver's estimate")
                                                            : fmt::format("change from {} elements", disc.elements));
      if (check.value > check.tolerance) c.round_off_note += "; fewer elements would be more accurate";
      c.checks.push_back(check);
    }
  }
  c.round_off_estimate = round_off.measured ? std::max(round_off.w, round_off.r) : -1.0;

  detail::conclude(c, model);
  return c;
}

// ---- von Karman arches: the membrane's nodal forces -------------------------------------------

// One arch element's membrane part under von Karman theory, recomputed from its dofs (local order
// of fe::ArchElement: Hermite w, w'; quartic u) by the strain fe/arch_von_karman_element.hpp
// defines: eps = u' - sigma w + beta^2 / 2, beta = -(u + sigma w'), chi = u' + sigma w'', N = EA
// eps (tension positive). force: the element's f_int = integral of (N d eps/dq + chi d chi/dq)
// less its linear part (arch_element::stiffness q, which nodal_forces counts); terms: the forces
// summed into each row, in magnitude, at every point (the integrated K hides the cancellation of
// u' against w of nearly inextensional bending: EA R^2 / EI ~ 1e6); normal_force: the Gauss
// rule's mean of N over the element (as the solver reports it); strain_terms: the largest EA
// (|eps's linear terms| + beta^2 / 2) at its points, the scale of N.
struct ArchMembrane {
  Eigen::Matrix<double, 9, 1> force, terms;
  double normal_force = 0.0, strain_terms = 0.0;
};

ArchMembrane arch_membrane(const MemberModel& model, const Discretisation& d, const VectorXd& u, int element) {
  const double h = d.mesh.element_size(element), ea = model.membrane_stiffness;
  const bool outside = model.foundation_outside;
  const std::vector<int> dofs = d.element_dofs(element);
  Eigen::Matrix<double, 9, 1> q;
  for (int j = 0; j < 9; ++j) q[j] = u[dofs[j]];
  const Eigen::Matrix<double, 9, 1> size = q.cwiseAbs();
  ArchMembrane out;
  out.force = -fe::arch_element::stiffness(h, ea, outside) * q;
  out.terms.setZero();
  for (const fe::GaussPoint& g : fe::gauss5) {
    const fe::arch_element::Row9d a = fe::arch_element::membrane_strain_row(g.xi, h, outside),
                                  r = fe::arch_von_karman_element::rotation_row(g.xi, h, outside),
                                  c = fe::arch_element::bending_strain_row(g.xi, h, outside);
    const double beta = r.dot(q), strain = a.dot(q) + 0.5 * beta * beta, chi = c.dot(q), weight = g.weight * h;
    const double strain_terms = ea * (a.cwiseAbs().dot(size) + 0.5 * beta * beta);
    out.force += weight * (ea * strain * (a + beta * r).transpose() + chi * c.transpose());
    out.terms += weight * (strain_terms * (a + beta * r).cwiseAbs().transpose() +
                           c.cwiseAbs().dot(size) * c.cwiseAbs().transpose());
    out.normal_force += g.weight * ea * strain;
    out.strain_terms = std::max(out.strain_terms, strain_terms);
  }
  return out;
}

// ---- von Karman beams and arches ------------------------------------------------------------

Certificate certify(const MemberModel& model, const Discretisation& d, const VonKarmanAnswer& answer,
                    const CertifyOptions& options) {
  options.validate();
  Certificate c;
  const VectorXd& u_given = answer.displacement;
  const VectorXd& r_given = answer.reaction;
  const VectorXd& axial = answer.axial;
  const int elements = d.mesh.elements(), nodes = elements + 1;
  if (model.kind != d.kind || model.theory != model::Theory::von_karman || model.has_axial_force() ||
      !(model.membrane_stiffness > 0.0)) {
    c.message =
        "not a von Karman beam or arch (the von Karman certificate needs theory = von_karman, EA, no axial load)";
    return c;
  }
  const bool arch = model.kind == StructureKind::arch;
  if (u_given.size() != d.dofs() || r_given.size() != d.reactions() || axial.size() != nodes ||
      static_cast<int>(answer.normal_force.size()) != elements || !u_given.allFinite() || !r_given.allFinite() ||
      !axial.allFinite()) {
    c.message =
        "no answer to certify: the displacements, axial displacements, reactions or normal forces are missing "
        "or not finite";
    return c;
  }
  const double lambda = options.load_factor, ea = model.membrane_stiffness;
  // The linear parts (bending K_e u_e, the foundation's C^T r and gaps, springs, loads), as for
  // a linear answer (the model has no given axial force, so no second-order term).
  NodalForces f = nodal_forces(model, d, u_given, r_given, lambda);
  // The membrane's nodal forces per element, from the fields: f_int of the von Karman element
  // (fe/von_karman_element.hpp) less its bending part, N (a_0 + K_g w) on w and (-N, N) on u; and
  // the membrane strain's terms in magnitude, EA (|u0| + |u1| + integral |w0' w'| + w'^2 / 2) / h,
  // the scale of N (its terms cancel where u' relieves w'^2 / 2).
  VectorXd membrane = VectorXd::Zero(d.dofs()), axial_residual = VectorXd::Zero(nodes),
           axial_magnitude = VectorXd::Zero(nodes);
  std::vector<double> normal_force(elements), strain_terms(elements);
  double membrane_scale = 0.0, strain_integral = 0.0;  // strain_integral: integral of w0' w' + w'^2 / 2
  fe::ElementResponse response;
  for (int e = 0; e < elements; ++e) {
    if (arch) {
      const ArchMembrane element = arch_membrane(model, d, u_given, e);
      const std::vector<int> dofs = d.element_dofs(e);
      for (std::size_t j = 0; j < dofs.size(); ++j) {
        membrane[dofs[j]] += element.force[j];
        f.magnitude[dofs[j]] += element.terms[j];
      }
      normal_force[e] = element.normal_force;
      strain_terms[e] = element.strain_terms;
      membrane_scale = std::max(membrane_scale, strain_terms[e]);
      continue;
    }
    const double s0 = d.mesh.nodes[e], h = d.mesh.element_size(e);
    const std::vector<int> dofs = d.element_dofs(e);
    VectorXd local(6);
    for (int j = 0; j < 4; ++j) local[j] = u_given[dofs[j]];
    local[4] = axial[e];
    local[5] = axial[e + 1];
    const fe::von_karman_element::InitialSlopes slopes =
        fe::von_karman_element::sample_initial_slopes([&model](double s) { return model.initial_slope(s); }, s0, h);
    const fe::VonKarmanBeamElement element(h, ea, slopes);
    element.evaluate(fe::ElementState{local, 0.0}, response);
    const Eigen::Vector4d bending = fe::beam_element::stiffness(h) * local.head<4>();
    // |u0| + |u1|, not |u1 - u0|: u carries its round-off relative to its own size.
    double terms = std::abs(local[5]) + std::abs(local[4]);
    Eigen::Vector4d coupling_terms = Eigen::Vector4d::Zero();  // |integral of N_w' (w0' + w')|, in magnitude
    for (int q = 0; q < fe::von_karman_element::quadrature_points; ++q) {
      const Eigen::Vector4d d1 = fe::hermite_cubic(fe::gauss5[q].xi, h).d1;
      const double slope = d1.dot(local.head<4>()), weight = fe::gauss5[q].weight * h;
      terms += weight * (std::abs(slopes[q] * slope) + 0.5 * slope * slope);
      strain_integral += weight * (slopes[q] * slope + 0.5 * slope * slope);
      coupling_terms += weight * d1.cwiseAbs() * (std::abs(slopes[q]) + d1.cwiseAbs().dot(local.head<4>().cwiseAbs()));
    }
    strain_terms[e] = ea * terms / h;
    membrane_scale = std::max(membrane_scale, strain_terms[e]);
    normal_force[e] = element.normal_force(local);
    for (int j = 0; j < 4; ++j) {
      const double value = response.internal_force[j] - bending[j];
      membrane[dofs[j]] += value;
      // N's own terms (it is a difference of them: u' relieves w'^2 / 2) times the coupling's.
      f.magnitude[dofs[j]] += std::abs(value) + (std::abs(normal_force[e]) + strain_terms[e]) * coupling_terms[j];
    }
    for (int j = 0; j < 2; ++j) {
      axial_residual[e + j] += response.internal_force[4 + j];
      axial_magnitude[e + j] += strain_terms[e];
    }
  }
  const VectorXd residual = f.internal + membrane + f.foundation + f.springs - f.applied;
  const std::vector<int> supported = detail::supported_dofs(model, d);
  std::vector<bool> is_supported(d.dofs(), false);
  for (int dof : supported) is_supported[dof] = true;
  // Arches: u is a discretisation dof (its rows are the backward error's, its supports the
  // support reactions' tangential); no separate axial rows.
  const bool left = !arch && model.left_axially_restrained, right = !arch && model.right_axially_restrained;
  auto axially_held = [&](int node) { return (node == 0 && left) || (node == nodes - 1 && right); };

  // backward_error: the transverse rows (w, w') the supports leave free, and the axial rows of
  // every node not held axially. The solver accepts a row at 256 eps of the forces summed into it
  // (VonKarmanOptions::residual_tolerance), summed in magnitude as here; computing it again rounds
  // a few eps more: 512 eps.
  const double row_tolerance = 512 * eps;
  {
    Check check = detail::make_check(check_name::backward_error, 0.0, row_tolerance);
    for (int dof = 0; dof < d.dofs(); ++dof) {
      if (d.equation_of_dof[dof] < 0 || f.magnitude[dof] == 0.0) continue;
      const double value = std::abs(residual[dof]) / f.magnitude[dof];
      if (value > check.value) check.value = value, check.at = d.position_of_dof(dof);
    }
    for (int node = 0; node < nodes; ++node) {
      if (axially_held(node) || axial_magnitude[node] == 0.0) continue;
      const double value = std::abs(axial_residual[node]) / axial_magnitude[node];
      if (value > check.value) check.value = value, check.at = d.mesh.nodes[node];
    }
    c.checks.push_back(check);
  }

  // Support reactions: the residual at the fixed dofs; the axial one (the thrust) at a held end,
  // along increasing s, in `tangential`.
  c.support_reactions = detail::support_reactions(model, d, residual, is_supported);
  for (int node : {0, nodes - 1}) {
    if (!axially_held(node)) continue;
    auto it = std::find_if(c.support_reactions.begin(), c.support_reactions.end(),
                           [&](const SupportReaction& s) { return s.at == d.mesh.nodes[node]; });
    if (it == c.support_reactions.end()) {
      SupportReaction held;
      held.at = d.mesh.nodes[node];
      c.support_reactions.push_back(held);
      it = c.support_reactions.end() - 1;
    }
    it->tangential = axial_residual[node];
  }
  std::stable_sort(c.support_reactions.begin(), c.support_reactions.end(),
                   [](const SupportReaction& a, const SupportReaction& b) { return a.at < b.at; });

  // Balance on the translation and the rotation (beams about the begin, arches about the centre).
  // The membrane's nodal forces do no work on a translation (beams: the Hermite slopes of a
  // translation vanish; arches: a rigid translation has beta = 0, to the interpolation's O(h^4)),
  // and on the rotation they are the moment of N at the displaced ends (beams: N [w0 + w] between
  // the ends; arches: -integral of N beta, the thrust's moment about the centre): counted like a
  // load. The rows' residuals at the solver's 256 eps.
  check_balance(c, model, d, f, membrane, residual, is_supported, r_given, 256 * eps);

  // The membrane force. Continuum: N' = 0 (axial equilibrium, no axial load), so N is uniform;
  // N = 0 at an axially free end; with both ends held, u(0) = u(L) = 0 and N = EA/L integral
  // of (w0' w' + w'^2 / 2) (compatibility). Discrete: the axial row at node i is N_(i-1) - N_i,
  // so N's spread is a sum of the axial rows' residuals (each within 256 eps of its terms, of
  // random sign: 4 sqrt(n) of them, as the balance's random walk), relative to the largest
  // element's strain terms; a free end's N is one row (512 eps). Compatibility compares the
  // reported N (what the outputs carry) with EA eps of the fields: per element and, with both
  // ends held, its length-weighted mean with EA/L integral (...) (the same quadrature as the
  // element's: 64 eps of the terms for the sums' rounding).
  {
    const double scale = std::max(membrane_scale, std::numeric_limits<double>::min());
    const auto [lowest, highest] = std::minmax_element(normal_force.begin(), normal_force.end());
    if (!arch)
      c.checks.push_back(detail::make_check(check_name::membrane_uniform, (*highest - *lowest) / scale,
                                            4 * std::sqrt(static_cast<double>(nodes)) * row_tolerance));
    if (!arch && (!left || !right)) {
      const double end = !left ? normal_force.front() : normal_force.back();
      Check check = detail::make_check(check_name::membrane_free_end, std::abs(end) / scale, row_tolerance);
      check.at = !left ? d.mesh.nodes.front() : d.mesh.nodes.back();
      c.checks.push_back(check);
    }
    Check compatibility = detail::make_check(check_name::membrane_compatibility, 0.0, 64 * eps);
    double weighted = 0.0;
    for (int e = 0; e < elements; ++e) {
      const double value = std::abs(answer.normal_force[e] - normal_force[e]) / scale;
      if (!(value <= compatibility.value)) compatibility.value = value, compatibility.at = d.mesh.nodes[e];
      weighted += answer.normal_force[e] * d.mesh.element_size(e);
    }
    if (arch) {
      // The reported u is the field's: the tangential dofs at the nodes.
      double u_scale = std::numeric_limits<double>::min();
      for (int node = 0; node < nodes; ++node) u_scale = std::max(u_scale, std::abs(u_given[d.tangential_dof(node)]));
      for (int node = 0; node < nodes; ++node) {
        const double value = std::abs(axial[node] - u_given[d.tangential_dof(node)]) / u_scale;
        if (!(value <= compatibility.value)) compatibility.value = value, compatibility.at = d.mesh.nodes[node];
      }
    }
    if (left && right) {
      const double length = d.mesh.nodes.back() - d.mesh.nodes.front();
      const double value = std::abs(weighted - ea * strain_integral) / length / scale;
      if (!(value <= compatibility.value)) compatibility.value = value, compatibility.at.reset();
    }
    c.checks.push_back(compatibility);
  }

  // Contact conditions at the nodes (the discrete ones, weighted gaps recomputed from the fields
  // by quadrature). The solver changes a node's state only beyond VonKarmanOptions::sign_tolerance
  // (1e-10) of the largest reaction or C w term, so a node at r = gap = 0 may keep a value of
  // either sign of that relative size: the tolerance is that, times the sign safety factor
  // (CertifyOptions::sign_floor carries it; at least 16 eps). Pointwise conditions inside the
  // elements are not checked for von Karman answers.
  const double sign_tolerance = detail::sign_safety * std::max(detail::minimum_round_off, options.sign_floor);
  const int m = d.reactions();
  const double r_scale = m > 0 ? r_given.cwiseAbs().maxCoeff() : 0.0;
  double w_largest = 0.0;
  for (int node = 0; node < nodes; ++node) w_largest = std::max(w_largest, std::abs(u_given[d.deflection_dof(node)]));
  const std::vector<std::array<int, 2>> reaction_of_node = detail::element_reactions(d);
  Check sign = detail::make_check(check_name::reaction_sign, 0.0, sign_tolerance);
  Check penetration = detail::make_check(check_name::penetration, 0.0, sign_tolerance);
  Check complementarity = detail::make_check(check_name::complementarity, 0.0, sign_tolerance);
  auto worse = [](Check& check, double value, double s) {
    if (value > check.value) check.value = value, check.at = s;
  };
  for (int i = 0; i < m; ++i) {
    const int node = d.reaction_nodes[i];
    const double s = d.mesh.nodes[node];
    double support = 0.0;
    if (node > 0 && on_foundation(d, node - 1) && reaction_of_node[node - 1][1] == i)
      support += 0.5 * d.mesh.element_size(node - 1);
    if (node < elements && on_foundation(d, node) && reaction_of_node[node][0] == i)
      support += 0.5 * d.mesh.element_size(node);
    const double gap_terms = std::max(f.gap_terms[i], support * w_largest);
    const double relative_r = r_scale > 0 ? r_given[i] / r_scale : 0.0;
    const double relative_gap = gap_terms > 0 ? f.gap[i] / gap_terms : 0.0;
    if (d.tensionless) {
      if (d.equation_of_dof[d.deflection_dof(node)] >= 0) worse(sign, -relative_r, s);
      worse(penetration, -relative_gap, s);
      worse(complementarity, std::min(std::abs(relative_r), std::abs(relative_gap)), s);
    } else {
      worse(complementarity, std::abs(relative_gap), s);
    }
  }
  if (d.tensionless) c.checks.push_back(sign), c.checks.push_back(penetration);
  c.checks.push_back(complementarity);
  c.round_off_note = "round-off not measured for von Karman answers";
  detail::conclude(c, model);
  return c;
}

}  // namespace liftoff::certify
