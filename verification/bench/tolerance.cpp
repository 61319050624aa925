#include "tolerance.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "app/solve_command.hpp"
#include "measure.hpp"
#include "targets.hpp"

namespace fs = std::filesystem;

namespace liftoff::bench {
namespace {

struct Row {
  std::string scene, method, method_used;
  double tolerance = NAN;
  std::string termination, note;
  bool usable = false;
  int size = -1;                                   // elements (FE) or modes (Ritz)
  double limit_error = NAN, limit_estimate = NAN;  // relative to the length
  double w_error = NAN, w_estimate = NAN, reaction_error = NAN, reaction_estimate = NAN;
  double order = NAN;
  double time_s = NAN;
  int runs = 0;
  double honesty() const { return limit_estimate / limit_error; }
};

double or_nan(double estimate) { return estimate >= 0 ? estimate : NAN; }

// The interior contact limits (user coordinate) of regions given in the user's coordinate.
std::vector<double> interior_limits(const std::vector<ContactRegion>& regions, double begin, double end) {
  std::vector<double> limits;
  const double edge = 1e-9 * std::abs(end - begin);
  for (const auto& r : regions)
    for (double t : {r.begin, r.end})
      if (t > std::min(begin, end) + edge && t < std::max(begin, end) - edge) limits.push_back(t);
  std::sort(limits.begin(), limits.end());
  return limits;
}

// The true errors of one answer against the closed form.
void measure_errors(const ClosedFormScene& t, const io::SolveReport& r, Row& row) {
  const model::MemberModel& m = t.model;
  const double begin = m.user_from_s(m.s_begin), end = m.user_from_s(m.s_end), length = std::abs(end - begin);
  const std::vector<double> found = interior_limits(r.contact_regions, begin, end);
  std::vector<double> exact;
  for (double s : t.exact) exact.push_back(m.user_from_s(s));
  std::sort(exact.begin(), exact.end());
  if (found.size() == exact.size()) {
    double worst = 0.0;
    for (std::size_t k = 0; k < found.size(); ++k) worst = std::max(worst, std::abs(found[k] - exact[k]));
    row.limit_error = worst / length;
  } else {
    row.note = fmt::format("{} contact limits, the exact solution has {}", found.size(), exact.size());
  }
  // w and the reaction k max(w, 0), nondimensional (the reaction divided by k: it is k w).
  const closed_form::BeamSolution& exact_w = t.solution.solution;
  auto w_exact = [&](double x) { return exact_w.deflection(m.s_from_user(x) - m.s_begin); };
  const double w_scale = m.scales.displacement();
  const double reaction_scale = m.k * m.scales.force_per_length();
  double w_largest = 0.0, pressed_largest = 0.0;  // max |w| and max w of the exact solution
  for (int i = 0; i <= 20000; ++i) {
    const double w = exact_w.deflection(m.length() * i / 20000.0);
    w_largest = std::max(w_largest, std::abs(w)), pressed_largest = std::max(pressed_largest, w);
  }
  // The sampled fields (16 points per element, Ritz: its grid); the FE nodes when there are none
  // (a refused answer).
  const io::FieldTable& f = r.fields.coordinate.empty() ? r.nodes : r.fields;
  if (f.coordinate.empty() || f.w.size() != f.coordinate.size()) return;
  double w_worst = 0.0, reaction_worst = 0.0;
  for (std::size_t i = 0; i < f.coordinate.size(); ++i) {
    const double w = w_exact(f.coordinate[i]);
    w_worst = std::max(w_worst, std::abs(f.w[i] / w_scale - w));
    if (i < f.reaction.size())
      reaction_worst = std::max(reaction_worst, std::abs(f.reaction[i] / reaction_scale - std::max(w, 0.0)));
  }
  row.w_error = w_worst / w_largest;
  if (f.reaction.size() == f.coordinate.size()) row.reaction_error = reaction_worst / pressed_largest;
}

Row run_one(const ClosedFormScene& t, scene::Method method, double tolerance, int repeats) {
  Row row;
  row.scene = t.name, row.method = std::string(scene::to_string(method)), row.tolerance = tolerance;
  app::SolveRequest request;
  request.method = method;
  request.tolerance = tolerance;
  request.fields = true;  // for the errors: w inside the elements, not only at the nodes
  try {
    const io::SolveReport r = app::solve_scene(t.scene, request);
    row.method_used = r.method;
    row.termination = r.termination;
    row.usable = r.usable;
    row.size = r.modes > 0 ? r.modes : r.elements;
    if (!r.refinement_elements.empty() && row.size <= 0) row.size = r.refinement_elements.back();
    const double length = std::abs(t.model.user_from_s(t.model.s_end) - t.model.user_from_s(t.model.s_begin));
    row.limit_estimate = or_nan(r.estimated_limit_error) / length;
    row.w_estimate = or_nan(r.estimated_w_error), row.reaction_estimate = or_nan(r.estimated_reaction_error);
    row.order = or_nan(r.observed_order);
    // A refused answer that still has limits and an estimate (a failed certificate) is measured
    // too: its figures are printed beside the reason, outside the honesty summary.
    if (r.usable || (!r.contact_regions.empty() && r.estimated_limit_error >= 0)) measure_errors(t, r, row);
    if (!r.usable) row.note = r.message;
    // The time without fields (as `liftoff solve --json` without --output), repeated while cheap.
    request.fields = false;
    std::vector<double> times{app::solve_scene(t.scene, request).time_s};
    const int more = times.front() > 0.5 ? 0 : repeats - 1;
    for (int i = 0; i < more; ++i) times.push_back(app::solve_scene(t.scene, request).time_s);
    row.time_s = median(times);
    row.runs = static_cast<int>(times.size());
  } catch (const std::exception& e) {  // SolverFailure or InputError: the method refuses the scene
    row.termination = "refused";
    row.note = e.what();
  }
  return row;
}

std::string number(double v, const char* format = "{:.2e}") {
  return std::isfinite(v) ? fmt::format(fmt::runtime(format), v) : std::string("-");
}

std::string time_text(double t) {
  if (!std::isfinite(t)) return "-";
  return t < 1e-3 ? fmt::format("{:.0f} us", 1e6 * t)
         : t < 1  ? fmt::format("{:.2f} ms", 1e3 * t)
                  : fmt::format("{:.2f} s", t);
}

// A reason on one line, without the scene's file name the solver prefixes.
std::string short_reason(std::string note, const std::string& file) {
  for (std::size_t at; (at = note.find(file + ": ")) != std::string::npos;) note.erase(at, file.size() + 2);
  std::replace(note.begin(), note.end(), '\n', ' ');
  return note.size() > 150 ? note.substr(0, 147) + "..." : note;
}

}  // namespace

void run_tolerance(const ToleranceBenchOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<double> tolerances = {1e-6, 1e-8, 1e-10};
  if (o.full) tolerances.push_back(1e-12);
  const std::vector<scene::Method> methods = {scene::Method::automatic, scene::Method::fast, scene::Method::dual,
                                              scene::Method::primal, scene::Method::ritz};
  const std::vector<ClosedFormScene> scenes = closed_form_scenes(o.source_dir, o.scratch, o.only);
  std::printf(
      "\ntolerance: `liftoff solve --tolerance T --method M` in process (app::solve_scene, no fields) against the "
      "closed form.\n  errors relative to L (limits), max |w| (w: 16 samples per element, Ritz on its grid), the "
      "largest reaction k max(w, 0) (r); est/true = estimated_limit_error / true limit error; time: report.time_s, "
      "median\n");
  std::vector<Row> rows;
  for (const ClosedFormScene& t : scenes) {
    std::printf("\n%s: exact limits x =", t.name.c_str());
    for (double s : t.exact) std::printf(" %.12g", t.model.user_from_s(s));
    std::printf("\n  %-11s | %-5s | %-21s | %8s | %9s | %9s | %8s | %5s | %9s | %9s | %9s | %9s | %9s\n", "method",
                "tol", "termination", "size", "limit err", "estimate", "est/true", "order", "w err", "w est", "r err",
                "r est", "time");
    for (scene::Method method : methods) {
      for (double tolerance : tolerances) {
        const Row& row = rows.emplace_back(run_one(t, method, tolerance, o.repeats));
        const std::string label =
            row.method_used.empty() || row.method_used == row.method ? row.method : row.method + ">" + row.method_used;
        if (!row.usable) {
          std::printf("  %-11s | %5.0e | %-21s | %s\n", label.c_str(), tolerance, row.termination.c_str(),
                      short_reason(row.note, t.scene.source_name).c_str());
          if (std::isfinite(row.limit_error) || std::isfinite(row.limit_estimate))
            std::printf(
                "  %-11s   %5s   %-21s   (the refused answer: %d %s, limit err %s, estimate %s, est/true %s, "
                "order %s; w err %s, est %s; r err %s, est %s)\n",
                "", "", "", row.size, row.method_used == "ritz" ? "modes" : "el", number(row.limit_error).c_str(),
                number(row.limit_estimate).c_str(), number(row.honesty(), "{:.3g}").c_str(),
                number(row.order, "{:.2f}").c_str(), number(row.w_error).c_str(), number(row.w_estimate).c_str(),
                number(row.reaction_error).c_str(), number(row.reaction_estimate).c_str());
        } else {
          std::printf("  %-11s | %5.0e | %-21s | %5d %-2s | %9s | %9s | %8s | %5s | %9s | %9s | %9s | %9s | %9s%s%s\n",
                      label.c_str(), tolerance, row.termination.c_str(), row.size,
                      row.method_used == "ritz" ? "md" : "el", number(row.limit_error).c_str(),
                      number(row.limit_estimate).c_str(), number(row.honesty(), "{:.3g}").c_str(),
                      number(row.order, "{:.2f}").c_str(), number(row.w_error).c_str(), number(row.w_estimate).c_str(),
                      number(row.reaction_error).c_str(), number(row.reaction_estimate).c_str(),
                      time_text(row.time_s).c_str(), row.note.empty() ? "" : "  ", row.note.c_str());
        }
        std::fflush(stdout);
      }
    }
  }

  // Per method: the honesty floor and ceiling of the limit estimate, and of w's and the
  // reaction's where both are measured; the answers that are not honest, or not within T.
  std::printf(
      "\ntolerance: honesty of the estimates per method (estimate / true error over every scene and tolerance)\n");
  std::printf("  %-7s | %7s | %-40s | %-40s | %-18s | %-18s\n", "method", "answers", "limits: floor (scene, T)",
              "limits: ceiling (scene, T)", "w: floor .. ceil", "r: floor .. ceil");
  std::vector<std::pair<const Row*, std::string>> findings;  // an answer and what is wrong with it
  for (scene::Method method : methods) {
    const std::string name(scene::to_string(method));
    const Row *floor = nullptr, *ceiling = nullptr;
    double w_floor = INFINITY, w_ceiling = -INFINITY, r_floor = INFINITY, r_ceiling = -INFINITY;
    int answers = 0, refusals = 0;
    for (const Row& r : rows) {
      if (r.method != name) continue;
      if (!r.usable) {
        ++refusals;
        continue;
      }
      ++answers;
      if (std::isfinite(r.honesty())) {
        if (!floor || r.honesty() < floor->honesty()) floor = &r;
        if (!ceiling || r.honesty() > ceiling->honesty()) ceiling = &r;
      }
      const double w = r.w_estimate / r.w_error, q = r.reaction_estimate / r.reaction_error;
      if (std::isfinite(w)) w_floor = std::min(w_floor, w), w_ceiling = std::max(w_ceiling, w);
      if (std::isfinite(q)) r_floor = std::min(r_floor, q), r_ceiling = std::max(r_ceiling, q);
      // The limits are what the tolerance asks for; w and r beside them (Ritz reports no w or r
      // estimate: its w and r are held to nothing).
      std::string wrong;
      auto add = [&wrong](bool bad, const char* what) {
        if (bad) wrong += (wrong.empty() ? "" : ", ") + std::string(what);
      };
      add(!(r.honesty() >= 1.0 / 3.0), "limit estimate < 1/3 of the true error");
      add(!(r.limit_error <= r.tolerance), "true limit error > T");
      add(w < 1.0 / 3.0, "w estimate < 1/3 of the true error");
      add(q < 1.0 / 3.0, "r estimate < 1/3 of the true error");
      add(r.w_error > r.tolerance || r.reaction_error > r.tolerance, "true w or r error > T");
      if (!wrong.empty()) findings.push_back({&r, wrong});
    }
    auto where = [](const Row* r) {
      return r ? fmt::format("{:.3g} ({}, {:.0e})", r->honesty(), r->scene, r->tolerance) : std::string("-");
    };
    auto range = [](double a, double b) {
      return std::isfinite(a) ? fmt::format("{:.3g} .. {:.3g}", a, b) : std::string("-");
    };
    std::printf("  %-7s | %3d/%-3d | %-40s | %-40s | %-18s | %-18s\n", name.c_str(), answers, answers + refusals,
                where(floor).c_str(), where(ceiling).c_str(), range(w_floor, w_ceiling).c_str(),
                range(r_floor, r_ceiling).c_str());
  }
  if (findings.empty()) {
    std::printf(
        "  every answer: limit estimate >= 1/3 of the true error, true errors of the limits, w and r <= T, w and r "
        "estimates >= 1/3 of theirs\n");
  } else {
    std::printf(
        "  every other answer: limit estimate >= 1/3 of the true error, true errors of the limits, w and r <= T, w and "
        "r estimates >= 1/3 of theirs; these not:\n");
    for (const auto& [r, wrong] : findings)
      std::printf(
          "    %s, %s, T = %.0e (%s): limits true %.3e, estimate %.3e (est/true %.3g); w true %.3e, est %s; r true "
          "%.3e, est %s; %d %s\n",
          r->scene.c_str(), r->method.c_str(), r->tolerance, wrong.c_str(), r->limit_error, r->limit_estimate,
          r->honesty(), r->w_error, number(r->w_estimate).c_str(), r->reaction_error,
          number(r->reaction_estimate).c_str(), r->size, r->method_used == "ritz" ? "modes" : "elements");
  }
  std::printf("\ntolerance: section wall time %.1f s\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());

  std::ofstream csv(fs::path(o.out) / "tolerance.csv");
  csv << "scene,method,method_used,tolerance,termination,usable,size,limit_error,limit_estimate,honesty,observed_order,"
         "w_error,w_estimate,reaction_error,reaction_estimate,time_s,runs,note\n";
  for (const Row& r : rows) {
    std::string note = r.note;
    std::replace(note.begin(), note.end(), '"', '\'');
    csv << fmt::format(
        "{},{},{},{:.0e},{},{},{},{:.6e},{:.6e},{:.6e},{:.4f},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{},\"{}\"\n", r.scene,
        r.method, r.method_used, r.tolerance, r.termination, r.usable ? 1 : 0, r.size, r.limit_error, r.limit_estimate,
        r.honesty(), r.order, r.w_error, r.w_estimate, r.reaction_error, r.reaction_estimate, r.time_s, r.runs, note);
  }
}

}  // namespace liftoff::bench
