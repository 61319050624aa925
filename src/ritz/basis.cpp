#include "ritz/basis.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "core/enum_names.hpp"

namespace liftoff::ritz {

// Why the families are complete.
//
// The energy space of w is H^2(0, 1) with the kinematic conditions ("V"); a family is complete
// when its span is dense in V in the H^2 norm. Four trigonometric families are dense in known
// subspaces of H^2, because the corresponding periodic extension of an H^2 function is again H^2
// (an odd reflection needs f = 0 at the mirror point, an even one f' = 0; the reflected f'' may
// jump, which H^2 allows), and Fourier series converge in H^2_per:
//   S  = {sin(j pi xi)}            dense in {f(0) = f(1) = 0}        (odd at 0, odd at 1)
//   C  = {cos(j pi xi), j >= 0}    dense in {f'(0) = f'(1) = 0}      (even, even)
//   Q  = {sin((j-1/2) pi xi)}      dense in {f(0) = 0, f'(1) = 0}    (odd at 0, even at 1)
// Each family below is one of these, or a subspace of finite codimension of one, or one plus a
// few functions:
//   pinned-pinned: S itself, V = {f(0) = f(1) = 0}.
//   clamped-clamped: sin(pi xi) sin(j pi xi) = (cos((j-1) pi xi) - cos((j+1) pi xi))/2, so the
//     span for j = 1..N is {cosine sums of degree <= N+1 vanishing at 0 and 1}: dimensions agree
//     (N + 2 coefficients, 2 conditions). Given f in V (f' = 0 at both ends, so f in the closure
//     of C), its truncated cosine series g_N -> f in H^2, hence g_N(0), g_N(1) -> 0, and
//     g_N - g_N(0) (1 + cos pi xi)/2 - g_N(1) (1 - cos pi xi)/2 is in the span and -> f.
//   pinned-clamped: sin(j pi xi) cos(pi xi/2) = (sin((j+1/2) pi xi) + sin((j-1/2) pi xi))/2, so
//     the span is {Q-sums of degree <= N+1 vanishing at 1}; V = {f in closure(Q), f(1) = 0},
//     corrected with sin(pi xi/2) (value 1 at xi = 1) as above.
//   clamped-free: V = {f(0) = f'(0) = 0}. f' ranges over {g in H^1, g(0) = 0}, where Q is dense
//     in the H^1 norm (odd reflection at 0 needs only g(0) = 0); integrating from 0 maps that
//     density to H^2 density of the antiderivatives (1 - cos((j-1/2) pi xi))/((j-1/2) pi).
//   pinned-free: V = {f(0) = 0} = closure(Q) + span{xi}: subtract f'(1) xi from f to get an
//     element of closure(Q). xi is the rigid rotation about the pin.
//   free-free: V = H^2 = closure(C) + span{xi, xi^2}: subtract a xi + b xi^2 matching f'(0) and
//     f'(1). 1 (in C) and xi are the rigid motions.
// Speed: the Ritz solution is the energy-best element of the span, so it converges at least as
// fast as these truncations; for the pinned-pinned beam under a point load the deflection error
// falls like N^-3 (tested).
//
// Arches. The energy 1/2 int EA (u' - w)^2 + (u' + w'')^2 is finite exactly for u in H^1 and
// w in H^2, and the conditions on u (pinned, clamped) and on w (as for beams) are independent,
// so the pair space is the product of the two. w takes the beam family (complete as above).
// The partner u_j = antiderivative of w_j (+ constant, and for u fixed at both ends a
// combination with zero integral): since the w family is dense in L^2, the u' of the partners
// are dense in L^2 (the zero-integral side condition corrected by one fixed w of nonzero
// integral), and u = u(a) + integral of u' carries L^2 density of u' to H^1 density of u. So
// the partners alone are complete in H^1 with u's conditions; the end-strain functions only add.
// Completeness of both halves gives completeness of the pair.
//
// Why partners: the inextensional fields (u' = w) of the span are then all of the partner part,
// which keeps the stiff membrane term from locking. A basis where u' is not in the w span (e.g.
// u and w both sin(j pi psi) for pinned ends, the obvious choice) has no exact inextensional
// field at all, and pays EA R^2/EI times the L^2 mismatch. Measured, pinned arch, gamma = 10
// degrees, point load, crown deflection / converged value at N = 4, 8, 16, 32:
//   EA R^2/EI = 3e6 (the seed, R/h = 500): both-sines 0.84 0.98 0.997 0.9996; ours 0.93 0.989 0.9985 0.9998
//   EA R^2/EI = 3e8 (R/h = 5000):          both-sines 0.07 0.67 0.88  0.98;   ours 0.92 0.988 0.9984 0.9998
// so at the seed's slenderness the obvious basis is only a few times worse, but it locks as
// the arch gets thinner; ours does not depend on EA R^2/EI.
// Why end-strain functions: every partner has u' = w at the ends, so where w = 0 (pinned,
// clamped) the membrane strain u' - w of the partners vanishes at the end. The thrust of a
// pinned or clamped arch does not vanish there, and approximating it with functions that do
// converges slowly (measured, pinned arch with a crown load against the FE: deflection errors
// falling like N^-1, 9e-4 at N = 48; with the two end-strain functions 6e-5, like N^-3). At
// roller and free ends the strain is zero anyway (natural condition EA eps + chi = 0, chi = 0).

namespace {

constexpr double pi = std::numbers::pi;

enum class DeflectionEnd { hinge, clamp, free };  // w = 0; w = w' = 0; nothing
enum class TangentialEnd { fixed, loose };        // u = 0; nothing

DeflectionEnd deflection_end(model::EndSupport support) {
  switch (support) {
    case model::EndSupport::pinned:
    case model::EndSupport::roller:
      return DeflectionEnd::hinge;
    case model::EndSupport::clamped:
      return DeflectionEnd::clamp;
    case model::EndSupport::free:
      return DeflectionEnd::free;
  }
  return DeflectionEnd::free;
}

TangentialEnd tangential_end(model::EndSupport support) {
  return support == model::EndSupport::pinned || support == model::EndSupport::clamped ? TangentialEnd::fixed
                                                                                       : TangentialEnd::loose;
}

using Family = std::vector<TrigPolynomial>;

TrigPolynomial sin_xi(double frequency) { return TrigPolynomial::sine(frequency * pi); }
TrigPolynomial cos_xi(double frequency) { return TrigPolynomial::cosine(frequency * pi); }

// The families in xi on [0, 1] for the canonical orientations; `description` in words.
Family canonical_family(DeflectionEnd left, DeflectionEnd right, int count, std::string& description) {
  Family f;
  using D = DeflectionEnd;
  if (left == D::hinge && right == D::hinge) {
    description = "sin(j pi xi)";
    for (int j = 1; j <= count; ++j) f.push_back(sin_xi(j));
  } else if (left == D::clamp && right == D::clamp) {
    description = "sin(pi xi) sin(j pi xi)";
    for (int j = 1; j <= count; ++j) f.push_back(sin_xi(1) * sin_xi(j));
  } else if (left == D::hinge && right == D::clamp) {
    description = "sin(j pi xi) cos(pi xi/2)";
    for (int j = 1; j <= count; ++j) f.push_back(sin_xi(j) * cos_xi(0.5));
  } else if (left == D::clamp && right == D::free) {
    description = "1 - cos((j - 1/2) pi xi)";
    for (int j = 1; j <= count; ++j) f.push_back(TrigPolynomial::constant(1.0) - cos_xi(j - 0.5));
  } else if (left == D::hinge && right == D::free) {
    description = "xi, sin((j - 1/2) pi xi)";
    f.push_back(TrigPolynomial::monomial(1));
    for (int j = 1; static_cast<int>(f.size()) < count; ++j) f.push_back(sin_xi(j - 0.5));
  } else if (left == D::free && right == D::free) {
    description = "1, xi, xi^2, cos(j pi xi)";
    f.push_back(TrigPolynomial::constant(1.0));
    f.push_back(TrigPolynomial::monomial(1));
    f.push_back(TrigPolynomial::monomial(2));
    for (int j = 1; static_cast<int>(f.size()) < count; ++j) f.push_back(cos_xi(j));
  } else {
    throw std::logic_error("canonical_family: not a canonical orientation");
  }
  f.resize(count);
  return f;
}

bool canonical(DeflectionEnd left, DeflectionEnd right) {
  using D = DeflectionEnd;
  return (left == right) || (left == D::hinge && right == D::clamp) || (left == D::clamp && right == D::free) ||
         (left == D::hinge && right == D::free);
}

constexpr EnumName<DeflectionEnd> deflection_end_names[] = {
    {DeflectionEnd::hinge, "w = 0"},
    {DeflectionEnd::clamp, "w = w' = 0"},
    {DeflectionEnd::free, "free"},
};

std::string_view name(DeflectionEnd e) { return name_in<DeflectionEnd>(deflection_end_names, e); }

// The w family in s for the given end conditions: canonical family, mirrored if needed, mapped
// from xi to s.
Family deflection_family(DeflectionEnd left, DeflectionEnd right, double s_begin, double s_end, int count,
                         std::string& description) {
  const double length = s_end - s_begin;
  const bool mirror = !canonical(left, right);
  Family f =
      mirror ? canonical_family(right, left, count, description) : canonical_family(left, right, count, description);
  // xi = (s - s_begin)/length, or 1 - xi for the mirror image.
  const double alpha = mirror ? -1.0 / length : 1.0 / length;
  const double beta = mirror ? s_end / length : -s_begin / length;
  for (TrigPolynomial& p : f) p = p.composed_affine(alpha, beta);
  if (mirror) description = "mirror image (xi -> 1 - xi) of " + description;
  description = fmt::format("{} ({} at the left end, {} at the right)", description, name(left), name(right));
  return f;
}

// Scale to a largest absolute value of 1 on [s_begin, s_end] (sampled finely: the scale only
// needs to be about right).
void normalise(Family& family, double s_begin, double s_end) {
  constexpr int samples = 400;
  // Every function on the grid in one pass (add_on_grid, a row per function).
  std::vector<TrigTerm> terms;
  std::vector<int> rows;
  for (std::size_t f = 0; f < family.size(); ++f)
    for (const TrigTerm& t : family[f].terms()) terms.push_back(t), rows.push_back(static_cast<int>(f));
  const std::vector<double> ones(terms.size(), 1.0);
  std::vector<double> values(family.size() * (samples + 1), 0.0);
  add_on_grid(terms.data(), ones.data(), static_cast<int>(terms.size()), s_begin, (s_end - s_begin) / samples,
              samples + 1, values.data(), rows.data());
  for (std::size_t f = 0; f < family.size(); ++f) {
    double largest = 0.0;
    for (int i = 0; i <= samples; ++i) largest = std::max(largest, std::abs(values[f * (samples + 1) + i]));
    if (!(largest > 0.0)) throw std::logic_error("ritz basis: a basis function vanishes identically");
    family[f] *= 1.0 / largest;
  }
}

void check_arguments(double s_begin, double s_end, int modes) {
  if (modes < 1) throw std::invalid_argument(fmt::format("ritz basis: modes must be at least 1, got {}", modes));
  if (!(s_begin < s_end) || !std::isfinite(s_begin) || !std::isfinite(s_end))
    throw std::invalid_argument(fmt::format("ritz basis: expected s_begin < s_end, got [{}, {}]", s_begin, s_end));
}

}  // namespace

namespace {

// A cubic in eta (0 at the pinned end, 1 at the other) with w = 0 and w'' != 0 at the pinned end,
// meeting the kinematic conditions of the other end and, if that end is pinned too, w'' = 0
// there (so the two cubics of a pinned-pinned beam carry one end curvature each).
TrigPolynomial end_curvature_cubic(DeflectionEnd other) {
  const auto eta = [](int p) { return TrigPolynomial::monomial(p); };
  switch (other) {
    case DeflectionEnd::hinge:
      return 2.0 * eta(1) - 3.0 * eta(2) + eta(3);  // w(1) = w''(1) = 0
    case DeflectionEnd::clamp:
      return eta(1) - 2.0 * eta(2) + eta(3);  // w(1) = w'(1) = 0
    case DeflectionEnd::free:
      return eta(2);
  }
  return eta(2);
}

}  // namespace

// Every family above has w'' = 0 at a pinned end, where an applied end moment makes the exact
// w'' non-zero: the sine coefficients then decay only like j^-3 and contact limits converge
// slowly (measured on the seed's end-moment beams). One cubic per pinned end, carrying that end
// curvature, restores the faster decay; it replaces the family's last function so N stays N.
Basis beam_basis(model::EndSupport left, model::EndSupport right, double s_begin, double s_end, int modes) {
  check_arguments(s_begin, s_end, modes);
  const DeflectionEnd left_end = deflection_end(left), right_end = deflection_end(right);
  const int cubics = (left_end == DeflectionEnd::hinge) + (right_end == DeflectionEnd::hinge);
  const bool enriched = modes >= cubics + 3;
  Basis basis;
  basis.w =
      deflection_family(left_end, right_end, s_begin, s_end, enriched ? modes - cubics : modes, basis.description);
  if (enriched) {
    const double length = s_end - s_begin;
    if (left_end == DeflectionEnd::hinge)  // eta = xi
      basis.w.push_back(end_curvature_cubic(right_end).composed_affine(1.0 / length, -s_begin / length));
    if (right_end == DeflectionEnd::hinge)  // eta = 1 - xi
      basis.w.push_back(end_curvature_cubic(left_end).composed_affine(-1.0 / length, s_end / length));
    basis.description += fmt::format(", and {} cubic(s) carrying the curvature of the pinned end(s)", cubics);
  }
  basis.description = "beam, w: " + basis.description;
  normalise(basis.w, s_begin, s_end);
  return basis;
}

Basis arch_basis(model::EndSupport left, model::EndSupport right, double s_begin, double s_end, int modes) {
  check_arguments(s_begin, s_end, modes);
  const TangentialEnd u_left = tangential_end(left), u_right = tangential_end(right);
  const bool fixed_left = u_left == TangentialEnd::fixed, fixed_right = u_right == TangentialEnd::fixed;
  const bool u_fixed_both = fixed_left && fixed_right;
  // u: `partners` antiderivatives of w functions, then `end_strain` functions (one per end
  // where u is fixed) that give u' (and so the membrane strain) a free value at that end.
  const int fixed_ends = static_cast<int>(fixed_left) + static_cast<int>(fixed_right);
  const int partners = std::max(1, modes - fixed_ends);
  const int end_strain = modes - partners;
  std::string w_description;
  Family w = deflection_family(deflection_end(left), deflection_end(right), s_begin, s_end, modes, w_description);
  std::string unused;
  const Family sources = deflection_family(deflection_end(left), deflection_end(right), s_begin, s_end,
                                           u_fixed_both ? partners + 1 : partners, unused);

  Family u;
  for (const TrigPolynomial& wj : sources) {
    const TrigPolynomial primitive = wj.antiderivative();
    if (fixed_left)  // u = integral from s_begin (also the start for fixed-both)
      u.push_back(primitive - TrigPolynomial::constant(primitive(s_begin)));
    else if (fixed_right)
      u.push_back(primitive - TrigPolynomial::constant(primitive(s_end)));
    else  // zero mean: the gauge against the unresisted rotation about the centre
      u.push_back(primitive - TrigPolynomial::constant(primitive.integral(s_begin, s_end) / (s_end - s_begin)));
  }
  if (u_fixed_both) {
    // u(s_end) = integral of w_j over the member must vanish: eliminate with a pivot of large
    // integral (the first whose integral is at least half the largest).
    std::vector<double> integrals;
    double largest = 0.0;
    for (const TrigPolynomial& wj : sources) {
      integrals.push_back(wj.integral(s_begin, s_end));
      largest = std::max(largest, std::abs(integrals.back()));
    }
    std::size_t pivot = u.size() - 1;
    if (largest > 0.0) {
      for (std::size_t j = 0; j < integrals.size(); ++j)
        if (std::abs(integrals[j]) >= 0.5 * largest) {
          pivot = j;
          break;
        }
    }
    Family combined;
    for (std::size_t j = 0; j < u.size(); ++j) {
      if (j == pivot) continue;
      combined.push_back(largest > 0.0 ? u[j] - (integrals[j] / integrals[pivot]) * u[pivot] : u[j]);
    }
    u = std::move(combined);
  }
  // End-strain functions, in xi: fixed both: sin(pi xi), sin(2 pi xi) (end slopes (pi, -pi) and
  // (2 pi, 2 pi): independent); fixed left: sin(pi xi/2); fixed right: cos(pi xi/2).
  Family extra;
  if (u_fixed_both) {
    extra = {sin_xi(1), sin_xi(2)};
  } else if (fixed_left) {
    extra = {sin_xi(0.5)};
  } else if (fixed_right) {
    extra = {cos_xi(0.5)};
  }
  const double length = s_end - s_begin;
  for (int j = 0; j < end_strain; ++j) u.push_back(extra[j].composed_affine(1.0 / length, -s_begin / length));

  std::string u_description;
  if (u_fixed_both)
    u_description =
        "integrals from the left end of w functions, combined to vanish at the right end, then sin(pi psi), "
        "sin(2 pi psi)";
  else if (fixed_left)
    u_description = "integrals of w functions from the left end, then sin(pi psi/2)";
  else if (fixed_right)
    u_description = "integrals of w functions from the right end, then cos(pi psi/2)";
  else
    u_description =
        "zero-mean integrals of the w functions (the rigid rotation about the centre, u = const, is excluded as a "
        "gauge)";
  normalise(w, s_begin, s_end);
  normalise(u, s_begin, s_end);
  Basis basis;
  basis.w = std::move(w);
  basis.u = std::move(u);
  basis.description = fmt::format("arch, w: {}, with psi for xi; u: {}", w_description, u_description);
  return basis;
}

namespace {

// |s - a|^3 + p(s) (see KinkedFunction in basis.hpp), scaled to a largest |e| of 1. The
// conditions on e at each end, as rows of a linear system in p's coefficients (in xi).
KinkedFunction kinked_function(const model::MemberModel& model, double a) {
  const double length = model.s_end - model.s_begin;
  const double alpha = (a - model.s_begin) / length;  // the kink in xi
  constexpr int degree = 5;
  // Derivative `order` of |xi - alpha|^3 at xi, and of xi^p.
  const auto kink_derivative = [alpha](double xi, int order) {
    const double d = xi - alpha, sign = d < 0 ? -1.0 : 1.0;
    switch (order) {
      case 0:
        return std::abs(d) * d * d;
      case 1:
        return 3.0 * d * std::abs(d);
      case 2:
        return 6.0 * std::abs(d);
      default:
        return 6.0 * sign;
    }
  };
  const auto monomial_derivative = [](double xi, int p, int order) {
    if (order > p) return 0.0;
    double factor = 1.0;
    for (int i = 0; i < order; ++i) factor *= p - i;
    return factor * std::pow(xi, p - order);
  };
  std::vector<std::pair<double, int>> conditions;  // (xi, derivative order) where e^(order) = 0
  for (const auto& [xi, support] : {std::pair{0.0, model.left}, std::pair{1.0, model.right}}) {
    switch (deflection_end(support)) {
      case DeflectionEnd::hinge:
        conditions.insert(conditions.end(), {{xi, 0}, {xi, 2}});
        break;
      case DeflectionEnd::clamp:
        conditions.insert(conditions.end(), {{xi, 0}, {xi, 1}});
        break;
      case DeflectionEnd::free:
        conditions.insert(conditions.end(), {{xi, 2}, {xi, 3}});
        break;
    }
  }
  Eigen::MatrixXd m(conditions.size(), degree + 1);
  Eigen::VectorXd rhs(conditions.size());
  for (std::size_t r = 0; r < conditions.size(); ++r) {
    const auto [xi, order] = conditions[r];
    for (int p = 0; p <= degree; ++p) m(r, p) = monomial_derivative(xi, p, order);
    rhs(r) = -kink_derivative(xi, order);
  }
  const Eigen::VectorXd c = m.completeOrthogonalDecomposition().solve(rhs);
  TrigPolynomial polynomial;
  for (int p = 0; p <= degree; ++p) polynomial += TrigPolynomial::monomial(p, c(p));
  // |xi - alpha|^3 = -(xi - alpha)^3 left of the kink, +(xi - alpha)^3 right of it.
  const TrigPolynomial cube = TrigPolynomial::monomial(3) - 3.0 * alpha * TrigPolynomial::monomial(2) +
                              3.0 * alpha * alpha * TrigPolynomial::monomial(1) -
                              TrigPolynomial::constant(alpha * alpha * alpha);
  KinkedFunction e;
  e.kink = a;
  e.halves = {polynomial - cube, polynomial + cube};
  double largest = 0.0;
  constexpr int samples = 400;
  for (int i = 0; i <= samples; ++i) {
    const double xi = static_cast<double>(i) / samples;
    largest = std::max(largest, std::abs(e.halves[xi < alpha ? 0 : 1](xi)));
  }
  for (TrigPolynomial& half : e.halves)
    half = (half * (1.0 / largest)).composed_affine(1.0 / length, -model.s_begin / length);
  return e;
}

}  // namespace

Basis make_basis(const model::MemberModel& model, int modes, Enrichment enrichment) {
  if (model.kind != model::StructureKind::beam)
    return arch_basis(model.left, model.right, model.s_begin, model.s_end, modes);
  Basis basis = beam_basis(model.left, model.right, model.s_begin, model.s_end, modes);
  if (enrichment == Enrichment::none) return basis;
  std::vector<double> kinks;
  const double edge = 1e-9 * (model.s_end - model.s_begin);
  for (const model::MemberLoad& load : model.loads)
    if (load.kind == model::LoadKind::force && load.at > model.s_begin + edge && load.at < model.s_end - edge)
      kinks.push_back(load.at);
  std::sort(kinks.begin(), kinks.end());
  kinks.erase(std::unique(kinks.begin(), kinks.end()), kinks.end());
  for (double a : kinks) basis.kinked_w.push_back(kinked_function(model, a));
  if (!kinks.empty())
    basis.description +=
        fmt::format(", enriched with |s - a|^3 at {} point force{}", kinks.size(), kinks.size() == 1 ? "" : "s");
  return basis;
}

}  // namespace liftoff::ritz
