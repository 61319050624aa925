// Independent closed-form reference for beams on a (tensionless) Winkler foundation.
// See beam_on_foundation.hpp for the physics, the sign conventions and the numerics.
#include "closed_form/beam_on_foundation.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <memory>
#include <sstream>
#include <utility>

namespace liftoff::closed_form {

namespace detail {

// Builds BeamSolution objects from the internals below.
struct SolutionAccess {
  static BeamSolution make(double length, double ei, double k, double beta, double lambda, std::vector<double> x,
                           std::vector<Segment> segs, std::vector<double> coef, double condition, double residual) {
    BeamSolution s;
    s.length_ = length;
    s.ei_ = ei;
    s.k_ = k;
    s.beta_ = beta;
    s.lambda_ = lambda;
    s.breakpoints_ = std::move(x);
    s.segments_ = std::move(segs);
    s.coefficients_ = std::move(coef);
    s.condition_ = condition;
    s.residual_ = residual;
    return s;
  }
  static const std::vector<Segment>& segments(const BeamSolution& s) { return s.segments_; }
  static double lambda(const BeamSolution& s) { return s.lambda_; }
  static const std::vector<double>& coefficients(const BeamSolution& s) { return s.coefficients_; }
};

}  // namespace detail

namespace {

using detail::Segment;
using Eigen::MatrixXd;
using Eigen::VectorXd;

constexpr double kMergeTolerance = 1e-14;  // relative to L: coincident breakpoints
constexpr double kLoadTolerance = 1e-12;   // relative to L: load matches a breakpoint

// phi_k(u) = sum_n (-4 kappa)^n u^(4n+k) / (4n+k)!, k = 0..5.
// d/du phi_k = phi_{k-1} (k >= 1), d/du phi_0 = -4 kappa phi_3; phi_0'''' + 4 kappa phi_0 = 0;
// phi_4'''' + 4 kappa phi_4 = 1 and phi_5'''' + 4 kappa phi_5 = u (the particular solutions).
constexpr int kSeries = 6;
void series(double u, double kappa, double out[kSeries]) {
  double term[kSeries];
  term[0] = 1.0;
  for (int k = 1; k < kSeries; ++k) term[k] = term[k - 1] * u / k;
  for (int k = 0; k < kSeries; ++k) out[k] = 0.0;
  const double u4 = u * u * u * u;
  for (int n = 0; n < 60; ++n) {
    double biggest = 0.0, total = 0.0;
    for (int k = 0; k < kSeries; ++k) {
      out[k] += term[k];
      biggest = std::max(biggest, std::abs(term[k]));
      total = std::max(total, std::abs(out[k]));
    }
    if (kappa == 0.0 || u == 0.0) break;
    if (n > 0 && biggest <= 1e-19 * std::max(total, 1e-300)) break;
    for (int k = 0; k < kSeries; ++k) {
      const double m = 4.0 * n + k;
      term[k] *= -4.0 * kappa * u4 / ((m + 1) * (m + 2) * (m + 3) * (m + 4));
    }
  }
}

// d-th u-derivative of phi_k.
double dphi(const double phi[kSeries], int k, int d, double kappa) {
  double factor = 1.0;
  int idx = k;
  for (int i = 0; i < d; ++i) {
    if (idx == 0) {
      factor *= -4.0 * kappa;
      idx = 3;
    } else {
      --idx;
    }
  }
  return factor * phi[idx];
}

struct Params {
  double L = 1.0, EI = 1.0, K = 0.0, beta = 0.0, lambda = 1.0;
  double P = 0.0;  // axial force, compression positive
};

// Beam-column series (basis 2): the u-derivatives d = 0..3 of the six functions with Taylor
// coefficients c_{m+4} = -axial c_{m+2} - kk c_m, started from c_j = 1 (j = 0..5, the others 0):
// out[d][j] = sum_m c^{(j)}_{m+d} u^m / m!. phi_0..3 are the homogeneous basis, phi_4 and phi_5
// solve phi'''' + axial phi'' + kk phi = 1 and = u. With |axial|, kk <= 1 and 0 <= u <= 1 the
// terms fall like 1.3^m / m!: 40 of them reach round-off.
void column_series(double u, double axial, double kk, double out[4][6]) {
  constexpr int kTerms = 44;
  for (int j = 0; j < 6; ++j) {
    double c[kTerms + 4] = {};
    if (j < 4) {
      c[j] = 1.0;
    }
    for (int m = 0; m + 4 < kTerms + 4; ++m) c[m + 4] = -axial * c[m + 2] - kk * c[m] + (m == j - 4 ? 1.0 : 0.0);
    for (int d = 0; d < 4; ++d) {
      double sum = 0.0, power = 1.0;  // u^m / m!
      for (int m = 0; m < kTerms; ++m) {
        sum += c[m + d] * power;
        power *= u / (m + 1);
      }
      out[d][j] = sum;
    }
  }
}

// B[d][j] = lambda^d d^d phi_j/dx^d (x), P[d] = lambda^d d^d w_p/dx^d (x), d = 0..3.
void evaluate_basis(const Params& p, const Segment& s, double x, double B[4][4], double P[4]) {
  if (s.basis == 2) {
    double f[4][6];
    column_series((x - s.a) / s.ell, s.axial, s.kappa, f);
    const double r = p.lambda / s.ell, ell4 = s.ell * s.ell * s.ell * s.ell;
    const double p4 = s.q0 * ell4 / p.EI, p5 = s.q1 * ell4 * s.ell / p.EI;
    double scale = 1.0;
    for (int d = 0; d < 4; ++d) {
      for (int j = 0; j < 4; ++j) B[d][j] = scale * f[d][j];
      P[d] = scale * (p4 * f[d][4] + p5 * f[d][5]);
      scale *= r;
    }
    return;
  }
  if (s.basis == 1) {
    using C = std::complex<double>;
    const double bl = s.beta * p.lambda;
    const double z1 = s.beta * (x - s.a);  // >= 0
    const double z2 = s.beta * (x - s.b);  // <= 0
    const C e1 = std::exp(C(-z1, z1));     // e^{(-1+i) z1}
    const C e2 = std::exp(C(z2, z2));      // e^{(1+i) z2}
    C f1 = e1, f2 = e2;
    double scale = 1.0;
    for (int d = 0; d < 4; ++d) {
      B[d][0] = scale * f1.real();
      B[d][1] = scale * f1.imag();
      B[d][2] = scale * f2.real();
      B[d][3] = scale * f2.imag();
      f1 *= C(-1.0, 1.0);
      f2 *= C(1.0, 1.0);
      scale *= bl;
      P[d] = 0.0;
    }
    // Linear load (q + k g): w_p = (q0 + q1 (x - a)) / k.
    P[0] = (s.q0 + s.q1 * (x - s.a)) / s.k;
    P[1] = p.lambda * s.q1 / s.k;
    return;
  }
  const double u = (x - s.a) / s.ell;
  double phi[kSeries];
  series(u, s.kappa, phi);
  const double r = p.lambda / s.ell;
  double scale = 1.0;
  const double ell4 = s.ell * s.ell * s.ell * s.ell;
  const double p4 = s.q0 * ell4 / p.EI, p5 = s.q1 * ell4 * s.ell / p.EI;
  for (int d = 0; d < 4; ++d) {
    for (int j = 0; j < 4; ++j) B[d][j] = scale * dphi(phi, j, d, s.kappa);
    P[d] = scale * (p4 * dphi(phi, 4, d, s.kappa) + p5 * dphi(phi, 5, d, s.kappa));
    scale *= r;
  }
}

Params params_of(const BeamProblem& pr) {
  Params p;
  p.L = pr.length;
  p.EI = pr.bending_stiffness;
  p.beta = pr.beta();
  p.K = pr.foundation_segments.empty() ? pr.foundation_modulus : 0.0;  // K_ref, as in beta()
  for (const auto& f : pr.foundation_segments) p.K = std::max(p.K, f.modulus);
  p.lambda = (p.K > 0.0) ? std::min(p.L, 1.0 / p.beta) : p.L;
  p.P = pr.axial_force;
  return p;
}

void validate(const BeamProblem& pr) {
  if (!(pr.length > 0.0) || !std::isfinite(pr.length))
    throw std::invalid_argument("closed_form: length must be positive");
  if (!(pr.bending_stiffness > 0.0) || !std::isfinite(pr.bending_stiffness))
    throw std::invalid_argument("closed_form: bending stiffness must be positive");
  if (!(pr.foundation_modulus >= 0.0) || !std::isfinite(pr.foundation_modulus))
    throw std::invalid_argument("closed_form: foundation modulus must be >= 0");
  const double L = pr.length, tol = kLoadTolerance * L;
  auto inside = [&](double x) { return std::isfinite(x) && x >= -tol && x <= L + tol; };
  for (const auto& f : pr.forces)
    if (!inside(f.at)) throw std::invalid_argument("closed_form: force outside the beam");
  for (const auto& m : pr.moments)
    if (!inside(m.at)) throw std::invalid_argument("closed_form: moment outside the beam");
  for (const auto& u : pr.uniform_loads)
    if (!(u.from <= u.to) || !std::isfinite(u.from) || !std::isfinite(u.to))
      throw std::invalid_argument("closed_form: uniform load with from > to");
  for (const auto& d : pr.distributed_loads) {
    if (!(d.from < d.to) || !std::isfinite(d.from) || !std::isfinite(d.to))
      throw std::invalid_argument("closed_form: distributed load needs from < to");
    if (!std::isfinite(d.start_value) || !std::isfinite(d.end_value))
      throw std::invalid_argument("closed_form: distributed load value not finite");
  }
  std::vector<FoundationSegment> pieces = pr.foundation_segments;
  std::sort(pieces.begin(), pieces.end(), [](const auto& a, const auto& b) { return a.from < b.from; });
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    const auto& f = pieces[i];
    if (!inside(f.from) || !inside(f.to) || !(f.from < f.to))
      throw std::invalid_argument("closed_form: foundation segment outside the beam or with from >= to");
    if (!(f.modulus >= 0.0) || !std::isfinite(f.modulus))
      throw std::invalid_argument("closed_form: foundation segment modulus must be >= 0");
    if (i > 0 && f.from < pieces[i - 1].to - tol)
      throw std::invalid_argument("closed_form: overlapping foundation segments");
  }
  if (pr.gap.at.size() != pr.gap.value.size())
    throw std::invalid_argument("closed_form: gap table needs as many values as positions");
  for (std::size_t i = 0; i < pr.gap.at.size(); ++i) {
    if (!std::isfinite(pr.gap.at[i]) || !std::isfinite(pr.gap.value[i]))
      throw std::invalid_argument("closed_form: gap table entry not finite");
    if (i > 0 && pr.gap.at[i] < pr.gap.at[i - 1])
      throw std::invalid_argument("closed_form: gap positions must not decrease");
    if (i > 1 && pr.gap.at[i] == pr.gap.at[i - 2])
      throw std::invalid_argument("closed_form: at most two gap values at one position");
  }
  if (!(pr.tension_modulus >= 0.0) || !std::isfinite(pr.tension_modulus))
    throw std::invalid_argument("closed_form: tension modulus must be >= 0");
  if (!std::isfinite(pr.axial_force)) throw std::invalid_argument("closed_form: axial force not finite");
}

// Value and slope of the gap on the open interval (a, b) free of table positions: g = g0 + g1 (x - a).
void gap_on(const GapProfile& gp, double a, double b, double& g0, double& g1) {
  g0 = g1 = 0.0;
  const std::size_t n = gp.at.size();
  if (n == 0) return;
  const double mid = 0.5 * (a + b);
  if (mid <= gp.at.front()) {
    g0 = gp.value.front();
    return;
  }
  if (mid >= gp.at.back()) {
    g0 = gp.value.back();
    return;
  }
  std::size_t i = 0;
  while (i + 1 < n && !(mid >= gp.at[i] && mid < gp.at[i + 1])) ++i;
  g1 = (gp.value[i + 1] - gp.value[i]) / (gp.at[i + 1] - gp.at[i]);
  g0 = gp.value[i] + g1 * (a - gp.at[i]);
}

// Sum of the linear loads on (a, b): q = q0 + q1 (x - a).
void load_on(const BeamProblem& pr, double a, double b, double& q0, double& q1) {
  const double mid = 0.5 * (a + b);
  q0 = q1 = 0.0;
  for (const auto& u : pr.uniform_loads)
    if (mid >= u.from && mid <= u.to) q0 += u.value;
  for (const auto& d : pr.distributed_loads)
    if (mid >= d.from && mid <= d.to) {
      const double slope = (d.end_value - d.start_value) / (d.to - d.from);
      q0 += d.start_value + slope * (a - d.from);
      q1 += slope;
    }
}

// Points where the data jumps, so that a contact region may end there with w != g: void edges
// (foundation on one side only) and gap steps.
std::vector<double> jump_points(const BeamProblem& pr) {
  std::vector<double> out;
  const double L = pr.length, tol = kLoadTolerance * L;
  for (const auto& f : pr.foundation_segments)
    for (double e : {f.from, f.to}) {
      if (e <= tol || e >= L - tol) continue;
      const bool left = pr.modulus_at(e - 2 * tol) > 0.0, right = pr.modulus_at(e + 2 * tol) > 0.0;
      if (left != right) out.push_back(e);
    }
  for (std::size_t i = 1; i < pr.gap.at.size(); ++i)
    if (pr.gap.at[i] == pr.gap.at[i - 1] && pr.gap.value[i] != pr.gap.value[i - 1]) out.push_back(pr.gap.at[i]);
  return out;
}

std::vector<double> merge_sorted(std::vector<double> pts, double L) {
  std::sort(pts.begin(), pts.end());
  std::vector<double> out;
  for (double x : pts) {
    x = std::clamp(x, 0.0, L);
    if (out.empty() || x - out.back() > kMergeTolerance * L) out.push_back(x);
  }
  if (out.empty() || out.front() != 0.0) out.insert(out.begin(), 0.0);
  if (out.back() < L - kMergeTolerance * L) out.push_back(L);
  out.back() = L;
  return out;
}

// A model: segments plus loads mapped to breakpoints.
struct Model {
  Params p;
  EndCondition left = EndCondition::free, right = EndCondition::free;
  std::vector<double> x;
  std::vector<Segment> segs;
  std::vector<double> force, moment;  // per breakpoint (0 and L: end loads)
};

Model build_model(const BeamProblem& pr, const std::vector<double>& x, const std::vector<bool>& contact) {
  validate(pr);
  Model m;
  m.p = params_of(pr);
  m.left = pr.left;
  m.right = pr.right;
  const double L = pr.length;
  if (x.size() < 2 || contact.size() != x.size() - 1)
    throw std::invalid_argument("closed_form: need m+1 breakpoints and m contact flags");
  if (std::abs(x.front()) > kMergeTolerance * L || std::abs(x.back() - L) > kMergeTolerance * L)
    throw std::invalid_argument("closed_form: breakpoints must run from 0 to L");
  for (std::size_t i = 1; i < x.size(); ++i)
    if (!(x[i] > x[i - 1])) throw std::invalid_argument("closed_form: breakpoints not increasing");
  m.x = x;
  m.x.front() = 0.0;
  m.x.back() = L;
  std::vector<bool> flags = contact;
  if (pr.axial_force != 0.0) {
    // Beam-column: split every segment into pieces with |P| h^2 / EI <= 1 and k h^4 / EI <= 1.
    std::vector<double> xs = {0.0};
    std::vector<bool> fs;
    for (std::size_t i = 0; i + 1 < m.x.size(); ++i) {
      const double a = m.x[i], b = m.x[i + 1], mid = 0.5 * (a + b);
      const double ground = pr.modulus_at(mid);
      const double k = ground > 0.0 ? (contact[i] ? ground : pr.tension_modulus) : 0.0;
      const double rate = std::max(std::sqrt(std::abs(pr.axial_force) / m.p.EI), std::pow(k / m.p.EI, 0.25));
      const int pieces = std::max(1, static_cast<int>(std::ceil((b - a) * rate)));
      for (int j = 1; j <= pieces; ++j) {
        xs.push_back(j == pieces ? b : a + (b - a) * j / pieces);
        fs.push_back(contact[i]);
      }
    }
    m.x = std::move(xs);
    flags = std::move(fs);
  }
  const std::size_t nb = m.x.size();
  m.force.assign(nb, 0.0);
  m.moment.assign(nb, 0.0);
  auto locate = [&](double at) -> std::size_t {
    std::size_t best = 0;
    double dist = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < nb; ++i)
      if (std::abs(m.x[i] - at) < dist) {
        dist = std::abs(m.x[i] - at);
        best = i;
      }
    if (dist > kLoadTolerance * L) throw std::invalid_argument("closed_form: a load point is not a breakpoint");
    return best;
  };
  for (const auto& f : pr.forces) m.force[locate(f.at)] += f.value;
  for (const auto& mo : pr.moments) m.moment[locate(mo.at)] += mo.value;
  for (const auto& u : pr.uniform_loads) {
    const double a = std::clamp(u.from, 0.0, L), b = std::clamp(u.to, 0.0, L);
    if (b > a) {
      locate(a);
      locate(b);
    }
  }
  const std::size_t ns = nb - 1;
  m.segs.resize(ns);
  for (std::size_t i = 0; i < ns; ++i) {
    Segment& s = m.segs[i];
    s.a = m.x[i];
    s.b = m.x[i + 1];
    s.contact = flags[i];
    const double mid = 0.5 * (s.a + s.b);
    s.ground = pr.modulus_at(mid);
    s.k = s.ground > 0.0 ? (s.contact ? s.ground : pr.tension_modulus) : 0.0;
    s.beta = s.k > 0.0 ? std::pow(s.k / (4.0 * m.p.EI), 0.25) : 0.0;
    gap_on(pr.gap, s.a, s.b, s.g0, s.g1);
    load_on(pr, s.a, s.b, s.q0, s.q1);
    s.q0 += s.k * s.g0;  // EI w'''' + k w = q + k g
    s.q1 += s.k * s.g1;
    const double h = s.b - s.a;
    const bool foundation = s.k > 0.0;
    if (pr.axial_force != 0.0) {
      s.basis = 2;
      s.ell = h;
      s.axial = pr.axial_force * h * h / m.p.EI;
      s.kappa = s.k * h * h * h * h / m.p.EI;
    } else if (foundation && s.beta * h > 2.0) {
      s.basis = 1;
      s.ell = m.p.lambda;
      s.kappa = 1.0;
    } else if (foundation) {
      s.basis = 0;
      s.ell = h <= 2.0 * m.p.lambda ? m.p.lambda : h;  // a soft piece (K_t << K) may be long
      const double bl = s.beta * s.ell;
      s.kappa = bl * bl * bl * bl;
    } else {
      s.basis = 0;
      s.ell = std::max(h, m.p.lambda);
      s.kappa = 0.0;
    }
  }
  return m;
}

MatrixXd assemble_matrix(const Model& m) {
  const int ns = static_cast<int>(m.segs.size());
  const int n = 4 * ns;
  MatrixXd A = MatrixXd::Zero(n, n);
  double B[4][4], P[4];
  int row = 0;
  auto end_rows = [&](EndCondition e, int seg, double x) {
    evaluate_basis(m.p, m.segs[seg], x, B, P);
    int d0 = 0, d1 = 0;
    switch (e) {
      case EndCondition::pinned:
        d0 = 0;
        d1 = 2;
        break;
      case EndCondition::clamped:
        d0 = 0;
        d1 = 1;
        break;
      case EndCondition::free:
        d0 = 2;
        d1 = 3;
        break;
    }
    // A free end's transverse force is EI w''' + P w' (beam-column): lambda^2 P / EI times lambda w'.
    const double axial = (e == EndCondition::free) ? m.p.P * m.p.lambda * m.p.lambda / m.p.EI : 0.0;
    for (int j = 0; j < 4; ++j) {
      A(row, 4 * seg + j) = B[d0][j];
      A(row + 1, 4 * seg + j) = B[d1][j] + axial * B[1][j];
    }
    row += 2;
  };
  end_rows(m.left, 0, 0.0);
  for (int i = 1; i < ns; ++i) {
    double BL[4][4], BR[4][4];
    evaluate_basis(m.p, m.segs[i - 1], m.x[i], BL, P);
    evaluate_basis(m.p, m.segs[i], m.x[i], BR, P);
    for (int d = 0; d < 4; ++d) {
      for (int j = 0; j < 4; ++j) {
        A(row, 4 * i + j) = BR[d][j];
        A(row, 4 * (i - 1) + j) = -BL[d][j];
      }
      ++row;
    }
  }
  end_rows(m.right, ns - 1, m.p.L);
  return A;
}

// Right-hand side. with_particular: include the uniform-load particular solutions; the point
// loads are taken from `force` and `moment` (per breakpoint).
VectorXd assemble_rhs(const Model& m, const std::vector<double>& force, const std::vector<double>& moment,
                      bool with_particular) {
  const int ns = static_cast<int>(m.segs.size());
  VectorXd b = VectorXd::Zero(4 * ns);
  const double lam = m.p.lambda, EI = m.p.EI;
  const double l2 = lam * lam, l3 = l2 * lam;
  const double axial = m.p.P * l2 / EI;  // the free end's P w' term, as in assemble_matrix
  double B[4][4], P[4];
  int row = 0;
  auto particular = [&](int seg, double x, double out[4]) {
    if (with_particular) {
      evaluate_basis(m.p, m.segs[seg], x, B, out);
    } else {
      for (int d = 0; d < 4; ++d) out[d] = 0.0;
    }
  };
  // Left end.
  particular(0, 0.0, P);
  switch (m.left) {
    case EndCondition::pinned:
      b(row) = -P[0];
      b(row + 1) = l2 * moment.front() / EI - P[2];
      break;
    case EndCondition::clamped:
      b(row) = -P[0];
      b(row + 1) = -P[1];
      break;
    case EndCondition::free:
      b(row) = l2 * moment.front() / EI - P[2];
      b(row + 1) = l3 * force.front() / EI - P[3] - axial * P[1];
      break;
  }
  row += 2;
  for (int i = 1; i < ns; ++i) {
    double PL[4], PR[4];
    particular(i - 1, m.x[i], PL);
    particular(i, m.x[i], PR);
    const double jump[4] = {0.0, 0.0, l2 * moment[i] / EI, l3 * force[i] / EI};
    for (int d = 0; d < 4; ++d) b(row++) = jump[d] - PR[d] + PL[d];
  }
  particular(ns - 1, m.p.L, P);
  switch (m.right) {
    case EndCondition::pinned:
      b(row) = -P[0];
      b(row + 1) = -l2 * moment.back() / EI - P[2];
      break;
    case EndCondition::clamped:
      b(row) = -P[0];
      b(row + 1) = -P[1];
      break;
    case EndCondition::free:
      b(row) = -l2 * moment.back() / EI - P[2];
      b(row + 1) = -l3 * force.back() / EI - P[3] - axial * P[1];
      break;
  }
  return b;
}

// Equilibrated FullPivLU factorisation with iterative refinement.
struct Factorization {
  MatrixXd A;
  VectorXd r, c;
  Eigen::FullPivLU<MatrixXd> lu;
  double condition = 0.0;

  explicit Factorization(MatrixXd a) : A(std::move(a)) {
    const int n = static_cast<int>(A.rows());
    r = VectorXd::Ones(n);
    c = VectorXd::Ones(n);
    for (int i = 0; i < n; ++i) {
      const double mx = A.row(i).cwiseAbs().maxCoeff();
      if (mx > 0.0) r(i) = 1.0 / mx;
    }
    for (int j = 0; j < n; ++j) {
      const double mx = (r.asDiagonal() * A.col(j)).cwiseAbs().maxCoeff();
      if (mx > 0.0) c(j) = 1.0 / mx;
    }
    const MatrixXd S = r.asDiagonal() * A * c.asDiagonal();
    lu.compute(S);
    if (!lu.isInvertible())
      throw SingularSystem("closed_form: singular segment system (rank " + std::to_string(lu.rank()) + " of " +
                           std::to_string(n) + ")");
    const double rc = lu.rcond();
    if (!(rc > 1e-15))
      throw SingularSystem("closed_form: numerically singular segment system (rcond " + std::to_string(rc) + ")");
    condition = 1.0 / rc;
  }

  VectorXd solve(const VectorXd& b) const {
    VectorXd x = c.asDiagonal() * lu.solve(r.asDiagonal() * b);
    const VectorXd res = b - A * x;
    x += c.asDiagonal() * lu.solve(r.asDiagonal() * res);
    return x;
  }

  double residual(const VectorXd& x, const VectorXd& b) const {
    const double num = (A * x - b).cwiseAbs().maxCoeff();
    const double an = A.cwiseAbs().rowwise().sum().maxCoeff();
    const double den = an * x.cwiseAbs().maxCoeff() + b.cwiseAbs().maxCoeff();
    return den > 0.0 ? num / den : 0.0;
  }
};

BeamSolution make_solution(const Model& m, const VectorXd& coef, double condition, double residual,
                           bool with_loads = true) {
  std::vector<Segment> segs = m.segs;
  if (!with_loads)
    for (auto& s : segs) s.q0 = s.q1 = 0.0;
  return detail::SolutionAccess::make(m.p.L, m.p.EI, m.p.K, m.p.beta, m.p.lambda, m.x, std::move(segs),
                                      std::vector<double>(coef.data(), coef.data() + coef.size()), condition, residual);
}

// Breakpoints and contact flags for the given regions (assumed clean: sorted, disjoint).
void layout_for_regions(const BeamProblem& pr, const std::vector<Interval>& regions, std::vector<double>& x,
                        std::vector<bool>& contact) {
  std::vector<double> pts = load_points(pr);
  for (const auto& r : regions) {
    pts.push_back(r.start);
    pts.push_back(r.end);
  }
  x = merge_sorted(pts, pr.length);
  contact.assign(x.size() - 1, false);
  for (std::size_t i = 0; i + 1 < x.size(); ++i) {
    const double mid = 0.5 * (x[i] + x[i + 1]);
    for (const auto& r : regions)
      if (mid > r.start && mid < r.end) contact[i] = true;
  }
}

struct FullSolve {
  Model model;
  std::unique_ptr<Factorization> factor;
  BeamSolution solution;
};

FullSolve full_solve(const BeamProblem& pr, const std::vector<double>& x, const std::vector<bool>& contact) {
  FullSolve fs;
  fs.model = build_model(pr, x, contact);
  fs.factor = std::make_unique<Factorization>(assemble_matrix(fs.model));
  const VectorXd b = assemble_rhs(fs.model, fs.model.force, fs.model.moment, true);
  const VectorXd c = fs.factor->solve(b);
  fs.solution = make_solution(fs.model, c, fs.factor->condition, fs.factor->residual(c, b));
  return fs;
}

// Deflection under a unit force at breakpoint `index`, same contact set, no other load.
BeamSolution green(const FullSolve& fs, std::size_t index) {
  std::vector<double> force(fs.model.x.size(), 0.0), moment(fs.model.x.size(), 0.0);
  force[index] = 1.0;
  const VectorXd b = assemble_rhs(fs.model, force, moment, false);
  const VectorXd c = fs.factor->solve(b);
  return make_solution(fs.model, c, fs.factor->condition, fs.factor->residual(c, b), false);
}

// ---- tensionless topology -------------------------------------------------------------------

struct Topology {
  std::vector<Interval> fixed;   // regions with the fixed end values
  std::vector<int> start_limit;  // index into limits, or -1 (beam end 0)
  std::vector<int> end_limit;    // index into limits, or -1 (beam end L)
  std::vector<double> sign;      // per limit: +1 region start, -1 region end
  std::vector<double> initial;   // initial limit values

  std::vector<Interval> regions(const std::vector<double>& t) const {
    std::vector<Interval> out = fixed;
    for (std::size_t r = 0; r < out.size(); ++r) {
      if (start_limit[r] >= 0) out[r].start = t[start_limit[r]];
      if (end_limit[r] >= 0) out[r].end = t[end_limit[r]];
    }
    return out;
  }
};

// Returns an empty string when fine, a message otherwise.
std::string make_topology(const BeamProblem& pr, std::vector<Interval> regions, Topology& topo) {
  const double L = pr.length, snap = kLoadTolerance * L;
  for (auto& r : regions) {
    if (!std::isfinite(r.start) || !std::isfinite(r.end)) return "non-finite contact region";
    if (r.start < -snap || r.end > L + snap) return "contact region outside [0, L]";
    if (r.start <= snap) r.start = 0.0;
    if (r.end >= L - snap) r.end = L;
    if (!(r.end - r.start > snap)) return "empty or reversed contact region";
  }
  std::sort(regions.begin(), regions.end(), [](const Interval& a, const Interval& b) { return a.start < b.start; });
  for (std::size_t i = 1; i < regions.size(); ++i)
    if (!(regions[i].start > regions[i - 1].end + snap)) return "overlapping or touching contact regions (merge them)";
  topo = Topology{};
  topo.fixed = regions;
  // An end at a jump of the data (void edge, gap step) is fixed, like a beam end.
  const std::vector<double> jumps = jump_points(pr);
  auto at_jump = [&](double e) {
    for (double j : jumps)
      if (std::abs(e - j) <= snap) return true;
    return false;
  };
  for (const auto& r : regions) {
    if (r.start > 0.0 && !at_jump(r.start)) {
      topo.start_limit.push_back(static_cast<int>(topo.initial.size()));
      topo.initial.push_back(r.start);
      topo.sign.push_back(+1.0);
    } else {
      topo.start_limit.push_back(-1);
    }
    if (r.end < L && !at_jump(r.end)) {
      topo.end_limit.push_back(static_cast<int>(topo.initial.size()));
      topo.initial.push_back(r.end);
      topo.sign.push_back(-1.0);
    } else {
      topo.end_limit.push_back(-1);
    }
  }
  return {};
}

std::size_t breakpoint_index(const std::vector<double>& x, double t) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < x.size(); ++i)
    if (std::abs(x[i] - t) < std::abs(x[best] - t)) best = i;
  return best;
}

struct LimitState {
  FullSolve fs;
  std::vector<double> F;
  double scale = 0.0;
};

LimitState evaluate_limits(const BeamProblem& pr, const Topology& topo, const std::vector<double>& t) {
  LimitState s;
  std::vector<double> x;
  std::vector<bool> contact;
  layout_for_regions(pr, topo.regions(t), x, contact);
  s.fs = full_solve(pr, x, contact);
  s.F.resize(t.size());
  for (std::size_t k = 0; k < t.size(); ++k) {
    const double xk = s.fs.model.x[breakpoint_index(s.fs.model.x, t[k])];
    s.F[k] = s.fs.solution.deflection(xk) - s.fs.solution.gap(xk);
  }
  s.scale = s.fs.solution.max_abs_deflection(32);
  return s;
}

MatrixXd limit_jacobian(const BeamProblem& pr, const Topology& topo, const std::vector<double>& t,
                        const LimitState& s) {
  const std::size_t n = t.size();
  MatrixXd J = MatrixXd::Zero(n, n);
  const auto& x = s.fs.model.x;
  std::vector<double> tk(n);
  for (std::size_t k = 0; k < n; ++k) tk[k] = x[breakpoint_index(x, t[k])];
  for (std::size_t j = 0; j < n; ++j) {
    const BeamSolution G = green(s.fs, breakpoint_index(x, t[j]));
    // Moving the limit trades (K - K_t)(w - g) dt of reaction; K of the contact side.
    const Side inside = topo.sign[j] > 0 ? Side::right : Side::left;
    const double ground = s.fs.solution.ground_modulus(tk[j], inside);
    const double strength = topo.sign[j] * (ground - pr.tension_modulus) * s.F[j];
    for (std::size_t k = 0; k < n; ++k) J(k, j) = strength * G.deflection(tk[k]);
  }
  for (std::size_t k = 0; k < n; ++k) J(k, k) += s.fs.solution.slope(tk[k]) - s.fs.solution.gap_slope(tk[k]);
  return J;
}

double max_abs(const std::vector<double>& v) {
  double m = 0.0;
  for (double e : v) m = std::max(m, std::abs(e));
  return m;
}

// Worst wrong-sign |w| / scale on the grid.
double inequality_violation(const BeamSolution& sol, double scale, int samples) {
  double worst = 0.0;
  const auto& x = sol.breakpoints();
  for (std::size_t i = 0; i + 1 < x.size(); ++i) {
    const double h = x[i + 1] - x[i];
    const int n = std::max(samples, static_cast<int>(std::ceil(20.0 * sol.beta() * h)));
    const bool contact = sol.segment_in_contact(i);
    if (sol.ground_modulus(0.5 * (x[i] + x[i + 1])) == 0.0) continue;  // a void: no condition
    for (int s = 0; s <= n; ++s) {
      const double xs = (s == n) ? x[i + 1] : x[i] + h * s / n;
      const Side side = s == n ? Side::left : Side::right;
      const double w = sol.derivative(xs, 0, side) - sol.gap(xs, side);
      const double bad = contact ? std::max(0.0, -w) : std::max(0.0, w);
      worst = std::max(worst, scale > 0.0 ? bad / scale : bad);
    }
  }
  return worst;
}

}  // namespace

// ---------------------------------------------------------------------------------------------

double BeamProblem::beta() const {
  double k = foundation_segments.empty() ? foundation_modulus : 0.0;
  for (const auto& f : foundation_segments) k = std::max(k, f.modulus);
  return k > 0.0 ? std::pow(k / (4.0 * bending_stiffness), 0.25) : 0.0;
}

double BeamProblem::modulus_at(double x) const {
  if (foundation_segments.empty()) return foundation_modulus;
  double k = 0.0;
  for (const auto& f : foundation_segments)
    if (x >= f.from && x < f.to) k = f.modulus;
  if (x >= length)  // the right end belongs to the piece that reaches it
    for (const auto& f : foundation_segments)
      if (f.to >= length) k = f.modulus;
  return k;
}

double BeamProblem::gap_at(double x) const {
  const std::size_t n = gap.at.size();
  if (n == 0) return 0.0;
  if (x < gap.at.front()) return gap.value.front();
  for (std::size_t i = n - 1; i-- > 0;)  // the last interval starting at or left of x
    if (x >= gap.at[i] && gap.at[i + 1] > gap.at[i] && x < gap.at[i + 1])
      return gap.value[i] + (gap.value[i + 1] - gap.value[i]) * (x - gap.at[i]) / (gap.at[i + 1] - gap.at[i]);
  return gap.value.back();
}

std::size_t BeamSolution::segment_index(double x, Side side) const {
  if (segments_.empty()) throw std::logic_error("closed_form: empty solution");
  const std::size_t ns = segments_.size();
  if (x <= 0.0) return 0;
  if (x >= length_) return ns - 1;
  // First breakpoint > x (right side) or >= x (left side).
  auto it = side == Side::right ? std::upper_bound(breakpoints_.begin(), breakpoints_.end(), x)
                                : std::lower_bound(breakpoints_.begin(), breakpoints_.end(), x);
  std::size_t i = static_cast<std::size_t>(it - breakpoints_.begin());
  i = (i == 0) ? 0 : i - 1;
  return std::min(i, ns - 1);
}

double BeamSolution::derivative(double x, int order, Side side) const {
  if (order < 0 || order > 3) throw std::invalid_argument("closed_form: derivative order 0..3");
  const std::size_t i = segment_index(x, side);
  const Segment& s = segments_[i];
  x = std::clamp(x, s.a, s.b);
  Params p;
  p.L = length_;
  p.EI = ei_;
  p.K = k_;
  p.beta = beta_;
  p.lambda = lambda_;
  double B[4][4], P[4];
  evaluate_basis(p, s, x, B, P);
  double v = P[order];
  for (int j = 0; j < 4; ++j) v += B[order][j] * coefficients_[4 * i + j];
  return v / std::pow(lambda_, order);
}

double BeamSolution::bending_moment(double x, Side side) const { return -ei_ * derivative(x, 2, side); }

double BeamSolution::shear_force(double x, Side side) const { return -ei_ * derivative(x, 3, side); }

double BeamSolution::reaction(double x, Side side) const {
  const Segment& s = segments_[segment_index(x, side)];
  if (s.k == 0.0) return 0.0;
  return s.k * (derivative(x, 0, side) - gap(x, side));
}

double BeamSolution::gap(double x, Side side) const {
  const Segment& s = segments_[segment_index(x, side)];
  return s.g0 + s.g1 * (std::clamp(x, s.a, s.b) - s.a);
}

double BeamSolution::gap_slope(double x, Side side) const { return segments_[segment_index(x, side)].g1; }

double BeamSolution::acting_modulus(double x, Side side) const { return segments_[segment_index(x, side)].k; }

double BeamSolution::ground_modulus(double x, Side side) const { return segments_[segment_index(x, side)].ground; }

double BeamSolution::max_abs_deflection(int samples_per_segment) const {
  double m = 0.0;
  for (std::size_t i = 0; i < segments_.size(); ++i) {
    const Segment& s = segments_[i];
    for (int k = 0; k <= samples_per_segment; ++k) {
      const double x = s.a + (s.b - s.a) * k / samples_per_segment;
      m = std::max(m, std::abs(derivative(x, 0, k == samples_per_segment ? Side::left : Side::right)));
    }
  }
  return m;
}

std::vector<double> load_points(const BeamProblem& pr) {
  validate(pr);
  std::vector<double> pts = {0.0, pr.length};
  for (const auto& f : pr.forces) pts.push_back(f.at);
  for (const auto& m : pr.moments) pts.push_back(m.at);
  for (const auto& u : pr.uniform_loads) {
    pts.push_back(std::clamp(u.from, 0.0, pr.length));
    pts.push_back(std::clamp(u.to, 0.0, pr.length));
  }
  for (const auto& d : pr.distributed_loads) {
    pts.push_back(std::clamp(d.from, 0.0, pr.length));
    pts.push_back(std::clamp(d.to, 0.0, pr.length));
  }
  for (const auto& f : pr.foundation_segments) {
    pts.push_back(f.from);
    pts.push_back(f.to);
  }
  for (double a : pr.gap.at) pts.push_back(std::clamp(a, 0.0, pr.length));
  return merge_sorted(pts, pr.length);
}

BeamSolution solve_segments(const BeamProblem& problem, const std::vector<double>& breakpoints,
                            const std::vector<bool>& in_contact) {
  return full_solve(problem, breakpoints, in_contact).solution;
}

BeamSolution solve_with_contact(const BeamProblem& problem, const std::vector<Interval>& regions) {
  validate(problem);
  Topology topo;
  const std::string err = make_topology(problem, regions, topo);
  if (!err.empty()) throw std::invalid_argument("closed_form: " + err);
  std::vector<double> x;
  std::vector<bool> contact;
  layout_for_regions(problem, topo.fixed, x, contact);
  return solve_segments(problem, x, contact);
}

BeamSolution solve_bilateral(const BeamProblem& problem) {
  return solve_with_contact(problem, {Interval{0.0, problem.length}});
}

std::vector<Interval> contact_regions(const BeamSolution& sol, int samples_per_segment, double zero_tolerance) {
  std::vector<Interval> out;
  if (sol.empty()) return out;
  const double eps = zero_tolerance * sol.max_abs_deflection(samples_per_segment / 4 + 1);
  // w - g where a foundation exists; -inf over a void (never in contact).
  auto excess = [&](double x, Side side) {
    if (sol.ground_modulus(x, side) == 0.0) return -std::numeric_limits<double>::infinity();
    return sol.derivative(x, 0, side) - sol.gap(x, side);
  };
  struct Sample {
    double x, w;
  };
  std::vector<Sample> samples;
  const auto& bp = sol.breakpoints();
  for (std::size_t i = 0; i + 1 < bp.size(); ++i) {
    const double h = bp[i + 1] - bp[i];
    const int n = std::max(samples_per_segment, static_cast<int>(std::ceil(16.0 * sol.beta() * h)));
    for (int k = 0; k < n; ++k) {
      const double x = bp[i] + h * k / n;
      samples.push_back({x, excess(x, Side::right)});
    }
    // The left limit at the segment's end too, so that a jump (void edge, gap step) is seen.
    samples.push_back({bp[i + 1], excess(bp[i + 1], Side::left)});
  }
  auto positive = [&](double w) { return w > eps; };
  // Root of w between a (w <= eps side) and b, refined by bisection on the sign of w.
  auto root = [&](Sample lo, Sample hi) {
    // lo and hi have different "positive" status.
    if (std::abs(lo.w) <= eps) return lo.x;
    if (std::abs(hi.w) <= eps) return hi.x;
    double a = lo.x, b = hi.x;
    if (b <= a) return a;  // the two sides of a jump
    const bool pa = lo.w > 0.0;
    for (int it = 0; it < 200; ++it) {
      const double m = 0.5 * (a + b);
      if (m <= std::min(a, b) || m >= std::max(a, b)) break;
      const double wm = excess(m, Side::right);
      if ((wm > 0.0) == pa)
        a = m;
      else
        b = m;
    }
    return 0.5 * (a + b);
  };
  bool inside = false;
  double start = 0.0;
  for (std::size_t s = 0; s < samples.size(); ++s) {
    const bool pos = positive(samples[s].w);
    if (pos && !inside) {
      start = (s == 0) ? samples[0].x : root(samples[s - 1], samples[s]);
      inside = true;
    } else if (!pos && inside) {
      const double end = root(samples[s - 1], samples[s]);
      if (end > start) out.push_back({start, end});
      inside = false;
    }
  }
  if (inside) out.push_back({start, samples.back().x});
  return out;
}

std::string to_string(TensionlessStatus status) {
  // One table of names (this library stays independent of liftoff's core/enum_names.hpp).
  constexpr std::pair<TensionlessStatus, const char*> names[] = {
      {TensionlessStatus::converged, "converged"},
      {TensionlessStatus::no_convergence, "no convergence"},
      {TensionlessStatus::inequalities_violated, "inequalities violated"},
      {TensionlessStatus::singular_system, "singular system"},
      {TensionlessStatus::invalid_input, "invalid input"},
  };
  for (const auto& [value, name] : names)
    if (value == status) return name;
  return "unknown";
}

LimitEquations limit_equations(const BeamProblem& problem, const std::vector<Interval>& regions) {
  validate(problem);
  Topology topo;
  const std::string err = make_topology(problem, regions, topo);
  if (!err.empty()) throw std::invalid_argument("closed_form: " + err);
  const LimitState s = evaluate_limits(problem, topo, topo.initial);
  const MatrixXd J = limit_jacobian(problem, topo, topo.initial, s);
  LimitEquations out;
  out.limits = topo.initial;
  out.residuals = s.F;
  out.jacobian.assign(J.rows(), std::vector<double>(J.cols()));
  for (int k = 0; k < J.rows(); ++k)
    for (int j = 0; j < J.cols(); ++j) out.jacobian[k][j] = J(k, j);
  out.solution = s.fs.solution;
  return out;
}

TensionlessResult solve_tensionless(const BeamProblem& problem, const std::vector<Interval>& initial_contact_regions,
                                    const TensionlessOptions& opt) {
  TensionlessResult res;
  try {
    validate(problem);
  } catch (const std::exception& e) {
    res.status = TensionlessStatus::invalid_input;
    res.message = e.what();
    return res;
  }
  Topology topo;
  if (std::string err = make_topology(problem, initial_contact_regions, topo); !err.empty()) {
    res.status = TensionlessStatus::invalid_input;
    res.message = err;
    return res;
  }
  const double L = problem.length;
  const double min_gap = 1e-10 * L;
  const double beta = problem.beta();
  const double radius = beta > 0.0 ? std::min(L, opt.max_step / beta) : L;
  std::vector<double> t = topo.initial;
  const std::size_t n = t.size();
  // Regions keep a positive length and their order; no limit strays onto a void.
  auto feasible = [&](const std::vector<double>& v) {
    bool first = true;
    double prev = 0.0;
    for (const auto& r : topo.regions(v)) {
      if (!first && !(r.start - prev > min_gap)) return false;
      if (!(r.end - r.start > min_gap)) return false;
      prev = r.end;
      first = false;
    }
    for (double e : v) {
      if (!(e > min_gap && e < L - min_gap)) return false;
      if (problem.modulus_at(e) == 0.0 && problem.modulus_at(e - min_gap) == 0.0) return false;
    }
    return true;
  };
  auto finish = [&](TensionlessStatus st, std::string msg, const LimitState& s) {
    res.status = st;
    res.message = std::move(msg);
    res.limits = t;
    res.contact = topo.regions(t);
    res.solution = s.fs.solution;
    res.residual = s.scale > 0.0 ? max_abs(s.F) / s.scale : max_abs(s.F);
    return res;
  };
  try {
    LimitState s = evaluate_limits(problem, topo, t);
    int it = 0;
    bool converged = false;
    for (;; ++it) {
      if (max_abs(s.F) <= opt.tolerance * s.scale) {
        converged = true;
        break;
      }
      if (it >= opt.max_iterations) break;
      const MatrixXd J = limit_jacobian(problem, topo, t, s);
      VectorXd F(n);
      for (std::size_t k = 0; k < n; ++k) F(k) = s.F[k];
      // At an admissible solution J = diag(w'(t_k)) with s_k w'(t_k) > 0 (w rises into
      // contact). A diagonal of the wrong sign means the Newton step heads for an inadmissible
      // root: take the physical step instead (shrink a region whose edge has w < 0, grow it
      // where w > 0), without the merit test.
      bool physical = false;
      for (std::size_t k = 0; k < n; ++k)
        if (!(topo.sign[k] * J(k, k) > 0.0)) physical = true;
      VectorXd dt(n);
      if (!physical) {
        Eigen::FullPivLU<MatrixXd> lu(J);
        if (lu.isInvertible())
          dt = -lu.solve(F);
        else
          physical = true;
        for (std::size_t k = 0; k < n && !physical; ++k)
          if (!std::isfinite(dt(k))) physical = true;
      }
      if (physical) {
        for (std::size_t k = 0; k < n; ++k) {
          dt(k) = -topo.sign[k] * F(k) / std::abs(J(k, k));
          if (!std::isfinite(dt(k))) dt(k) = -topo.sign[k] * (F(k) > 0 ? 1.0 : -1.0) * radius;
        }
      }
      const double biggest = dt.cwiseAbs().maxCoeff();
      if (biggest > radius) dt *= radius / biggest;
      double alpha = 1.0;
      std::vector<double> trial(n);
      auto make_trial = [&]() {
        for (std::size_t k = 0; k < n; ++k) trial[k] = t[k] + alpha * dt(k);
      };
      make_trial();
      int halvings = 0;
      while (!feasible(trial) && halvings < 60) {
        alpha *= 0.5;
        ++halvings;
        make_trial();
      }
      if (!feasible(trial)) {
        res.iterations = it;
        return finish(TensionlessStatus::no_convergence, "a contact region collapsed (limits cannot stay ordered)", s);
      }
      const double f0 = max_abs(s.F);
      bool accepted = false;
      LimitState trial_state;
      for (int ls = 0; ls < 40; ++ls) {
        trial_state = evaluate_limits(problem, topo, trial);
        if (physical || max_abs(trial_state.F) < (1.0 - 1e-4 * alpha) * f0) {
          accepted = true;
          break;
        }
        alpha *= 0.5;
        make_trial();
      }
      if (!accepted) {
        res.iterations = it;
        std::ostringstream msg;
        msg << "line search failed at max|w(t)|/max|w| = " << f0 / s.scale;
        return finish(TensionlessStatus::no_convergence, msg.str(), s);
      }
      t = trial;
      s = std::move(trial_state);
      for (const auto& r : topo.regions(t))
        if (r.end - r.start < 1e-8 * radius) {
          res.iterations = it + 1;
          std::ostringstream msg;
          msg << "contact region near x = " << 0.5 * (r.start + r.end)
              << " collapsed: this topology has no admissible solution (drop the region)";
          return finish(TensionlessStatus::no_convergence, msg.str(), s);
        }
    }
    res.iterations = it;
    if (!converged) {
      std::ostringstream msg;
      msg << "no convergence in " << opt.max_iterations
          << " Newton steps, max|w(t)|/max|w| = " << max_abs(s.F) / s.scale;
      return finish(TensionlessStatus::no_convergence, msg.str(), s);
    }
    const double viol = inequality_violation(s.fs.solution, s.scale, opt.samples_per_segment);
    res.max_violation = viol;
    if (viol > opt.inequality_tolerance) {
      std::ostringstream msg;
      msg << "limits converged but the sign conditions fail: wrong-sign |w|/max|w| = " << viol;
      return finish(TensionlessStatus::inequalities_violated, msg.str(), s);
    }
    std::ostringstream msg;
    msg << "converged in " << it << " Newton steps";
    return finish(TensionlessStatus::converged, msg.str(), s);
  } catch (const SingularSystem& e) {
    res.status = TensionlessStatus::singular_system;
    res.message = e.what();
    res.limits = t;
    res.contact = topo.regions(t);
    return res;
  } catch (const std::invalid_argument& e) {
    res.status = TensionlessStatus::invalid_input;
    res.message = e.what();
    return res;
  }
}

TensionlessResult solve_tensionless_auto(const BeamProblem& problem, const TensionlessOptions& opt) {
  TensionlessResult last;
  try {
    validate(problem);
  } catch (const std::exception& e) {
    last.status = TensionlessStatus::invalid_input;
    last.message = e.what();
    return last;
  }
  const double L = problem.length, tiny = 1e-12 * L;
  // Clean a region list: drop slivers, merge regions separated by less than `tiny`.
  auto clean = [&](const std::vector<Interval>& in) {
    std::vector<Interval> out;
    for (const auto& r : in) {
      if (r.end - r.start <= tiny) continue;
      if (!out.empty() && r.start - out.back().end <= tiny)
        out.back().end = r.end;
      else
        out.push_back(r);
    }
    return out;
  };
  auto same = [&](const std::vector<Interval>& a, const std::vector<Interval>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
      if (std::abs(a[i].start - b[i].start) > 1e-12 * L || std::abs(a[i].end - b[i].end) > 1e-12 * L) return false;
    return true;
  };
  auto intersect = [&](const std::vector<Interval>& x, const std::vector<Interval>& y) {
    std::vector<Interval> out;
    for (const auto& p : x)
      for (const auto& q : y) {
        const double s0 = std::max(p.start, q.start), e0 = std::min(p.end, q.end);
        if (e0 > s0) out.push_back({s0, e0});
      }
    std::sort(out.begin(), out.end(), [](const Interval& u, const Interval& v) { return u.start < v.start; });
    return clean(out);
  };
  // Newton polish attempts: a good topology converges in a handful of steps.
  TensionlessOptions polish = opt;
  polish.max_iterations = std::min(opt.max_iterations, 20);
  std::vector<Interval> current = {Interval{0.0, L}};
  int total_iterations = 0;
  for (int round = 1; round <= opt.max_rounds; ++round) {
    BeamSolution sol;
    try {
      sol = solve_with_contact(problem, current);
    } catch (const SingularSystem& e) {
      last.status = TensionlessStatus::singular_system;
      last.message = e.what();
      last.rounds = round;
      return last;
    }
    // Shrink-only step C & {w > 0}; when that is stuck, one full step C = {w > 0}.
    const std::vector<Interval> positive = clean(contact_regions(sol));
    std::vector<Interval> next = intersect(current, positive);
    if (same(next, current)) {
      next = positive;
      if (same(next, current)) {
        // A fixed point of the contact-set map: the polish below decides.
        TensionlessResult r = solve_tensionless(problem, next, opt);
        total_iterations += r.iterations;
        r.rounds = round;
        if (r.status == TensionlessStatus::converged) {
          std::ostringstream msg;
          msg << "converged after " << round << " contact-set round(s) (" << total_iterations
              << " Newton steps in all)";
          r.message = msg.str();
          return r;
        }
        last = std::move(r);
        last.message = "contact-set iteration stuck: " + last.message;
        if (last.status == TensionlessStatus::converged) last.status = TensionlessStatus::no_convergence;
        return last;
      }
    }
    TensionlessResult r = solve_tensionless(problem, next, polish);
    total_iterations += r.iterations;
    r.rounds = round;
    if (r.status == TensionlessStatus::converged) {
      std::ostringstream msg;
      msg << "converged after " << round << " contact-set round(s), " << r.iterations
          << " Newton steps in the last polish (" << total_iterations << " in all)";
      r.message = msg.str();
      return r;
    }
    last = std::move(r);
    current = next;
  }
  last.message = "contact-set iteration did not settle: " + last.message;
  if (last.status == TensionlessStatus::converged) last.status = TensionlessStatus::no_convergence;
  return last;
}

}  // namespace liftoff::closed_form
