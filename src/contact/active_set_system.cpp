#include "contact/active_set_system.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace liftoff::contact {

using Eigen::VectorXd;

namespace {

constexpr double eps = std::numeric_limits<double>::epsilon();
enum Block { displacement = 0, stress = 1, reaction = 2 };

// The dofs of node j in the order they are numbered, and the element-interior dofs of element j
// (fixed-size: no allocation per node).
struct Dofs {
  std::array<int, 3> dof{};
  int count = 0;
};
Dofs node_dofs(const fe::Discretisation& d, int node) {
  if (d.kind == model::StructureKind::beam) return {{d.deflection_dof(node), d.slope_dof(node), 0}, 2};
  return {{d.tangential_dof(node), d.deflection_dof(node), d.slope_dof(node)}, 3};
}
Dofs interior_dofs(const fe::Discretisation& d, int element) {
  if (d.kind == model::StructureKind::beam) return {};
  return {{6 * element + 3, 6 * element + 4, 6 * element + 5}, 3};
}

}  // namespace

ActiveSetSystem::ActiveSetSystem(const fe::Discretisation& discretisation) : d_(discretisation) { assemble(); }

void ActiveSetSystem::reassemble() {
  in_contact_.clear();
  factorised_ = false;
  solved_ = false;
  assemble();
}

void ActiveSetSystem::assemble() {
  const int n = d_.equations, ns = d_.stresses(), m = d_.reactions(), size = n + ns + m;
  const int elements = d_.mesh.elements(), spe = d_.stresses_per_element;
  const int winkler_elements = static_cast<int>(d_.winkler_elements.size());
  if (ns != d_.spring_stress(static_cast<int>(d_.springs.size())) || d_.stress_coupling.rows() != ns ||
      d_.stress_coupling.cols() != n)
    throw std::invalid_argument("ActiveSetSystem: the discretisation has no mixed form (stress_coupling, compliance)");

  // Unknowns in order along the member: a node's dofs and reaction, then the element's interior
  // dofs and stresses (its own, then its Winkler stresses, fe/discretisation.hpp). Every coupling
  // is within an element or between neighbouring nodes' reactions, so the matrix is banded in this
  // order with a bandwidth independent of the mesh. A node where the reaction jumps has two
  // reactions, placed together (the left one first).
  int next_reaction = 0;
  slot_.assign(size, -1);
  reaction_of_slot_.assign(size, -1);
  block_of_slot_.assign(size, displacement);
  int next = 0, winkler = 0;
  auto place_dofs = [&](const Dofs& dofs) {
    for (int k = 0; k < dofs.count; ++k)
      if (d_.equation_of_dof[dofs.dof[k]] >= 0) slot_[d_.equation_of_dof[dofs.dof[k]]] = next++;
  };
  // A spring's stress goes with its node's dofs (the spring block of the stresses, discretisation.hpp).
  std::vector<std::vector<int>> springs_of_node(d_.mesh.nodes.size());
  for (std::size_t i = 0; i < d_.springs.size(); ++i)
    springs_of_node[d_.springs[i].node].push_back(d_.spring_stress(static_cast<int>(i)));
  for (int node = 0; node <= elements; ++node) {
    place_dofs(node_dofs(d_, node));
    for (int k : springs_of_node[node]) {
      slot_[n + k] = next;
      block_of_slot_[next++] = stress;
    }
    for (; next_reaction < m && d_.reaction_nodes[next_reaction] == node; ++next_reaction) {
      slot_[n + ns + next_reaction] = next;
      reaction_of_slot_[next] = next_reaction;
      block_of_slot_[next++] = reaction;
    }
    if (node == elements) break;
    place_dofs(interior_dofs(d_, node));
    for (int k = spe * node; k < spe * (node + 1); ++k) {
      slot_[n + k] = next;
      block_of_slot_[next++] = stress;
    }
    if (winkler < winkler_elements && d_.winkler_elements[winkler] == node) {
      const int first = d_.winkler_stress(winkler++);
      for (int k = first; k < first + fe::foundation_element::winkler_points; ++k) {
        slot_[n + k] = next;
        block_of_slot_[next++] = stress;
      }
    }
  }
  if (next != size) throw std::logic_error("ActiveSetSystem: an unknown was left unnumbered");

  // The mixed matrix, assembled straight into compressed columns (no triplet list: at 1e6
  // elements that and Eigen's sorting copy were ~1 GB of memory touched once). The blocks are
  // disjoint, so no entry comes twice.
  std::vector<bool> has_diagonal(m, false);
  for (int k = 0; k < d_.flexibility.outerSize(); ++k)
    for (fe::SparseMatrix::InnerIterator it(d_.flexibility, k); it; ++it)
      if (it.row() == it.col()) has_diagonal[it.row()] = true;
  auto visit = [&](auto&& entry) {
    for (int k = 0; k < d_.stress_coupling.outerSize(); ++k)
      for (fe::SparseMatrix::InnerIterator it(d_.stress_coupling, k); it; ++it) {
        entry(slot_[n + it.row()], slot_[it.col()], it.value());
        entry(slot_[it.col()], slot_[n + it.row()], it.value());
      }
    for (int k = 0; k < ns; ++k) entry(slot_[n + k], slot_[n + k], -d_.compliance[k]);
    // Second-order theory: -N K_g in the displacement block (empty otherwise), within elements.
    if (d_.has_axial_force())
      for (int k = 0; k < d_.geometric_stiffness.outerSize(); ++k)
        for (fe::SparseMatrix::InnerIterator it(d_.geometric_stiffness, k); it; ++it)
          entry(slot_[it.row()], slot_[it.col()], -d_.axial_force * it.value());
    for (int k = 0; k < d_.coupling.outerSize(); ++k)
      for (fe::SparseMatrix::InnerIterator it(d_.coupling, k); it; ++it) {
        entry(slot_[n + ns + it.row()], slot_[it.col()], it.value());
        entry(slot_[it.col()], slot_[n + ns + it.row()], it.value());
      }
    for (int k = 0; k < d_.flexibility.outerSize(); ++k)
      for (fe::SparseMatrix::InnerIterator it(d_.flexibility, k); it; ++it)
        entry(slot_[n + ns + it.row()], slot_[n + ns + it.col()], -it.value());
    // Every reaction node keeps its diagonal in the pattern, whatever T holds.
    for (int i = 0; i < m; ++i)
      if (!has_diagonal[i]) entry(slot_[n + ns + i], slot_[n + ns + i], 0.0);
  };
  std::vector<int> starts(size + 1, 0);
  int band = 0;
  visit([&](int row, int col, double) {
    ++starts[col + 1];
    band = std::max(band, std::abs(row - col));
  });
  for (int col = 0; col < size; ++col) starts[col + 1] += starts[col];
  full_.resize(size, size);
  full_.resizeNonZeros(starts[size]);
  std::copy(starts.begin(), starts.end(), full_.outerIndexPtr());
  int* rows = full_.innerIndexPtr();
  double* values = full_.valuePtr();
  visit([&](int row, int col, double value) {
    rows[starts[col]] = row;
    values[starts[col]++] = value;
  });
  for (int col = 0; col < size; ++col) {  // rows in increasing order within each column
    const int begin = full_.outerIndexPtr()[col], end = full_.outerIndexPtr()[col + 1];
    for (int p = begin + 1; p < end; ++p)
      for (int q = p; q > begin && rows[q - 1] > rows[q]; --q) {
        std::swap(rows[q - 1], rows[q]);
        std::swap(values[q - 1], values[q]);
      }
  }

  // The mixed matrix is symmetric when T is (the other blocks enter in pairs above): checked
  // exactly, since compute_defect then reads rows as columns.
  symmetric_ = true;
  for (int k = 0; k < d_.flexibility.outerSize() && symmetric_; ++k)
    for (fe::SparseMatrix::InnerIterator it(d_.flexibility, k); it; ++it)
      if (d_.flexibility.coeff(it.col(), it.row()) != it.value()) symmetric_ = false;

  // Symmetric equilibration: S A S has a largest entry of 1 in every row (A is symmetric).
  scaling_ = VectorXd::Zero(size);
  for (int col = 0; col < size; ++col)
    for (fe::SparseMatrix::InnerIterator it(full_, col); it; ++it)
      scaling_[it.row()] = std::max(scaling_[it.row()], std::abs(it.value()));
  for (int i = 0; i < size; ++i) scaling_[i] = scaling_[i] > 0 ? 1.0 / std::sqrt(scaling_[i]) : 1.0;

  lu_.set_structure(size, band, band);
  masked_.resize(full_.nonZeros());
  if (d_.free_rigid_motions.cols() > 0 && d_.free_rigid_motions.rows() != n)
    throw std::invalid_argument("ActiveSetSystem: free_rigid_motions must have one row per equation");
  coupled_motions_ =
      d_.free_rigid_motions.cols() > 0 ? Eigen::MatrixXd(d_.coupling * d_.free_rigid_motions) : Eigen::MatrixXd(m, 0);
  rhs_.resize(size);
  x_.resize(size);
  correction_.resize(size);
  defect_.resize(size);
  magnitude_.resize(size);
  accumulator_.resize(size);
}

bool ActiveSetSystem::in_system(int slot) const {
  const int node = reaction_of_slot_[slot];
  return node < 0 || in_contact_[node];
}

bool ActiveSetSystem::holds_rigid_motions(const std::vector<bool>& in_contact) const {
  const int r = static_cast<int>(coupled_motions_.cols());
  if (r == 0) return true;
  // The system is singular exactly when a free rigid motion q (K q = 0) has C_A q = 0. The Gram
  // matrix of the rows of C_A Q, accumulated in extended precision, is singular to ~1e-19 then;
  // two contact nodes one element apart at 1e6 elements still give ~1e-13 (h^2).
  using MatrixL = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
  MatrixL gram = MatrixL::Zero(r, r);
  for (int i = 0; i < d_.reactions(); ++i) {
    if (!in_contact[i]) continue;
    for (int a = 0; a < r; ++a)
      for (int b = 0; b <= a; ++b)
        gram(a, b) += static_cast<long double>(coupled_motions_(i, a)) * coupled_motions_(i, b);
  }
  if (!(gram.trace() > 0)) return false;
  Eigen::SelfAdjointEigenSolver<MatrixL> eigen(gram, Eigen::EigenvaluesOnly);  // reads the lower triangle
  return eigen.eigenvalues()[0] > 1e-16L * eigen.eigenvalues()[r - 1];
}

bool ActiveSetSystem::factorise(const std::vector<bool>& in_contact) {
  if (static_cast<int>(in_contact.size()) != d_.reactions())
    throw std::invalid_argument("ActiveSetSystem::factorise: one contact flag per reaction node expected");
  if (factorised_ && in_contact == in_contact_) return true;
  in_contact_ = in_contact;
  factorised_ = false;
  solved_ = false;
  if (!holds_rigid_motions(in_contact_)) return false;

  // A lifted-off node keeps a -1 diagonal and nothing else: r_i = 0.
  const double* values = full_.valuePtr();
  const int* rows = full_.innerIndexPtr();
  const int* starts = full_.outerIndexPtr();
  for (int col = 0; col < full_.outerSize(); ++col) {
    lu_.clear_column(col);  // the last factors' values and fill
    const bool col_in = in_system(col);
    if (!col_in) lu_.set(col, col, -1.0);
    for (int p = starts[col]; p < starts[col + 1]; ++p) {
      const bool in = col_in && in_system(rows[p]);
      masked_[p] = in ? values[p] : 0.0;
      if (in) lu_.set(rows[p], col, values[p] * scaling_[rows[p]] * scaling_[col]);
    }
  }
  ++factorisations_;
  factorised_ = lu_.factorise();
  return factorised_;
}

void ActiveSetSystem::solve_in_place(VectorXd& b) const {
  b.array() *= scaling_.array();
  lu_.solve(b.data());
  b.array() *= scaling_.array();
}

void ActiveSetSystem::compute_defect(const VectorXd& rhs, const VectorXd& x) const {
  const Eigen::Index size = full_.rows();
  // The matrix of the current set: entries of lifted-off reactions masked to zero.
  const double* values = masked_.data();
  const int* rows = full_.innerIndexPtr();
  const int* starts = full_.outerIndexPtr();
  if (symmetric_) {
    // Column i is row i: each row's sum in one extended-precision register, no scattered
    // long-double stores (those were most of the defect's time).
    for (int i = 0; i < size; ++i) {
      long double sum = rhs[i];
      double magnitude = std::abs(rhs[i]);
      for (int p = starts[i]; p < starts[i + 1]; ++p) {
        const double xr = x[rows[p]];
        sum -= static_cast<long double>(values[p]) * static_cast<long double>(xr);
        magnitude += std::abs(values[p]) * std::abs(xr);
      }
      defect_[i] = static_cast<double>(sum);
      magnitude_[i] = magnitude;
    }
    return;
  }
  for (Eigen::Index i = 0; i < size; ++i) {
    accumulator_[i] = rhs[i];
    magnitude_[i] = std::abs(rhs[i]);
  }
  for (int col = 0; col < size; ++col) {
    const long double xc = x[col];
    const double xd = std::abs(x[col]);
    for (int p = starts[col]; p < starts[col + 1]; ++p) {
      accumulator_[rows[p]] -= static_cast<long double>(values[p]) * xc;
      magnitude_[rows[p]] += std::abs(values[p]) * xd;
    }
  }
  for (Eigen::Index i = 0; i < size; ++i) defect_[i] = static_cast<double>(accumulator_[i]);
}

// Row-wise relative defect of the last compute_defect(): |A x - b|_i / (sum_j |A_ij x_j| + |b_i|),
// with a floor under the denominator of the row's share of the equilibrated system's scale,
// ||S^-1 x||_inf / S_i (the entries of S A S are at most 1). Without it a row whose true
// values are all zero (the bending moment at a free end, for one load) would show its
// round-off remnant (1e-37 against moments of 1e-3) as a relative defect of 1.
double ActiveSetSystem::relative_defect() const {
  double scaled_size = 0.0;
  for (Eigen::Index i = 0; i < x_.size(); ++i)
    if (in_system(static_cast<int>(i))) scaled_size = std::max(scaled_size, std::abs(x_[i]) / scaling_[i]);
  double residual = 0.0;
  for (Eigen::Index i = 0; i < defect_.size(); ++i) {
    const double denominator = magnitude_[i] + scaled_size / scaling_[i];
    if (denominator > 0) residual = std::max(residual, std::abs(defect_[i]) / denominator);
  }
  return residual;
}

double ActiveSetSystem::residual_of_last_solve() const {
  if (!factorised_) throw std::logic_error("ActiveSetSystem::residual_of_last_solve before a solve");
  compute_defect(rhs_, x_);
  return relative_defect();
}

ContactState ActiveSetSystem::solve(const VectorXd& load) const { return solve(load, RefinementOptions{}); }

ContactState ActiveSetSystem::solve(const VectorXd& load, const RefinementOptions& refinement) const {
  return solve(load, VectorXd::Zero(d_.reactions()), refinement);
}

ContactState ActiveSetSystem::solve(const VectorXd& load, const VectorXd& gap_offset,
                                    const RefinementOptions& refinement) const {
  if (!factorised_) throw std::logic_error("ActiveSetSystem::solve before a successful factorise()");
  const int n = d_.equations, ns = d_.stresses();
  if (load.size() != n) throw std::invalid_argument("ActiveSetSystem::solve: one load per equation expected");
  if (gap_offset.size() != d_.reactions())
    throw std::invalid_argument("ActiveSetSystem::solve: one gap offset per reaction node expected");
  rhs_.setZero();
  for (int e = 0; e < n; ++e) rhs_[slot_[e]] = load[e];
  // Contact rows: C_A u - T_AA r_A = c_A; a lifted-off node's row r_i = 0 keeps a zero right side.
  for (int i = 0; i < d_.reactions(); ++i)
    if (in_contact_[i]) rhs_[slot_[n + ns + i]] = gap_offset[i];
  offset_ = gap_offset;
  x_ = rhs_;
  solve_in_place(x_);
  solved_ = true;
  return refine(refinement);
}

ContactState ActiveSetSystem::refine_last_solve(const RefinementOptions& refinement) const {
  if (!factorised_ || !solved_) throw std::logic_error("ActiveSetSystem::refine_last_solve before a solve");
  return refine(refinement);
}

ContactState ActiveSetSystem::refine(const RefinementOptions& refinement) const {
  const int n = d_.equations, ns = d_.stresses(), m = d_.reactions();
  const Eigen::Index size = full_.rows();

  // Refinement: the defect b - A x on A as assembled, in extended precision. With the mixed
  // form's condition (~N^2) each step gains ~log10(1 / (eps cond)) digits: none are needed at
  // small meshes, two or three at 1e6 elements. The estimate is the last correction relative to
  // (u, r), block by block (the stresses are internal and may be far larger).
  auto relative_change = [&]() {
    double u_change = 0, u_size = 0, r_change = 0, r_size = 0;
    for (Eigen::Index s = 0; s < size; ++s) {
      if (block_of_slot_[s] == displacement) {
        u_change = std::max(u_change, std::abs(correction_[s]));
        u_size = std::max(u_size, std::abs(x_[s]));
      } else if (block_of_slot_[s] == reaction) {
        r_change = std::max(r_change, std::abs(correction_[s]));
        r_size = std::max(r_size, std::abs(x_[s]));
      }
    }
    double change = 0.0;
    if (u_size > 0) change = std::max(change, u_change / u_size);
    if (r_size > 0) change = std::max(change, r_change / r_size);
    return change;
  };
  double previous = INFINITY, estimate = INFINITY;
  int steps = 0;
  while (steps < refinement.max_steps) {
    compute_defect(rhs_, x_);
    correction_ = defect_;
    solve_in_place(correction_);
    x_ += correction_;
    ++steps;
    const double change = relative_change();
    estimate = change;
    if (!(change > 4 * eps) || change <= refinement.target_error || change > 0.5 * previous) break;
    previous = change;
  }
  if (refinement.residual) compute_defect(rhs_, x_);

  ContactState state;
  state.displacement.resize(n);
  for (int e = 0; e < n; ++e) state.displacement[e] = x_[slot_[e]];
  state.reaction = VectorXd::Zero(m);
  for (int i = 0; i < m; ++i)
    if (in_contact_[i]) state.reaction[i] = x_[slot_[n + ns + i]];
  state.gap = d_.flexibility * state.reaction - d_.coupling * state.displacement + offset_;
  for (int i = 0; i < m; ++i)
    if (in_contact_[i]) state.gap[i] = 0.0;  // exact by construction; the defect measures it
  if (refinement.residual) state.residual = relative_defect();
  state.error_estimate = steps == 0 ? -1.0 : estimate;
  state.refinement_steps = steps;
  return state;
}

double ActiveSetSystem::data_error(const ContactState& state, const VectorXd& load) const {
  if (!factorised_) throw std::logic_error("ActiveSetSystem::data_error before a successful factorise()");
  const int n = d_.equations, ns = d_.stresses(), m = d_.reactions();
  const Eigen::Index size = full_.rows();
  // The whole unknown vector, stresses m = H^-1 G u included.
  VectorXd x(size), b = VectorXd::Zero(size);
  const VectorXd stresses = (d_.stress_coupling * state.displacement).cwiseQuotient(d_.compliance);
  for (int e = 0; e < n; ++e) {
    x[slot_[e]] = state.displacement[e];
    b[slot_[e]] = load[e];
  }
  for (int k = 0; k < ns; ++k) x[slot_[n + k]] = stresses[k];
  for (int i = 0; i < m; ++i) {
    x[slot_[n + ns + i]] = state.reaction[i];
    if (in_contact_[i] && offset_.size() == m) b[slot_[n + ns + i]] = offset_[i];
  }
  compute_defect(b, x);
  const VectorXd weight = magnitude_;  // D = |A| |x| + |b| over the set
  // Hager's estimate of || P A^-1 D ||_inf = || D A^-T P^T ||_1 for the rows P of one block (the
  // displacements, or the reactions); A is symmetric, so A^-T = A^-1.
  auto block_norm = [&](Block block) {
    std::vector<int> rows;
    for (int s = 0; s < size; ++s)
      if (block_of_slot_[s] == block && in_system(s)) rows.push_back(s);
    const Eigen::Index count = static_cast<Eigen::Index>(rows.size());
    if (count == 0) return 0.0;
    VectorXd v = VectorXd::Constant(count, 1.0 / static_cast<double>(count)), embedded(size);
    double estimate = 0.0;
    for (int iteration = 0; iteration < 3; ++iteration) {
      embedded.setZero();
      for (Eigen::Index k = 0; k < count; ++k) embedded[rows[k]] = v[k];
      solve_in_place(embedded);
      const VectorXd y = weight.cwiseProduct(embedded);  // D A^-1 P^T v
      estimate = y.lpNorm<1>();
      VectorXd back = weight.cwiseProduct(y.unaryExpr([](double value) { return value >= 0 ? 1.0 : -1.0; }));
      solve_in_place(back);  // A^-1 D sign(y)
      VectorXd z(count);
      for (Eigen::Index k = 0; k < count; ++k) z[k] = back[rows[k]];
      Eigen::Index j = 0;
      if (z.cwiseAbs().maxCoeff(&j) <= z.dot(v)) break;
      v.setZero();
      v[j] = 1.0;
    }
    return estimate;
  };
  const double u_scale = state.displacement.lpNorm<Eigen::Infinity>();
  const double r_scale = state.reaction.lpNorm<Eigen::Infinity>();
  double error = 0.0;
  if (u_scale > 0) error = std::max(error, eps * block_norm(displacement) / u_scale);
  if (r_scale > 0) error = std::max(error, eps * block_norm(reaction) / r_scale);
  return error;
}

}  // namespace liftoff::contact
