#include "app/sweep_command.hpp"

#include <fmt/format.h>

#include <atomic>
#include <cmath>
#include <mutex>
#include <thread>

#include "core/error.hpp"
#include "scene/scene_edit.hpp"
#include "scene/scene_reader.hpp"

namespace liftoff::app {

namespace {

// A user's text on one line: control characters as \xNN.
std::string escaped(const std::string& s) {
  std::string out;
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    out += u < 0x20 || u == 0x7f ? fmt::format("\\x{:02x}", u) : std::string(1, c);
  }
  return out;
}

[[noreturn]] void bad(const std::string& text, const std::string& why) {
  throw InputError(
      fmt::format("--set '{}': {}; expected KEY=a,b,c or KEY=lin:a:b:n or KEY=log:a:b:n", escaped(text), why));
}

double number(const std::string& text, const std::string& item) {
  try {
    std::size_t used = 0;
    const double v = std::stod(item, &used);
    if (used != item.size() || !std::isfinite(v)) bad(text, fmt::format("'{}' is not a finite number", escaped(item)));
    return v;
  } catch (const std::logic_error&) {
    bad(text, fmt::format("'{}' is not a number", escaped(item)));
  }
}

std::vector<std::string> split(const std::string& s, char separator) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (true) {
    const std::size_t end = s.find(separator, start);
    parts.push_back(s.substr(start, end - start));
    if (end == std::string::npos) return parts;
    start = end + 1;
  }
}

}  // namespace

SweepParameter parse_sweep_parameter(const std::string& text) {
  const std::size_t equals = text.find('=');
  if (equals == std::string::npos || equals == 0) bad(text, "no KEY=");
  SweepParameter p;
  p.key = text.substr(0, equals);
  // Names, indices and dots only: anything else (a newline, a quote) is no scene key, and would
  // reach the messages and the edited TOML text.
  if (p.key.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_-.[]") !=
      std::string::npos)
    throw InputError(
        fmt::format("--set: expected KEY=VALUES with KEY a scene key such as foundation.modulus or "
                    "loads[0].value (letters, digits, _, -, ., [ and ]), got '{}'",
                    escaped(p.key)));
  const std::string values = text.substr(equals + 1);
  const std::vector<std::string> range = split(values, ':');
  if (range.size() == 4 && (range[0] == "lin" || range[0] == "log")) {
    const double a = number(text, range[1]), b = number(text, range[2]);
    const double n = number(text, range[3]);
    if (n < 2 || n != std::floor(n) || n > static_cast<double>(max_sweep_cases))
      bad(text, fmt::format("n must be an integer in [2, {}]", max_sweep_cases));
    if (range[0] == "log" && (a <= 0 || b <= 0)) bad(text, "a log range needs a > 0 and b > 0");
    for (int i = 0; i < n; ++i) {
      const double t = i / (n - 1);
      p.values.push_back(range[0] == "lin" ? a + (b - a) * t : a * std::pow(b / a, t));
    }
  } else {
    for (const std::string& item : split(values, ',')) p.values.push_back(number(text, item));
  }
  return p;
}

SweepGrid make_sweep_grid(const scene::Scene& scene, const std::vector<SweepParameter>& parameters) {
  for (std::size_t k = 0; k < parameters.size(); ++k)
    for (std::size_t j = 0; j < k; ++j)
      if (parameters[j].key == parameters[k].key)
        throw InputError(fmt::format("--set: key '{}' given twice; expected each key once (its values in one --set)",
                                     parameters[k].key));
  // The grid's size is checked before anything is allocated for it (the product of the counts
  // stops growing past the bound, so it cannot overflow).
  std::size_t total = 1;
  for (const auto& p : parameters) {
    if (p.values.empty()) throw InputError(fmt::format("--set '{}': expected at least one value", p.key));
    total = std::min(total * p.values.size(), max_sweep_cases + 1);
  }
  if (total > max_sweep_cases) {
    double product = 1;
    std::string counts;
    for (const auto& p : parameters) {
      product *= static_cast<double>(p.values.size());
      counts += fmt::format("{}{} values of {}", counts.empty() ? "" : " x ", p.values.size(), p.key);
    }
    throw InputError(fmt::format("--set: the grid has {:g} cases ({}), expected at most {}; sweep fewer values",
                                 product, counts, max_sweep_cases));
  }
  SweepGrid grid;
  std::vector<io::SweepCase>& cases = grid.cases;
  cases.resize(total);
  for (std::size_t i = 0; i < total; ++i) {  // mixed-radix digits: the last parameter fastest
    std::size_t rest = i;
    cases[i].values.resize(parameters.size());
    for (std::size_t k = parameters.size(); k-- > 0;) {
      cases[i].values[k] = parameters[k].values[rest % parameters[k].values.size()];
      rest /= parameters[k].values.size();
    }
  }
  // Every case's scene is edited and validated first, so a bad key stops the sweep before any
  // work (InputError), with the key named once.
  std::vector<scene::Scene>& scenes = grid.scenes;
  for (const io::SweepCase& c : cases) {
    std::string text = scene.text, label;
    for (std::size_t k = 0; k < parameters.size(); ++k) {
      text = scene::with_value(text, parameters[k].key, c.values[k], scene.source_name);
      label += fmt::format("{}{}={:.6g}", label.empty() ? "" : ", ", parameters[k].key, c.values[k]);
    }
    scenes.push_back(scene::parse_scene(text, fmt::format("{} [{}]", scene.source_name, label)));
  }
  return grid;
}

bool solves_every_method(const scene::Scene& scene, const SolveRequest& request) {
  return request.method.value_or(scene.solve.method) == scene::Method::all;
}

void solve_sweep_case(SweepGrid& grid, std::size_t i, const SolveRequest& request, bool all) {
  try {
    if (all)
      grid.cases[i].reports = solve_all_methods(grid.scenes[i], request);
    else
      grid.cases[i].reports = {solve_scene(grid.scenes[i], request)};
  } catch (const std::exception& e) {  // InputError, SolverFailure: the case's own failure
    grid.cases[i].error = e.what();
  }
}

std::vector<io::SweepCase> run_sweep(const scene::Scene& scene, const std::vector<SweepParameter>& parameters,
                                     const SolveRequest& request, int jobs,
                                     const std::function<void(int, int)>& progress) {
  SweepGrid grid = make_sweep_grid(scene, parameters);
  const std::size_t total = grid.cases.size();
  const bool all = solves_every_method(scene, request);
  std::atomic<std::size_t> next{0};
  int done = 0;
  std::mutex progress_lock;
  auto worker = [&] {
    for (std::size_t i = next++; i < total; i = next++) {
      solve_sweep_case(grid, i, request, all);
      // Counted and reported under one lock: a count taken outside it could be reported after a
      // larger one (a "2/4" after the final "4/4", on the line of the message that follows).
      const std::lock_guard<std::mutex> lock(progress_lock);
      ++done;
      if (progress) progress(done, static_cast<int>(total));
    }
  };
  std::vector<std::thread> threads;
  for (int t = 0; t < std::max(1, jobs); ++t) threads.emplace_back(worker);
  for (auto& t : threads) t.join();
  return std::move(grid.cases);
}

}  // namespace liftoff::app
