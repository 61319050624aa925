// The certificate of a Ritz answer (certificate.hpp says what each check means).

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "certify/certificate.hpp"
#include "certify/detail.hpp"
#include "fe/shape_functions.hpp"

namespace liftoff::certify {

using Eigen::VectorXd;
using model::EndSupport;
using model::MemberModel;
using model::StructureKind;
using ritz::RitzModel;

namespace {

using detail::eps;

// Work of the applied loads on balance mode j (continuum, exact).
double applied_work(const MemberModel& model, int mode, double lambda) {
  double work = 0.0;
  const bool arch = model.kind == StructureKind::arch;
  for (const model::MemberLoad& load : model.loads) {
    const double value = load.value * (load.load_case == model::LoadCase::dead ? 1.0 : lambda);
    if (load.kind == model::LoadKind::force) {
      work += value * detail::balance_mode_at(model, mode, load.at)[1];
    } else if (load.kind == model::LoadKind::moment) {
      const Eigen::Vector3d m = detail::balance_mode_at(model, mode, load.at);
      work -= value * (m[2] + (arch ? m[0] : 0.0));
    } else if (load.kind == model::LoadKind::sine) {
      // int q and int q (s - s0) of the sine in closed form (beams only: the reader refuses arches)
      if (arch) throw std::logic_error("ritz certificate: a sine load on an arch");
      const double factor = load.load_case == model::LoadCase::dead ? 1.0 : lambda;
      work += factor *
              (mode == 0 ? load.resultant(load.from, load.to) : -load.moment_about(model.s_begin, load.from, load.to));
    } else if (load.kind == model::LoadKind::uniform) {
      // integral of q m_w over [from, to] in closed form, q = q0 + q1 s linear
      const double a = load.from, b = load.to, factor = load.load_case == model::LoadCase::dead ? 1.0 : lambda;
      const double q1 = factor * load.slope, q0 = factor * load.value - q1 * a;
      if (!arch) {
        const double s0 = model.s_begin;
        // int (q0 + q1 s) ds and int (q0 + q1 s)(s - s0) ds
        const double i0 = b - a, i1 = 0.5 * (b * b - a * a), i2 = (b * b * b - a * a * a) / 3.0;
        work += mode == 0 ? q0 * i0 + q1 * i1 : q0 * (i1 - s0 * i0) + q1 * (i2 - s0 * i1);
      } else {
        // int (q0 + q1 s) sin s = q0 (cos a - cos b) + q1 [sin s - s cos s]_a^b, likewise cos.
        const double int_sin =
            q0 * (std::cos(a) - std::cos(b)) + q1 * ((std::sin(b) - b * std::cos(b)) - (std::sin(a) - a * std::cos(a)));
        const double int_cos =
            q0 * (std::sin(b) - std::sin(a)) + q1 * ((std::cos(b) + b * std::sin(b)) - (std::cos(a) + a * std::sin(a)));
        if (mode == 0) work -= int_sin;  // m_w = -sin
        if (mode == 1) work -= int_cos;  // m_w = -cos
      }
    }
  }
  return work;
}

// Integral of f over [a, b] by composite 5-point Gauss-Legendre on `pieces` subintervals.
template <class F>
double integrate(double a, double b, int pieces, const F& f) {
  double sum = 0.0;
  const double h = (b - a) / pieces;
  for (int p = 0; p < pieces; ++p)
    for (const fe::GaussPoint& g : fe::gauss5) sum += g.weight * h * f(a + (p + g.xi) * h);
  return sum;
}

// The answer's balance terms: applied work, the foundation's work and its absolute value, the
// supports' generalised forces (and their work), per balance mode; the support reactions.
struct Balance {
  std::vector<double> applied, applied_abs, foundation, foundation_abs, supports, supports_abs;
  // Beams under an axial force N: its work on each balance mode m, -N integral (w + w0)' m' (the
  // P term of the energy), which for a beam's rigid m (m' constant) is -N m' [w + w0] over the ends.
  std::vector<double> axial, axial_abs;
  std::vector<SupportReaction> reactions;
  double centroid = 0.0;
};

// The supports' part of the balance terms: b.reactions and their generalised forces b.supports
// (and work magnitudes) per balance mode.
void add_support_terms(const MemberModel& member, const RitzModel& ritz, const VectorXd& x, double lambda, Balance& b) {
  const int modes = detail::balance_mode_count(member.kind);
  b.supports.resize(modes, 0.0);
  b.supports_abs.resize(modes, 0.0);
  const bool arch = member.kind == StructureKind::arch;
  const double k = member.k;
  const double membrane = !arch && ritz.has_membrane() ? ritz.membrane_force(x) : 0.0;
  const int per_length = 8 * std::max(4, ritz.modes());
  // Supports: the variationally consistent reaction of each dof a support fixes (w; w' at a
  // clamped end; u at an arch's pinned or clamped end), as the FE's: the residual of the Ritz
  // equations on a test function v_c that moves that dof alone,
  //   g_c = a(w, v_c) + integral over contact of k w w_c - F(v_c),
  // v_c the Hermite cubic of the whole member with that end value or slope (w_c), or the linear
  // u_c, zero at the other constrained dofs. Not the end shear -chi' itself: in the clamped
  // families every function is even about the end (sin(pi xi) sin(j pi xi)), so w''' there is
  // zero at every N and the end shear never converges (seed arch, clamped: the radial support
  // force is 1e-16 at 16 to 128 modes where the FE gives -0.0183); at pinned ends it converges
  // slowly (seed beam: 3e-5 at 32 modes; seed arch: 4% at 64). g_c converges with the energy
  // norm. force = -g_w, moment = -g_w', tangential = g_u - g_w' (as the FE's).
  const double length = member.s_end - member.s_begin;
  const int quadrature = std::max(8, per_length);
  // The fields at the quadrature points, evaluated once for every constrained dof (integrate()'s
  // points and order, so each dof's integral is the same sum as integrating the field there).
  struct Point {
    double s, weight, w, dw, d2w, du;
  };
  const auto points_of = [&](double a, double b, bool energy) {
    std::vector<Point> points;
    const double h = (b - a) / quadrature;
    for (int p = 0; p < quadrature; ++p)
      for (const fe::GaussPoint& g : fe::gauss5) {
        const double at = a + (p + g.xi) * h;
        Point q{at, g.weight * h, !energy || arch ? ritz.w(x, at) : 0.0, 0.0, 0.0, 0.0};  // beams' energy: no w
        if (energy) {
          q.d2w = ritz.w(x, at, 2);
          if (arch) q.du = ritz.u(x, at, 1);
          if (!arch && membrane != 0.0) q.dw = ritz.w(x, at, 1);
        }
        points.push_back(q);
      }
    return points;
  };
  const auto sum = [](const std::vector<Point>& points, const auto& f) {
    double total = 0.0;
    for (const Point& q : points) total += q.weight * f(q);
    return total;
  };
  std::vector<Point> member_points;
  std::vector<std::vector<Point>> piece_points;
  for (int side = 0; side < 2; ++side) {
    const EndSupport support = side == 0 ? member.left : member.right;
    if (support == EndSupport::free) continue;
    const double end = side == 0 ? member.s_begin : member.s_end;
    // Constrained dofs here: 0 w, 1 w', 2 u.
    const bool fixed[3] = {true, support == EndSupport::clamped,
                           arch && (support == EndSupport::pinned || support == EndSupport::clamped)};
    double g[3] = {0.0, 0.0, 0.0};
    for (int c = 0; c < 3; ++c) {
      if (!fixed[c]) continue;
      // v_c at s: (u, u', w, w', w'').
      auto test = [&](double s) {
        const double xi = (s - member.s_begin) / length;
        std::array<double, 5> v{0, 0, 0, 0, 0};
        if (c < 2) {
          const fe::HermiteCubic h = fe::hermite_cubic(xi, length);
          const int k = 2 * side + c;  // (w0, w0', w1, w1')
          v[2] = h.value[k];
          v[3] = h.d1[k];
          v[4] = h.d2[k];
        } else {
          v[0] = side == 0 ? 1.0 - xi : xi;
          v[1] = (side == 0 ? -1.0 : 1.0) / length;
        }
        return v;
      };
      if (member_points.empty()) {
        member_points = points_of(member.s_begin, member.s_end, true);
        for (const ContactRegion& piece : ritz.contact_pieces(x))
          if (piece.end > piece.begin) piece_points.push_back(points_of(piece.begin, piece.end, false));
      }
      const double energy = sum(member_points, [&](const Point& q) {
        const std::array<double, 5> v = test(q.s);
        if (!arch)  // the membrane's virtual work N (w0' + w') v' (zero without the term)
          return q.d2w * v[4] + (membrane != 0.0 ? membrane * (member.initial_slope(q.s) + q.dw) * v[3] : 0.0);
        return member.membrane_stiffness * (q.du - q.w) * (v[1] - v[2]) + (q.du + q.d2w) * (v[1] + v[4]);
      });
      double foundation_work = 0.0;
      for (const std::vector<Point>& points : piece_points)
        foundation_work += sum(points, [&](const Point& q) { return k * q.w * test(q.s)[2]; });
      double load_work = 0.0;
      for (const model::MemberLoad& load : member.loads) {
        const double value = load.value * (load.load_case == model::LoadCase::dead ? 1.0 : lambda);
        if (load.kind == model::LoadKind::force) {
          load_work += value * test(load.at)[2];
        } else if (load.kind == model::LoadKind::moment) {
          const std::array<double, 5> v = test(load.at);
          load_work -= value * (v[3] + v[0]);
        } else if (load.is_distributed_force()) {  // q x cubic: exact (linear q) or to round-off (sine)
          const double scale = load.load_case == model::LoadCase::dead ? 1.0 : lambda;
          for (const model::LoadQuadraturePoint& g : model::load_quadrature(load, load.from, load.to))
            load_work += scale * g.weight * load.intensity(g.s) * test(g.s)[2];
        }
      }
      g[c] = energy + foundation_work - load_work;
    }
    // Beams: tangential carries the membrane's axial reaction at a held end (along +s): -N at the
    // begin, N at the end.
    b.reactions.push_back(
        {end, 0.0 - g[0], 0.0 - g[1], arch ? g[2] - g[1] : (side == 0 ? -membrane : membrane)});  // no -0
    for (int j = 0; j < modes; ++j) {
      const Eigen::Vector3d m = detail::balance_mode_at(member, j, end);  // (u, w, w')
      b.supports[j] += m[1] * g[0] + m[2] * g[1] + m[0] * g[2];
      b.supports_abs[j] += std::abs(m[1] * g[0]) + std::abs(m[2] * g[1]) + std::abs(m[0] * g[2]);
    }
  }
}

Balance balance_terms(const MemberModel& member, const RitzModel& ritz, const VectorXd& x, double lambda) {
  const int modes = detail::balance_mode_count(member.kind);
  Balance b;
  b.applied.assign(modes, 0.0);
  b.applied_abs = b.foundation = b.foundation_abs = b.supports = b.supports_abs = b.applied;
  b.axial = b.axial_abs = b.applied;
  const bool arch = member.kind == StructureKind::arch;
  const double k = member.k;
  // Von Karman beams with both ends held: the membrane force N (tension positive, uniform in this
  // model) acts as an axial load of value -N.
  const double membrane = !arch && ritz.has_membrane() ? ritz.membrane_force(x) : 0.0;
  if (!arch && (member.has_axial_force() || membrane != 0.0)) {
    const double n = member.has_axial_force() ? member.axial_force(lambda) : -membrane, begin = member.s_begin,
                 end = member.s_end;
    const auto y = [&](double s) {
      return ritz.w(x, s) + (member.has_initial_shape() ? member.initial_shape(s) : 0.0);
    };
    for (int j = 0; j < modes; ++j) {
      const double slope =
          (detail::balance_mode_at(member, j, end)[1] - detail::balance_mode_at(member, j, begin)[1]) / (end - begin);
      b.axial[j] = -n * slope * (y(end) - y(begin));
      b.axial_abs[j] = std::abs(n * slope) * (std::abs(y(end)) + std::abs(y(begin)));
    }
  }
  // Quadrature fine enough for the highest mode: 8 subintervals per half wave.
  const int per_length = 8 * std::max(4, ritz.modes());
  double integral = 0.0, first_moment = 0.0;
  for (const ContactRegion& piece : ritz.contact_pieces(x)) {
    if (!(piece.end > piece.begin)) continue;
    const int pieces = std::max(
        8, static_cast<int>(std::ceil(per_length * (piece.end - piece.begin) / (member.s_end - member.s_begin))));
    integral += integrate(piece.begin, piece.end, pieces, [&](double s) { return k * ritz.w(x, s); });
    first_moment += integrate(piece.begin, piece.end, pieces, [&](double s) { return k * ritz.w(x, s) * s; });
    for (int j = 0; j < modes; ++j) {
      b.foundation[j] += integrate(piece.begin, piece.end, pieces, [&](double s) {
        return k * ritz.w(x, s) * detail::balance_mode_at(member, j, s)[1];
      });
      b.foundation_abs[j] += integrate(piece.begin, piece.end, pieces, [&](double s) {
        return std::abs(k * ritz.w(x, s) * detail::balance_mode_at(member, j, s)[1]);
      });
    }
  }
  b.centroid = integral != 0.0 ? first_moment / integral : 0.0;
  for (int j = 0; j < modes; ++j) {
    b.applied[j] = applied_work(member, j, lambda);
    b.applied_abs[j] = std::abs(b.applied[j]);
  }

  add_support_terms(member, ritz, x, lambda, b);
  return b;
}

double w_scale_of(const RitzModel& ritz, const VectorXd& x, const MemberModel& member) {
  std::vector<double> w;
  ritz.w_on_grid(x, member.s_begin, member.s_end, 2000, w);
  double scale = std::max(std::abs(ritz.w(x, member.s_begin)), std::abs(ritz.w(x, member.s_end)));
  for (double v : w) scale = std::max(scale, std::abs(v));
  return scale;
}

}  // namespace

Certificate certify(const MemberModel& member, const ritz::RitzSolution& solution,
                    const ritz::RitzOptions& ritz_options, const CertifyOptions& options) {
  options.validate();
  Certificate c;
  if (!solution.model || solution.unknowns.size() != solution.model->unknowns() || !solution.unknowns.allFinite() ||
      !solution.model->admissible(solution.unknowns)) {
    c.message = "no answer to certify: the Ritz unknowns are missing, not finite or not admissible";
    return c;
  }
  const RitzModel& ritz = *solution.model;
  const VectorXd& x = solution.unknowns;
  const double lambda = ritz_options.load_factor;
  const double w_scale = w_scale_of(ritz, x, member);
  const int amplitudes = ritz.amplitudes();
  const double amplitude_scale = std::max(x.head(amplitudes).lpNorm<Eigen::Infinity>(), 1e-300);

  // backward_error: the amplitude rows of the Ritz equations against their terms.
  double amplitude_residual = 0.0;  // largest amplitude row of the Ritz equations, in force units
  {
    VectorXd f;
    ritz.residual(x, lambda, f);
    const Eigen::MatrixXd gram = ritz.contact_gram(x);
    const VectorXd load = ritz.dead_load() + lambda * ritz.live_load();
    const VectorXd a = x.head(amplitudes);
    VectorXd magnitude = ritz.stiffness().cwiseAbs() * a.cwiseAbs() + load.cwiseAbs();
    magnitude.head(ritz.modes()) += member.k * gram.cwiseAbs() * a.head(ritz.modes()).cwiseAbs();
    const double scale = std::max(magnitude.maxCoeff(), 1e-300);
    amplitude_residual = f.head(amplitudes).lpNorm<Eigen::Infinity>();
    Check check = detail::make_check(check_name::backward_error, f.head(amplitudes).lpNorm<Eigen::Infinity>() / scale,
                                     std::max(ritz_options.newton.residual_tolerance, detail::backward_tolerance));
    c.checks.push_back(check);
  }

  // The half-modes answer: the model's own convergence estimate for the balance and round_off.
  const int modes = solution.summary.modes > 0 ? solution.summary.modes : ritz.modes();
  std::optional<ritz::RitzSolution> half;
  if (modes >= 2) {
    ritz::RitzOptions half_options = ritz_options;
    half_options.modes = modes / 2;
    std::vector<double> limits(x.data() + ritz.limit_offset(), x.data() + ritz.unknowns());
    try {
      ritz::RitzSolution candidate = ritz::solve_ritz(member, ritz.topology(), limits, half_options);
      if (candidate.summary.is_usable()) half = std::move(candidate);
    } catch (const std::exception&) {
    }
  }

  // Balance.
  const Balance b = balance_terms(member, ritz, x, lambda);
  std::optional<Balance> b_half;
  if (half) b_half = balance_terms(member, *half->model, half->unknowns, lambda);
  c.support_reactions = b.reactions;
  for (int j = 0; j < detail::balance_mode_count(member.kind); ++j) {
    const double scale = std::max(b.applied_abs[j] + b.supports_abs[j] + b.foundation_abs[j] + b.axial_abs[j], 1e-300);
    const double value = std::abs(b.applied[j] + b.supports[j] - b.foundation[j] - b.axial[j]) / scale;
    // Truncation: the change of the support and foundation terms from half the modes, x 4; plus
    // the round-off of the terms (the quadrature sums many; 64 eps as the FE rows).
    double truncation = NAN;
    if (b_half)
      truncation =
          4.0 * (std::abs(b.supports[j] - b_half->supports[j]) + std::abs(b.foundation[j] - b_half->foundation[j]));
    // Newton's residual: Galerkin makes the balance exact only for the exact root, so the balance
    // carries the residual rows along the balance mode's expansion in the basis; bounded by the
    // largest row x sqrt(amplitudes) x the mode's largest value (1, or the lever L for a moment).
    const double lever =
        member.kind == StructureKind::beam && j == 1 ? std::max(1.0, member.s_end - member.s_begin) : 1.0;
    const double newton_term = amplitude_residual * std::sqrt(double(amplitudes)) * lever;
    Check check = detail::make_check(
        detail::balance_name(member.kind, j), value,
        ((std::isnan(truncation) ? 0.0 : truncation) + newton_term) / scale + detail::backward_tolerance);
    c.checks.push_back(check);
  }
  detail::fill_resultants(c, member, b.applied, b.foundation, b.centroid);

  // Contact conditions on a grid of every piece (as ritz_solver's check).
  // Tolerance: the round-off of evaluating w (eps times the sum of the amplitudes: every basis
  // function is at most 1) and the limits' Newton accuracy, times sign_safety.
  const double evaluation = eps * x.head(ritz.modes()).cwiseAbs().sum() / std::max(w_scale, 1e-300);
  const double newton = ritz_options.newton.residual_tolerance * amplitude_scale / std::max(w_scale, 1e-300);
  const double tolerance = detail::sign_safety * std::max({detail::minimum_round_off, evaluation, newton});
  Check sign = detail::make_check(check_name::reaction_sign, 0.0, tolerance);
  Check penetration = detail::make_check(check_name::penetration, 0.0, tolerance);
  Check separation = detail::make_check(check_name::separation, 0.0, tolerance);
  Check complementarity = detail::make_check(check_name::complementarity, 0.0, tolerance);
  if (w_scale > 0 && member.tensionless) {
    std::vector<double> w;
    for (const ContactRegion& piece : ritz.pieces(x)) {
      constexpr int per_piece = 400;
      ritz.w_on_grid(x, piece.begin, piece.end, per_piece, w);
      for (int i = 0; i < static_cast<int>(w.size()); ++i) {
        const double s = piece.begin + (piece.end - piece.begin) * (i + 1) / per_piece;
        const double wrong = (piece.in_contact ? -w[i] : w[i]) / w_scale;
        Check& check = piece.in_contact ? separation : penetration;
        if (wrong > check.value) {
          check.value = wrong;
          check.at = s;
        }
        if (piece.in_contact && wrong > sign.value) {  // the reaction k w is negative exactly there
          sign.value = wrong;
          sign.at = s;
        }
      }
    }
    for (int m = 0; m < ritz.limits(); ++m) {
      const double t = x[ritz.limit_offset() + m], value = std::abs(ritz.w(x, t)) / w_scale;
      if (value > complementarity.value) {
        complementarity.value = value;
        complementarity.at = t;
      }
    }
  }
  if (member.tensionless)
    for (const Check& check : {sign, penetration, separation}) c.checks.push_back(check);
  c.checks.push_back(complementarity);

  // round_off: eps times the condition of the (scaled) Jacobian against the change of w from
  // half the modes.
  {
    Eigen::MatrixXd jacobian;
    ritz.jacobian(x, lambda, jacobian);
    const int n = ritz.unknowns();
    const VectorXd load = ritz.dead_load() + lambda * ritz.live_load();
    const double force_scale = std::max(load.lpNorm<Eigen::Infinity>(), 1e-300);
    VectorXd rows = VectorXd::Constant(n, 1.0 / force_scale), columns = VectorXd::Constant(n, amplitude_scale);
    rows.tail(n - amplitudes).setConstant(1.0 / amplitude_scale);
    columns.tail(n - amplitudes).setConstant(1.0);
    const Eigen::MatrixXd scaled = rows.asDiagonal() * jacobian * columns.asDiagonal();
    const double rcond = Eigen::PartialPivLU<Eigen::MatrixXd>(scaled).rcond();
    const double round_off = rcond > 0 ? eps / rcond : INFINITY;
    c.round_off_estimate = round_off;
    if (options.round_off) {
      double truncation = NAN;
      if (half && w_scale > 0) {
        std::vector<double> w_full, w_half;
        ritz.w_on_grid(x, member.s_begin, member.s_end, 2000, w_full);
        half->model->w_on_grid(half->unknowns, member.s_begin, member.s_end, 2000, w_half);
        truncation = 0.0;
        for (std::size_t i = 0; i < w_full.size(); ++i)
          truncation = std::max(truncation, std::abs(w_full[i] - w_half[i]) / w_scale);
      }
      Check check =
          detail::make_check(check_name::round_off, round_off,
                             std::isnan(truncation) ? INFINITY : std::max(truncation, detail::negligible_error));
      c.round_off_note =
          std::isnan(truncation)
              ? fmt::format(
                    "round-off {:.1e} (eps times the Jacobian's condition); the half-modes solve that "
                    "estimates the truncation failed, so it is not compared",
                    round_off)
              : fmt::format(
                    "round-off {:.1e} (eps times the Jacobian's condition) against a truncation error of {:.1e} "
                    "(change of w from {} modes)",
                    round_off, truncation, modes / 2);
      c.checks.push_back(check);
    }
  }
  if (!half) {
    if (!c.round_off_note.empty()) c.round_off_note += "; ";
    c.round_off_note += "the balance tolerance has no truncation estimate (the half-modes solve failed)";
  }
  detail::conclude(c, member);
  return c;
}

std::vector<SupportReaction> ritz_support_reactions(const MemberModel& member, const RitzModel& ritz, const VectorXd& x,
                                                    double lambda) {
  Balance b;
  add_support_terms(member, ritz, x, lambda, b);
  return b.reactions;
}

}  // namespace liftoff::certify
