#include "targets.hpp"

#include <fmt/format.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "closed_form/beam_on_foundation.hpp"
#include "closed_form/member_problem.hpp"
#include "contact/active_set_solver.hpp"
#include "contact/contact_solver.hpp"
#include "contact/fitted_limits.hpp"
#include "fe/discretisation.hpp"
#include "measure.hpp"
#include "model/from_scene.hpp"
#include "model/member_model.hpp"
#include "post/contact_regions.hpp"
#include "ritz/ritz_solver.hpp"
#include "ritz/starting_point.hpp"
#include "scene/scene_reader.hpp"

namespace fs = std::filesystem;

namespace liftoff::bench {
namespace {

constexpr double targets[] = {1e-6, 1e-8, 1e-10};

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// ---- scenes and their exact limits ----------------------------------------------------------

// The closed form covers a beam on a foundation along its whole length without interior
// supports (verification/closed_form/main.cpp refuses the rest).
bool has_closed_form(const scene::Scene& s) {
  return s.structure.kind == scene::StructureKind::beam && s.supports.interior.empty() &&
         s.foundation.from <= s.begin() && s.foundation.to >= s.end() && s.foundation.tensionless;
}

// The exact solution: the closed form's Newton started from fast's regions at 4000 elements.
closed_form::TensionlessResult exact_solution(const model::MemberModel& model) {
  const fe::Discretisation d = fe::discretise(model, 4000);
  contact::ContactOptions options;
  options.method = contact::Method::fast;
  const contact::ContactSolution fast = contact::solve_contact(d, options);
  if (!fast.summary.is_usable())
    throw std::runtime_error("fast found no answer at 4000 elements: " + fast.summary.message);
  std::vector<closed_form::Interval> guess;
  for (const auto& r : post::contact_regions(model, d, fast.displacement))
    guess.push_back({r.begin - model.s_begin, r.end - model.s_begin});
  closed_form::TensionlessResult exact = closed_form::solve_tensionless(closed_form::problem_of(model), guess);
  if (exact.status != closed_form::TensionlessStatus::converged)
    throw std::runtime_error("the closed form did not converge: " + exact.message);
  return exact;
}

// A weightless free-free beam under a central point load, beta L = 6 (k = 4 * 6^4): its ends
// lift off; the issue's third target scene.
const char* free_beam_toml = R"(# Weightless free beam under a central point load, beta L = 6: both ends lift off.
[structure]
kind = "beam"
length = 1.0
EI = 1.0

[supports]
left = "free"
right = "free"

[foundation]
k = 5184.0
tensionless = true

[[loads]]
kind = "force"
at = 0.5
value = 1.0
)";

// The interior limits (s) of contact regions given in s.
template <class Intervals>
std::vector<double> interior_limits(const Intervals& regions, const model::MemberModel& model) {
  return ritz::starting_point_from_regions(regions, model).limits;
}

double limit_error(const std::vector<double>& found, const std::vector<double>& exact, double length) {
  if (found.size() != exact.size() || exact.empty()) return NAN;
  double worst = 0.0;
  for (std::size_t k = 0; k < found.size(); ++k) worst = std::max(worst, std::abs(found[k] - exact[k]));
  return worst / length;
}

// ---- one measured point, in a child process -------------------------------------------------

struct Sample {  // written through a pipe: plain data only
  int solved = 0;
  double error = NAN;   // contact-limit error / length
  double time_s = NAN;  // median
  int runs = 0;
  double peak_mb = NAN;  // the child's ru_maxrss
  char note[160] = {};
};

// One solve: the limits (s) and whether it is an answer; `note` says why not.
using Solve = std::function<bool(std::vector<double>& limits, std::string& note)>;

Sample measure(const Solve& solve, const std::vector<double>& exact, double length, int repeats) {
  int fds[2];
  if (::pipe(fds) != 0) throw std::runtime_error("pipe failed");
  std::fflush(stdout);
  const pid_t pid = ::fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    ::close(fds[0]);
    Sample s;
    auto start = std::chrono::steady_clock::now();
    try {
      std::vector<double> limits;
      std::string note;
      std::vector<double> times;
      s.solved = solve(limits, note) ? 1 : 0;
      times.push_back(seconds_since(start));
      if (s.solved) s.error = limit_error(limits, exact, length);
      // Repeats while they are cheap: at least `repeats` runs below 0.5 s, up to 0.3 s of them
      // for the microsecond solves (the clock's resolution and the cache).
      const double first = times.front();
      const int more = first > 2.0   ? 0
                       : first > 0.5 ? 2
                                     : std::max(repeats - 1, static_cast<int>(std::min(200.0, 0.3 / first)));
      for (int i = 0; i < more; ++i) {
        std::vector<double> again;
        std::string ignored;
        start = std::chrono::steady_clock::now();
        solve(again, ignored);
        times.push_back(seconds_since(start));
      }
      s.time_s = median(times);
      s.runs = static_cast<int>(times.size());
      std::snprintf(s.note, sizeof s.note, "%s", note.c_str());
    } catch (const std::exception& e) {  // a refusal: its time still ends a sequence that grew too slow
      s.solved = 0;
      s.time_s = seconds_since(start);
      std::snprintf(s.note, sizeof s.note, "refused: %s", e.what());
    }
    [[maybe_unused]] const auto written = ::write(fds[1], &s, sizeof s);
    ::close(fds[1]);
    ::_exit(0);
  }
  ::close(fds[1]);
  Sample s;
  const ssize_t got = ::read(fds[0], &s, sizeof s);
  ::close(fds[0]);
  int status = 0;
  rusage usage{};
  ::wait4(pid, &status, 0, &usage);
  if (got != static_cast<ssize_t>(sizeof s)) {
    s = Sample{};
    std::snprintf(s.note, sizeof s.note, "child died (status %d)", status);
  }
  s.peak_mb = usage.ru_maxrss / 1024.0;
  return s;
}

// ---- methods --------------------------------------------------------------------------------

struct Point {
  std::string scene, method;
  int size = 0;
  Sample sample;
};

Solve node_based(const model::MemberModel& model, contact::Method method, int elements) {
  return [&model, method, elements](std::vector<double>& limits, std::string& note) {
    const fe::Discretisation d = fe::discretise(model, elements);
    contact::ContactOptions options;
    options.method = method;
    const contact::ContactSolution solution = contact::solve_contact(d, options);
    if (!solution.summary.is_usable()) {
      note = solution.summary.message;
      return false;
    }
    limits = interior_limits(post::contact_regions(model, d, solution.displacement), model);
    return true;
  };
}

// fast on the mesh for the topology, then the limit-fitted solve with as many elements. fast
// starts from the set of a mesh 4x coarser (at least 32 elements, 4 per decay length 1/beta):
// two sets on this mesh instead of five to seven from the bilateral start; the topology is still
// this mesh's.
Solve fitted(const model::MemberModel& model, int elements) {
  return [&model, elements](std::vector<double>& limits, std::string& note) {
    const fe::Discretisation d = fe::discretise(model, elements);
    contact::NestedOptions nested;
    nested.coarsening = 4;
    nested.min_elements = 32;
    nested.elements_per_decay_length = 4.0;
    const contact::ActiveSetResult fast = contact::solve_active_set_nested(model, d, 1.0, {}, nested).result;
    if (!fast.summary.is_usable()) {
      note = "fast: " + fast.summary.message;
      return false;
    }
    contact::FittedOptions fitted_options;
    fitted_options.elements = elements;
    const contact::FittedResult r = contact::solve_fitted_limits(
        model, 1.0, contact::contact_intervals(d, fast.state.displacement, fast.in_contact), fitted_options);
    if (!r.summary.is_usable()) {
      note = r.summary.message;
      return false;
    }
    limits = r.limits;
    return true;
  };
}

Solve ritz_modes(const model::MemberModel& model, int modes) {
  return [&model, modes](std::vector<double>& limits, std::string& note) {
    const fe::Discretisation d = fe::discretise(model, 100);
    contact::ContactOptions options;
    options.method = contact::Method::fast;
    const contact::ContactSolution fast = contact::solve_contact(d, options);
    if (!fast.summary.is_usable()) {
      note = "fast start: " + fast.summary.message;
      return false;
    }
    const auto start = ritz::starting_point_from_regions(post::contact_regions(model, d, fast.displacement), model);
    ritz::RitzOptions ritz_options;
    ritz_options.modes = modes;
    const ritz::RitzSolution r = ritz::solve_ritz(model, start.topology, start.limits, ritz_options);
    if (!r.summary.is_usable() || !r.model) {
      note = r.summary.message;
      return false;
    }
    for (int m = 0; m < r.model->limits(); ++m) limits.push_back(r.unknowns[r.model->limit_offset() + m]);
    return true;
  };
}

struct Series {
  std::string method;
  std::vector<int> sizes;
  double time_limit_s;  // a run slower than this ends the sequence
  std::function<Solve(int)> solve;
};

// ---- report ---------------------------------------------------------------------------------

struct Reached {
  int size = 0;
  double time_s = NAN, peak_mb = NAN, error = NAN;
  bool reached() const { return size > 0; }
};

Reached first_reaching(const std::vector<Point>& points, const std::string& scene, const std::string& method,
                       double target) {
  for (const Point& p : points)
    if (p.scene == scene && p.method == method && p.sample.solved && p.sample.error <= target)
      return {p.size, p.sample.time_s, p.sample.peak_mb, p.sample.error};
  return {};
}

struct Exponents {
  double time = NAN, error = NAN;
};

Exponents fit(const std::vector<Point>& points, const std::string& scene, const std::string& method) {
  std::vector<double> n, t, ne, e;
  for (const Point& p : points) {
    if (p.scene != scene || p.method != method || !p.sample.solved) continue;
    n.push_back(p.size), t.push_back(p.sample.time_s);
    if (p.sample.error > 1e-13) ne.push_back(p.size), e.push_back(p.sample.error);
  }
  const std::size_t half = n.size() >= 4 ? n.size() / 2 : 0;
  Exponents x;
  x.time =
      fitted_exponent(std::vector<double>(n.begin() + half, n.end()), std::vector<double>(t.begin() + half, t.end()));
  x.error = -fitted_exponent(ne, e);
  return x;
}

std::string cell(const Reached& r, const char* unit) {
  if (!r.reached()) return "not reachable";
  const double t = r.time_s;
  const std::string time = t < 1e-3 ? fmt::format("{:.0f} us", 1e6 * t)
                           : t < 1  ? fmt::format("{:.1f} ms", 1e3 * t)
                                    : fmt::format("{:.2f} s", t);
  return fmt::format("{} {} {}, {:.0f} MB", r.size, unit, time, r.peak_mb);
}

}  // namespace

std::vector<ClosedFormScene> closed_form_scenes(const std::string& source_dir, const std::string& scratch,
                                                const std::string& only) {
  std::vector<std::pair<std::string, std::string>> files = {
      {"seed_beam_end_moments", source_dir + "/verification/scenes/seed_beam_end_moments.toml"},
      {"seed_beam_end_moments_central_load",
       source_dir + "/verification/scenes/seed_beam_end_moments_central_load.toml"}};
  std::vector<fs::path> engineering;
  for (const auto& entry : fs::directory_iterator(source_dir + "/verification/scenes/engineering"))
    if (entry.path().extension() == ".toml") engineering.push_back(entry.path());
  std::sort(engineering.begin(), engineering.end());
  for (const auto& p : engineering) files.push_back({p.stem().string(), p.string()});
  const fs::path free_beam = fs::path(scratch) / "free_beam_central_load.toml";
  std::ofstream(free_beam) << free_beam_toml;
  files.push_back({"free_beam_central_load", free_beam.string()});
  std::vector<ClosedFormScene> scenes;
  for (const auto& [name, file] : files) {
    if (!only.empty() && ("," + only + ",").find("," + name + ",") == std::string::npos) continue;
    ClosedFormScene t;
    t.name = name, t.file = file;
    t.scene = scene::read_scene_file(file);
    if (!has_closed_form(t.scene)) {
      std::printf("  %s: no closed form (arch, partial foundation or interior support): skipped\n", name.c_str());
      continue;
    }
    t.model = model::make_member_model(t.scene);
    t.solution = exact_solution(t.model);
    t.exact = t.solution.limits;
    for (double& s : t.exact) s += t.model.s_begin;
    if (t.exact.empty()) {
      std::printf("  %s: in contact along its whole length (no contact limit to measure): skipped\n", name.c_str());
      continue;
    }
    scenes.push_back(std::move(t));
  }
  return scenes;
}

void run_targets(const TargetOptions& o) {
  const std::vector<ClosedFormScene> scenes = closed_form_scenes(o.source_dir, o.scratch, o.only);

  auto doubling = [](int first, int last) {
    std::vector<int> sizes;
    for (int n = first; n <= last; n *= 2) sizes.push_back(n);
    return sizes;
  };
  std::vector<Point> points;
  // Peak memory of a child that does nothing: what every figure below includes.
  const Sample idle = measure([](std::vector<double>&, std::string&) { return false; }, {}, 1.0, 1);
  std::printf(
      "\ntargets: time to contact-limit errors of 1e-6, 1e-8, 1e-10 L against the closed form (child "
      "processes; their idle peak RSS is %.0f MB)\n",
      idle.peak_mb);
  for (const ClosedFormScene& t : scenes) {
    const model::MemberModel& model = t.model;
    const double length = model.length();
    std::printf("\n%s: exact limits x =", t.name.c_str());
    for (double s : t.exact) std::printf(" %.12g", model.user_from_s(s));
    std::printf("\n  %-8s %8s %-8s %11s %11s %8s %5s  %s\n", "method", "size", "", "limit err/L", "time", "peak MB",
                "runs", "note");
    const std::vector<Series> series = {
        {"dual", doubling(25, o.full ? 3200 : 1600), 20.0,
         [&](int n) { return node_based(model, contact::Method::dual, n); }},
        {"primal", doubling(25, o.full ? 200 : 100), 10.0,
         [&](int n) { return node_based(model, contact::Method::primal, n); }},
        {"fast", doubling(25, o.full ? 3276800 : 1638400), 30.0,
         [&](int n) { return node_based(model, contact::Method::fast, n); }},
        {"fitted", doubling(10, o.full ? 20480 : 10240), 10.0, [&](int n) { return fitted(model, n); }},
        {"ritz", doubling(4, 256), 30.0, [&](int n) { return ritz_modes(model, n); }},
    };
    for (const Series& s : series) {
      for (int n : s.sizes) {
        Point p{t.name, s.method, n, measure(s.solve(n), t.exact, length, o.repeats)};
        points.push_back(p);
        std::printf("  %-8s %8d %-8s %11.2e %9.3e s %8.0f %5d  %s\n", s.method.c_str(), n,
                    s.method == "ritz" ? "modes" : "elements", p.sample.error, p.sample.time_s, p.sample.peak_mb,
                    p.sample.runs, p.sample.solved ? "" : p.sample.note);
        std::fflush(stdout);
        if (p.sample.solved && p.sample.error <= 1e-11) break;  // the last target with margin
        if (!(p.sample.time_s <= s.time_limit_s)) break;
      }
    }
    if (o.dolfinx) {
      const fs::path json = fs::path(o.scratch) / fmt::format("dolfinx_{}.json", t.name);
      const ProcessRun run = run_process({o.python, o.source_dir + "/verification/dolfinx/penalty_reference.py", t.file,
                                          "--refine", "--start-elements", "50", "--max-elements",
                                          o.full ? "12800" : "6400", "--tolerance", "0", "--json", json.string()});
      if (run.exit_code != 0) {
        std::printf("  dolfinx: exit %d\n", run.exit_code);
      } else {
        const nlohmann::json r = nlohmann::json::parse(std::ifstream(json));
        for (const auto& level : r["refinement"]) {
          std::vector<ContactRegion> regions;
          for (const auto& g : level["contact_regions"])
            regions.push_back({model.s_from_user(g[0].get<double>()), model.s_from_user(g[1].get<double>())});
          Point p{t.name, "dolfinx", level["elements"].get<int>(), Sample{}};
          p.sample.solved = 1;
          p.sample.error = limit_error(interior_limits(regions, model), t.exact, length);
          p.sample.time_s = level["time_s"].get<double>();
          p.sample.runs = 1;
          p.sample.peak_mb = run.peak_rss_mb;  // the whole python process, all meshes
          points.push_back(p);
          std::printf("  %-8s %8d %-8s %11.2e %9.3e s %8.0f %5d  %s\n", "dolfinx", p.size, "elements", p.sample.error,
                      p.sample.time_s, p.sample.peak_mb, 1, "solve time only; memory: whole process");
        }
      }
    }
  }

  // The tables: per scene and method, the first size below each target.
  const std::vector<std::string> methods = {"dual", "primal", "fast", "fitted", "ritz", "dolfinx"};
  std::printf(
      "\ntargets: first size of each doubling sequence whose contact-limit error is below the target: size, "
      "solve time (median), peak MB\n");
  for (const ClosedFormScene& t : scenes) {
    std::printf("\n%s\n  %-8s | %-30s | %-30s | %-30s | %s\n", t.name.c_str(), "method", "1e-6 L", "1e-8 L", "1e-10 L",
                "time ~ n^a, error ~ n^-b");
    for (const std::string& m : methods) {
      const char* unit = m == "ritz" ? "modes" : "el.";
      const Exponents x = fit(points, t.name, m);
      auto number = [](double v) { return std::isfinite(v) ? fmt::format("{:.2f}", v) : std::string("-"); };
      std::printf("  %-8s | %-30s | %-30s | %-30s | a = %s, b = %s\n", m.c_str(),
                  cell(first_reaching(points, t.name, m, 1e-6), unit).c_str(),
                  cell(first_reaching(points, t.name, m, 1e-8), unit).c_str(),
                  cell(first_reaching(points, t.name, m, 1e-10), unit).c_str(), number(x.time).c_str(),
                  number(x.error).c_str());
    }
  }
  std::printf(
      "\ntargets: the best liftoff method per target, and dolfinx / best at 1e-8 L (target: 1e-8 L in <= 1 ms; "
      ">= 1000x faster than dolfinx)\n");
  std::printf("  %-36s | %-24s | %-24s | %-24s | %s\n", "scene", "1e-6 L", "1e-8 L", "1e-10 L", "dolfinx / best, 1e-8");
  for (const ClosedFormScene& t : scenes) {
    std::printf("  %-36s", t.name.c_str());
    double best8 = NAN;
    for (double target : targets) {
      std::string best_method;
      Reached best;
      for (const std::string& m : methods) {
        if (m == "dolfinx") continue;
        const Reached r = first_reaching(points, t.name, m, target);
        if (r.reached() && !(best.time_s <= r.time_s)) best = r, best_method = m;
      }
      if (target == 1e-8) best8 = best.time_s;
      std::printf(" | %-24s", best.reached() ? fmt::format("{} {:.3g} ms", best_method, 1e3 * best.time_s).c_str()
                                             : "not reachable");
    }
    const Reached d = first_reaching(points, t.name, "dolfinx", 1e-8);
    std::printf(" | %s\n",
                d.reached() && std::isfinite(best8)
                    ? fmt::format("{:.0f} ({:.3g} s / {:.3g} ms)", d.time_s / best8, d.time_s, 1e3 * best8).c_str()
                    : (o.dolfinx ? "dolfinx does not reach 1e-8" : "dolfinx not run"));
  }

  std::ofstream csv(fs::path(o.out) / "targets.csv");
  csv << "scene,method,size,solved,limit_error,time_s,runs,peak_mb,note\n";
  for (const Point& p : points)
    csv << fmt::format("{},{},{},{},{:.6e},{:.6e},{},{:.1f},\"{}\"\n", p.scene, p.method, p.size, p.sample.solved,
                       p.sample.error, p.sample.time_s, p.sample.runs, p.sample.peak_mb, p.sample.note);
}

}  // namespace liftoff::bench
