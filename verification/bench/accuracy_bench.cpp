// liftoff_accuracy_bench: the measurements behind the numerical core of issue 11 (round-off,
// contact limits, speed of `fast`, arches), in one executable with sections:
//
//   roundoff  bilateral nodal error against the closed form, N = 1e2 .. 1e6, for three ways to
//             build and solve the same FE equations: (a) element sizes as differences of rounded
//             node coordinates, K form, LDL^T with extended-precision refinement (liftoff before
//             issue 11); (b) the same with the stored per-segment sizes; (c) the mixed form with
//             banded LU (contact::ActiveSetSystem now). Scenes: the seed beam (k = 1e4, end
//             moments) and the 500 m pipeline (beta L = 100), both with a bilateral foundation.
//   ratio     fast / bilateral time on a long member with many lift-off zones (beta L = 1000,
//             self-weight and seven uplift forces), N = 1e4, 1e5, 1e6.
//   arch      time and peak memory of `fast` on the seed's pinned arch at 1e4 to 1e5 elements, fitted
//             exponents.
//   limits    contact-limit error against the closed forms: node-based (fast) and limit-fitted
//             (contact/fitted_limits.hpp), with observed orders and the time of both.
//   pipeline  the tensionless 500 m pipeline at 1e3 .. 1e6 elements by fast (nested): its
//             equilibrium and contact conditions from the assembled K form, its deflection and
//             limits against the closed form; then the limit-fitted solve.
//   newton    Newton over the sparse linear-solver seam (issue 14) on the long member's linear FE
//             residual, N = 1e4 .. 1e6: time against one direct sparse solve, a second solve with
//             the same KINSOL adapter, factor nonzeros per unknown, peak memory, fitted exponent.
//
// Speed is a benchmark, never a test: nothing here asserts. Run from the build directory:
//   verification/bench/liftoff_accuracy_bench [roundoff] [ratio] [arch] [limits] [pipeline] [newton] [--max-elements N]

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "closed_form/beam_on_foundation.hpp"
#include "closed_form/member_problem.hpp"
#include "contact/active_set_solver.hpp"
#include "contact/active_set_system.hpp"
#include "contact/contact_solver.hpp"
#include "contact/fitted_limits.hpp"
#include "core/allocator.hpp"
#include "fe/discretisation.hpp"
#include "fe/mixed_form.hpp"
#include "model/from_scene.hpp"
#include "model/member_model.hpp"
#include "nonlinear/linear_solver.hpp"
#include "nonlinear/newton.hpp"
#include "post/contact_regions.hpp"
#include "scene/scene.hpp"
#include "scene/scene_reader.hpp"

using namespace liftoff;
using Eigen::VectorXd;

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The median of a sample (the upper one of an even count).
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

scene::Scene shipped(const std::string& name) {
  return scene::read_scene_file(std::string(LIFTOFF_SOURCE_DIR) + "/verification/scenes/" + name + ".toml");
}

scene::Load load(scene::LoadKind kind, double at, double value, scene::LoadCase c = scene::LoadCase::live) {
  scene::Load l;
  l.kind = kind;
  l.at = at;
  l.value = value;
  l.load_case = c;
  return l;
}

scene::Scene beam(double length, double ei, scene::EndSupport ends, double modulus, bool tensionless) {
  scene::Scene s;
  s.source_name = "<bench>";
  s.structure.kind = scene::StructureKind::beam;
  s.structure.length = length;
  s.structure.bending_stiffness = ei;
  s.supports.left = s.supports.right = ends;
  s.foundation.modulus = modulus;
  s.foundation.tensionless = tensionless;
  s.foundation.from = 0.0;
  s.foundation.to = length;
  return s;
}

scene::Load uniform(double from, double to, double value, scene::LoadCase c) {
  scene::Load l = load(scene::LoadKind::uniform, 0.0, value, c);
  l.from = from;
  l.to = to;
  return l;
}

// The 500 m pipeline of issue 10: clamped, K = 2e5, self-weight 1000 N/m, -50 kN at mid-span.
scene::Scene pipeline(bool tensionless) {
  scene::Scene s = beam(500.0, 3.12e7, scene::EndSupport::clamped, 2.0e5, tensionless);
  s.loads = {uniform(0.0, 500.0, 1000.0, scene::LoadCase::dead), load(scene::LoadKind::force, 250.0, -50e3)};
  return s;
}

// A long member with many lift-off zones: beta L = 1000 (EI = 1, L = 1, K = 4 beta^4), pinned,
// self-weight q = 1 and seven uplift forces of 5 times the Hetenyi lift-off force 2 q / beta.
scene::Scene long_member() {
  const double beta = 1000.0;
  scene::Scene s = beam(1.0, 1.0, scene::EndSupport::pinned, 4.0 * std::pow(beta, 4), true);
  s.loads = {uniform(0.0, 1.0, 1.0, scene::LoadCase::dead)};
  for (double x : {0.11, 0.23, 0.37, 0.5, 0.61, 0.77, 0.9})
    s.loads.push_back(load(scene::LoadKind::force, x, -5.0 * 2.0 / beta));
  return s;
}

double nodal_error(const fe::Discretisation& d, const VectorXd& u, const closed_form::BeamSolution& exact) {
  const VectorXd all = d.expand(u);
  double error = 0.0, scale = 0.0;
  const int nodes = static_cast<int>(d.mesh.nodes.size());
  for (int node = 0; node < nodes; node += std::max(1, nodes / 20000)) {
    const double w = exact.deflection(d.mesh.nodes[node]);
    error = std::max(error, std::abs(all[d.deflection_dof(node)] - w));
    scale = std::max(scale, std::abs(w));
  }
  return error / scale;
}

// The K form as liftoff solved it before issue 11: [K C^T; C -T] equilibrated to a unit
// diagonal, LDL^T (AMD), refinement with extended-precision defects while it contracts.
VectorXd solve_k_form(const fe::Discretisation& d, const VectorXd& load) {
  const int n = d.equations, m = d.reactions(), size = n + m;
  std::vector<Eigen::Triplet<double>> t;
  for (int k = 0; k < d.stiffness.outerSize(); ++k)
    for (fe::SparseMatrix::InnerIterator it(d.stiffness, k); it; ++it) t.emplace_back(it.row(), it.col(), it.value());
  for (int k = 0; k < d.coupling.outerSize(); ++k)
    for (fe::SparseMatrix::InnerIterator it(d.coupling, k); it; ++it) {
      t.emplace_back(n + it.row(), it.col(), it.value());
      t.emplace_back(it.col(), n + it.row(), it.value());
    }
  for (int k = 0; k < d.flexibility.outerSize(); ++k)
    for (fe::SparseMatrix::InnerIterator it(d.flexibility, k); it; ++it)
      t.emplace_back(n + it.row(), n + it.col(), -it.value());
  fe::SparseMatrix a(size, size);
  a.setFromTriplets(t.begin(), t.end());
  VectorXd s = a.diagonal().cwiseAbs().cwiseSqrt().cwiseInverse();
  const fe::SparseMatrix scaled = s.asDiagonal() * a * s.asDiagonal();
  Eigen::SimplicialLDLT<fe::SparseMatrix, Eigen::Lower, Eigen::AMDOrdering<int>> ldlt(scaled);
  VectorXd b = VectorXd::Zero(size);
  b.head(n) = load;
  auto solve = [&](const VectorXd& r) { return VectorXd(s.cwiseProduct(ldlt.solve(VectorXd(s.cwiseProduct(r))))); };
  VectorXd x = solve(b);
  std::vector<long double> acc(size);
  double previous = INFINITY;
  for (int step = 0; step < 6; ++step) {
    for (int i = 0; i < size; ++i) acc[i] = b[i];
    for (int k = 0; k < a.outerSize(); ++k)
      for (fe::SparseMatrix::InnerIterator it(a, k); it; ++it)
        acc[it.row()] -= static_cast<long double>(it.value()) * x[it.col()];
    VectorXd defect(size);
    for (int i = 0; i < size; ++i) defect[i] = static_cast<double>(acc[i]);
    const VectorXd c = solve(defect);
    x += c;
    const double change = c.lpNorm<Eigen::Infinity>() / x.lpNorm<Eigen::Infinity>();
    if (!(change > 1e-15) || change > 0.5 * previous) break;
    previous = change;
  }
  return x.head(n);
}

// The bilateral answer (every reaction node in contact): variant 'c' the mixed form, LU of the
// active-set system; otherwise the K form (solve_k_form).
VectorXd bilateral_displacement(const fe::Discretisation& d, const VectorXd& load, char variant) {
  if (variant != 'c') return solve_k_form(d, load);
  contact::ActiveSetSystem system(d);
  system.factorise(std::vector<bool>(d.reactions(), true));
  return system.solve(load).displacement;
}

// ---- roundoff -------------------------------------------------------------------------------

void roundoff_section(int max_elements) {
  scene::Scene seed = shipped("seed_beam_end_moments");
  seed.foundation.tensionless = false;
  const std::pair<const char*, scene::Scene> scenes[] = {{"seed beam (bilateral, k = 1e4)", seed},
                                                         {"500 m pipeline (bilateral, beta L = 100)", pipeline(false)}};
  for (const auto& [name, s] : scenes) {
    const model::MemberModel model = model::make_member_model(s);
    const closed_form::BeamSolution exact = closed_form::solve_bilateral(closed_form::problem_of(model));
    std::printf("\nroundoff: %s: nodal error max|w - w_exact| / max|w_exact|, time (s)\n", name);
    std::printf("  %8s  %-26s %-26s %-26s\n", "N", "(a) rounded h, K, LDL^T", "(b) stored h, K, LDL^T",
                "(c) stored h, mixed, LU");
    for (int n : {100, 300, 1000, 3000, 10000, 30000, 100000, 300000, 1000000}) {
      if (n > max_elements) break;
      std::printf("  %8d", n);
      for (char variant : {'a', 'b', 'c'}) {
        if (variant != 'c' && n > 100000) {
          std::printf("  %-24s", "-");
          continue;
        }
        fe::Mesh mesh = fe::make_mesh(model, n);
        if (variant == 'a') mesh.sizes.clear();  // sizes from differences of the coordinates
        const fe::Discretisation d = fe::discretise(model, mesh);
        const VectorXd f = d.load(1.0);
        const auto start = std::chrono::steady_clock::now();
        const VectorXd u = bilateral_displacement(d, f, variant);
        std::printf("  %.1e (%6.2f s)        ", nodal_error(d, u, exact), seconds_since(start));
        std::fflush(stdout);
      }
      std::printf("\n");
    }
  }
}

// The arch has no closed form: the change of w at the nodes of N elements when the mesh is
// doubled (discretisation error ~h^4 plus round-off), for the K form (b) and the mixed form (c).
void arch_roundoff(int max_elements) {
  scene::Scene s = shipped("seed_arch_pinned");
  s.foundation.tensionless = false;
  const model::MemberModel model = model::make_member_model(s);
  std::printf(
      "\nroundoff: seed arch, pinned (bilateral, EA R^2 / EI = %.0e): max |w_N - w_2N| / max |w| at the nodes "
      "of N\n  %8s  %-26s %-26s\n",
      model.membrane_stiffness, "N", "(b) stored h, K, LDL^T", "(c) stored h, mixed, LU");
  for (int n : {100, 1000, 10000, 100000}) {
    if (2 * n > max_elements) break;
    std::printf("  %8d", n);
    for (char variant : {'b', 'c'}) {
      VectorXd w[2];
      for (int level = 0; level < 2; ++level) {
        const fe::Discretisation d = fe::discretise(model, n << level);
        const VectorXd f = d.load(1.0);
        const VectorXd u = bilateral_displacement(d, f, variant);
        const VectorXd all = d.expand(u);
        w[level].resize(n + 1);
        for (int node = 0; node <= n; ++node) w[level][node] = all[d.deflection_dof(node << level)];
      }
      std::printf("  %.1e                   ",
                  (w[0] - w[1]).lpNorm<Eigen::Infinity>() / w[1].lpNorm<Eigen::Infinity>());
      std::fflush(stdout);
    }
    std::printf("\n");
  }
}

// ---- ratio ----------------------------------------------------------------------------------

void ratio_section(int max_elements) {
  const scene::Scene tensionless = long_member();
  scene::Scene bilateral_scene = tensionless;
  bilateral_scene.foundation.tensionless = false;
  const model::MemberModel model = model::make_member_model(tensionless);
  const model::MemberModel bilateral_model = model::make_member_model(bilateral_scene);
  std::printf(
      "\nratio: fast / bilateral on the long member (beta L = 1000, 7 uplift forces), in-process, medians.\n"
      "  kernel: ActiveSetSystem set-up, one factorisation, one solve refined to round-off (the floor);\n"
      "  plain: solve_active_set from the bilateral start; nested: solve_active_set_nested (coarser meshes'\n"
      "  discretisation and sets included); solve_contact: the library call of `liftoff solve` (method fast,\n"
      "  nested start; bilateral: the same member with tensionless = false), residual and expansion included;\n"
      "  'with discretise': plus discretise(model, N), as in a whole solve\n");
  std::printf("  %8s %9s %9s %9s %9s %9s %9s | %6s %6s %6s | %6s %6s | %s\n", "N", "discretis", "kernel", "plain",
              "nested", "contact", "contact", "plain", "nested", "contact", "nested", "contact",
              "sets: plain, nested (coarse)");
  std::printf("  %8s %9s %9s %9s %9s %9s %9s | %20s | %13s |\n", "", "s", "s", "s", "s", "fast s", "bilat. s",
              "/ kernel", "with discretise");
  for (int n : {10000, 100000, 1000000}) {
    if (n > max_elements) break;
    const int repeats = n <= 10000 ? 7 : n <= 100000 ? 5 : 3;
    std::vector<double> discretise, kernel, fast, nested, app_fast, app_bilateral;
    contact::ActiveSetResult plain;
    contact::NestedResult layered;
    contact::ContactSolution app;
    contact::ContactOptions fast_options;
    fast_options.method = contact::Method::fast;
    // The first round is a warm-up, not recorded: memory first touched costs page faults that
    // would fall on whichever variant runs first.
    for (int r = -1; r < repeats; ++r) {
      if (r == 0)
        discretise.clear(), kernel.clear(), fast.clear(), nested.clear(), app_fast.clear(), app_bilateral.clear();
      auto start = std::chrono::steady_clock::now();
      const fe::Discretisation d = fe::discretise(model, n);
      discretise.push_back(seconds_since(start));
      const fe::Discretisation db = fe::discretise(bilateral_model, n);
      const VectorXd f = d.load(1.0);
      start = std::chrono::steady_clock::now();
      {
        contact::ActiveSetSystem system(d);
        system.factorise(std::vector<bool>(d.reactions(), true));
        const contact::ContactState state = system.solve(f);
      }
      kernel.push_back(seconds_since(start));
      start = std::chrono::steady_clock::now();
      plain = contact::solve_active_set(d, f, {});
      fast.push_back(seconds_since(start));
      start = std::chrono::steady_clock::now();
      layered = contact::solve_active_set_nested(model, d, 1.0, {});
      nested.push_back(seconds_since(start));
      start = std::chrono::steady_clock::now();
      app = contact::solve_contact(d, fast_options);
      app_fast.push_back(seconds_since(start));
      start = std::chrono::steady_clock::now();
      const contact::ContactSolution app_b = contact::solve_contact(db, fast_options);
      app_bilateral.push_back(seconds_since(start));
    }
    const double td = median(discretise), tk = median(kernel), tf = median(fast), tn = median(nested),
                 ta = median(app_fast), tb = median(app_bilateral);
    std::printf(
        "  %8d %9.4f %9.4f %9.4f %9.4f %9.4f %9.4f | %6.2f %6.2f %6.2f | %6.2f %6.2f | %d, %d (%d on %d coarser "
        "meshes)%s%s\n",
        n, td, tk, tf, tn, ta, tb, tf / tk, tn / tk, ta / tb, (td + tn) / (td + tk), (td + ta) / (td + tb),
        plain.summary.iterations, layered.result.summary.iterations, layered.coarse_sets, layered.levels - 1,
        plain.in_contact == layered.result.in_contact ? "" : " (the two contact sets differ!)",
        app.summary.is_usable() ? "" : " (solve_contact: NOT SOLVED)");
    std::fflush(stdout);
  }
}

// ---- arch -----------------------------------------------------------------------------------

// Runs `work` in a child process and returns its peak resident memory (MB) and wall time.
std::pair<double, double> in_child(const std::function<void()>& work) {
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid == 0) {
    work();
    std::fflush(stdout);
    _exit(0);
  }
  int status = 0;
  rusage usage{};
  wait4(pid, &status, 0, &usage);
  return {usage.ru_maxrss / 1024.0, seconds_since(start)};
}

void arch_section(int max_elements) {
  std::printf("\narch: `fast` on seed_arch_pinned (child process: wall time, peak memory)\n");
  std::vector<double> sizes, walls, peaks;
  for (int n : {10000, 20000, 50000, 100000}) {
    if (n > max_elements) break;
    std::fflush(stdout);
    const auto [mb, wall] = in_child([n] {
      const scene::Scene s = shipped("seed_arch_pinned");
      const model::MemberModel model = model::make_member_model(s);
      auto start = std::chrono::steady_clock::now();
      const fe::Discretisation d = fe::discretise(model, n);
      const double t_discretise = seconds_since(start);
      start = std::chrono::steady_clock::now();
      const auto result = contact::solve_active_set(d, d.load(1.0), {});
      std::printf("  %6d elements: discretise %.3f s, fast %.3f s (%s, %d sets, error estimate %.1e, band %d)\n", n,
                  t_discretise, seconds_since(start),
                  std::string(contact::to_string(result.summary.termination)).c_str(), result.summary.iterations,
                  result.state.error_estimate, contact::ActiveSetSystem(d).bandwidth());
    });
    std::printf("          child: %.2f s wall, peak %.0f MB\n", wall, mb);
    sizes.push_back(n), walls.push_back(wall), peaks.push_back(mb);
  }
  // Least squares on log-log (both figures include the child's fixed start, so the exponents
  // are lower bounds of the asymptotic ones only when that start matters).
  auto exponent = [&](const std::vector<double>& y) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    const double k = static_cast<double>(sizes.size());
    for (std::size_t i = 0; i < sizes.size(); ++i) {
      const double lx = std::log(sizes[i]), ly = std::log(y[i]);
      sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly;
    }
    return (k * sxy - sx * sy) / (k * sxx - sx * sx);
  };
  if (sizes.size() >= 2)
    std::printf("  fitted: wall time ~ N^%.2f, peak memory ~ N^%.2f\n", exponent(walls), exponent(peaks));
}

// ---- limits ---------------------------------------------------------------------------------

// The closed-form limits of a tensionless beam scene, started from a fine FE answer.
std::vector<double> exact_limits(const model::MemberModel& model) {
  const fe::Discretisation d = fe::discretise(model, 2000);
  const auto fast = contact::solve_active_set(d, d.load(1.0), {});
  std::vector<closed_form::Interval> guess;
  for (const auto& r : contact::contact_intervals(d, fast.state.displacement, fast.in_contact))
    guess.push_back({r.begin, r.end});
  const auto exact = closed_form::solve_tensionless(closed_form::problem_of(model), guess);
  if (exact.status != closed_form::TensionlessStatus::converged)
    throw std::runtime_error("the closed form did not converge: " + exact.message);
  return exact.limits;
}

double limit_error(const std::vector<ContactRegion>& regions, const model::MemberModel& model,
                   const std::vector<double>& exact) {
  std::vector<double> limits;
  for (const auto& r : regions) {
    if (r.begin > model.foundation_begin + 1e-12) limits.push_back(r.begin);
    if (r.end < model.foundation_end - 1e-12) limits.push_back(r.end);
  }
  if (limits.size() != exact.size()) return INFINITY;
  double error = 0.0;
  for (std::size_t k = 0; k < limits.size(); ++k) error = std::max(error, std::abs(limits[k] - exact[k]));
  return error;
}

// A weightless free-free beam under a central point load (beta L = 6): its ends lift off.
scene::Scene free_beam() {
  scene::Scene s = beam(1.0, 1.0, scene::EndSupport::free, 4.0 * std::pow(6.0, 4), true);
  s.loads = {load(scene::LoadKind::force, 0.5, 1.0)};
  return s;
}

void limits_section(int max_elements) {
  const std::pair<const char*, scene::Scene> scenes[] = {
      {"seed_beam_end_moments", shipped("seed_beam_end_moments")},
      {"seed_beam_end_moments_central_load", shipped("seed_beam_end_moments_central_load")},
      {"free beam, central point load (beta L = 6)", free_beam()}};
  for (const auto& [name, s] : scenes) {
    const model::MemberModel model = model::make_member_model(s);
    const std::vector<double> exact = exact_limits(model);
    std::printf("\nlimits: %s; exact limits", name);
    for (double t : exact) std::printf(" %.12f", t);
    std::printf(" (closed form)\n  %6s | %-22s | %-58s | %s\n", "N", "node-based (fast)", "limit-fitted",
                "CPU time: fast + fitted");
    std::printf("  %6s | %9s %12s | %9s %7s %6s %9s %10s |\n", "", "error", "order", "error", "order", "steps",
                "last step", "est./true");
    double previous_node = 0, previous_fitted = 0;
    std::vector<double> previous_limits;
    for (int n : {10, 20, 40, 80, 160, 320, 640, 1280, 2560}) {
      if (n > max_elements) break;
      contact::FittedOptions options;
      options.elements = n;
      // Time: repeated until 0.2 s have passed; CPU time of this process (the machine is shared).
      int repeats = 0;
      const std::clock_t cpu_start = std::clock();
      double node_error = 0, fitted_error = 0;
      contact::FittedResult fitted;
      const auto start = std::chrono::steady_clock::now();
      do {
        const fe::Discretisation d = fe::discretise(model, n);
        const auto fast = contact::solve_active_set(d, d.load(1.0), {});
        const auto regions = contact::contact_intervals(d, fast.state.displacement, fast.in_contact);
        node_error = limit_error(regions, model, exact);
        fitted = contact::solve_fitted_limits(model, 1.0, regions, options);
        ++repeats;
      } while (seconds_since(start) < 0.2);
      const double time = static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC / repeats;
      fitted_error = fitted.summary.is_usable() ? limit_error(fitted.contact, model, exact) : INFINITY;
      auto order = [](double previous, double now) { return previous > 0 ? std::log2(previous / now) : NAN; };
      // A posteriori: Richardson with the order 4 from the mesh of half the elements,
      // |t_N - t_N/2| / (2^4 - 1), against the true error.
      double estimate = NAN;
      if (fitted.summary.is_usable() && previous_limits.size() == fitted.limits.size()) {
        estimate = 0.0;
        for (std::size_t k = 0; k < fitted.limits.size(); ++k)
          estimate = std::max(estimate, std::abs(fitted.limits[k] - previous_limits[k]) / 15.0);
      }
      previous_limits = fitted.summary.is_usable() ? fitted.limits : std::vector<double>{};
      std::printf("  %6d | %9.2e %12.2f | %9.2e %7.2f %6d %9.1e %10.2f | %8.1f us  %s\n", n, node_error,
                  order(previous_node, node_error), fitted_error, order(previous_fitted, fitted_error),
                  fitted.summary.iterations, fitted.summary.last_step, estimate / fitted_error, 1e6 * time,
                  fitted.summary.is_usable() ? "" : std::string(fitted.summary.message).c_str());
      std::fflush(stdout);
      previous_node = node_error;
      previous_fitted = fitted_error;
    }
  }
}

// ---- pipeline -------------------------------------------------------------------------------

// |A| |x|: the size of the terms a row of A x sums.
VectorXd absolute_product(const fe::SparseMatrix& a, const VectorXd& x) {
  VectorXd out = VectorXd::Zero(a.rows());
  for (int k = 0; k < a.outerSize(); ++k)
    for (fe::SparseMatrix::InnerIterator it(a, k); it; ++it) out[it.row()] += std::abs(it.value() * x[it.col()]);
  return out;
}

void pipeline_section(int max_elements) {
  const scene::Scene s = pipeline(true);
  const model::MemberModel model = model::make_member_model(s);
  const closed_form::BeamProblem problem = closed_form::problem_of(model);
  const std::vector<double> exact = exact_limits(model);
  std::vector<closed_form::Interval> regions;
  {
    const fe::Discretisation d = fe::discretise(model, 2000);
    const auto fast = contact::solve_active_set(d, d.load(1.0), {});
    for (const auto& r : contact::contact_intervals(d, fast.state.displacement, fast.in_contact))
      regions.push_back({r.begin, r.end});
  }
  const auto reference = closed_form::solve_tensionless(problem, regions);
  std::printf(
      "\npipeline (tensionless, L = 500 m, clamped, beta L = 100): fast (nested) against the closed form "
      "(limits x/L:");
  for (double t : exact) std::printf(" %.12f", t);
  std::printf(")\n  %8s %9s %5s %11s %11s %11s %11s %11s %11s\n", "N", "time s", "sets", "equilibrium", "min r/max r",
              "min gap", "r.gap", "w error", "limit error");
  for (int n : {1000, 10000, 100000, 1000000}) {
    if (n > max_elements) break;
    const auto start = std::chrono::steady_clock::now();
    const fe::Discretisation d = fe::discretise(model, n);
    const auto nested = contact::solve_active_set_nested(model, d, 1.0, {});
    const double time = seconds_since(start);
    const auto& result = nested.result;
    const VectorXd& u = result.state.displacement;
    const VectorXd& r = result.state.reaction;
    const VectorXd f = d.load(1.0);
    // The answer's physics from the assembled K form (not the solver's own system).
    const VectorXd equilibrium = d.stiffness * u + d.coupling.transpose() * r - f;
    const VectorXd terms =
        absolute_product(d.stiffness, u) + absolute_product(d.coupling.transpose(), r) + f.cwiseAbs();
    const VectorXd gap = d.flexibility * r - d.coupling * u;
    const double gap_scale = (absolute_product(d.flexibility, r) + absolute_product(d.coupling, u)).maxCoeff();
    const double r_scale = r.cwiseAbs().maxCoeff();
    const VectorXd all = d.expand(u);
    double w_error = 0.0, w_scale = 0.0;
    for (int node = 0; node <= n; node += std::max(1, n / 20000)) {
      const double w = reference.solution.deflection(d.mesh.nodes[node]);
      w_error = std::max(w_error, std::abs(all[d.deflection_dof(node)] - w));
      w_scale = std::max(w_scale, std::abs(w));
    }
    const auto fitted_regions = contact::contact_intervals(d, u, result.in_contact);
    std::printf("  %8d %9.2f %5d %11.1e %11.1e %11.1e %11.1e %11.1e %11.1e %s\n", n, time,
                result.summary.iterations + nested.coarse_sets,
                (equilibrium.cwiseAbs().array() / terms.array().max(1e-300)).maxCoeff(), r.minCoeff() / r_scale,
                gap.minCoeff() / gap_scale, r.cwiseProduct(gap).cwiseAbs().maxCoeff() / (r_scale * gap_scale),
                w_error / w_scale, limit_error(fitted_regions, model, exact),
                result.summary.is_usable() ? "" : "NOT SOLVED");
    std::fflush(stdout);
  }
  contact::FittedOptions options;
  for (int n : {100, 200, 400}) {
    options.elements = n;
    const fe::Discretisation d = fe::discretise(model, n);
    const auto fast = contact::solve_active_set(d, d.load(1.0), {});
    const auto fitted = contact::solve_fitted_limits(
        model, 1.0, contact::contact_intervals(d, fast.state.displacement, fast.in_contact), options);
    std::printf("  fitted, %d elements: limit error %.1e L (%s)\n", n, limit_error(fitted.contact, model, exact),
                fitted.summary.message.c_str());
  }
}

// ---- newton ---------------------------------------------------------------------------------

// Newton over the sparse linear-solver seam (nonlinear/newton.hpp, linear_solver.hpp) on the
// linear FE residual of the long member in mixed form (fe/mixed_form.hpp), bilateral so that the
// residual is linear: it must cost what one direct sparse solve costs, times the iterations, and
// grow like n. Columns: one Eigen SparseLU analyse + factorise + solve (the floor); a NewtonSolver
// set up and solved (KINSOL set-up, SparseLu analysis, one factorisation per iteration); a second
// solve with the same adapter (no set-up, no analysis); the factor's nonzeros per unknown; the
// peak memory of a child process doing discretise + one Newton solve.
// Newton on the linear residual R(z) = A z - b through a SparseLu and a NewtonSolver set up once:
// the Jacobian A is copied into the LU's matrix at the first iteration and its values after.
struct LinearNewton {
  const Eigen::SparseMatrix<double>& matrix;
  const VectorXd& rhs;
  nonlinear::SparseLu lu{static_cast<int>(matrix.rows())};
  nonlinear::NewtonSolver newton{lu};
  nonlinear::NewtonSummary solve(VectorXd& z, const nonlinear::NewtonOptions& options) {
    return newton.solve(
        [&](const VectorXd& x, VectorXd& f) {
          f.noalias() = matrix * x;
          f -= rhs;
          return true;
        },
        [&](const VectorXd&, const VectorXd&) {
          if (lu.matrix().nonZeros() == 0)
            lu.matrix() = matrix;
          else
            std::copy(matrix.valuePtr(), matrix.valuePtr() + matrix.nonZeros(), lu.matrix().valuePtr());
          return true;
        },
        z, options);
  }
};

// The mixed system of the member on n elements and its right-hand side.
struct MixedSystem {
  fe::Discretisation d;
  Eigen::SparseMatrix<double> matrix;
  VectorXd rhs;
  MixedSystem(const model::MemberModel& model, int n)
      : d(fe::discretise(model, n)), matrix(fe::mixed_matrix(d)), rhs(VectorXd::Zero(matrix.rows())) {
    rhs.tail(d.equations) = d.load(1.0);
  }
};

void newton_section(int max_elements) {
  scene::Scene bilateral_scene = long_member();
  bilateral_scene.foundation.tensionless = false;
  const model::MemberModel model = model::make_member_model(bilateral_scene);
  std::printf(
      "\nnewton: Newton over the sparse seam on the long member's linear FE residual (mixed form, bilateral),\n"
      "  in-process medians; peak memory of a child doing discretise + one Newton solve\n");
  std::printf("  %8s %9s %9s %9s %9s %6s %6s %6s %9s %8s\n", "N", "unknowns", "direct s", "newton s", "again s",
              "ratio", "iters", "nnz/n", "|dz|/|z|", "peak MB");
  std::vector<double> sizes, times;
  for (int n : {10000, 100000, 1000000}) {
    if (n > max_elements) break;
    const int repeats = n <= 10000 ? 7 : n <= 100000 ? 5 : 3;
    const MixedSystem system(model, n);
    const Eigen::SparseMatrix<double>& matrix = system.matrix;
    const VectorXd& rhs = system.rhs;
    const int m = system.d.stresses(), unknowns = static_cast<int>(matrix.rows());
    std::vector<double> direct_s, newton_s, again_s;
    VectorXd z_direct, z_newton;
    nonlinear::NewtonSummary summary;
    nonlinear::NewtonOptions options;
    long factor_nonzeros = 0;
    for (int r = -1; r < repeats; ++r) {  // r = -1: warm-up, not recorded
      auto start = std::chrono::steady_clock::now();
      Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> direct(matrix);
      z_direct = direct.solve(rhs);
      const double t_direct = seconds_since(start);
      if (r == -1) {  // scales from the answer's block sizes, as the Newton test does
        VectorXd typical(unknowns);
        typical.head(m).setConstant(std::max(z_direct.head(m).lpNorm<Eigen::Infinity>(), 1e-300));
        typical.tail(unknowns - m).setConstant(std::max(z_direct.tail(unknowns - m).lpNorm<Eigen::Infinity>(), 1e-300));
        const VectorXd row_size =
            (Eigen::SparseMatrix<double>(matrix.cwiseAbs()) * typical).array() + rhs.cwiseAbs().array();
        options.residual_scale = row_size.cwiseInverse();
        options.unknown_scale = typical.cwiseInverse();
        options.max_newton_step = 10.0 * std::sqrt(static_cast<double>(unknowns));
      }
      start = std::chrono::steady_clock::now();
      LinearNewton newton{matrix, rhs};
      z_newton = VectorXd::Zero(unknowns);
      summary = newton.solve(z_newton, options);
      const double t_newton = seconds_since(start);
      start = std::chrono::steady_clock::now();
      VectorXd z_again = VectorXd::Zero(unknowns);
      newton.solve(z_again, options);
      const double t_again = seconds_since(start);
      factor_nonzeros = newton.lu.factor_nonzeros();
      if (r >= 0) direct_s.push_back(t_direct), newton_s.push_back(t_newton), again_s.push_back(t_again);
    }
    std::fflush(stdout);  // the child inherits unflushed output
    const double peak_mb = in_child([&] {
                             const MixedSystem fresh(model, n);
                             LinearNewton newton{fresh.matrix, fresh.rhs};
                             VectorXd z = VectorXd::Zero(fresh.matrix.rows());
                             newton.solve(z, options);
                           }).first;
    const double td = median(direct_s), tn = median(newton_s), ta = median(again_s);
    sizes.push_back(unknowns), times.push_back(tn);
    std::printf("  %8d %9d %9.4f %9.4f %9.4f %6.2f %6d %6.1f %9.1e %8.0f%s\n", n, unknowns, td, tn, ta, tn / td,
                summary.iterations, static_cast<double>(factor_nonzeros) / unknowns,
                (z_newton - z_direct).lpNorm<Eigen::Infinity>() / z_direct.lpNorm<Eigen::Infinity>(), peak_mb,
                summary.is_usable() ? "" : " (Newton: NOT CONVERGED)");
    std::fflush(stdout);
  }
  if (sizes.size() >= 2) {
    const double exponent = std::log(times.back() / times.front()) / std::log(sizes.back() / sizes.front());
    std::printf("  fitted exponent of Newton's time in the unknowns: %.2f (1 = O(n))\n", exponent);
  }
}

}  // namespace

int main(int argc, char** argv) {
  liftoff::tune_allocator();  // as the liftoff executable does: the same allocator in both timings
  std::vector<std::string> sections;
  int max_elements = 1000000;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--max-elements") == 0 && i + 1 < argc)
      max_elements = std::atoi(argv[++i]);
    else
      sections.push_back(argv[i]);
  }
  if (sections.empty()) sections = {"roundoff", "ratio", "arch", "limits", "pipeline", "newton"};
  for (const auto& s : sections) {
    if (s == "roundoff") {
      roundoff_section(max_elements);
      arch_roundoff(max_elements);
    } else if (s == "ratio")
      ratio_section(max_elements);
    else if (s == "arch")
      arch_section(max_elements);
    else if (s == "limits")
      limits_section(max_elements);
    else if (s == "pipeline")
      pipeline_section(max_elements);
    else if (s == "newton")
      newton_section(max_elements);
    else {
      std::fprintf(stderr,
                   "liftoff_accuracy_bench: unknown section '%s' (roundoff, ratio, arch, limits, pipeline, newton)\n",
                   s.c_str());
      return 2;
    }
  }
}
