#include "post/design.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "fe/shape_functions.hpp"

namespace liftoff::post {

namespace {

// A polynomial in xi on [0, 1], coefficients from the constant up (degree <= 5).
using Poly = std::array<double, 6>;

double eval(const Poly& p, double xi) {
  double v = 0.0;
  for (int k = 5; k >= 0; --k) v = v * xi + p[k];
  return v;
}

Poly derivative(const Poly& p) {
  Poly d{};
  for (int k = 1; k < 6; ++k) d[k - 1] = k * p[k];
  return d;
}

// The antiderivative vanishing at 0 (p of degree <= 4).
Poly integral(const Poly& p) {
  Poly out{};
  for (int k = 0; k < 5; ++k) out[k + 1] = p[k] / (k + 1);
  return out;
}

int degree(const Poly& p) {
  for (int k = 5; k > 0; --k)
    if (p[k] != 0.0) return k;
  return 0;
}

// The zeros of p in (0, 1) where it changes sign: between consecutive zeros of p' (found the
// same way) p is monotone, so each sign change is one zero, found by bisection to round-off.
std::vector<double> sign_changes(const Poly& p) {
  const int n = degree(p);
  std::vector<double> out;
  if (n == 0) return out;
  if (n == 1) {
    const double xi = -p[0] / p[1];
    if (xi > 0.0 && xi < 1.0) out.push_back(xi);
    return out;
  }
  std::vector<double> points{0.0};
  for (double xi : sign_changes(derivative(p))) points.push_back(xi);
  points.push_back(1.0);
  for (std::size_t i = 0; i + 1 < points.size(); ++i) {
    double a = points[i], b = points[i + 1], fa = eval(p, a);
    const double fb = eval(p, b);
    if (!(fa * fb < 0.0)) continue;
    for (int step = 0; step < 200 && b - a > 0.0; ++step) {
      const double m = 0.5 * (a + b);
      if (m <= a || m >= b) break;
      const double fm = eval(p, m);
      if (fm == 0.0)
        a = b = m;
      else if ((fm < 0.0) == (fa < 0.0))
        a = m, fa = fm;
      else
        b = m;
    }
    out.push_back(0.5 * (a + b));
  }
  return out;
}

// The zeros in (0, 1) where f changes sign, for f not a polynomial (an element under a sine
// load): f on 64 equal parts, each sign change bisected to round-off. A pair of zeros inside one
// part is missed; a part is at most 1/64 of an element, where the sine's phase moves < 0.05 rad
// on any mesh that resolves the load.
template <class F>
std::vector<double> sign_changes_of(const F& f) {
  constexpr int parts = 64;
  std::vector<double> out;
  double a = 0.0, fa = f(0.0);
  for (int i = 1; i <= parts; ++i) {
    const double b0 = static_cast<double>(i) / parts, fb0 = f(b0);
    if (fa * fb0 < 0.0) {
      double lo = a, hi = b0, flo = fa;
      for (int step = 0; step < 200; ++step) {
        const double m = 0.5 * (lo + hi);
        if (m <= lo || m >= hi) break;
        const double fm = f(m);
        if (fm == 0.0) {
          lo = hi = m;
          break;
        }
        ((fm < 0.0) == (flo < 0.0) ? lo : hi) = m;
        if ((fm < 0.0) == (flo < 0.0)) flo = fm;
      }
      out.push_back(0.5 * (lo + hi));
    }
    a = b0, fa = fb0;
  }
  return out;
}

// Where a polynomial may take its extremes on [0, 1]: the ends and its stationary points.
std::vector<double> candidates(const Poly& p) {
  std::vector<double> out{0.0, 1.0};
  for (double xi : sign_changes(derivative(p))) out.push_back(xi);
  return out;
}

// A cubic from its Taylor data at xi = 0 of an element of size h: value and s-derivatives.
Poly taylor(double value, double d1, double d2, double d3, double h) {
  return {value, h * d1, h * h * d2 / 2.0, h * h * h * d3 / 6.0, 0.0, 0.0};
}
Poly linear(double at0, double at1) { return {at0, at1 - at0, 0.0, 0.0, 0.0, 0.0}; }

Poly operator+(Poly a, const Poly& b) {
  for (int k = 0; k < 6; ++k) a[k] += b[k];
  return a;
}
Poly operator*(double c, Poly a) {
  for (double& v : a) v *= c;
  return a;
}

void keep_max(Extreme& x, double value, double s) {
  if (!x.s || value > x.value) x.value = value, x.s = s;
}
void keep_min(Extreme& x, double value, double s) {
  if (!x.s || value < x.value) x.value = value, x.s = s;
}

double factor_of(const model::MemberLoad& load, double load_factor) {
  return load.load_case == model::LoadCase::dead ? 1.0 : load_factor;
}

// Uplift below this fraction of the deflections' scale is round-off at a contact limit.
constexpr double uplift_round_off = 64 * std::numeric_limits<double>::epsilon();

}  // namespace

DesignValues recover_beam_statics(const model::MemberModel& model, const fe::Discretisation& d,
                                  const contact::ContactSolution& solution, const std::vector<PointReaction>& supports,
                                  double load_factor, Fields* fields) {
  DesignValues out;
  out.from_statics = true;
  const int elements = d.mesh.elements();
  const Eigen::VectorXd& u = solution.displacement;

  // Concentrated actions at nodes: the jumps of V and M there.
  std::vector<double> jump_v(elements + 1, 0.0), jump_m(elements + 1, 0.0);
  double force_terms = 0.0, moment_terms = 0.0;
  for (const model::MemberLoad& load : model.loads) {
    if (load.kind != model::LoadKind::force && load.kind != model::LoadKind::moment) continue;
    const int node = d.mesh.node_at(load.at);
    if (node < 0) continue;  // the mesh has a node at every load (mesh.hpp)
    const double value = load.value * factor_of(load, load_factor);
    if (load.kind == model::LoadKind::force)
      jump_v[node] -= value, force_terms += std::abs(value);
    else
      jump_m[node] -= value, moment_terms += std::abs(value);
  }
  for (const PointReaction& support : supports) {
    const int node = d.mesh.node_at(support.s);
    if (node < 0) continue;
    jump_v[node] += support.force;
    jump_m[node] -= support.moment;
    force_terms += std::abs(support.force);
    moment_terms += std::abs(support.moment);
  }

  // Per element: the distributed force p = r - q (r the foundation's reaction, upward; q the
  // applied load, toward the foundation), V = V0 + h int p, M = M0 + h int V + N (y - y0) with
  // y = w + w0 the axis' offset from the straight line (second order: the axial force's moment
  // at the deflected shape, 0 without N).
  const double axial_force = model.kind == model::StructureKind::beam ? model.axial_force(load_factor) : 0.0;
  std::vector<Poly> shear(elements), moment(elements), pressure(elements);
  // Sine loads per element (load, case factor): q, and their V and M from the element's start,
  // exact (MemberLoad::resultant, moment_about), added to the polynomials' values.
  std::vector<std::vector<std::pair<const model::MemberLoad*, double>>> sines(elements);
  const auto sine_q = [&](int e, double xi) {
    double sum = 0.0;
    for (const auto& [load, c] : sines[e]) sum += c * load->intensity(d.mesh.nodes[e] + xi * d.mesh.element_size(e));
    return sum;
  };
  const auto sine_v = [&](int e, double xi) {
    const double a = d.mesh.nodes[e], x = a + xi * d.mesh.element_size(e);
    double sum = 0.0;
    for (const auto& [load, c] : sines[e]) sum -= c * load->resultant(a, x);
    return sum;
  };
  const auto sine_m = [&](int e, double xi) {
    const double a = d.mesh.nodes[e], x = a + xi * d.mesh.element_size(e);
    double sum = 0.0;
    for (const auto& [load, c] : sines[e]) sum -= c * load->moment_about(x, a, x);
    return sum;
  };
  std::vector<double> v_start(elements), m_start(elements), v_end(elements), m_end(elements);
  double v = 0.0, m = 0.0, w_scale = 0.0, g_scale = 0.0;
  for (int e = 0; e < elements; ++e) {
    const double a = d.mesh.nodes[e], h = d.mesh.element_size(e);
    v += jump_v[e];
    m += jump_m[e];
    const fe::HermiteCubic n0 = fe::hermite_cubic(0.0, h);
    const std::vector<int> dofs = d.element_dofs(e);
    const Eigen::Vector4d wd(u[dofs[0]], u[dofs[1]], u[dofs[2]], u[dofs[3]]);
    const Poly w = taylor(n0.value.dot(wd), n0.d1.dot(wd), n0.d2.dot(wd), n0.d3.dot(wd), h);
    const Poly g = linear(model.ground_gap_in(a, h, 0.0), model.ground_gap_in(a, h, 1.0));
    w_scale = std::max({w_scale, std::abs(w[0]), std::abs(eval(w, 1.0))});
    g_scale = std::max({g_scale, std::abs(g[0]), std::abs(g[0] + g[1])});
    Poly r = linear(reaction_at(d, solution.reaction, e, 0.0), reaction_at(d, solution.reaction, e, 1.0));
    if (const double kt = d.element_tension_k[e]; kt != 0.0) r = r + kt * (w + (-1.0) * g);
    Poly q{};
    const double middle = a + 0.5 * h;
    for (const model::MemberLoad& load : model.loads) {
      // As the assembly applies it: on the elements whose middle the load covers.
      if (!load.is_distributed_force() || middle < load.from || middle > load.to) continue;
      const double c = factor_of(load, load_factor);
      if (load.kind == model::LoadKind::sine)
        sines[e].push_back({&load, c});  // not a polynomial: its V and M added in closed form
      else
        q = q + linear(c * load.intensity(a), c * load.intensity(a + h));
    }
    const Poly p = r + (-1.0) * q;
    for (double xi : {0.0, 0.5, 1.0})
      force_terms += h / 3.0 * (std::abs(eval(r, xi)) + std::abs(eval(q, xi)) + std::abs(sine_q(e, xi)));
    pressure[e] = r;
    shear[e] = integral(h * p);
    shear[e][0] = v;
    moment[e] = integral(h * shear[e]);
    if (axial_force != 0.0) {
      // w0 linear between the element's ends: exact where its table's points are nodes (a
      // sampled shape's kinks inside an element move M there by N times w0's deviation from
      // the chord; the ends, and so the closure, stay exact).
      const Poly y = w + linear(model.initial_shape(a), model.initial_shape(a + h));
      moment[e] = moment[e] + axial_force * (y + Poly{-eval(y, 0.0)});
      moment_terms += std::abs(axial_force) * (std::abs(eval(y, 1.0)) + std::abs(eval(y, 0.0)));
    }
    moment[e][0] = m;
    v_start[e] = v, m_start[e] = m;
    v = v_end[e] = eval(shear[e], 1.0) + sine_v(e, 1.0);
    m = m_end[e] = eval(moment[e], 1.0) + sine_m(e, 1.0);
  }
  v += jump_v[elements];
  m += jump_m[elements];
  const double length = d.mesh.nodes.back() - d.mesh.nodes.front();
  out.shear_closure = force_terms > 0.0 ? std::abs(v) / force_terms : 0.0;
  const double moment_scale = force_terms * length + moment_terms;
  out.moment_closure = moment_scale > 0.0 ? std::abs(m) / moment_scale : 0.0;

  // The extremes.
  for (int e = 0; e < elements; ++e) {
    const double a = d.mesh.nodes[e], h = d.mesh.element_size(e);
    // M' = h V + N y' (h V alone without N, whose zeros are taken from V itself).
    if (sines[e].empty()) {
      for (double xi : sign_changes(axial_force != 0.0 ? derivative(moment[e]) : shear[e])) {
        const double value = eval(moment[e], xi);
        keep_max(out.moment_max, value, a + xi * h);
        keep_min(out.moment_min, value, a + xi * h);
      }
      for (double xi : candidates(shear[e])) keep_max(out.shear_max_abs, std::abs(eval(shear[e], xi)), a + xi * h);
    } else {  // with a sine's exact V and M: their derivatives' sign changes by bisection
      const Poly dm = derivative(moment[e]), dv = derivative(shear[e]);
      for (double xi : sign_changes_of([&](double t) { return eval(dm, t) + h * sine_v(e, t); })) {
        const double value = eval(moment[e], xi) + sine_m(e, xi);
        keep_max(out.moment_max, value, a + xi * h);
        keep_min(out.moment_min, value, a + xi * h);
      }
      std::vector<double> at{0.0, 1.0};
      for (double xi : sign_changes_of([&](double t) { return eval(dv, t) - h * sine_q(e, t); })) at.push_back(xi);
      for (double xi : at) keep_max(out.shear_max_abs, std::abs(eval(shear[e], xi) + sine_v(e, xi)), a + xi * h);
    }
    // Element ends: the values on this element's side of the node (jumps are between elements).
    keep_max(out.moment_max, m_start[e], a), keep_min(out.moment_min, m_start[e], a);
    keep_max(out.moment_max, m_end[e], a + h), keep_min(out.moment_min, m_end[e], a + h);
    if (d.foundation_on_element[e] || d.element_tension_k[e] != 0.0)
      for (double xi : candidates(pressure[e])) keep_max(out.pressure_max, eval(pressure[e], xi), a + xi * h);
    // Uplift over the foundation's extent (a limit-fitted lift-off element included).
    if (model.k_at(a + 0.5 * h) > 0.0) {
      const std::vector<int> dofs = d.element_dofs(e);
      const Eigen::Vector4d wd(u[dofs[0]], u[dofs[1]], u[dofs[2]], u[dofs[3]]);
      const fe::HermiteCubic n0 = fe::hermite_cubic(0.0, h);
      const Poly lift = linear(model.ground_gap_in(a, h, 0.0), model.ground_gap_in(a, h, 1.0)) +
                        (-1.0) * taylor(n0.value.dot(wd), n0.d1.dot(wd), n0.d2.dot(wd), n0.d3.dot(wd), h);
      for (double xi : candidates(lift)) {
        const double value = eval(lift, xi);
        if (value > uplift_round_off * std::max(w_scale, g_scale)) keep_max(out.uplift_max, value, a + xi * h);
      }
    }
  }
  if (!out.pressure_max.s) out.pressure_max = {0.0, std::nullopt};
  if (!out.uplift_max.s) out.uplift_max = {0.0, std::nullopt};

  if (fields && !fields->s.empty()) {
    // The samples in sample_fields' order: per element its samples, a jump node's left value
    // first, and the member's end.
    std::vector<char> jumps(d.mesh.nodes.size(), 0);
    int jump_count = 0;
    for (int i = 0; i + 1 < d.reactions(); ++i)
      if (d.reaction_nodes[i] == d.reaction_nodes[i + 1] && !jumps[d.reaction_nodes[i]])
        jumps[d.reaction_nodes[i]] = 1, ++jump_count;
    const int per_element = (static_cast<int>(fields->s.size()) - 1 - jump_count) / elements;
    std::vector<double> vs, ms;
    vs.reserve(fields->s.size()), ms.reserve(fields->s.size());
    auto add = [&](int e, double xi) {
      vs.push_back(eval(shear[e], xi) + sine_v(e, xi));
      ms.push_back(eval(moment[e], xi) + sine_m(e, xi));
    };
    for (int e = 0; e < elements; ++e) {
      if (e > 0 && jumps[e]) add(e - 1, 1.0);
      for (int i = 0; i < per_element; ++i) add(e, static_cast<double>(i) / per_element);
    }
    add(elements - 1, 1.0);
    if (vs.size() == fields->s.size()) {
      fields->shear_force = std::move(vs);
      fields->bending_moment = std::move(ms);
    }
  }
  return out;
}

DesignValues recover_beam_statics(const model::MemberModel& model, const std::function<double(double)>& reaction,
                                  const std::vector<double>& reaction_breaks,
                                  const std::vector<PointReaction>& supports, double load_factor, Fields& fields) {
  DesignValues out;
  out.from_statics = true;
  // Concentrated actions by position: (s, jump of V, jump of M).
  struct Jump {
    double s, v, m;
  };
  std::vector<Jump> jumps;
  double force_terms = 0.0, moment_terms = 0.0;
  for (const model::MemberLoad& load : model.loads) {
    const double value = load.value * factor_of(load, load_factor);
    if (load.kind == model::LoadKind::force) jumps.push_back({load.at, -value, 0.0}), force_terms += std::abs(value);
    if (load.kind == model::LoadKind::moment) jumps.push_back({load.at, 0.0, -value}), moment_terms += std::abs(value);
  }
  for (const PointReaction& support : supports) {
    jumps.push_back({support.s, support.force, -support.moment});
    force_terms += std::abs(support.force);
    moment_terms += std::abs(support.moment);
  }
  std::vector<double> points = fields.s;
  for (const Jump& j : jumps) points.push_back(j.s);
  for (const model::MemberLoad& load : model.loads)
    if (load.is_distributed_force()) points.insert(points.end(), {load.from, load.to});
  for (const model::FoundationPiece& piece : model.pieces()) points.insert(points.end(), {piece.begin, piece.end});
  points.insert(points.end(), reaction_breaks.begin(), reaction_breaks.end());
  std::erase_if(points, [&](double s) { return !(s >= model.s_begin && s <= model.s_end); });
  std::sort(points.begin(), points.end());
  points.erase(std::unique(points.begin(), points.end()), points.end());

  // q at s inside an interval (load ranges end at breakpoints): linear loads (sine: false) or sines.
  auto applied = [&](double s, bool sine) {
    double q = 0.0;
    for (const model::MemberLoad& load : model.loads)
      if (load.is_distributed_force() && (load.kind == model::LoadKind::sine) == sine && s >= load.from && s <= load.to)
        q += factor_of(load, load_factor) * load.intensity(s);
    return q;
  };
  // V and M at x in [a, b] from their values at a (no breakpoint inside): the reaction and the
  // linear loads by Gauss (exact for the loads), the sines' resultant and moment in closed form.
  auto advance = [&](double a, double x, double v, double m, bool count = false) {
    double dv = 0.0, dm = 0.0;
    for (const fe::GaussPoint& g : fe::gauss5) {
      const double t = a + g.xi * (x - a), r = reaction(t), q = applied(t, false), weight = g.weight * (x - a);
      const double p = r - q;
      dv += weight * p;
      dm += weight * (x - t) * p;
      if (count) force_terms += weight * (std::abs(r) + std::abs(q) + std::abs(applied(t, true)));
    }
    for (const model::MemberLoad& load : model.loads)
      if (load.kind == model::LoadKind::sine) {
        dv -= factor_of(load, load_factor) * load.resultant(a, x);
        dm -= factor_of(load, load_factor) * load.moment_about(x, a, x);
      }
    return std::pair{v + dv, m + v * (x - a) + dm};
  };
  double v = 0.0, m = 0.0;
  std::vector<double> v_right(points.size()), m_right(points.size()), v_left(points.size()), m_left(points.size());
  auto consider = [&](double value_v, double value_m, double s) {
    keep_max(out.moment_max, value_m, s);
    keep_min(out.moment_min, value_m, s);
    keep_max(out.shear_max_abs, std::abs(value_v), s);
  };
  for (std::size_t i = 0; i < points.size(); ++i) {
    v_left[i] = v, m_left[i] = m;
    if (i > 0) consider(v, m, points[i]);
    for (const Jump& j : jumps)
      if (j.s == points[i]) v += j.v, m += j.m;
    v_right[i] = v, m_right[i] = m;
    if (i + 1 == points.size()) break;
    consider(v, m, points[i]);
    if (model.k_at(points[i]) > 0.0) keep_max(out.pressure_max, reaction(points[i]), points[i]);
    const double a = points[i], b = points[i + 1];
    const auto [vb, mb] = advance(a, b, v, m, true);
    if ((v < 0.0) != (vb < 0.0) && v != 0.0 && vb != 0.0) {  // V = 0 inside: M's extreme
      double lo = a, hi = b;
      for (int step = 0; step < 100; ++step) {
        const double mid = 0.5 * (lo + hi);
        if (mid <= lo || mid >= hi) break;
        ((advance(a, mid, v, m).first < 0.0) == (v < 0.0) ? lo : hi) = mid;
      }
      const double root = 0.5 * (lo + hi);
      consider(0.0, advance(a, root, v, m).second, root);
    }
    v = vb, m = mb;
  }
  if (model.k_at(points.back()) > 0.0) keep_max(out.pressure_max, reaction(points.back()), points.back());
  out.shear_closure = force_terms > 0.0 ? std::abs(v) / force_terms : 0.0;
  const double moment_scale = force_terms * (model.s_end - model.s_begin) + moment_terms;
  out.moment_closure = moment_scale > 0.0 ? std::abs(m) / moment_scale : 0.0;

  // The samples: right of a point's jumps, the end left of its own.
  std::vector<double> vs, ms;
  for (std::size_t k = 0; k < fields.s.size(); ++k) {
    const std::size_t i = std::lower_bound(points.begin(), points.end(), fields.s[k]) - points.begin();
    const bool end = k + 1 == fields.s.size();
    vs.push_back(end ? v_left[i] : v_right[i]);
    ms.push_back(end ? m_left[i] : m_right[i]);
  }
  fields.shear_force = std::move(vs);
  fields.bending_moment = std::move(ms);
  // Uplift at the samples (the Ritz model's w between them is smooth).
  const DesignValues sampled = design_from_samples(model, fields);
  out.uplift_max = sampled.uplift_max;
  if (!out.pressure_max.s) out.pressure_max = {0.0, std::nullopt};
  return out;
}

DesignValues design_from_samples(const model::MemberModel& model, const Fields& f) {
  DesignValues out;
  double scale = 0.0;
  for (std::size_t i = 0; i < f.s.size(); ++i) scale = std::max({scale, std::abs(f.w[i]), model.ground_gap(f.s[i])});
  for (std::size_t i = 0; i < f.s.size(); ++i) {
    const double s = f.s[i];
    keep_max(out.moment_max, f.bending_moment[i], s);
    keep_min(out.moment_min, f.bending_moment[i], s);
    keep_max(out.shear_max_abs, std::abs(f.shear_force[i]), s);
    if (f.reaction[i] != 0.0) keep_max(out.pressure_max, f.reaction[i], s);
    const double lift = model.ground_gap(s) - f.w[i];
    if (model.k_at(s) > 0.0 && lift > uplift_round_off * scale) keep_max(out.uplift_max, lift, s);
  }
  if (!out.pressure_max.s) out.pressure_max = {0.0, std::nullopt};
  if (!out.uplift_max.s) out.uplift_max = {0.0, std::nullopt};
  return out;
}

DesignTable user_design(const DesignValues& design, const model::MemberModel& model) {
  const model::Scales& scales = model.scales;
  auto convert = [&](const Extreme& x, double factor) {
    DesignValue v{x.value * factor, std::nullopt};
    if (x.s) v.at = model.user_from_s(*x.s);
    return v;
  };
  DesignTable t;
  t.moment_max = convert(design.moment_max, scales.moment());
  t.moment_min = convert(design.moment_min, scales.moment());
  t.shear_max_abs = convert(design.shear_max_abs, scales.force());
  t.pressure_max = convert(design.pressure_max, scales.force_per_length());
  t.uplift_max = convert(design.uplift_max, scales.displacement());
  t.shear_closure = design.shear_closure;
  t.moment_closure = design.moment_closure;
  t.from_statics = design.from_statics;
  return t;
}

}  // namespace liftoff::post
