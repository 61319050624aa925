#include "ritz/ritz_model.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "core/error.hpp"
#include "ritz/von_karman_membrane.hpp"

namespace liftoff::ritz {

using Eigen::MatrixXd;
using Eigen::VectorXd;

void Topology::validate() const {
  if (limits < 0) throw std::invalid_argument(fmt::format("Topology: limits must be >= 0, got {}", limits));
}

std::string to_string(const Topology& topology) {
  std::string text;
  bool contact = topology.first_in_contact;
  for (int p = 0; p <= topology.limits; ++p, contact = !contact)
    text += (p ? " | " : "") + std::string(contact ? "contact" : "lift-off");
  return fmt::format("{} ({} limit{})", text, topology.limits, topology.limits == 1 ? "" : "s");
}

namespace {

void require_finite(double value, const char* what) {
  if (!std::isfinite(value)) throw std::invalid_argument(fmt::format("RitzModel: {} is not finite", what));
}

// Integral over [a, b] of every pairwise product of the functions f (symmetric).
MatrixXd gram(const std::vector<TrigPolynomial>& f, double a, double b) {
  MatrixXd g = MatrixXd::Zero(f.size(), f.size());
  ProductTable(f).add_integrals(a, b, 1.0, g);
  return g.selfadjointView<Eigen::Upper>();
}

}  // namespace

std::optional<Unsupported> unsupported_input(const model::MemberModel& model, const std::string& gap_key,
                                             const std::string& tension_key) {
  const bool arch = model.kind == model::StructureKind::arch;
  if (!model.point_supports.empty()) return Unsupported{"supports.interior", "takes no interior point supports"};
  if (model.has_springs() || model.has_settlements())
    return Unsupported{"supports",
                       "takes rigid supports without settlement only, not springs (kind = \"spring\") or a settlement"};
  if (model.foundation_pieces.size() > 1 || !model.k_is_constant())  // none: built in code, one piece
    return Unsupported{"foundation.segments", "takes one foundation piece of constant modulus"};
  if (model.has_ground_gap()) return Unsupported{gap_key, "takes the ground at the member's axis (no ground gap)"};
  if (model.has_tension_k())
    return Unsupported{tension_key, "takes a tensionless or bilateral foundation (no modulus in tension)"};
  if (arch && model.foundation_outside)
    return Unsupported{"foundation.side", "takes the foundation inside the arch only, not side = \"outside\""};
  if (arch && model.theory == model::Theory::von_karman)
    return Unsupported{"structure.theory",
                       "takes von Karman kinematics (theory = \"von_karman\") on beams only, not on arches"};
  if (arch && model.has_axial_force())
    return Unsupported{"loads",
                       "takes an axial force (kind = \"axial\" or \"temperature\") on beams only, not on arches"};
  for (const model::MemberLoad& load : model.loads) {
    if (load.kind == model::LoadKind::curvature)
      return Unsupported{"loads",
                         "has no imposed curvature (kind = \"curvature\", an initial strain) in its energy in this "
                         "version"};
    if (arch && load.kind == model::LoadKind::sine)
      return Unsupported{"loads", "takes a sine load (kind = \"sine\") on beams only, not on arches"};
    if (arch && load.kind != model::LoadKind::moment && load.direction != model::LoadDirection::radial)
      return Unsupported{"loads", fmt::format("takes radial arch loads only, not direction = \"{}\"",
                                              model::to_string(load.direction))};
  }
  return std::nullopt;
}

RitzModel::RitzModel(const model::MemberModel& model, int modes, Topology topology, Enrichment enrichment)
    : arch_(model.kind == model::StructureKind::arch),
      tensionless_(model.tensionless),
      modes_(modes),
      topology_(topology) {
  if (const std::optional<Unsupported> unsupported = unsupported_input(model))
    throw std::invalid_argument(unsupported->message());
  topology_.validate();
  for (double value :
       {model.s_begin, model.s_end, model.membrane_stiffness, model.k, model.foundation_begin, model.foundation_end})
    require_finite(value, "a member model value");
  for (const model::MemberLoad& load : model.loads) {
    require_finite(load.value, "a load value");
    require_finite(load.slope, "a load slope");
    require_finite(load.at, "a load position");
    require_finite(load.from, "a load extent");
    require_finite(load.to, "a load extent");
  }
  if (!model.tensionless && (topology.limits != 0 || !topology.first_in_contact))
    throw std::invalid_argument(
        fmt::format("RitzModel: a bilateral foundation is in contact everywhere; expected the topology "
                    "{{first_in_contact = true, limits = 0}}, got {}",
                    to_string(topology)));
  if (!(model.foundation_begin <= model.foundation_end) ||
      (topology.limits > 0 && model.foundation_begin == model.foundation_end))
    throw std::invalid_argument(
        fmt::format("RitzModel: the foundation's extent [{}, {}] has no room for contact limits",
                    model.foundation_begin, model.foundation_end));
  k_ = model.k;
  foundation_begin_ = model.foundation_begin;
  foundation_end_ = model.foundation_end;

  basis_ = make_basis(model, modes, enrichment);  // checks modes >= 1
  modes_ = static_cast<int>(basis_.w.size() + basis_.kinked_w.size());
  amplitudes_ = arch_ ? 2 * modes_ : modes_;
  for (const KinkedFunction& e : basis_.kinked_w) breakpoints_.push_back(e.kink);
  std::sort(breakpoints_.begin(), breakpoints_.end());
  const int regions = static_cast<int>(breakpoints_.size()) + 1;
  w_derivatives_.assign(regions, std::vector<std::vector<TrigPolynomial>>(4));
  u_derivatives_.resize(arch_ ? 4 : 0);
  for (int r = 0; r < regions; ++r) {
    // The w functions as they are in region r: the smooth ones, then each kinked one's half.
    std::vector<TrigPolynomial> w = basis_.w;
    for (const KinkedFunction& e : basis_.kinked_w) {
      const bool right = r > 0 && breakpoints_[r - 1] >= e.kink;
      w.push_back(e.halves[right ? 1 : 0]);
    }
    for (int order = 0; order < 4; ++order)
      for (const TrigPolynomial& phi : w) w_derivatives_[r][order].push_back(phi.derivative(order));
    w_products_.emplace_back(w);
    w_terms_.emplace_back();
    w_term_function_.emplace_back();
    for (int i = 0; i < modes_; ++i)
      for (const TrigTerm& t : w[i].terms()) w_terms_[r].push_back(t), w_term_function_[r].push_back(i);
    w_slope_terms_.emplace_back();
    w_slope_term_function_.emplace_back();
    for (int i = 0; i < modes_; ++i)
      for (const TrigTerm& t : w_derivatives_[r][1][i].terms())
        w_slope_terms_[r].push_back(t), w_slope_term_function_[r].push_back(i);
  }
  for (int order = 0; arch_ && order < 4; ++order)
    for (const TrigPolynomial& psi : basis_.u) u_derivatives_[order].push_back(psi.derivative(order));

  // Stiffness: beam  int phi_i'' phi_j'';  arch  int EA eps_a eps_b + chi_a chi_b with the
  // strains of each amplitude: W_j: eps = -phi_j, chi = phi_j''; U_i: eps = chi = psi_i'.
  const double a = model.s_begin, b = model.s_end;
  if (!arch_) {
    stiffness_ = MatrixXd::Zero(modes_, modes_);
    for (int r = 0; r < regions; ++r) {
      const double lo = r == 0 ? a : std::max(a, breakpoints_[r - 1]);
      const double hi = r == regions - 1 ? b : std::min(b, breakpoints_[r]);
      if (hi > lo) stiffness_ += gram(w_derivatives_[r][2], lo, hi);
    }
  } else {
    const auto& curvature = w_derivatives_[0][2];
    std::vector<TrigPolynomial> membrane, bending;
    for (int j = 0; j < modes_; ++j) membrane.push_back(-basis_.w[j]), bending.push_back(curvature[j]);
    for (int i = 0; i < modes_; ++i) membrane.push_back(u_derivatives_[1][i]), bending.push_back(u_derivatives_[1][i]);
    stiffness_ = model.membrane_stiffness * gram(membrane, a, b) + gram(bending, a, b);
  }
  stiffness_ = 0.5 * (stiffness_ + stiffness_.transpose());  // exactly symmetric

  // Second-order theory (beams): K_g = int phi_i' phi_j' over the member, and the imperfection's
  // load per unit N, int w0' phi_i' = sum over the table's pieces of slope (phi_i(hi) - phi_i(lo))
  // (w0' is constant on each piece and 0 beyond the table).
  geometric_stiffness_ = MatrixXd::Zero(modes_, modes_);
  imperfection_load_ = VectorXd::Zero(modes_);
  if (!arch_ && model.has_axial_force()) {
    axial_dead_ = model.axial_dead;
    axial_live_ = model.axial_live;
    require_finite(axial_dead_, "the axial force");
    require_finite(axial_live_, "the axial force");
    for (int r = 0; r < regions; ++r) {
      const double lo = r == 0 ? a : std::max(a, breakpoints_[r - 1]);
      const double hi = r == regions - 1 ? b : std::min(b, breakpoints_[r]);
      if (hi > lo) geometric_stiffness_ += gram(w_derivatives_[r][1], lo, hi);
    }
    geometric_stiffness_ = 0.5 * (geometric_stiffness_ + geometric_stiffness_.transpose());
    const std::vector<double>& at = model.initial_shape_at;
    const std::vector<double>& w0 = model.initial_shape_value;
    for (std::size_t i = 0; i + 1 < at.size() && i + 1 < w0.size(); ++i) {
      require_finite(at[i + 1], "an initial shape position");
      require_finite(w0[i + 1], "an initial shape value");
      const double lo = std::max(at[i], a), hi = std::min(at[i + 1], b);
      if (!(hi > lo)) continue;
      const double slope = (w0[i + 1] - w0[i]) / (at[i + 1] - at[i]);
      imperfection_load_ += slope * (phi_at(hi, 0) - phi_at(lo, 0));
    }
  }

  // Loads: the work of each load is F . A.
  dead_load_ = VectorXd::Zero(amplitudes_);
  live_load_ = VectorXd::Zero(amplitudes_);
  double moment_sum[2] = {0.0, 0.0}, moment_size[2] = {0.0, 0.0};
  for (const model::MemberLoad& load : model.loads) {
    const bool dead = load.load_case == model::LoadCase::dead;
    VectorXd& target = dead ? dead_load_ : live_load_;
    switch (load.kind) {
      case model::LoadKind::force:
        target.head(modes_) += load.value * phi_at(load.at, 0);
        break;
      case model::LoadKind::moment:
        // Work of a counterclockwise moment: M * rotation, rotation = -w' (beam), -(u + w') (arch).
        target.head(modes_) -= load.value * phi_at(load.at, 1);
        if (arch_)
          for (int i = 0; i < modes_; ++i) target[modes_ + i] -= load.value * basis_.u[i](load.at);
        moment_sum[dead] += load.value;
        moment_size[dead] += std::abs(load.value);
        break;
      case model::LoadKind::uniform: {
        // q(s) = q0 + q1 s, linear on [from, to]: q0 int phi + q1 int s phi, both exact.
        const double q1 = load.slope, q0 = load.value - q1 * load.from;
        const TrigPolynomial s_times = TrigPolynomial::monomial(1);
        for (int j = 0; j < modes_; ++j)
          target[j] += split_integral(load.from, load.to, [&](int r, double lo, double hi) {
            const TrigPolynomial& phi = w_derivatives_[r][0][j];
            return q0 * phi.integral(lo, hi) + (q1 != 0.0 ? q1 * (s_times * phi).integral(lo, hi) : 0.0);
          });
        break;
      }
      case model::LoadKind::sine: {
        // q = value sin(k (s - from)) on [from, to]: a trigonometric term, so int q phi is exact.
        const TrigPolynomial q = TrigPolynomial::sine(load.wavenumber(), -load.wavenumber() * load.from, load.value);
        for (int j = 0; j < modes_; ++j)
          target[j] += split_integral(load.from, load.to, [&](int r, double lo, double hi) {
            return (q * w_derivatives_[r][0][j]).integral(lo, hi);
          });
        break;
      }
      default:  // curvature: refused above
        break;
    }
  }
  const bool u_free_at_both_ends =
      arch_ && model.left != model::EndSupport::pinned && model.left != model::EndSupport::clamped &&
      model.right != model::EndSupport::pinned && model.right != model::EndSupport::clamped;
  for (int c = 0; c < 2; ++c)
    if (u_free_at_both_ends && std::abs(moment_sum[c]) > 1e-12 * moment_size[c])
      throw MechanismError(
          "key 'supports': the supports leave the arch free to rotate rigidly about its centre of curvature, which "
          "the foundation cannot resist, and the moments drive that rotation, so no equilibrium exists; expected "
          "supports that prevent it (e.g. a pinned end)");

  // Von Karman beams: the membrane term, when both ends hold the member axially (else N = 0).
  if (!arch_ && model.theory == model::Theory::von_karman && model.left_axially_restrained &&
      model.right_axially_restrained) {
    MembraneOptions options;
    options.membrane_stiffness = model.membrane_stiffness;
    options.ends = AxialEnds::restrained;
    // A half sine over the whole member is kept exact; anything else is the table (piecewise linear).
    if (const auto& sine = model.initial_sine) {
      const double tolerance = 1e-12 * model.length();
      if (std::abs(sine->from - a) <= tolerance && std::abs(sine->from + sine->length - b) <= tolerance &&
          sine->length > 0.0)
        options.initial_shape = TrigPolynomial::sine(std::numbers::pi / sine->length,
                                                     -std::numbers::pi * sine->from / sine->length, sine->amplitude);
    }
    membrane_ = std::make_shared<const VonKarmanMembrane>(model, *this, std::move(options));
  }
}

double RitzModel::membrane_force(const VectorXd& x) const {
  check_size(x);
  return membrane_ ? membrane_->normal_force(x) : 0.0;
}

void RitzModel::check_size(const VectorXd& x) const {
  if (x.size() != unknowns())
    throw std::invalid_argument(fmt::format("RitzModel: x has {} entries, expected {} ({} amplitudes, {} limits)",
                                            x.size(), unknowns(), amplitudes_, limits()));
}

double RitzModel::piece_sign(int limit) const {
  // Limit m ends piece m and starts piece m + 1; piece p is in contact iff first_in_contact
  // for even p.
  const bool ends_contact = topology_.first_in_contact == (limit % 2 == 0);
  return ends_contact ? 1.0 : -1.0;
}

int RitzModel::region_of(double s) const {
  return static_cast<int>(std::upper_bound(breakpoints_.begin(), breakpoints_.end(), s) - breakpoints_.begin());
}

template <class Integrate>
double RitzModel::split_integral(double a, double b, const Integrate& integrate) const {
  if (b < a) return -split_integral(b, a, integrate);
  double sum = 0.0;
  const int regions = static_cast<int>(breakpoints_.size()) + 1;
  for (int r = region_of(a); r < regions; ++r) {
    const double lo = r == 0 ? a : std::max(a, breakpoints_[r - 1]);
    const double hi = r == regions - 1 ? b : std::min(b, breakpoints_[r]);
    if (hi > lo) sum += integrate(r, lo, hi);
    if (r < regions - 1 && breakpoints_[r] >= b) break;
  }
  return sum;
}

VectorXd RitzModel::phi_at(double s, int derivative) const {
  VectorXd values(modes_);
  const auto& functions = w_derivatives_[region_of(s)][derivative];
  for (int i = 0; i < modes_; ++i) values[i] = functions[i](s);
  return values;
}

std::vector<ContactRegion> RitzModel::pieces(const VectorXd& x) const {
  check_size(x);
  std::vector<ContactRegion> out;
  double begin = foundation_begin_;
  bool contact = topology_.first_in_contact;
  for (int m = 0; m <= limits(); ++m, contact = !contact) {
    const double end = m < limits() ? x[limit_offset() + m] : foundation_end_;
    out.push_back({begin, end, contact});
    begin = end;
  }
  return out;
}

std::vector<ContactRegion> RitzModel::contact_pieces(const VectorXd& x) const {
  std::vector<ContactRegion> all = pieces(x);
  std::erase_if(all, [](const ContactRegion& p) { return !p.in_contact; });
  return all;
}

bool RitzModel::admissible(const VectorXd& x) const {
  check_size(x);
  if (!x.allFinite()) return false;
  double previous = foundation_begin_;
  for (int m = 0; m < limits(); ++m) {
    const double t = x[limit_offset() + m];
    if (!(t > previous)) return false;
    previous = t;
  }
  return limits() == 0 || previous < foundation_end_;
}

MatrixXd RitzModel::contact_gram(const VectorXd& x) const {
  MatrixXd g = MatrixXd::Zero(modes_, modes_);
  for (const ContactRegion& piece : contact_pieces(x)) {
    split_integral(piece.begin, piece.end, [&](int r, double lo, double hi) {
      // Called with lo < hi; the sign of a reversed piece is applied below through `sign`.
      w_products_[r].add_integrals(lo, hi, piece.end < piece.begin ? -1.0 : 1.0, g);
      return 0.0;
    });
  }
  return g.selfadjointView<Eigen::Upper>();
}

double RitzModel::energy(const VectorXd& x, double lambda) const {
  check_size(x);
  const VectorXd amplitudes = x.head(amplitudes_);
  const VectorXd deflection = x.head(modes_);
  const double n = axial_force(lambda);
  double axial = 0.0;
  if (n != 0.0)
    axial = -0.5 * n * deflection.dot(geometric_stiffness_ * deflection) - n * imperfection_load_.dot(deflection);
  if (membrane_) axial += membrane_->energy(x);
  return 0.5 * amplitudes.dot(stiffness_ * amplitudes) + 0.5 * k_ * deflection.dot(contact_gram(x) * deflection) -
         load(lambda).dot(amplitudes) + axial;
}

VectorXd RitzModel::gradient(const VectorXd& x, double lambda) const {
  VectorXd g;
  residual(x, lambda, g);
  for (int m = 0; m < limits(); ++m) {
    const double wt = g[limit_offset() + m];  // the residual's limit row is w(t_m)
    g[limit_offset() + m] = piece_sign(m) * 0.5 * k_ * wt * wt;
  }
  return g;
}

MatrixXd RitzModel::hessian(const VectorXd& x, double lambda) const {
  MatrixXd h;
  jacobian(x, lambda, h);
  // The Jacobian's limit rows are (phi(t_m), w'(t_m)); the Hessian's are its columns' transpose
  // (sigma_m k w phi) and sigma_m k w w' on the diagonal.
  for (int m = 0; m < limits(); ++m) {
    const int row = limit_offset() + m;
    const double t = x[row];
    const double wt = w(x, t), slope = w(x, t, 1);
    h.row(row).setZero();
    h.block(row, 0, 1, modes_) = h.block(0, row, modes_, 1).transpose();
    h(row, row) = piece_sign(m) * k_ * wt * slope;
  }
  return h;
}

void RitzModel::residual(const VectorXd& x, double lambda, VectorXd& f) const {
  check_size(x);
  f.resize(unknowns());
  const VectorXd amplitudes = x.head(amplitudes_);
  f.head(amplitudes_) = stiffness_ * amplitudes - load(lambda);
  f.head(modes_) += k_ * (contact_gram(x) * x.head(modes_));
  if (const double n = axial_force(lambda); n != 0.0)
    f.head(modes_) -= n * (geometric_stiffness_ * x.head(modes_) + imperfection_load_);
  if (membrane_) membrane_->add_to_residual(x, f);
  for (int m = 0; m < limits(); ++m) f[limit_offset() + m] = w(x, x[limit_offset() + m]);
}

void RitzModel::jacobian(const VectorXd& x, double lambda, MatrixXd& J) const {
  check_size(x);
  J.setZero(unknowns(), unknowns());
  J.topLeftCorner(amplitudes_, amplitudes_) = stiffness_;
  J.topLeftCorner(modes_, modes_) += k_ * contact_gram(x);
  // Through N only: without an axial force the Jacobian does not depend on the load factor.
  if (const double n = axial_force(lambda); n != 0.0) J.topLeftCorner(modes_, modes_) -= n * geometric_stiffness_;
  if (membrane_) membrane_->add_to_jacobian(x, J);
  for (int m = 0; m < limits(); ++m) {
    const int row = limit_offset() + m;
    const double t = x[row];
    const VectorXd phi = phi_at(t, 0);
    const double wt = phi.dot(x.head(modes_));
    // d/dt_m of k int_contact phi w = sigma_m k phi(t_m) w(t_m)  (amplitude rows)
    J.block(0, row, modes_, 1) = piece_sign(m) * k_ * wt * phi;
    // d w(t_m) = phi(t_m) . dW + w'(t_m) dt_m  (limit rows)
    J.block(row, 0, 1, modes_) = phi.transpose();
    J(row, row) = w(x, t, 1);
  }
}

VectorXd RitzModel::residual_lambda_derivative(const VectorXd& x) const {
  check_size(x);
  VectorXd d = VectorXd::Zero(unknowns());
  d.head(amplitudes_) = -live_load_;
  if (axial_live_ != 0.0) d.head(modes_) -= axial_live_ * (geometric_stiffness_ * x.head(modes_) + imperfection_load_);
  return d;
}

MatrixXd RitzModel::reduced_hessian(const VectorXd& x, double lambda) const {
  check_size(x);
  MatrixXd h = stiffness_;
  h.topLeftCorner(modes_, modes_) += k_ * contact_gram(x);
  if (const double n = axial_force(lambda); n != 0.0) h.topLeftCorner(modes_, modes_) -= n * geometric_stiffness_;
  if (membrane_) h.topLeftCorner(modes_, modes_) += membrane_->amplitude_hessian(x);
  return h;
}

double RitzModel::stability_margin(const VectorXd& x, double lambda) const {
  const MatrixXd h = reduced_hessian(x, lambda);
  // Scaled by the bending stiffness's diagonal (positive, growing like j^4), so that the margin
  // compares with 1 whatever the mode numbers.
  VectorXd scale = stiffness_.diagonal();
  for (Eigen::Index i = 0; i < scale.size(); ++i) scale[i] = scale[i] > 0.0 ? 1.0 / std::sqrt(scale[i]) : 1.0;
  const MatrixXd scaled = scale.asDiagonal() * h * scale.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<MatrixXd> eigen(scaled, Eigen::EigenvaluesOnly);
  if (eigen.info() != Eigen::Success) return std::numeric_limits<double>::quiet_NaN();
  return eigen.eigenvalues().minCoeff();
}

std::optional<VectorXd> RitzModel::minimiser_for_limits(const VectorXd& limits_in, double lambda) const {
  if (limits_in.size() != limits())
    throw std::invalid_argument(fmt::format("RitzModel: {} limits given, expected {}", limits_in.size(), limits()));
  VectorXd x = VectorXd::Zero(unknowns());
  x.tail(limits()) = limits_in;
  const MatrixXd h = reduced_hessian(x, lambda);
  // Scale to unit diagonal first: the bending stiffness of mode j grows like j^4, so unscaled
  // pivots span many decades for a well-posed problem. After scaling, a rigid motion nothing
  // resists shows as a pivot at round-off level. (The diagonal without the axial force: with it
  // the matrix may be indefinite, an unstable state that solve_ritz refuses once it is found.)
  VectorXd diagonal = stiffness_.diagonal();
  diagonal.head(modes_) += k_ * contact_gram(x).diagonal();
  if (!(diagonal.minCoeff() > 0.0)) return std::nullopt;
  const VectorXd scale = diagonal.cwiseSqrt().cwiseInverse();
  const Eigen::LDLT<MatrixXd> ldlt(scale.asDiagonal() * h * scale.asDiagonal());
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().cwiseAbs().minCoeff() > 1e-12)) return std::nullopt;
  VectorXd rhs = load(lambda);
  rhs.head(modes_) += axial_force(lambda) * imperfection_load_;
  x.head(amplitudes_) = scale.asDiagonal() * ldlt.solve(scale.asDiagonal() * rhs);
  if (!x.allFinite()) return std::nullopt;
  return x;
}

double RitzModel::w(const VectorXd& x, double s, int derivative) const {
  check_size(x);
  if (derivative < 0 || derivative > 3)
    throw std::invalid_argument(fmt::format("RitzModel::w: derivative order {} outside 0..3", derivative));
  double sum = 0.0;
  const auto& functions = w_derivatives_[region_of(s)][derivative];
  for (int i = 0; i < modes_; ++i) sum += x[w_offset() + i] * functions[i](s);
  return sum;
}

double RitzModel::u(const VectorXd& x, double s, int derivative) const {
  check_size(x);
  if (!arch_) throw std::invalid_argument("RitzModel::u: a beam has no tangential displacement in this model");
  if (derivative < 0 || derivative > 3)
    throw std::invalid_argument(fmt::format("RitzModel::u: derivative order {} outside 0..3", derivative));
  double sum = 0.0;
  for (int i = 0; i < modes_; ++i) sum += x[u_offset() + i] * u_derivatives_[derivative][i](s);
  return sum;
}

void RitzModel::w_on_grid(const VectorXd& x, double a, double b, int n, std::vector<double>& values,
                          int derivative) const {
  check_size(x);
  if (derivative != 0 && derivative != 1)
    throw std::invalid_argument(fmt::format("RitzModel::w_on_grid: expected derivative 0 or 1, got {}", derivative));
  const auto& all_terms = derivative == 0 ? w_terms_ : w_slope_terms_;
  const auto& term_function = derivative == 0 ? w_term_function_ : w_slope_term_function_;
  values.assign(std::max(n - 1, 0), 0.0);
  const double h = (b - a) / n;
  auto point = [&](int i) { return a + (b - a) * i / n; };
  std::vector<double> factors;
  for (int first = 1; first < n;) {
    // A run of points in one region, where the basis is smooth.
    const int region = region_of(point(first));
    int last = first;
    while (last + 1 < n && region_of(point(last + 1)) == region) ++last;
    const auto& terms = all_terms[region];
    factors.resize(terms.size());
    for (std::size_t t = 0; t < terms.size(); ++t) factors[t] = x[w_offset() + term_function[region][t]];
    add_on_grid(terms.data(), factors.data(), static_cast<int>(terms.size()), point(first), h, last - first + 1,
                values.data() + first - 1);
    first = last + 1;
  }
}

double RitzModel::reaction(const VectorXd& x, double s) const { return reaction(x, s, contact_pieces(x)); }

double RitzModel::reaction(const VectorXd& x, double s, const std::vector<ContactRegion>& pieces) const {
  for (const ContactRegion& piece : pieces)
    if (s >= piece.begin && s <= piece.end) return k_ * w(x, s);
  return 0.0;
}

}  // namespace liftoff::ritz
