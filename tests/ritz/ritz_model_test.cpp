// The Ritz model: analytic derivatives against finite differences, convergence with the number
// of modes against closed forms and against independent finite-element solutions, the seed's
// arch, and misuse.
#include "ritz/ritz_model.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "core/error.hpp"
#include "fe/discretisation.hpp"
#include "fe/shape_functions.hpp"
#include "model/from_scene.hpp"
#include "support/scenes.hpp"

using namespace liftoff;
using namespace liftoff::ritz;
using Eigen::MatrixXd;
using Eigen::VectorXd;
using model::EndSupport;

namespace {

constexpr double pi = std::numbers::pi;
constexpr double degree = pi / 180.0;

model::MemberLoad force(double at, double value, model::LoadCase c = model::LoadCase::live) {
  model::MemberLoad l;
  l.kind = model::LoadKind::force;
  l.at = at;
  l.value = value;
  l.load_case = c;
  return l;
}

model::MemberLoad moment(double at, double value, model::LoadCase c = model::LoadCase::live) {
  model::MemberLoad l = force(at, value, c);
  l.kind = model::LoadKind::moment;
  return l;
}

model::MemberLoad uniform(double from, double to, double value, model::LoadCase c = model::LoadCase::live) {
  model::MemberLoad l = force(0.0, value, c);
  l.kind = model::LoadKind::uniform;
  l.from = from;
  l.to = to;
  return l;
}

model::MemberModel beam(EndSupport left, EndSupport right, double k, std::vector<model::MemberLoad> loads) {
  model::MemberModel m;
  m.kind = model::StructureKind::beam;
  m.left = left;
  m.right = right;
  m.k = k;
  m.loads = std::move(loads);
  return m;
}

model::MemberModel arch(EndSupport left, EndSupport right, double gamma_deg, double membrane, double k,
                        std::vector<model::MemberLoad> loads) {
  model::MemberModel m;
  m.kind = model::StructureKind::arch;
  m.s_begin = m.foundation_begin = -gamma_deg * degree;
  m.s_end = m.foundation_end = gamma_deg * degree;
  m.membrane_stiffness = membrane;
  m.left = left;
  m.right = right;
  m.k = k;
  m.loads = std::move(loads);
  return m;
}

// The seed's arch (sec. 5): R/h = 500, EI = 1.4, EA = 420, R = 100, so EA R^2/EI = 3e6;
// gamma = 10 degrees; k = K R^4/EI = 1e6; crown force P = 0.1, i.e. P R^2/EI = 0.1e4/1.4.
model::MemberModel seed_arch(EndSupport ends) {
  return arch(ends, ends, 10.0, 420.0 * 1e4 / 1.4, 1e6, {force(0.0, 0.1 * 1e4 / 1.4)});
}

// A random admissible point near the physics: random limits (increasing, jittered), the
// amplitudes that minimise the energy for them, perturbed by 20%.
VectorXd random_point(const RitzModel& model, const model::MemberModel& member, std::mt19937& rng, double lambda) {
  std::uniform_real_distribution<double> jitter(-0.3, 0.3), unit(-1.0, 1.0);
  const int m = model.limits();
  VectorXd limits(m);
  const double a = member.foundation_begin, b = member.foundation_end;
  for (int i = 0; i < m; ++i) limits[i] = a + (b - a) * (i + 1 + jitter(rng)) / (m + 1);
  VectorXd x = model.minimiser_for_limits(limits, lambda).value();
  const double scale = x.head(model.amplitudes()).cwiseAbs().maxCoeff();
  for (int i = 0; i < model.amplitudes(); ++i) x[i] += 0.2 * scale * unit(rng);
  REQUIRE(model.admissible(x));
  return x;
}

// Steps for central differences: 1e-5 of the amplitudes' size, 1e-5 of the foundation's extent
// for the limits.
VectorXd steps(const RitzModel& model, const model::MemberModel& member, const VectorXd& x) {
  VectorXd h(x.size());
  h.head(model.amplitudes()).setConstant(1e-5 * x.head(model.amplitudes()).cwiseAbs().maxCoeff());
  h.tail(model.limits()).setConstant(1e-5 * (member.foundation_end - member.foundation_begin));
  return h;
}

template <typename F>
MatrixXd central_differences(F f, const VectorXd& x, const VectorXd& h) {
  MatrixXd d(f(x).size(), x.size());
  for (int j = 0; j < x.size(); ++j) {
    VectorXd plus = x, minus = x;
    plus[j] += h[j];
    minus[j] -= h[j];
    d.col(j) = (f(plus) - f(minus)) / (2.0 * h[j]);
  }
  return d;
}

// Compares block by block (amplitude/limit rows x amplitude/limit columns), each relative to its
// own largest entry: the blocks have different units (force, deflection, ...).
// Tolerance: a central difference with step h errs by h^2/6 |f'''| (truncation) + eps |f|/h
// (round-off). With h = 1e-5 of each variable's scale, truncation is ~1e-10 times (scale x
// frequency)^2 (below 1e-7 for the frequencies used here) and round-off ~1e-11 relative, so
// 1e-6 relative leaves a wide margin while catching any wrong term (which errs by O(1)).
void check_blocks(const MatrixXd& analytic, const MatrixXd& fd, int rows_a, int cols_a, double tol = 1e-6) {
  REQUIRE(analytic.rows() == fd.rows());
  REQUIRE(analytic.cols() == fd.cols());
  const int rs[2] = {0, rows_a}, rn[2] = {rows_a, static_cast<int>(analytic.rows()) - rows_a};
  const int cs[2] = {0, cols_a}, cn[2] = {cols_a, static_cast<int>(analytic.cols()) - cols_a};
  for (int i = 0; i < 2; ++i) {
    for (int j = 0; j < 2; ++j) {
      if (rn[i] == 0 || cn[j] == 0) continue;
      const MatrixXd a = analytic.block(rs[i], cs[j], rn[i], cn[j]), f = fd.block(rs[i], cs[j], rn[i], cn[j]);
      const double scale = std::max(a.cwiseAbs().maxCoeff(), 1e-12 * analytic.cwiseAbs().maxCoeff());
      CAPTURE(i, j, scale, (a - f).cwiseAbs().maxCoeff());
      CHECK((a - f).cwiseAbs().maxCoeff() <= tol * scale);
    }
  }
}

struct DerivativeCase {
  std::string name;
  model::MemberModel member;
  int modes;
  Topology topology;
};

std::vector<DerivativeCase> derivative_cases() {
  const std::vector<model::MemberLoad> beam_loads = {force(0.3, 2.0), moment(0.8, -0.7), uniform(0.1, 0.6, 5.0),
                                                     force(0.55, 1.0, model::LoadCase::dead)};
  model::MemberModel partial = beam(EndSupport::pinned, EndSupport::clamped, 1e4, beam_loads);
  partial.foundation_begin = 0.05;
  partial.foundation_end = 0.9;
  const std::vector<model::MemberLoad> arch_loads = {force(0.0, 700.0), force(3.0 * degree, 150.0),
                                                     uniform(-6.0 * degree, 2.0 * degree, 300.0)};
  std::vector<model::MemberLoad> pinned_arch_loads = arch_loads;
  pinned_arch_loads.push_back(moment(-4.0 * degree, 20.0));
  return {
      {"beam pinned-pinned, one contact region",
       beam(EndSupport::pinned, EndSupport::pinned, 1e4, beam_loads),
       8,
       {false, 2}},
      {"beam pinned-pinned, two contact regions",
       beam(EndSupport::pinned, EndSupport::pinned, 1e4, beam_loads),
       8,
       {true, 2}},
      {"beam pinned-clamped on part of the span, one limit", partial, 6, {true, 1}},
      {"beam free-free, two contact regions", beam(EndSupport::free, EndSupport::free, 1e3, beam_loads), 9, {true, 3}},
      {"arch roller (seed stiffness), one contact region",
       arch(EndSupport::roller, EndSupport::roller, 10, 3e6, 1e6, arch_loads),
       6,
       {false, 2}},
      {"arch roller (seed stiffness), two contact regions",
       arch(EndSupport::roller, EndSupport::roller, 10, 3e6, 1e6, arch_loads),
       6,
       {true, 2}},
      {"arch pinned-clamped with a moment, one contact region",
       arch(EndSupport::pinned, EndSupport::clamped, 10, 3e6, 1e6, pinned_arch_loads),
       5,
       {false, 2}},
  };
}

// Tiny independent reference: Hermite cubic beam elements with a consistent bilateral Winkler
// foundation, point force at a node; dense solve. Deflection error O(h^4).
VectorXd hermite_beam(EndSupport left, EndSupport right, double k, int elements, double load_at, double load) {
  const int n = 2 * (elements + 1);
  const double h = 1.0 / elements;
  MatrixXd kg = MatrixXd::Zero(n, n);
  Eigen::Matrix4d ke, me;
  ke << 12, 6 * h, -12, 6 * h, 6 * h, 4 * h * h, -6 * h, 2 * h * h, -12, -6 * h, 12, -6 * h, 6 * h, 2 * h * h, -6 * h,
      4 * h * h;
  ke /= h * h * h;
  me << 156, 22 * h, 54, -13 * h, 22 * h, 4 * h * h, 13 * h, -3 * h * h, 54, 13 * h, 156, -22 * h, -13 * h, -3 * h * h,
      -22 * h, 4 * h * h;
  me *= k * h / 420.0;
  for (int e = 0; e < elements; ++e) kg.block(2 * e, 2 * e, 4, 4) += ke + me;
  VectorXd f = VectorXd::Zero(n);
  f[2 * static_cast<int>(std::lround(load_at * elements))] = load;
  auto fix = [&](int dof) {
    kg.row(dof).setZero();
    kg.col(dof).setZero();
    kg(dof, dof) = 1.0;
    f[dof] = 0.0;
  };
  auto support = [&](EndSupport e, int node) {
    if (e != EndSupport::free) fix(2 * node);
    if (e == EndSupport::clamped) fix(2 * node + 1);
  };
  support(left, 0);
  support(right, elements);
  return kg.ldlt().solve(f);
}

// Slope of log(error) against log(N).
double observed_order(const std::vector<int>& n, const std::vector<double>& error) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < n.size(); ++i) {
    const double x = std::log(n[i]), y = std::log(error[i]);
    sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  const double m = static_cast<double>(n.size());
  return -(m * sxy - sx * sy) / (m * sxx - sx * sx);
}

// w at s of an independent FE solution of the arch: the project's arch elements (fe::discretise:
// Hermite w, quartic u, locking-free) with a bilateral Winkler foundation added as the consistent
// Hermite matrix k int N_w^T N_w (not the seed's mixed reaction form, whose saddle-point system
// loses digits to round-off on fine meshes); SPD sparse solve. Deflection error O(h^4); 320
// elements, as round-off (EA R^2/EI = 3e6, element stiffness ~ 1/h^3) costs digits beyond ~400.
std::vector<double> fe_arch_deflection(const model::MemberModel& member, int elements, const std::vector<double>& at) {
  const fe::Discretisation d = fe::discretise(member, elements);
  std::vector<Eigen::Triplet<double>> t;
  for (int c = 0; c < d.stiffness.outerSize(); ++c)
    for (fe::SparseMatrix::InnerIterator it(d.stiffness, c); it; ++it) t.emplace_back(it.row(), it.col(), it.value());
  for (int e = 0; e < d.mesh.elements(); ++e) {
    const double h = d.mesh.element_size(e);
    Eigen::Matrix4d foundation = Eigen::Matrix4d::Zero();
    for (const fe::GaussPoint& g : fe::gauss5) {
      const Eigen::Vector4d n = fe::hermite_cubic(g.xi, h).value;
      foundation += g.weight * h * member.k * n * n.transpose();
    }
    const std::vector<int> dofs = d.element_dofs(e);  // the first four are w's Hermite dofs
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) {
        const int ei = d.equation_of_dof[dofs[i]], ej = d.equation_of_dof[dofs[j]];
        if (ei >= 0 && ej >= 0) t.emplace_back(ei, ej, foundation(i, j));
      }
  }
  fe::SparseMatrix a(d.equations, d.equations);
  a.setFromTriplets(t.begin(), t.end());
  const Eigen::SimplicialLDLT<fe::SparseMatrix> ldlt(a);
  const VectorXd all = d.expand(ldlt.solve(d.load(1.0)));
  std::vector<double> out;
  for (double s : at) {
    const int node = d.mesh.node_at(s);
    REQUIRE(node >= 0);
    out.push_back(all[d.deflection_dof(node)]);
  }
  return out;
}

}  // namespace

TEST_CASE("ritz model: gradient and Hessian agree with finite differences of the energy", "[ritz][model]") {
  std::mt19937 rng(4242);
  for (const DerivativeCase& c : derivative_cases()) {
    SECTION(c.name) {
      const RitzModel model(c.member, c.modes, c.topology);
      const double lambda = 1.7;
      for (int trial = 0; trial < 3; ++trial) {
        const VectorXd x = random_point(model, c.member, rng, lambda);
        const VectorXd h = steps(model, c.member, x);
        const auto energy = [&](const VectorXd& y) { return VectorXd::Constant(1, model.energy(y, lambda)); };
        const auto gradient = [&](const VectorXd& y) { return model.gradient(y, lambda); };
        const VectorXd g = model.gradient(x, lambda);
        const MatrixXd g_fd = central_differences(energy, x, h).transpose();
        check_blocks(g, g_fd, model.amplitudes(), 1);
        const MatrixXd hess = model.hessian(x, lambda);
        CHECK((hess - hess.transpose()).cwiseAbs().maxCoeff() <= 1e-14 * hess.cwiseAbs().maxCoeff());
        check_blocks(hess, central_differences(gradient, x, h), model.amplitudes(), model.amplitudes());
      }
    }
  }
}

TEST_CASE("ritz model: the regularised Jacobian agrees with finite differences of the residual", "[ritz][model]") {
  std::mt19937 rng(99);
  const Enrichment enrichment = GENERATE(Enrichment::none, Enrichment::load_points);
  CAPTURE(static_cast<int>(enrichment));
  for (const DerivativeCase& c : derivative_cases()) {
    SECTION(c.name) {
      const RitzModel model(c.member, c.modes, c.topology, enrichment);
      const double lambda = 0.6;
      const VectorXd x = random_point(model, c.member, rng, lambda);
      const auto residual = [&](const VectorXd& y) {
        VectorXd f;
        model.residual(y, lambda, f);
        return f;
      };
      MatrixXd j;
      model.jacobian(x, lambda, j);
      check_blocks(j, central_differences(residual, x, steps(model, c.member, x)), model.amplitudes(),
                   model.amplitudes());
      // The amplitude rows are the energy gradient; the limit rows are w(t_m).
      const VectorXd f = residual(x), g = model.gradient(x, lambda);
      CHECK((f.head(model.amplitudes()) - g.head(model.amplitudes())).norm() == 0.0);
      for (int m = 0; m < model.limits(); ++m)
        CHECK(f[model.limit_offset() + m] == model.w(x, x[model.limit_offset() + m]));
      // The residual is affine in lambda with slope residual_lambda_derivative.
      const VectorXd slope = model.residual_lambda_derivative(x);
      VectorXd f2;
      model.residual(x, lambda + 0.5, f2);
      CHECK(((f2 - f) / 0.5 - slope).cwiseAbs().maxCoeff() <= 1e-9 * f.cwiseAbs().maxCoeff());
      CHECK(slope.tail(model.limits()).isZero(0.0));
    }
  }
}

TEST_CASE("ritz model: at a solution the Jacobian is block triangular", "[ritz][model]") {
  // Put the limits at roots of w: then sigma k phi(t) w(t) = 0 in the amplitude-limit block.
  const model::MemberModel member = seed_arch(EndSupport::roller);
  const RitzModel model(member, 10, {false, 2});
  VectorXd limits(2);
  limits << -5.0 * degree, 5.0 * degree;
  VectorXd x = model.minimiser_for_limits(limits, 1.0).value();
  for (int m = 0; m < 2; ++m) {  // move each limit onto the nearest root of w (bisection)
    double a = x[model.limit_offset() + m] - 3 * degree, b = x[model.limit_offset() + m] + 3 * degree;
    REQUIRE(model.w(x, a) * model.w(x, b) < 0);
    for (int it = 0; it < 200; ++it) {
      const double c = 0.5 * (a + b);
      (model.w(x, a) * model.w(x, c) <= 0 ? b : a) = c;
    }
    x[model.limit_offset() + m] = 0.5 * (a + b);
  }
  MatrixXd j;
  model.jacobian(x, 1.0, j);
  const double coupling = j.block(0, model.limit_offset(), model.amplitudes(), 2).cwiseAbs().maxCoeff();
  CHECK(coupling <= 1e-9 * j.cwiseAbs().maxCoeff());
}

TEST_CASE("ritz model: simply supported beam, central load, no contact: w(1/2) -> 1/48 like N^-3", "[ritz][model]") {
  // Two ways to have no contact: no foundation (k = 0), or a foundation entirely lifted off.
  const auto topology = GENERATE(Topology{true, 0}, Topology{false, 0});
  const double k = topology.first_in_contact ? 0.0 : 1e4;
  const model::MemberModel member = beam(EndSupport::pinned, EndSupport::pinned, k, {force(0.5, 1.0)});
  std::vector<int> ns;
  std::vector<double> errors;
  fmt::print("simply supported beam, central load (k = {}, {}):\n     N   w(1/2) - 1/48\n", k, to_string(topology));
  for (int n : {1, 3, 5, 9, 17, 33, 65}) {
    const RitzModel model(member, n, topology);
    const VectorXd x = model.minimiser_for_limits(VectorXd(0), 1.0).value();
    const double error = std::abs(model.w(x, 0.5) - 1.0 / 48.0);
    fmt::print("  {:4d}   {:.3e}\n", n, error);
    if (!errors.empty()) CHECK(error < errors.back());
    ns.push_back(n);
    errors.push_back(error);
  }
  // The exact tail: sum over odd i > N of 2/(pi^4 i^4), about 1/(3 pi^4 N^3).
  // Order over the last three N (the first ones are pre-asymptotic).
  const double order = observed_order({ns.end() - 3, ns.end()}, {errors.end() - 3, errors.end()});
  fmt::print("  observed order {:.2f}\n", order);
  CHECK(order >= 2.9);
  CHECK(errors.back() <= 2e-8);
}

TEST_CASE("ritz model: closed-form deflections of beams without a foundation", "[ritz][model]") {
  struct Case {
    EndSupport left, right;
    double at, exact;
    const char* name;
  };
  const Case cases[] = {
      {EndSupport::clamped, EndSupport::free, 1.0, 1.0 / 3.0, "cantilever, tip load: P/3 at the tip"},
      {EndSupport::free, EndSupport::clamped, 0.0, 1.0 / 3.0, "cantilever (mirror), tip load: P/3 at the tip"},
      {EndSupport::clamped, EndSupport::clamped, 0.5, 1.0 / 192.0, "clamped-clamped, central load: P/192"},
      {EndSupport::pinned, EndSupport::clamped, 0.5, 7.0 / 768.0, "propped cantilever, central load: 7P/768"},
      {EndSupport::clamped, EndSupport::pinned, 0.5, 7.0 / 768.0, "propped cantilever (mirror): 7P/768"},
  };
  for (const Case& c : cases) {
    const model::MemberModel member = beam(c.left, c.right, 0.0, {force(c.at, 1.0)});
    fmt::print("{}:\n     N   relative error\n", c.name);
    std::vector<int> ns;
    std::vector<double> errors;
    for (int n : {2, 4, 8, 16, 32, 64}) {
      const RitzModel model(member, n, {true, 0});
      const VectorXd x = model.minimiser_for_limits(VectorXd(0), 1.0).value();
      const double error = std::abs(model.w(x, c.at) / c.exact - 1.0);
      fmt::print("  {:4d}   {:.3e}\n", n, error);
      ns.push_back(n);
      errors.push_back(error);
    }
    // Order over the last three N (the first ones are pre-asymptotic).
    const double order = observed_order({ns.end() - 3, ns.end()}, {errors.end() - 3, errors.end()});
    fmt::print("  observed order {:.2f}\n", order);
    CAPTURE(c.name, order);
    CHECK(order >= 2.8);
    CHECK(errors.back() <= 1e-5);
  }
}

TEST_CASE("ritz model: beams with free ends on a bilateral foundation converge to an FE solution", "[ritz][model]") {
  // The free-end families (with their rigid motions) against the independent Hermite solution.
  struct Case {
    EndSupport left, right;
    double load_at;
  };
  const Case cases[] = {{EndSupport::free, EndSupport::free, 0.3},
                        {EndSupport::pinned, EndSupport::free, 0.7},
                        {EndSupport::free, EndSupport::pinned, 0.7},
                        {EndSupport::clamped, EndSupport::free, 0.4}};
  const double k = 200.0;
  for (const Case& c : cases) {
    model::MemberModel member = beam(c.left, c.right, k, {force(c.load_at, 1.0)});
    member.tensionless = false;
    const VectorXd reference = hermite_beam(c.left, c.right, k, 400, c.load_at, 1.0);
    const double w0 = reference[0], w1 = reference[2 * 400], wp = reference[2 * std::lround(c.load_at * 400)];
    fmt::print("{}-{} beam, k = {}, load at {}: relative error of w at (0, load, 1)\n", model::to_string(c.left),
               model::to_string(c.right), k, c.load_at);
    const double scale = std::max({std::abs(w0), std::abs(w1), std::abs(wp)});
    double last = 0.0;
    for (int n : {4, 8, 16, 32, 64}) {
      const RitzModel model(member, n, {true, 0});
      const VectorXd x = model.minimiser_for_limits(VectorXd(0), 1.0).value();
      const double e0 = std::abs(model.w(x, 0.0) - w0) / scale, ep = std::abs(model.w(x, c.load_at) - wp) / scale,
                   e1 = std::abs(model.w(x, 1.0) - w1) / scale;
      fmt::print("  {:4d}   {:.2e} {:.2e} {:.2e}\n", n, e0, ep, e1);
      last = std::max({e0, ep, e1});
    }
    CHECK(last <= 1e-5);  // the Hermite reference (400 elements) is good to about 1e-9
  }
  // A uniform load on a free-free beam is carried by a rigid translation q/k: exact for any N.
  model::MemberModel member = beam(EndSupport::free, EndSupport::free, k, {uniform(0.0, 1.0, 3.0)});
  member.tensionless = false;
  const RitzModel model(member, 5, {true, 0});
  const VectorXd x = model.minimiser_for_limits(VectorXd(0), 1.0).value();
  for (double s : {0.0, 0.37, 1.0}) CHECK(model.w(x, s) == Approx(3.0 / k).epsilon(1e-12));
}

TEST_CASE("ritz model: arches converge to the FE solution, without membrane locking", "[ritz][model]") {
  // EA R^2/EI = 3e6 (the seed's R/h = 500). A locking basis would be stiff by orders of magnitude
  // at these N; ours matches the locking-free FE arch elements.
  struct Case {
    EndSupport left, right;
    double k;
    double load_at_deg;
  };
  const Case cases[] = {{EndSupport::pinned, EndSupport::pinned, 0.0, 0.0},
                        {EndSupport::clamped, EndSupport::clamped, 0.0, 3.0},
                        // non-symmetric load: needs the antisymmetric half of the seed's family
                        {EndSupport::roller, EndSupport::roller, 1e6, 3.0},
                        {EndSupport::pinned, EndSupport::pinned, 1e6, -4.0},
                        // free ends: rigid motions only approximately in the span (see basis.hpp)
                        {EndSupport::free, EndSupport::free, 1e4, 3.0},
                        {EndSupport::pinned, EndSupport::free, 1e4, 3.0},
                        {EndSupport::clamped, EndSupport::roller, 1e5, -2.0}};
  for (const Case& c : cases) {
    model::MemberModel member = arch(c.left, c.right, 10.0, 3e6, c.k, {force(c.load_at_deg * degree, 500.0)});
    member.tensionless = false;
    const std::vector<double> at = {-5.0 * degree, c.load_at_deg * degree, 7.5 * degree};
    const std::vector<double> reference = fe_arch_deflection(member, 320, at);
    const double scale = std::max({std::abs(reference[0]), std::abs(reference[1]), std::abs(reference[2])});
    fmt::print("{}-{} arch, k = {}, load at {} deg: relative error of w at (-5, load, 7.5) deg vs FE (320 el.)\n",
               model::to_string(c.left), model::to_string(c.right), c.k, c.load_at_deg);
    double first = 0.0, last = 0.0;
    for (int n : {4, 8, 16, 32, 64}) {
      const RitzModel model(member, n, {true, 0});
      const VectorXd x = model.minimiser_for_limits(VectorXd(0), 1.0).value();
      double e = 0.0;
      std::string row;
      for (std::size_t i = 0; i < at.size(); ++i) {
        const double ei = std::abs(model.w(x, at[i]) - reference[i]) / scale;
        row += fmt::format(" {:.2e}", ei);
        e = std::max(e, ei);
      }
      fmt::print("  {:4d}  {}\n", n, row);
      if (n == 4) first = e;
      last = e;
    }
    // Pointwise deflections under a point load converge like N^-2.5 to N^-3.
    CHECK(last <= 1e-4);
    CHECK(last <= first / 100);
  }
}

TEST_CASE("ritz model: the seed's arch on rollers at a plausible point", "[ritz][model]") {
  const model::MemberModel member = seed_arch(EndSupport::roller);
  const RitzModel model(member, 12, {false, 2});  // lift-off | contact | lift-off
  VectorXd limits(2);
  limits << -4.0 * degree, 4.0 * degree;
  const VectorXd x = model.minimiser_for_limits(limits, 1.0).value();
  REQUIRE(model.admissible(x));
  VectorXd f;
  MatrixXd j;
  model.residual(x, 1.0, f);
  model.jacobian(x, 1.0, j);
  CHECK(f.allFinite());
  CHECK(j.allFinite());
  CHECK(f.head(model.amplitudes()).norm() <= 1e-8 * model.live_load().norm());  // the amplitudes minimise
  const Eigen::JacobiSVD<MatrixXd> svd(j);
  const double condition = svd.singularValues()(0) / svd.singularValues().tail(1)(0);
  CAPTURE(condition);
  CHECK(condition < 1e14);
  // The crown presses into the foundation, the contact piece is the middle one.
  CHECK(model.w(x, 0.0) > 0.0);
  REQUIRE(model.contact_pieces(x).size() == 1);
  CHECK(model.reaction(x, 0.0) == Approx(1e6 * model.w(x, 0.0)));
  CHECK(model.reaction(x, 8.0 * degree) == 0.0);

  // A few plain Newton steps on the regularised system (no line search but a step halving that
  // keeps the limits admissible) reach the solution quadratically; the FE/LCP solution of the
  // same scene has its contact limits at +-5.669 degrees and w(0) = 7.9969e-3.
  VectorXd y = x;
  std::vector<double> history;
  for (int it = 0; it < 30; ++it) {
    model.residual(y, 1.0, f);
    history.push_back(f.head(model.amplitudes()).norm() / model.live_load().norm() + f.tail(2).norm());
    if (history.back() < 1e-12) break;
    model.jacobian(y, 1.0, j);
    const VectorXd dy = j.fullPivLu().solve(-f);
    double step = 1.0;
    while (!model.admissible(y + step * dy)) step *= 0.5;
    y += step * dy;
  }
  fmt::print("seed arch on rollers, N = 12, Newton from limits +-4 deg: residuals");
  for (double r : history) fmt::print(" {:.1e}", r);
  fmt::print("\n  contact limits {:.6f} {:.6f} deg, w(0) = {:.6e}\n", y[model.limit_offset()] / degree,
             y[model.limit_offset() + 1] / degree, model.w(y, 0.0));
  CHECK(history.back() < 1e-12);
  CHECK(history.size() <= 10);
  CHECK(y[model.limit_offset() + 1] / degree == Approx(5.669).epsilon(0.01));
  CHECK(y[model.limit_offset()] == Approx(-y[model.limit_offset() + 1]).epsilon(1e-10));
  CHECK(model.w(y, 0.0) == Approx(7.9969e-3).epsilon(0.01));
}

TEST_CASE("ritz model: pieces, admissibility and layout", "[ritz][model]") {
  const model::MemberModel member = beam(EndSupport::pinned, EndSupport::pinned, 1e3, {force(0.5, 1.0)});
  const RitzModel model(member, 4, {true, 2});
  CHECK(model.unknowns() == 6);
  CHECK(model.limit_offset() == 4);
  CHECK(to_string(model.topology()) == "contact | lift-off | contact (2 limits)");
  VectorXd x = VectorXd::Zero(6);
  x[4] = 0.3, x[5] = 0.6;
  CHECK(model.admissible(x));
  const auto pieces = model.pieces(x);
  REQUIRE(pieces.size() == 3);
  CHECK(pieces[0].begin == 0.0);
  CHECK(pieces[0].end == 0.3);
  CHECK(pieces[0].in_contact);
  CHECK_FALSE(pieces[1].in_contact);
  CHECK(pieces[2].end == 1.0);
  CHECK(model.contact_pieces(x).size() == 2);
  x[5] = 0.3;
  CHECK_FALSE(model.admissible(x));  // not strictly increasing
  x[5] = 1.0;
  CHECK_FALSE(model.admissible(x));  // on the foundation's end
  x[5] = 0.6, x[0] = std::nan("");
  CHECK_FALSE(model.admissible(x));
  CHECK_THROWS_AS(model.energy(VectorXd::Zero(5), 1.0), std::invalid_argument);
  CHECK_THROWS_AS(model.u(VectorXd::Zero(6), 0.5), std::invalid_argument);  // a beam has no u
  CHECK_THROWS_AS(model.w(VectorXd::Zero(6), 0.5, 4), std::invalid_argument);
  // With the load-point enrichment: 4 modes plus one kinked function for the interior force.
  const RitzModel enriched(member, 4, {true, 2}, Enrichment::load_points);
  CHECK(enriched.modes() == 5);
  CHECK(enriched.unknowns() == 7);
  CHECK(enriched.limit_offset() == 5);
  // w on a grid is w pointwise, on both sides of the kink too; the bound is round-off of the
  // phase rotations (add_on_grid), a few hundred eps of sum |W_i| (each |phi_i| <= 1).
  for (const RitzModel* m : {&model, &enriched}) {
    VectorXd y = VectorXd::Zero(m->unknowns());
    for (int i = 0; i < m->modes(); ++i) y[i] = std::cos(1.0 + i) / (1 + i);
    y[m->limit_offset()] = 0.3, y[m->limit_offset() + 1] = 0.6;
    std::vector<double> values;
    m->w_on_grid(y, 0.1, 0.9, 400, values);
    REQUIRE(values.size() == 399);
    const double bound = 500 * 2.2e-16 * y.head(m->modes()).lpNorm<1>();
    for (int i = 1; i < 400; ++i) CHECK(std::abs(values[i - 1] - m->w(y, 0.1 + 0.8 * i / 400)) <= bound);
    // And w' (the event scans' grid): each function's slope is its terms' times their frequency,
    // at most (j + 2) pi for the j-th (the enrichment's cubic halves: a few units), so the bound
    // is the same times that.
    m->w_on_grid(y, 0.1, 0.9, 400, values, 1);
    REQUIRE(values.size() == 399);
    double slope_sum = 0.0;
    for (int j = 0; j < m->modes(); ++j) slope_sum += std::abs(y[j]) * (j + 2) * 3.14159265358979;
    for (int i = 1; i < 400; ++i)
      CHECK(std::abs(values[i - 1] - m->w(y, 0.1 + 0.8 * i / 400, 1)) <= 500 * 2.2e-16 * slope_sum);
  }
  std::vector<double> unused;
  CHECK_THROWS_AS(model.w_on_grid(VectorXd::Zero(6), 0.1, 0.9, 10, unused, 2), std::invalid_argument);
}

TEST_CASE("ritz model: the minimiser for fixed limits detects unresisted rigid motions", "[ritz][model]") {
  // A free-free beam whose foundation is lifted off everywhere floats: no minimiser.
  const model::MemberModel floating = beam(EndSupport::free, EndSupport::free, 1e3, {force(0.5, 1.0)});
  CHECK_FALSE(RitzModel(floating, 6, {false, 0}).minimiser_for_limits(VectorXd(0), 1.0).has_value());
  // One contact piece resists both rigid motions.
  const RitzModel held(floating, 6, {false, 2});
  VectorXd limits(2);
  limits << 0.2, 0.4;
  CHECK(held.minimiser_for_limits(limits, 1.0).has_value());
  // A well-posed problem with many modes is not mistaken for a singular one, although its
  // stiffness spans many decades (mode j's bending stiffness grows like j^4).
  model::MemberModel many = arch(EndSupport::free, EndSupport::free, 10.0, 3e6, 1e4, {force(0.05, 500.0)});
  many.tensionless = false;
  const RitzModel fine(many, 160, {true, 0});
  CHECK(fine.minimiser_for_limits(VectorXd(0), 1.0).has_value());
  CHECK_THROWS_AS(held.minimiser_for_limits(VectorXd(1), 1.0), std::invalid_argument);
}

TEST_CASE("ritz model: misuse is refused", "[ritz][model]") {
  model::MemberModel supported = beam(EndSupport::pinned, EndSupport::pinned, 1e3, {force(0.5, 1.0)});
  supported.point_supports = {0.5};
  CHECK_THROWS_WITH(RitzModel(supported, 4, {true, 0}),
                    "key 'supports.interior': the moving-boundary model takes no interior point supports");
  const model::MemberModel plain = beam(EndSupport::pinned, EndSupport::pinned, 1e3, {force(0.5, 1.0)});
  CHECK_THROWS_AS(RitzModel(plain, 0, {true, 0}), std::invalid_argument);
  CHECK_THROWS_AS(RitzModel(plain, 4, {true, -1}), std::invalid_argument);
  model::MemberModel bilateral = plain;
  bilateral.tensionless = false;
  CHECK_THROWS_AS(RitzModel(bilateral, 4, {false, 2}), std::invalid_argument);
  // Moments on an arch whose u is free at both ends drive the rigid rotation about the centre.
  const model::MemberModel roller = arch(EndSupport::roller, EndSupport::roller, 10, 3e6, 1e6, {moment(0.0, 1.0)});
  CHECK_THROWS_AS(RitzModel(roller, 4, {true, 0}), MechanismError);
  // Balanced moments do no work on it.
  const model::MemberModel balanced =
      arch(EndSupport::roller, EndSupport::roller, 10, 3e6, 1e6, {moment(-0.1, 1.0), moment(0.1, -1.0)});
  CHECK_NOTHROW(RitzModel(balanced, 4, {true, 0}));
}

TEST_CASE("ritz model: unsupported_input names the key of each input the model cannot take", "[ritz][model]") {
  // One place lists them (solve --method ritz and the trace path refuse with its key): each input
  // on an otherwise plain beam is found, and RitzModel refuses it with the same message.
  const scene::Scene plain = test::beam_scene(1.0, 1.0, scene::EndSupport::pinned, scene::EndSupport::pinned, 1e3);
  CHECK_FALSE(unsupported_input(model::make_member_model(plain)).has_value());
  auto key_of = [](const scene::Scene& s) {
    const model::MemberModel model = model::make_member_model(s);
    const std::optional<Unsupported> u = unsupported_input(model, "foundation.gap_file", "foundation.tension_k");
    REQUIRE(u.has_value());
    // (RitzModel sees no scene: it names the keys' default spellings.)
    CHECK_THROWS_WITH(RitzModel(model, 4, {true, 0}), unsupported_input(model)->message());
    return u->key;
  };
  scene::Scene s = plain;
  s.supports.interior = {0.5};
  s.supports.interior_settlement = {0.0};
  CHECK(key_of(s) == "supports.interior");
  s = plain;
  s.supports.left_detail.settlement = 1e-3;
  CHECK(key_of(s) == "supports");
  s = plain;
  s.foundation.k.reset();
  s.foundation.segments = {{0.0, 1.0, 3e3, std::nullopt, 1e3}};
  CHECK(key_of(s) == "foundation.segments");
  s = plain;
  s.foundation.gap_at = {0.0};
  s.foundation.gap_value = {1e-3};
  CHECK(key_of(s) == "foundation.gap_file");
  s = plain;
  s.foundation.tension_k = 10.0;
  CHECK(key_of(s) == "foundation.tension_k");
  s = plain;
  scene::Load curvature;
  curvature.kind = scene::LoadKind::curvature;
  curvature.value = 1e-3;
  curvature.to = 1.0;
  s.loads = {curvature};
  CHECK(key_of(s) == "loads");
}
