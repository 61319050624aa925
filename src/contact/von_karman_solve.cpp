#include "contact/von_karman_solve.hpp"

#include <fmt/format.h>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <set>
#include <stdexcept>

#include "fe/arch_element.hpp"
#include "fe/arch_von_karman_element.hpp"
#include "fe/beam_element.hpp"
#include "fe/shape_functions.hpp"

namespace liftoff::contact {

namespace {

using Eigen::VectorXd;
using SparseMatrix = Eigen::SparseMatrix<double>;
using Triplets = std::vector<Eigen::Triplet<double>>;

bool all_finite(const VectorXd& v) { return v.allFinite(); }

// The contact set's selection with T_AA's factor (SPD: T is a flexibility).
struct ContactSet : ContactSelection {
  std::shared_ptr<Eigen::SimplicialLDLT<SparseMatrix>> factor;  // shared: the factor is not copyable
};

ContactSet make_set(const fe::Discretisation& d, std::vector<bool> in_contact) {
  ContactSet set{select_contact_set(d, std::move(in_contact)), nullptr};
  if (set.size() > 0) set.factor = std::make_shared<Eigen::SimplicialLDLT<SparseMatrix>>(set.flexibility);
  return set;
}

// Everything one evaluation at x gives.
struct Evaluation {
  VectorXd residual;            // R = f_int + C_A^T r_A - F on the unknowns
  VectorXd reaction_a;          // r_A
  double backward_error = 0.0;  // max_i |R_i| / (the forces summed into R_i, in magnitude)
  double energy = 0.0;          // Pi_A
  Triplets membrane;            // the membrane part of K_t (the linear part is the discretisation's K)
};

}  // namespace

ContactSelection select_contact_set(const fe::Discretisation& d, std::vector<bool> in_contact) {
  ContactSelection set;
  set.in_contact = std::move(in_contact);
  for (int i = 0; i < d.reactions(); ++i)
    if (set.in_contact[i]) set.members.push_back(i);
  Triplets select;
  for (int a = 0; a < set.size(); ++a) select.emplace_back(a, set.members[a], 1.0);
  SparseMatrix p(set.size(), d.reactions());
  p.setFromTriplets(select.begin(), select.end());
  set.coupling = p * d.coupling;
  set.flexibility = p * d.flexibility * SparseMatrix(p.transpose());
  set.ground_gap = VectorXd::Zero(set.size());
  if (d.ground_gap.size() == d.reactions())
    for (int a = 0; a < set.size(); ++a) set.ground_gap[a] = d.ground_gap[set.members[a]];
  return set;
}

void VonKarmanOptions::validate() const {
  auto positive = [](double v, const char* name) {
    if (!(v > 0.0) || !std::isfinite(v)) throw std::invalid_argument(fmt::format("{} must be > 0 and finite", name));
  };
  if (max_newton_iterations < 1) throw std::invalid_argument("max_newton_iterations must be >= 1");
  if (max_contact_sets < 1) throw std::invalid_argument("max_contact_sets must be >= 1");
  if (max_backtracks < 0) throw std::invalid_argument("max_backtracks must be >= 0");
  if (max_shifts < 1) throw std::invalid_argument("max_shifts must be >= 1");
  positive(residual_tolerance, "residual_tolerance");
  positive(initial_shift, "initial_shift");
  positive(sign_tolerance, "sign_tolerance");
  positive(max_error, "max_error");
  if (!(armijo > 0.0 && armijo < 0.5)) throw std::invalid_argument("armijo must be in (0, 0.5)");
}

std::string_view to_string(VonKarmanTermination t) {
  switch (t) {
    case VonKarmanTermination::solved:
      return "solved";
    case VonKarmanTermination::iteration_limit:
      return "iteration_limit";
    case VonKarmanTermination::line_search_failed:
      return "line_search_failed";
    case VonKarmanTermination::diverged:
      return "diverged";
    case VonKarmanTermination::singular_system:
      return "singular_system";
    case VonKarmanTermination::contact_cycling:
      return "contact_cycling";
    case VonKarmanTermination::contact_set_limit:
      return "contact_set_limit";
    case VonKarmanTermination::inaccurate:
      return "inaccurate";
  }
  return "unknown";
}

VonKarmanSystem::VonKarmanSystem(const model::MemberModel& model, const fe::Discretisation& d)
    : discretisation_(&d), membrane_stiffness_(model.membrane_stiffness) {
  if (model.kind != d.kind)
    throw std::invalid_argument("von Karman solve: the model and the discretisation are of different kinds");
  if (model.theory != model::Theory::von_karman)
    throw std::invalid_argument("von Karman solve: the model's theory must be von_karman");
  if (!(model.membrane_stiffness > 0.0) || !std::isfinite(model.membrane_stiffness))
    throw std::invalid_argument("von Karman solve: membrane_stiffness must be > 0 and finite");
  if (model.has_axial_force() || d.has_axial_force())
    throw std::invalid_argument(
        "von Karman solve: a given axial force is second-order theory; under von Karman N is computed");
  const int nodes = static_cast<int>(d.mesh.nodes.size());
  axial_unknown_.assign(nodes, -1);
  if (model.kind == model::StructureKind::arch) {
    // The arch's u is a discretisation dof: every local dof is one (element_dofs' local order is
    // ArchElement's, which ArchVonKarmanElement keeps); its linear part is ArchElement's stiffness,
    // the one discretise assembled.
    for (int e = 0; e < d.mesh.elements(); ++e) {
      const double h = d.mesh.element_size(e);
      auto element =
          std::make_shared<const fe::ArchVonKarmanElement>(h, model.membrane_stiffness, model.foundation_outside);
      Piece piece;
      piece.element = element;
      piece.linear = fe::arch_element::stiffness(h, model.membrane_stiffness, model.foundation_outside);
      piece.dof = d.element_dofs(e);
      for (int dof : piece.dof) piece.unknown.push_back(d.equation_of_dof[dof]);
      piece.energy = [element](const VectorXd& local) { return element->energy(local); };
      piece.normal_force = [element](const VectorXd& local, double xi) {
        return element->membrane_stiffness() * element->membrane_strain(local, xi);
      };
      const bool outside = model.foundation_outside;
      const double ea = model.membrane_stiffness;
      piece.force_terms = [h, ea, outside](const VectorXd& local) {
        VectorXd terms = VectorXd::Zero(local.size());
        const VectorXd size = local.cwiseAbs();
        for (const fe::GaussPoint& g : fe::gauss5) {
          const fe::arch_element::Row9d a = fe::arch_element::membrane_strain_row(g.xi, h, outside);
          const fe::arch_element::Row9d r = fe::arch_von_karman_element::rotation_row(g.xi, h, outside);
          const fe::arch_element::Row9d c = fe::arch_element::bending_strain_row(g.xi, h, outside);
          const double beta = r.dot(local);
          const double eps_terms = a.cwiseAbs().dot(size) + 0.5 * beta * beta, chi_terms = c.cwiseAbs().dot(size);
          terms += (g.weight * h) *
                   (ea * eps_terms * (a + beta * r).cwiseAbs().transpose() + chi_terms * c.cwiseAbs().transpose());
        }
        return terms;
      };
      pieces_.push_back(std::move(piece));
    }
    return;
  }
  const bool left = model.left_axially_restrained, right = model.right_axially_restrained;
  for (int node = 0; node < nodes; ++node) {
    const bool fixed = (node == 0 && (left || !right)) || (node == nodes - 1 && right);  // !left && !right: gauge
    if (fixed) continue;
    axial_unknown_[node] = d.equations + static_cast<int>(axial_nodes_.size());
    axial_nodes_.push_back(node);
  }
  for (int e = 0; e < d.mesh.elements(); ++e) {
    const double s0 = d.mesh.nodes[e], h = d.mesh.element_size(e);
    auto element = std::make_shared<const fe::VonKarmanBeamElement>(
        h, model.membrane_stiffness,
        fe::von_karman_element::sample_initial_slopes([&model](double s) { return model.initial_slope(s); }, s0, h));
    // Local (w0, w0', w1, w1', u0, u1): the Hermite dofs are the discretisation's, u the system's own.
    Piece piece;
    piece.element = element;
    piece.linear = Eigen::MatrixXd::Zero(6, 6);
    piece.linear.topLeftCorner<4, 4>() = fe::beam_element::stiffness(h);
    const std::vector<int> dofs = d.element_dofs(e);
    for (int i = 0; i < 4; ++i) {
      piece.dof.push_back(dofs[i]);
      piece.unknown.push_back(d.equation_of_dof[dofs[i]]);
    }
    for (int i = 0; i < 2; ++i) {
      piece.dof.push_back(-1);
      piece.unknown.push_back(axial_unknown_[e + i]);
    }
    piece.energy = [element](const VectorXd& local) { return element->energy(local); };
    piece.normal_force = [element](const VectorXd& local, double) { return element->normal_force(local); };
    pieces_.push_back(std::move(piece));
  }
}

VonKarmanResult solve_arch_von_karman(const model::MemberModel& model, const fe::Discretisation& discretisation,
                                      double load_factor, const VonKarmanOptions& options, const VectorXd& start,
                                      std::vector<bool> initial_set) {
  if (model.kind != model::StructureKind::arch)
    throw std::invalid_argument("solve_arch_von_karman: the model is not an arch");
  const VonKarmanSystem system(model, discretisation);
  return system.solve(load_factor, options, start, std::move(initial_set));
}

VectorXd VonKarmanSystem::load(double load_factor) const {
  VectorXd f = VectorXd::Zero(unknowns());
  f.head(discretisation_->equations) = discretisation_->load(load_factor);
  return f;
}

namespace {

// The evaluation, with the system's parts passed in (keeps the class's header small).
struct Evaluator {
  const fe::Discretisation& d;
  const std::vector<VonKarmanSystem::Piece>& pieces;
  int unknowns;

  // Element e's local displacement: discretisation dofs from w_all (settled supports included),
  // the system's own unknowns (the beam's u) from x, 0 where fixed.
  void gather(int e, const VectorXd& x, const VectorXd& w_all, VectorXd& local) const {
    const VonKarmanSystem::Piece& piece = pieces[e];
    const int n = static_cast<int>(piece.dof.size());
    local.resize(n);
    for (int i = 0; i < n; ++i)
      local[i] = piece.dof[i] >= 0 ? w_all[piece.dof[i]] : (piece.unknown[i] >= 0 ? x[piece.unknown[i]] : 0.0);
  }

  Evaluation operator()(const VectorXd& x, const VectorXd& load, const ContactSet& set, bool with_tangent) const {
    Evaluation ev;
    const int n = d.equations;
    const VectorXd q = x.head(n);
    const VectorXd w_all = d.expand_displacement(q);
    VectorXd size_vector = VectorXd::Zero(unknowns);
    ev.residual = VectorXd::Zero(unknowns);
    const VectorXd kq = d.stiffness * q;
    ev.residual.head(n) = kq;
    size_vector.head(n) = SparseMatrix(d.stiffness.cwiseAbs()) * q.cwiseAbs();
    ev.energy = 0.5 * q.dot(kq) - load.dot(x);
    size_vector += load.cwiseAbs();
    VectorXd local;
    fe::ElementResponse response;
    for (int e = 0; e < static_cast<int>(pieces.size()); ++e) {
      const VonKarmanSystem::Piece& piece = pieces[e];
      gather(e, x, w_all, local);
      piece.element->evaluate(fe::ElementState{local, 0.0}, response);
      // The linear part is in the discretisation's K (with the rest of the linear structure).
      const VectorXd linear_force = piece.linear * local;
      response.internal_force -= linear_force;
      response.tangent -= piece.linear;
      ev.energy += piece.energy(local) - 0.5 * local.dot(linear_force);
      // The nonlinear terms before they cancel: |K_m| |q_e| holds EA |b| (|b| . |q_e|), the strain's
      // terms (u1, u0, w0' w', w'^2) summed in magnitude.
      const VectorXd local_size =
          piece.force_terms
              ? piece.force_terms(local)
              : VectorXd(response.tangent.cwiseAbs() * local.cwiseAbs() + response.internal_force.cwiseAbs());
      const int m = static_cast<int>(local.size());
      for (int i = 0; i < m; ++i) {
        const int row = piece.unknown[i];
        if (row < 0) continue;
        ev.residual[row] += response.internal_force[i];
        size_vector[row] += local_size[i];
        if (with_tangent)
          for (int j = 0; j < m; ++j)
            if (piece.unknown[j] >= 0 && response.tangent(i, j) != 0.0)
              ev.membrane.emplace_back(row, piece.unknown[j], response.tangent(i, j));
      }
    }
    if (set.size() > 0) {
      const VectorXd gap_a = set.coupling * q - set.ground_gap;
      ev.reaction_a = set.factor->solve(gap_a);
      ev.residual.head(n) += set.coupling.transpose() * ev.reaction_a;
      size_vector.head(n) += SparseMatrix(set.coupling.cwiseAbs().transpose()) * ev.reaction_a.cwiseAbs();
      ev.energy += 0.5 * gap_a.dot(ev.reaction_a);
    } else {
      ev.reaction_a.resize(0);
    }
    ev.residual -= load;
    // The componentwise backward error: |R_i| against the sizes that summed to it (rows with none
    // hold R_i = 0 exactly).
    ev.backward_error = 0.0;
    for (int i = 0; i < unknowns; ++i)
      if (ev.residual[i] != 0.0)
        ev.backward_error = std::max(ev.backward_error, std::abs(ev.residual[i]) / size_vector[i]);
    return ev;
  }

  // The saddle matrix [K_t + mu D, C_A^T; C_A, -T_AA] (full, symmetric) and D = diag|K_t|.
  SparseMatrix saddle(const Evaluation& ev, const ContactSet& set, double shift, VectorXd* diagonal) const {
    const int n = d.equations, m = set.size();
    SparseMatrix kt(unknowns, unknowns);
    {
      Triplets t(ev.membrane);
      for (int k = 0; k < d.stiffness.outerSize(); ++k)
        for (SparseMatrix::InnerIterator it(d.stiffness, k); it; ++it) t.emplace_back(it.row(), it.col(), it.value());
      kt.setFromTriplets(t.begin(), t.end());
    }
    VectorXd diag = kt.diagonal().cwiseAbs();
    const double floor = std::max(diag.maxCoeff(), std::numeric_limits<double>::min()) * 1e-12;
    diag = diag.cwiseMax(floor);
    if (diagonal) *diagonal = diag;
    Triplets t;
    t.reserve(kt.nonZeros() + unknowns + 2 * set.coupling.nonZeros() + set.flexibility.nonZeros());
    for (int k = 0; k < kt.outerSize(); ++k)
      for (SparseMatrix::InnerIterator it(kt, k); it; ++it) t.emplace_back(it.row(), it.col(), it.value());
    if (shift > 0.0)
      for (int i = 0; i < unknowns; ++i) t.emplace_back(i, i, shift * diag[i]);
    for (int k = 0; k < set.coupling.outerSize(); ++k)
      for (SparseMatrix::InnerIterator it(set.coupling, k); it; ++it) {
        t.emplace_back(unknowns + it.row(), it.col(), it.value());
        t.emplace_back(it.col(), unknowns + it.row(), it.value());
      }
    for (int k = 0; k < set.flexibility.outerSize(); ++k)
      for (SparseMatrix::InnerIterator it(set.flexibility, k); it; ++it)
        t.emplace_back(unknowns + it.row(), unknowns + it.col(), -it.value());
    SparseMatrix a(unknowns + m, unknowns + m);
    a.setFromTriplets(t.begin(), t.end());
    (void)n;
    return a;
  }
};

// Sylvester: the condensed Hessian S is positive definite iff the saddle matrix's LDL^T has
// exactly |A| negative pivots (and no zero one).
bool positive_definite(const Eigen::SimplicialLDLT<SparseMatrix>& ldlt, int set_size) {
  if (ldlt.info() != Eigen::Success) return false;
  const VectorXd dd = ldlt.vectorD();
  if (!dd.allFinite()) return false;
  int negative = 0;
  for (int i = 0; i < dd.size(); ++i) {
    if (dd[i] == 0.0) return false;
    negative += dd[i] < 0.0;
  }
  return negative == set_size;
}

}  // namespace

std::vector<double> VonKarmanSystem::normal_forces(const VectorXd& x) const {
  const fe::Discretisation& d = *discretisation_;
  const Evaluator evaluate{d, pieces_, unknowns()};
  const VectorXd w_all = d.expand_displacement(x.head(d.equations));
  std::vector<double> forces;
  VectorXd local;
  for (int e = 0; e < static_cast<int>(pieces_.size()); ++e) {
    evaluate.gather(e, x, w_all, local);
    double mean = 0.0;  // the Gauss rule's mean (exact for the beam's constant N)
    for (const fe::GaussPoint& g : fe::gauss5) mean += g.weight * pieces_[e].normal_force(local, g.xi);
    forces.push_back(mean);
  }
  return forces;
}

double VonKarmanSystem::normal_force(const VectorXd& x, int element, double xi) const {
  const fe::Discretisation& d = *discretisation_;
  if (element < 0 || element >= static_cast<int>(pieces_.size()) || !(xi >= 0.0 && xi <= 1.0))
    throw std::invalid_argument(
        fmt::format("von Karman solve: normal_force at element {} of {}, xi = {}", element, pieces_.size(), xi));
  VectorXd local;
  Evaluator{d, pieces_, unknowns()}.gather(element, x, d.expand_displacement(x.head(d.equations)), local);
  return pieces_[element].normal_force(local, xi);
}

VectorXd VonKarmanSystem::internal_force(const VectorXd& x) const {
  const fe::Discretisation& d = *discretisation_;
  const Evaluator evaluate{d, pieces_, unknowns()};
  return evaluate(x, VectorXd::Zero(unknowns()), make_set(d, std::vector<bool>(d.reactions(), false)), false).residual;
}

SparseMatrix VonKarmanSystem::tangent_stiffness(const VectorXd& x) const {
  const fe::Discretisation& d = *discretisation_;
  const Evaluator evaluate{d, pieces_, unknowns()};
  const Evaluation ev =
      evaluate(x, VectorXd::Zero(unknowns()), make_set(d, std::vector<bool>(d.reactions(), false)), true);
  Triplets t(ev.membrane);
  // Explicit zeros on every element coupling: the pattern must not depend on x (a zero normal
  // force or a straight member leaves some membrane terms exactly zero).
  for (const Piece& piece : pieces_)
    for (int i : piece.unknown)
      for (int j : piece.unknown)
        if (i >= 0 && j >= 0) t.emplace_back(i, j, 0.0);
  for (int k = 0; k < d.stiffness.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(d.stiffness, k); it; ++it) t.emplace_back(it.row(), it.col(), it.value());
  SparseMatrix kt(unknowns(), unknowns());
  kt.setFromTriplets(t.begin(), t.end());
  return kt;
}

double VonKarmanSystem::energy(const VectorXd& x, const VectorXd& load, const std::vector<bool>& in_contact) const {
  const Evaluator evaluate{*discretisation_, pieces_, unknowns()};
  return evaluate(x, load, make_set(*discretisation_, in_contact), false).energy;
}

VonKarmanResult VonKarmanSystem::solve(const VectorXd& load, const VonKarmanOptions& options, const VectorXd& start,
                                       std::vector<bool> initial_set) const {
  options.validate();
  const fe::Discretisation& d = *discretisation_;
  const int n = unknowns();
  if (load.size() != n)
    throw std::invalid_argument(fmt::format("von Karman solve: load has {} entries, expected {}", load.size(), n));
  if (start.size() != 0 && start.size() != n)
    throw std::invalid_argument(fmt::format("von Karman solve: start has {} entries, expected {}", start.size(), n));
  if (!initial_set.empty() && static_cast<int>(initial_set.size()) != d.reactions())
    throw std::invalid_argument(fmt::format("von Karman solve: initial_set has {} entries, expected {} reactions",
                                            initial_set.size(), d.reactions()));
  if (initial_set.empty() || !d.tensionless) initial_set.assign(d.reactions(), true);

  const Evaluator evaluate{d, pieces_, n};
  const bool line_search = options.globalisation == VonKarmanGlobalisation::energy_line_search;
  VonKarmanResult result;
  result.x = start.size() == n ? start : VectorXd::Zero(n);
  ContactSet set = make_set(d, initial_set);

  auto fail = [&](VonKarmanTermination t, std::string message) {
    result.termination = t;
    result.message = std::move(message);
  };

  // Newton on one contact set; true when converged (else result's termination is set).
  auto newton = [&](int set_index) -> bool {
    const int m = set.size();
    for (int it = 0;; ++it) {
      const Evaluation ev = evaluate(result.x, load, set, true);
      const double residual = ev.residual.lpNorm<Eigen::Infinity>();
      if (!std::isfinite(residual) || !all_finite(result.x)) {
        fail(VonKarmanTermination::diverged,
             fmt::format("set {}: the iterate is no longer finite after {} Newton steps", set_index, it));
        return false;
      }
      if (!(ev.backward_error > options.residual_tolerance)) {
        result.set_residuals.push_back(residual);
        return true;
      }
      if (it == options.max_newton_iterations) {
        fail(VonKarmanTermination::iteration_limit,
             fmt::format("set {}: |R| = {:.3e}, backward error {:.3e} (tolerance {:.3e}) after {} Newton steps",
                         set_index, residual, ev.backward_error, options.residual_tolerance, it));
        return false;
      }
      VonKarmanIteration record{set_index, residual, ev.energy, 1.0, 0.0, false};
      VectorXd rhs = VectorXd::Zero(n + m);
      rhs.head(n) = -ev.residual;
      VectorXd p;
      if (!line_search) {
        Eigen::SparseLU<SparseMatrix> lu;
        const SparseMatrix a = evaluate.saddle(ev, set, 0.0, nullptr);
        lu.compute(a);
        if (lu.info() != Eigen::Success) {
          fail(VonKarmanTermination::singular_system,
               fmt::format("set {}: the tangent is singular at Newton step {}", set_index, it));
          return false;
        }
        p = lu.solve(rhs).head(n);
        result.x += p;
        result.history.push_back(record);
        if (!(p.lpNorm<Eigen::Infinity>() < 1e100)) {
          fail(VonKarmanTermination::diverged, fmt::format("set {}: Newton step {} exploded", set_index, it));
          return false;
        }
        continue;
      }
      // Modified Newton: shift until S is positive definite.
      Eigen::SimplicialLDLT<SparseMatrix> ldlt;
      SparseMatrix saddle_matrix;
      VectorXd diagonal;
      double shift = 0.0;
      bool ok = false;
      for (int k = 0; k <= options.max_shifts; ++k) {
        saddle_matrix = evaluate.saddle(ev, set, shift, &diagonal);
        ldlt.compute(saddle_matrix);
        if (positive_definite(ldlt, m)) {
          ok = true;
          break;
        }
        shift = shift == 0.0 ? options.initial_shift : 10.0 * shift;
      }
      if (!ok) {
        fail(VonKarmanTermination::singular_system,
             fmt::format("set {}: no shift up to {:.1e} made the tangent positive definite at Newton step {}",
                         set_index, shift / 10.0, it));
        return false;
      }
      record.shift = shift;
      {
        // One step of iterative refinement. The factor's backward error is ~3e-16, but K_t's
        // condition grows like h^-4 (and EA R^2 / EI = 3e6 in the seed's arch): without the step,
        // the seed arch on 400 elements stalls at |R| ~ 1e-7 (relative 2e-10), every direction
        // rejected by the line search; with it, it converges on 400 to 2000 elements.
        VectorXd full = ldlt.solve(rhs);
        full += ldlt.solve(VectorXd(rhs - saddle_matrix * full));
        p = full.head(n);
      }
      double slope = ev.residual.dot(p);
      if (!(slope < 0.0) || !p.allFinite()) {
        p = -ev.residual.cwiseQuotient(diagonal);
        slope = ev.residual.dot(p);
        record.gradient_step = true;
        record.shift = 0.0;
      }
      double alpha = 1.0;
      bool accepted = false;
      for (int b = 0; b <= options.max_backtracks; ++b, alpha *= 0.5) {
        const VectorXd trial = result.x + alpha * p;
        const Evaluation at = evaluate(trial, load, set, false);
        const bool decrease = at.energy <= ev.energy + options.armijo * alpha * slope;
        // Near the answer Pi's change drops below its round-off: a full Newton step that halves |R| is
        // progress too (only unshifted, so that it is the Newton step of a convex model).
        const bool residual_halves =
            b == 0 && shift == 0.0 && !record.gradient_step && at.residual.lpNorm<Eigen::Infinity>() <= 0.5 * residual;
        if (std::isfinite(at.energy) && (decrease || residual_halves)) {
          accepted = true;
          break;
        }
      }
      if (!accepted) {
        fail(VonKarmanTermination::line_search_failed,
             fmt::format("set {}: no step along the {} direction decreased the energy (|R| = {:.3e}, backward error "
                         "{:.1e} against the tolerance {:.1e}, Newton step {})",
                         set_index, record.gradient_step ? "gradient" : "Newton", residual, ev.backward_error,
                         options.residual_tolerance, it));
        return false;
      }
      record.step = alpha;
      result.x += alpha * p;
      result.history.push_back(record);
    }
  };

  std::set<std::vector<bool>> seen;
  bool single_flips = false;
  for (int set_index = 0;; ++set_index) {
    if (set_index == options.max_contact_sets) {
      fail(VonKarmanTermination::contact_set_limit,
           fmt::format("{} contact sets tried without one whose signs hold", set_index));
      break;
    }
    result.contact_sets = set_index + 1;
    if (!newton(set_index)) break;
    // The set's reactions and gaps, and the nodes whose signs are wrong.
    const Evaluation ev = evaluate(result.x, load, set, false);
    VectorXd reaction = VectorXd::Zero(d.reactions());
    for (int a = 0; a < set.size(); ++a) reaction[set.members[a]] = ev.reaction_a[a];
    const VectorXd q = result.x.head(d.equations);
    const VectorXd gap = d.gap_of(reaction, q);
    result.reaction = reaction;
    result.gap = gap;
    result.in_contact = set.in_contact;
    result.energy = ev.energy;
    if (!d.tensionless) {
      fail(VonKarmanTermination::solved, fmt::format("bilateral foundation: {} Newton steps", result.history.size()));
      break;
    }
    VectorXd gap_terms = SparseMatrix(d.coupling.cwiseAbs()) * q.cwiseAbs();
    if (d.ground_gap.size() == d.reactions()) gap_terms += d.ground_gap.cwiseAbs();
    const double reaction_scale = std::max(reaction.lpNorm<Eigen::Infinity>(), std::numeric_limits<double>::min());
    const double gap_scale = std::max(gap_terms.lpNorm<Eigen::Infinity>(), std::numeric_limits<double>::min());
    std::vector<int> infeasible;
    int worst = -1;
    double worst_violation = 0.0;
    for (int i = 0; i < d.reactions(); ++i) {
      const double violation = set.in_contact[i] ? -reaction[i] / reaction_scale : -gap[i] / gap_scale;
      if (violation > options.sign_tolerance) {
        infeasible.push_back(i);
        if (violation > worst_violation) worst_violation = violation, worst = i;
      }
    }
    if (infeasible.empty()) {
      fail(VonKarmanTermination::solved,
           fmt::format("{} contact sets, {} Newton steps", set_index + 1, result.history.size()));
      break;
    }
    seen.insert(set.in_contact);
    std::vector<bool> next = set.in_contact;
    if (!single_flips) {
      for (int i : infeasible) next[i] = !next[i];
      if (seen.count(next)) {
        single_flips = true;
        next = set.in_contact;
      }
    }
    if (single_flips) {
      next[worst] = !next[worst];
      if (seen.count(next)) {
        fail(VonKarmanTermination::contact_cycling,
             fmt::format("contact set {} came back after single flips ({} nodes with wrong signs)", set_index + 1,
                         infeasible.size()));
        break;
      }
    }
    set = make_set(d, std::move(next));
  }

  // Fields on the nodes.
  const VectorXd w_all = d.expand_displacement(result.x.head(d.equations));
  const int nodes = static_cast<int>(d.mesh.nodes.size());
  result.w.resize(nodes);
  result.theta.resize(nodes);
  result.u.resize(nodes);
  for (int node = 0; node < nodes; ++node) {
    result.w[node] = w_all[d.deflection_dof(node)];
    result.theta[node] = w_all[d.slope_dof(node)];
    if (d.kind == model::StructureKind::arch)
      result.u[node] = w_all[d.tangential_dof(node)];
    else
      result.u[node] = axial_unknown_[node] >= 0 ? result.x[axial_unknown_[node]] : 0.0;
  }
  result.normal_force = normal_forces(result.x);
  if (result.is_usable()) {
    // Stability from the inertia; the error from one more Newton correction, which at a converged
    // answer is what the residual's round-off moves it by (the primal K's condition grows like h^-4).
    const Evaluation ev = evaluate(result.x, load, set, true);
    const SparseMatrix a = evaluate.saddle(ev, set, 0.0, nullptr);
    Eigen::SimplicialLDLT<SparseMatrix> ldlt(a);
    result.stable = positive_definite(ldlt, set.size());
    Eigen::SparseLU<SparseMatrix> lu(a);
    VectorXd rhs = VectorXd::Zero(a.rows());
    rhs.head(n) = -ev.residual;
    const double size = std::max(result.x.lpNorm<Eigen::Infinity>(), std::numeric_limits<double>::min());
    result.error_estimate = lu.info() == Eigen::Success ? lu.solve(rhs).head(n).lpNorm<Eigen::Infinity>() / size
                                                        : std::numeric_limits<double>::infinity();
    if (!(result.error_estimate <= options.max_error))
      fail(VonKarmanTermination::inaccurate,
           fmt::format("the answer's estimated relative error {:.1e} exceeds max_error {:.1e}: round-off of the "
                       "primal system on {} elements (its condition grows like h^-4); use fewer elements",
                       result.error_estimate, options.max_error, d.mesh.elements()));
  }
  return result;
}

}  // namespace liftoff::contact
