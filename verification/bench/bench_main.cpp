// liftoff_bench: how fast each method reaches a given accuracy, how it scales, and the ratios
// the project's targets are stated in. Prints tables and writes CSV (accuracy.csv,
// scaling.csv, ratios.csv) to --out; verification/bench/plot_bench.py draws them.
//
//  1. accuracy: on the seed beam scenes, for each method over a range of elements (or modes),
//     the error of the contact limits (in L) and of the maximum deflection (relative) against
//     the exact tensionless solution (verification/closed_form), and the median wall time of
//     --repeats in-process runs. liftoff's FE methods are timed from the scene to the contact
//     limits (member model, assembly, contact solve, regions); the Ritz model from the scene
//     too, including the coarse FE solve (25 elements) that gives its topology and start. The
//     dolfinx reference is run by verification/dolfinx/penalty_reference.py --repeat: its solve
//     time only (start-up, mesh set-up and form compilation excluded).
//  2. scaling: whole-process wall time and peak memory (ru_maxrss of a spawned `liftoff solve`)
//     against the number of elements, dense methods up to where they fit, sparse ones up to
//     --max-elements; fitted exponents.
//  3. ratios, measured side by side in one run: the fast solver against the bilateral floor
//     (the same beam on a bilateral foundation: one sparse factorisation and solve) at 1e5
//     elements, whole process; dense dual Lemke against the fast solver at 2000 elements; Ritz
//     against FE at equal contact-limit error; and the best method against dolfinx at a
//     contact-limit error of 1e-6 L.
//  4. targets (on request): time to contact-limit errors of 1e-6, 1e-8, 1e-10 L on every scene
//     with a closed form (targets.hpp).
//  5. tolerance (on request): the honesty of `liftoff solve --tolerance`'s error estimates, estimate
//     / true error, on the same scenes for every method and tolerance (tolerance.hpp).
//
// The fast contact solver (method "fast") is developed on another branch: it is benchmarked
// wherever from_string<contact::Method>("fast") knows it, and skipped with a note otherwise.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "closed_form/scene_problem.hpp"
#include "contact/active_set_system.hpp"
#include "contact/contact_solver.hpp"
#include "core/allocator.hpp"
#include "core/error.hpp"
#include "fe/discretisation.hpp"
#include "measure.hpp"
#include "model/from_scene.hpp"
#include "model/member_model.hpp"
#include "post/contact_regions.hpp"
#include "post/fields.hpp"
#include "ritz/ritz_solver.hpp"
#include "scene/scene_reader.hpp"
#include "targets.hpp"
#include "tolerance.hpp"

namespace fs = std::filesystem;
using namespace liftoff;
using bench::Timing;
using contact::Method;

namespace {

struct Options {
  std::string out = "bench-results";
  bool full = false;
  int repeats = 5;
  int max_elements = 0;  // scaling: 0 = 1e5 (quick) or 1e6 (full)
  std::string sections = "accuracy,scaling,ratios";
  bool dolfinx = true;
  std::string liftoff = LIFTOFF_EXECUTABLE;
  std::string python = "/usr/bin/python3";
  std::string source_dir = LIFTOFF_SOURCE_DIR;
  std::string only;  // targets: scene names
  bool has(const std::string& section) const { return sections.find(section) != std::string::npos; }
};

const std::vector<std::string> seed_beams = {"seed_beam_end_moments", "seed_beam_end_moments_central_load"};

std::optional<Method> fast_method() { return from_string<Method>("fast"); }

std::string scene_path(const Options& o, const std::string& name) {
  return o.source_dir + "/verification/scenes/" + name + ".toml";
}

// ---------------------------------------------------------------------------------------------
// The exact reference: contact limits and maximum deflection of a seed beam.
// ---------------------------------------------------------------------------------------------
struct Reference {
  std::vector<double> limits;  // interior contact limits, x
  double w_max = 0.0;
};

// The maximum of a smooth function on [a, b]: dense samples, then bisection on its derivative
// around the best sample.
template <class F, class DF>
double maximum_of(F f, DF df, double a, double b, int samples) {
  double best = a, best_value = f(a);
  for (int i = 1; i <= samples; ++i) {
    const double x = a + (b - a) * i / samples;
    if (f(x) > best_value) best = x, best_value = f(x);
  }
  double lo = std::max(a, best - (b - a) / samples), hi = std::min(b, best + (b - a) / samples);
  if (df(lo) > 0 && df(hi) < 0) {
    for (int i = 0; i < 200 && hi - lo > 1e-15 * (b - a); ++i) {
      const double mid = 0.5 * (lo + hi);
      (df(mid) > 0 ? lo : hi) = mid;
    }
    best_value = std::max(best_value, f(0.5 * (lo + hi)));
  }
  return best_value;
}

Reference exact_reference(const scene::Scene& s, const std::vector<ContactRegion>& guess_regions) {
  std::vector<closed_form::Interval> guess;
  for (const auto& r : guess_regions) guess.push_back({r.begin, r.end});
  const auto exact = closed_form::solve_tensionless(closed_form::problem_of(s), guess);
  if (exact.status != closed_form::TensionlessStatus::converged)
    throw std::runtime_error("the closed form did not converge: " + exact.message);
  Reference ref;
  ref.limits = exact.limits;
  const auto& sol = exact.solution;
  ref.w_max = maximum_of([&](double x) { return sol.deflection(x); }, [&](double x) { return sol.slope(x); }, 0.0,
                         s.structure.length, 20000);
  return ref;
}

// ---------------------------------------------------------------------------------------------
// One measured point: method, size, errors, time.
// ---------------------------------------------------------------------------------------------
struct Point {
  std::string scene, method, parameter;  // parameter: "elements" or "modes"
  int size = 0;
  std::string termination;
  double limit_error = NAN, w_max_error = NAN;
  Timing timing;
};

Point make_point(std::string scene, std::string method, std::string parameter, int size) {
  Point p;
  p.scene = std::move(scene), p.method = std::move(method), p.parameter = std::move(parameter), p.size = size;
  return p;
}

double limit_error(const std::vector<double>& found, const Reference& ref) {
  if (found.size() != ref.limits.size()) return NAN;
  double worst = 0.0;
  for (std::size_t i = 0; i < found.size(); ++i) worst = std::max(worst, std::abs(found[i] - ref.limits[i]));
  return worst;
}

std::vector<double> interior_limits(const std::vector<ContactRegion>& regions, double begin, double end) {
  std::vector<double> limits;
  const double edge = 1e-9 * (end - begin);
  for (const auto& r : regions)
    for (double t : {r.begin, r.end})
      if (t > begin + edge && t < end - edge) limits.push_back(t);
  return limits;
}

// FE + LCP from the scene to the contact limits.
struct FeRun {
  model::MemberModel model;
  fe::Discretisation discretisation;
  contact::ContactSolution solution;
  std::vector<ContactRegion> regions;
};

FeRun run_fe(const scene::Scene& s, Method method, int elements) {
  FeRun r;
  r.model = model::make_member_model(s);
  r.discretisation = fe::discretise(r.model, elements);
  contact::ContactOptions options;
  options.method = method;
  r.solution = contact::solve_contact(r.discretisation, options);
  r.regions = post::contact_regions(r.model, r.discretisation, r.solution.displacement);
  return r;
}

// The FE maximum deflection: the largest value of each element's cubic (beams, L = length).
double fe_w_max(const FeRun& r) {
  double best = -INFINITY;
  const int elements = r.discretisation.mesh.elements();
  for (int e = 0; e < elements; ++e) {
    auto w = [&](double xi) { return post::evaluate(r.discretisation, r.solution.displacement, e, xi).w; };
    auto dw = [&](double xi) { return post::evaluate(r.discretisation, r.solution.displacement, e, xi).dw; };
    best = std::max(best, maximum_of(w, dw, 0.0, 1.0, 4));
  }
  return best * r.model.scales.length;
}

Point measure_fe(const Options& o, const std::string& name, const scene::Scene& s, const Reference& ref, Method method,
                 int elements) {
  Point p = make_point(name, std::string(to_string(method)), "elements", elements);
  try {
    const FeRun r = run_fe(s, method, elements);
    p.termination = std::string(contact::to_string(r.solution.summary.termination));
    if (r.solution.summary.is_usable()) {
      std::vector<ContactRegion> regions;
      for (const auto& g : r.regions) regions.push_back({r.model.user_from_s(g.begin), r.model.user_from_s(g.end)});
      p.limit_error = limit_error(interior_limits(regions, s.begin(), s.end()), ref) / s.structure.length;
      p.w_max_error = std::abs(fe_w_max(r) - ref.w_max) / std::abs(ref.w_max);
    }
    p.timing = bench::time_median([&] { run_fe(s, method, elements); }, o.repeats);
  } catch (const std::exception& e) {
    p.termination = std::string("refused: ") + e.what();
  }
  return p;
}

// Ritz with N modes from the scene: topology and start from a coarse FE solve (25 elements).
struct RitzRun {
  model::MemberModel model;
  ritz::RitzSolution solution;
};

RitzRun run_ritz(const scene::Scene& s, int modes) {
  RitzRun r;
  const FeRun start = run_fe(s, Method::automatic, 25);
  r.model = start.model;
  ritz::Topology topology;
  const double begin = r.model.foundation_begin, end = r.model.foundation_end, edge = 1e-9 * r.model.length();
  topology.first_in_contact = !start.regions.empty() && start.regions.front().begin <= begin + edge;
  std::vector<double> limits;
  for (const auto& g : start.regions)
    for (double t : {g.begin, g.end})
      if (t > begin + edge && t < end - edge) limits.push_back(t);
  topology.limits = static_cast<int>(limits.size());
  ritz::RitzOptions options;
  options.modes = modes;
  r.solution = ritz::solve_ritz(r.model, topology, limits, options);
  return r;
}

Point measure_ritz(const Options& o, const std::string& name, const scene::Scene& s, const Reference& ref, int modes) {
  Point p = make_point(name, "ritz", "modes", modes);
  try {
    const RitzRun r = run_ritz(s, modes);
    p.termination = std::string(ritz::to_string(r.solution.summary.termination));
    if (r.solution.summary.is_usable() && r.solution.model) {
      const auto& model = *r.solution.model;
      const auto& x = r.solution.unknowns;
      std::vector<double> found;
      for (int m = 0; m < model.limits(); ++m) found.push_back(r.model.user_from_s(x[model.limit_offset() + m]));
      p.limit_error = limit_error(found, ref) / s.structure.length;
      const double w_max =
          maximum_of([&](double t) { return model.w(x, t); }, [&](double t) { return model.w(x, t, 1); },
                     r.model.s_begin, r.model.s_end, 4000) *
          r.model.scales.length;
      p.w_max_error = std::abs(w_max - ref.w_max) / std::abs(ref.w_max);
    }
    p.timing = bench::time_median([&] { run_ritz(s, modes); }, o.repeats);
  } catch (const std::exception& e) {
    p.termination = std::string("refused: ") + e.what();
  }
  return p;
}

Point measure_dolfinx(const Options& o, const std::string& name, const scene::Scene& s, const Reference& ref,
                      int elements, const fs::path& scratch) {
  Point p = make_point(name, "dolfinx", "elements", elements);
  const fs::path json = scratch / fmt::format("dolfinx_{}_{}.json", name, elements);
  const bench::ProcessRun run = bench::run_process(
      {o.python, o.source_dir + "/verification/dolfinx/penalty_reference.py", scene_path(o, name), "--elements",
       std::to_string(elements), "--repeat", std::to_string(o.repeats), "--json", json.string()});
  if (run.exit_code != 0) {
    p.termination = fmt::format("exit {}", run.exit_code);
    return p;
  }
  const nlohmann::json r = nlohmann::json::parse(std::ifstream(json));
  std::vector<ContactRegion> regions;
  for (const auto& g : r["contact_regions"]) regions.push_back({g[0].get<double>(), g[1].get<double>()});
  p.termination = "solved";
  p.limit_error = limit_error(interior_limits(regions, s.begin(), s.end()), ref) / s.structure.length;
  p.w_max_error = std::abs(r["w_max"].get<double>() - ref.w_max) / std::abs(ref.w_max);
  p.timing.median_s = r["time_s"].get<double>();
  std::vector<double> runs;
  if (r.contains("time_s_runs")) runs = r["time_s_runs"].get<std::vector<double>>();
  p.timing.min_s = runs.empty() ? p.timing.median_s : *std::min_element(runs.begin(), runs.end());
  p.timing.runs = runs.empty() ? 1 : static_cast<int>(runs.size());
  return p;
}

void print_point(const Point& p) {
  std::printf("  %-8s %-8s %8d  %-17s limit err %9.2e L  w_max err %9.2e  median %10.3e s (min %.3e, %d runs)\n",
              p.method.c_str(), p.parameter.c_str(), p.size, p.termination.substr(0, 17).c_str(), p.limit_error,
              p.w_max_error, p.timing.median_s, p.timing.min_s, p.timing.runs);
  std::fflush(stdout);
}

std::vector<Point> accuracy_section(const Options& o, const fs::path& scratch) {
  std::vector<Point> points;
  const std::vector<int> dual_sizes =
      o.full ? std::vector<int>{25, 50, 100, 200, 400, 800, 1600} : std::vector<int>{25, 50, 100, 200, 400, 800};
  const std::vector<int> primal_sizes = o.full ? std::vector<int>{25, 50, 100, 200} : std::vector<int>{25, 50, 100};
  const std::vector<int> fast_sizes =
      o.full ? std::vector<int>{25, 50, 100, 200, 400, 800, 1600, 3200, 6400, 12800, 25600, 51200, 102400}
             : std::vector<int>{25, 50, 100, 200, 400, 800, 1600, 3200, 6400, 12800};
  const std::vector<int> modes =
      o.full ? std::vector<int>{4, 8, 16, 32, 64, 128, 256} : std::vector<int>{4, 8, 16, 32, 64, 128};
  const std::vector<int> dolfinx_sizes =
      o.full ? std::vector<int>{50, 100, 200, 400, 800, 1600, 3200} : std::vector<int>{50, 100, 200, 400, 800};
  for (const std::string& name : seed_beams) {
    const scene::Scene s = scene::read_scene_file(scene_path(o, name));
    const Reference ref = exact_reference(s, run_fe(s, Method::dual, 100).regions);
    std::printf("\n%s: exact limits", name.c_str());
    for (double t : ref.limits) std::printf(" %.12f", t);
    std::printf(", exact w_max %.12e\n", ref.w_max);
    for (int n : dual_sizes) print_point(points.emplace_back(measure_fe(o, name, s, ref, Method::dual, n)));
    for (int n : primal_sizes) print_point(points.emplace_back(measure_fe(o, name, s, ref, Method::primal, n)));
    if (const auto fast = fast_method())
      for (int n : fast_sizes) print_point(points.emplace_back(measure_fe(o, name, s, ref, *fast, n)));
    else
      std::printf("  fast     (not in this build: from_string<contact::Method>(\"fast\") is empty; skipped)\n");
    for (int n : modes) print_point(points.emplace_back(measure_ritz(o, name, s, ref, n)));
    if (o.dolfinx)
      for (int n : dolfinx_sizes) print_point(points.emplace_back(measure_dolfinx(o, name, s, ref, n, scratch)));
  }
  std::ofstream csv(fs::path(o.out) / "accuracy.csv");
  csv << "scene,method,parameter,size,termination,limit_error,w_max_error,median_s,min_s,runs\n";
  for (const Point& p : points)
    csv << fmt::format("{},{},{},{},\"{}\",{:.6e},{:.6e},{:.6e},{:.6e},{}\n", p.scene, p.method, p.parameter, p.size,
                       p.termination.substr(0, 60), p.limit_error, p.w_max_error, p.timing.median_s, p.timing.min_s,
                       p.timing.runs);
  return points;
}

// Time for a method to reach a contact-limit error (log-log interpolation between its points,
// in order of size). NaN if never reached.
double time_to_error(const std::vector<Point>& points, const std::string& scene, const std::string& method,
                     double target, bool bracketed_only = false) {
  std::vector<double> errors, times;
  for (const Point& p : points)
    if (p.scene == scene && p.method == method && std::isfinite(p.limit_error) && p.timing.median_s > 0) {
      errors.push_back(std::max(p.limit_error, 1e-300));
      times.push_back(p.timing.median_s);
    }
  // The coarsest point already below the target gives only an upper bound on the time.
  if (bracketed_only && (errors.empty() || errors.front() <= target)) return NAN;
  return bench::interpolate_loglog(errors, times, target);
}

// ---------------------------------------------------------------------------------------------
// Scaling: whole process, time and peak memory.
// ---------------------------------------------------------------------------------------------
struct ScalingRow {
  std::string method;
  int elements = 0;
  int exit_code = -1;
  double wall_s = NAN, solver_s = NAN, peak_rss_mb = NAN;
};

// `liftoff solve SCENE --method M --elements N --json`, median wall time of `repeats` runs.
ScalingRow spawn_solve(const Options& o, const std::string& scene_file, const std::string& method,
                       const std::string& label, int elements, int repeats) {
  ScalingRow row;
  row.method = label;
  row.elements = elements;
  std::vector<double> wall, solver, rss;
  for (int i = 0; i < std::max(1, repeats); ++i) {
    const bench::ProcessRun run = bench::run_process(
        {o.liftoff, "solve", scene_file, "--method", method, "--elements", std::to_string(elements), "--json"});
    row.exit_code = run.exit_code;
    wall.push_back(run.wall_s);
    rss.push_back(run.peak_rss_mb);
    if (run.exit_code == 0) {
      try {
        solver.push_back(nlohmann::json::parse(run.out)["time_s"].get<double>());
      } catch (const std::exception&) {
      }
    }
  }
  row.wall_s = bench::median(wall);
  row.solver_s = bench::median(solver);
  row.peak_rss_mb = *std::max_element(rss.begin(), rss.end());
  return row;
}

std::string bilateral_scene(const Options& o, const fs::path& scratch, const std::string& name) {
  std::ifstream in(scene_path(o, name));
  std::stringstream text;
  text << in.rdbuf();
  std::string t = text.str();
  const std::string from = "tensionless = true", to = "tensionless = false";
  t.replace(t.find(from), from.size(), to);
  const fs::path file = scratch / (name + "_bilateral.toml");
  std::ofstream(file) << t;
  return file.string();
}

void scaling_section(const Options& o, const fs::path& scratch) {
  const int largest = o.max_elements > 0 ? o.max_elements : (o.full ? 1'000'000 : 100'000);
  std::vector<int> sizes;  // 1, 2, 5 per decade
  for (int decade = 100; decade <= largest; decade *= 10)
    for (int step : {1, 2, 5})
      if (decade * step <= largest) sizes.push_back(decade * step);
  const std::string tensionless = scene_path(o, "seed_beam_end_moments");
  const std::string bilateral = bilateral_scene(o, scratch, "seed_beam_end_moments");
  struct Series {
    std::string label, method, scene;
    int largest;
  };
  // Dense methods stop where their matrices stop fitting a shared machine: the dual LCP holds
  // about 24 N^2 bytes (P and K^-1 C^T), the primal 200 N^2 (its 5N x 5N matrix).
  // The primal's Lemke also takes time ~N^4 (43 s at 320 elements on the reference machine).
  std::vector<Series> series = {{"dual", "dual", tensionless, o.full ? 5000 : 2000},
                                {"primal", "primal", tensionless, o.full ? 500 : 200},
                                {"bilateral", "dual", bilateral, largest}};
  if (fast_method())
    series.push_back({"fast", "fast", tensionless, largest});
  else
    std::printf("  fast: not in this build (from_string<contact::Method>(\"fast\") is empty); skipped\n");

  std::vector<ScalingRow> rows;
  std::printf("\nscaling (seed_beam_end_moments, whole process `liftoff solve --json`, median of runs; peak RSS):\n");
  std::printf("  %-9s %8s %5s %11s %11s %10s\n", "method", "elements", "exit", "wall s", "solver s", "peak MiB");
  for (const Series& s : series) {
    for (int n : sizes) {
      if (n > s.largest) break;
      const bool dense = s.label == "dual" || s.label == "primal";
      const int repeats = (n >= 1'000'000 || (dense && n >= 1000)) ? 1
                          : n >= 100'000                           ? std::max(1, o.repeats / 2)
                                                                   : o.repeats;
      const ScalingRow row = spawn_solve(o, s.scene, s.method, s.label, n, repeats);
      rows.push_back(row);
      std::printf("  %-9s %8d %5d %11.4f %11.4f %10.1f\n", row.method.c_str(), row.elements, row.exit_code, row.wall_s,
                  row.solver_s, row.peak_rss_mb);
      std::fflush(stdout);
    }
  }
  // Fitted on the larger half of each method's sizes (at least two): the small ones measure
  // the process start-up more than the method.
  std::printf(
      "\n  fitted exponents (least squares on log-log over the larger half of the sizes; whole-process wall "
      "time, peak memory):\n");
  for (const Series& s : series) {
    std::vector<const ScalingRow*> mine;
    for (const ScalingRow& r : rows)
      if (r.method == s.label) mine.push_back(&r);
    const std::size_t first = mine.size() >= 4 ? mine.size() / 2 : 0;
    std::vector<double> n, t, m;
    for (std::size_t i = first; i < mine.size(); ++i)
      n.push_back(mine[i]->elements), t.push_back(mine[i]->wall_s), m.push_back(mine[i]->peak_rss_mb);
    std::printf("  %-9s time ~ N^%.2f, peak memory ~ N^%.2f (%zu sizes, %d to %d elements)\n", s.label.c_str(),
                bench::fitted_exponent(n, t), bench::fitted_exponent(n, m), n.size(), n.empty() ? 0 : int(n.front()),
                n.empty() ? 0 : int(n.back()));
  }
  std::ofstream csv(fs::path(o.out) / "scaling.csv");
  csv << "method,elements,exit_code,wall_s,solver_s,peak_rss_mb\n";
  for (const ScalingRow& r : rows)
    csv << fmt::format("{},{},{},{:.6e},{:.6e},{:.3f}\n", r.method, r.elements, r.exit_code, r.wall_s, r.solver_s,
                       r.peak_rss_mb);
}

// ---------------------------------------------------------------------------------------------
// Ratios, measured side by side.
// ---------------------------------------------------------------------------------------------
struct Ratio {
  std::string name;
  double numerator_s = NAN, denominator_s = NAN;
  std::string note;
  double value() const { return numerator_s / denominator_s; }
};

void ratios_section(const Options& o, const fs::path& scratch, const std::vector<Point>& accuracy) {
  std::vector<Ratio> ratios;
  const auto fast = fast_method();
  const std::string tensionless = scene_path(o, "seed_beam_end_moments");
  const std::string bilateral = bilateral_scene(o, scratch, "seed_beam_end_moments");
  std::printf("\nratios (seed_beam_end_moments unless said):\n");

  // (a) the fast solver against the bilateral floor at 1e5 elements, whole process, runs
  // interleaved so that both see the same machine load.
  {
    const int n = 100'000;
    std::vector<double> floor_wall, fast_wall;
    int floor_exit = -1, fast_exit = -1;
    for (int i = 0; i < std::max(3, o.repeats); ++i) {
      const auto f = bench::run_process({o.liftoff, "solve", bilateral, "--elements", std::to_string(n), "--json"});
      floor_wall.push_back(f.wall_s), floor_exit = f.exit_code;
      if (fast) {
        const auto r = bench::run_process(
            {o.liftoff, "solve", tensionless, "--method", "fast", "--elements", std::to_string(n), "--json"});
        fast_wall.push_back(r.wall_s), fast_exit = r.exit_code;
      }
    }
    // The same floor in-process: ActiveSetSystem with every node in contact is exactly one
    // sparse factorisation and solve of the bilateral system (assembly included).
    const scene::Scene sb = scene::read_scene_file(bilateral);
    const Timing in_process = bench::time_median(
        [&] {
          const model::MemberModel model = model::make_member_model(sb);
          const fe::Discretisation d = fe::discretise(model, n);
          contact::ActiveSetSystem system(d);
          system.factorise(std::vector<bool>(d.reactions(), true));
          system.solve(d.load(1.0));
        },
        o.repeats);
    std::printf(
        "  bilateral floor at %d elements: whole process %.4f s (median of %zu, exit %d), in-process assembly + "
        "factorisation + solve %.4f s\n",
        n, bench::median(floor_wall), floor_wall.size(), floor_exit, in_process.median_s);
    if (floor_exit != 0)
      std::printf(
          "    (exit %d: `liftoff solve` refuses the bilateral answer at this size: round-off in the "
          "assembled stiffness (cond ~ N^4) leaves iterative refinement unsettled; the time is still one "
          "factorisation and solve)\n",
          floor_exit);
    if (fast) {
      ratios.push_back({"fast / bilateral floor, 1e5 elements, whole process", bench::median(fast_wall),
                        bench::median(floor_wall), fmt::format("target <= 1.5; fast exit {}", fast_exit)});
    } else {
      std::printf("  fast / floor: the fast solver is not in this build; skipped\n");
    }
  }

  // (b) dense dual Lemke against the fast solver at 2000 elements, in process.
  {
    const scene::Scene s = scene::read_scene_file(tensionless);
    std::string dual_outcome;
    const Timing dual = bench::time_median(
        [&] {
          dual_outcome = std::string(contact::to_string(run_fe(s, Method::dual, 2000).solution.summary.termination));
        },
        o.repeats);
    std::printf("  dual at 2000 elements: %.4f s (median of %d), %s\n", dual.median_s, dual.runs, dual_outcome.c_str());
    if (fast) {
      std::string fast_outcome;
      const Timing f = bench::time_median(
          [&] { fast_outcome = std::string(contact::to_string(run_fe(s, *fast, 2000).solution.summary.termination)); },
          o.repeats);
      std::printf("  fast at 2000 elements: %.6f s (median of %d), %s\n", f.median_s, f.runs, fast_outcome.c_str());
      ratios.push_back({"dual / fast, 2000 elements, in process", dual.median_s, f.median_s,
                        "dual " + dual_outcome + ", fast " + fast_outcome});
    } else {
      std::printf("  dual / fast: the fast solver is not in this build; skipped\n");
    }
  }

  // (c) Ritz against FE at equal contact-limit error; (d) best method against dolfinx at 1e-6 L.
  for (const std::string& name : seed_beams) {
    for (const Point& p : accuracy) {
      if (p.scene != name || p.method != "ritz" || !std::isfinite(p.limit_error)) continue;
      for (const std::string fe_method : {"dual", "fast"}) {
        const double t_fe = time_to_error(accuracy, name, fe_method, p.limit_error, /*bracketed_only=*/true);
        if (!std::isfinite(t_fe)) continue;
        ratios.push_back({fmt::format("{} / Ritz at equal limit error {:.1e} L ({}, {} modes)", fe_method,
                                      p.limit_error, name, p.size),
                          t_fe, p.timing.median_s, "FE time interpolated (log-log) at the Ritz error"});
      }
    }
    const double target = 1e-6;
    std::string best_method;
    double best = INFINITY;
    for (const std::string method : {"dual", "primal", "fast", "ritz"}) {
      const double t = time_to_error(accuracy, name, method, target);
      std::printf("  %s: time to a contact-limit error of 1e-6 L, %-7s %s\n", name.c_str(), method.c_str(),
                  std::isfinite(t) ? fmt::format("{:.3e} s", t).c_str() : "not reached");
      if (std::isfinite(t) && t < best) best = t, best_method = method;
    }
    const double t_dolfinx = time_to_error(accuracy, name, "dolfinx", target);
    std::printf(
        "  %s: time to a contact-limit error of 1e-6 L, dolfinx %s\n", name.c_str(),
        std::isfinite(t_dolfinx) ? fmt::format("{:.3e} s (solve only)", t_dolfinx).c_str() : "not reached / not run");
    if (std::isfinite(best) && std::isfinite(t_dolfinx))
      ratios.push_back({fmt::format("dolfinx / best ({}) at limit error 1e-6 L, {}", best_method, name), t_dolfinx,
                        best, "target >= 1000"});
  }

  std::printf("\n  %-96s %11s %11s %9s  %s\n", "ratio", "numer. s", "denom. s", "ratio", "note");
  for (const Ratio& r : ratios)
    std::printf("  %-96s %11.4e %11.4e %9.3g  %s\n", r.name.c_str(), r.numerator_s, r.denominator_s, r.value(),
                r.note.c_str());
  std::ofstream csv(fs::path(o.out) / "ratios.csv");
  csv << "ratio,numerator_s,denominator_s,value,note\n";
  for (const Ratio& r : ratios)
    csv << fmt::format("\"{}\",{:.6e},{:.6e},{:.6e},\"{}\"\n", r.name, r.numerator_s, r.denominator_s, r.value(),
                       r.note);
}

}  // namespace

int main(int argc, char** argv) {
  liftoff::tune_allocator();  // as the liftoff executable does: the same allocator in both timings
  Options o;
  CLI::App app{"liftoff_bench: run time against error, scaling and speed ratios of liftoff's methods"};
  app.add_option("--out", o.out,
                 "Directory for accuracy.csv, scaling.csv, ratios.csv, targets.csv, tolerance.csv (created)");
  app.add_flag("--full", o.full, "Finer meshes, more modes, scaling to 1e6 elements (default: the quick set)");
  app.add_option("--repeats", o.repeats, "Runs per measurement (the median is reported)")->check(CLI::Range(1, 1000));
  app.add_option("--max-elements", o.max_elements, "Largest mesh of the scaling section (default 1e5 quick, 1e6 full)")
      ->check(CLI::Range(100, 10'000'000));
  app.add_option("--sections", o.sections,
                 "Comma-separated: accuracy, scaling, ratios (the default), targets (time to limit errors of 1e-6, "
                 "1e-8, 1e-10 L on every closed-form scene, every method), tolerance (the honesty of --tolerance's "
                 "error estimates on the same scenes, every method)");
  app.add_option("--scenes", o.only, "targets, tolerance: only these scenes (comma-separated names, default all)");
  app.add_flag("!--no-dolfinx", o.dolfinx, "Skip the dolfinx reference");
  app.add_option("--liftoff", o.liftoff, "The liftoff executable (whole-process runs)");
  app.add_option("--python", o.python, "Python with dolfinx (default /usr/bin/python3)");
  app.add_option("--source-dir", o.source_dir, "liftoff's source tree (scenes, the dolfinx script)");
  CLI11_PARSE(app, argc, argv);

  const fs::path scratch = fs::path(o.out) / "scratch";
  fs::create_directories(scratch);
  std::printf("liftoff_bench (%s set, %d runs per measurement), fast solver %s\n", o.full ? "full" : "quick", o.repeats,
              fast_method() ? "present" : "absent (skipped where it appears)");
  try {
    std::vector<Point> accuracy;
    if (o.has("accuracy") || o.has("ratios")) accuracy = accuracy_section(o, scratch);
    if (o.has("scaling")) scaling_section(o, scratch);
    if (o.has("ratios")) ratios_section(o, scratch, accuracy);
    if (o.has("targets"))
      bench::run_targets({o.out, scratch.string(), o.source_dir, o.python, o.dolfinx, o.full, o.repeats, o.only});
    if (o.has("tolerance")) bench::run_tolerance({o.out, scratch.string(), o.source_dir, o.full, o.repeats, o.only});
  } catch (const std::exception& e) {
    std::fprintf(stderr, "liftoff_bench: %s\n", e.what());
    return 1;
  }
  fs::remove_all(scratch);
  std::printf("\nCSV written to %s (plot: /usr/bin/python3 verification/bench/plot_bench.py %s)\n", o.out.c_str(),
              o.out.c_str());
  return 0;
}
