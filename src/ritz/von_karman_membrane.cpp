#include "ritz/von_karman_membrane.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

#include "ritz/product_table.hpp"

namespace liftoff::ritz {

using Eigen::MatrixXd;
using Eigen::VectorXd;

void MembraneOptions::validate() const {
  if (!std::isfinite(membrane_stiffness) || membrane_stiffness < 0.0 ||
      (ends == AxialEnds::restrained && membrane_stiffness == 0.0))
    throw std::invalid_argument(fmt::format(
        "MembraneOptions: membrane_stiffness must be finite and > 0 for restrained ends (>= 0 if free), got {}",
        membrane_stiffness));
  if (initial_shape)
    for (const TrigTerm& t : initial_shape->terms())
      if (!std::isfinite(t.coefficient) || !std::isfinite(t.omega))
        throw std::invalid_argument("MembraneOptions: initial_shape has a non-finite term");
}

VonKarmanMembrane::VonKarmanMembrane(const model::MemberModel& member, const RitzModel& ritz, MembraneOptions options)
    : options_(std::move(options)), modes_(ritz.modes()), unknowns_(ritz.unknowns()) {
  options_.validate();
  if (ritz.is_arch() || member.kind != model::StructureKind::beam)
    throw std::invalid_argument("VonKarmanMembrane: beams only (an arch has its own membrane energy)");
  const double a = member.s_begin, b = member.s_end;
  if (!(std::isfinite(a) && std::isfinite(b) && b > a))
    throw std::invalid_argument(fmt::format("VonKarmanMembrane: expected s_begin < s_end, got [{}, {}]", a, b));
  length_ = b - a;

  // The w functions region by region (the basis is smooth between the kinks of the enrichment),
  // in RitzModel's order: the smooth ones, then each kinked one's half on that side.
  const Basis& basis = ritz.basis();
  std::vector<double> kinks;
  for (const KinkedFunction& e : basis.kinked_w) kinks.push_back(e.kink);
  std::sort(kinks.begin(), kinks.end());
  const int regions = static_cast<int>(kinks.size()) + 1;
  if (static_cast<int>(basis.w.size() + basis.kinked_w.size()) != modes_)
    throw std::invalid_argument("VonKarmanMembrane: the Ritz model's basis does not match its modes");

  derivative_gram_ = MatrixXd::Zero(modes_, modes_);
  initial_coupling_ = VectorXd::Zero(modes_);
  for (int r = 0; r < regions; ++r) {
    const double lo = r == 0 ? a : std::max(a, kinks[r - 1]);
    const double hi = r == regions - 1 ? b : std::min(b, kinks[r]);
    if (!(hi > lo)) continue;
    std::vector<TrigPolynomial> slopes;
    for (const TrigPolynomial& phi : basis.w) slopes.push_back(phi.derivative());
    for (const KinkedFunction& e : basis.kinked_w)
      slopes.push_back(e.halves[r > 0 && kinks[r - 1] >= e.kink ? 1 : 0].derivative());
    ProductTable(slopes).add_integrals(lo, hi, 1.0, derivative_gram_);
    if (options_.initial_shape) {
      const TrigPolynomial w0_slope = options_.initial_shape->derivative();
      for (int i = 0; i < modes_; ++i) initial_coupling_[i] += (w0_slope * slopes[i]).integral(lo, hi);
    }
  }
  derivative_gram_ = derivative_gram_.selfadjointView<Eigen::Upper>();

  if (!options_.initial_shape) {
    // w0' is constant on each piece of the table and 0 beyond it: int w0' phi_i' over a piece is
    // slope (phi_i(hi) - phi_i(lo)) (the kinked functions are continuous: either half's value).
    auto phi_at = [&](double s) {
      VectorXd values(modes_);
      const int n = static_cast<int>(basis.w.size());
      for (int i = 0; i < n; ++i) values[i] = basis.w[i](s);
      for (std::size_t j = 0; j < basis.kinked_w.size(); ++j) {
        const KinkedFunction& e = basis.kinked_w[j];
        values[n + static_cast<int>(j)] = e.halves[s >= e.kink ? 1 : 0](s);
      }
      return values;
    };
    const std::vector<double>& at = member.initial_shape_at;
    const std::vector<double>& w0 = member.initial_shape_value;
    for (std::size_t i = 0; i + 1 < at.size() && i + 1 < w0.size(); ++i) {
      if (!std::isfinite(at[i + 1]) || !std::isfinite(w0[i + 1]) || !std::isfinite(at[i]) || !std::isfinite(w0[i]))
        throw std::invalid_argument("VonKarmanMembrane: the initial shape has a non-finite point");
      const double lo = std::max(at[i], a), hi = std::min(at[i + 1], b);
      if (!(hi > lo)) continue;
      const double slope = (w0[i + 1] - w0[i]) / (at[i + 1] - at[i]);
      initial_coupling_ += slope * (phi_at(hi) - phi_at(lo));
    }
  }
}

void VonKarmanMembrane::check_size(const VectorXd& x) const {
  if (x.size() != unknowns_)
    throw std::invalid_argument(fmt::format("VonKarmanMembrane: x has {} entries, expected {}", x.size(), unknowns_));
}

double VonKarmanMembrane::stretch(const VectorXd& x) const {
  check_size(x);
  const auto W = x.head(modes_);
  return initial_coupling_.dot(W) + 0.5 * W.dot(derivative_gram_ * W);
}

double VonKarmanMembrane::normal_force(const VectorXd& x) const {
  const double e = stretch(x);
  return active() ? options_.membrane_stiffness / length_ * e : 0.0;
}

double VonKarmanMembrane::energy(const VectorXd& x) const {
  const double e = stretch(x);
  return active() ? 0.5 * options_.membrane_stiffness / length_ * e * e : 0.0;
}

VectorXd VonKarmanMembrane::gradient(const VectorXd& x) const {
  VectorXd g = VectorXd::Zero(unknowns_);
  add_to_residual(x, g);
  return g;
}

MatrixXd VonKarmanMembrane::amplitude_hessian(const VectorXd& x) const {
  const double n = normal_force(x);
  if (!active()) return MatrixXd::Zero(modes_, modes_);
  const VectorXd b = initial_coupling_ + derivative_gram_ * x.head(modes_);
  const MatrixXd h = options_.membrane_stiffness / length_ * (b * b.transpose()) + n * derivative_gram_;
  return 0.5 * (h + h.transpose());  // exactly symmetric (vectorised and scalar paths round differently)
}

MatrixXd VonKarmanMembrane::hessian(const VectorXd& x) const {
  MatrixXd h = MatrixXd::Zero(unknowns_, unknowns_);
  add_to_jacobian(x, h);
  return h;
}

void VonKarmanMembrane::add_to_residual(const VectorXd& x, VectorXd& f) const {
  const double n = normal_force(x);  // checks the size
  if (f.size() != unknowns_)
    throw std::invalid_argument(fmt::format("VonKarmanMembrane: f has {} entries, expected {}", f.size(), unknowns_));
  if (active()) f.head(modes_) += n * (initial_coupling_ + derivative_gram_ * x.head(modes_));
}

void VonKarmanMembrane::add_to_jacobian(const VectorXd& x, MatrixXd& J) const {
  check_size(x);
  if (J.rows() != unknowns_ || J.cols() != unknowns_)
    throw std::invalid_argument(
        fmt::format("VonKarmanMembrane: J is {} x {}, expected {} x {}", J.rows(), J.cols(), unknowns_, unknowns_));
  if (active()) J.topLeftCorner(modes_, modes_) += amplitude_hessian(x);
}

}  // namespace liftoff::ritz
