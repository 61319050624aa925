#pragma once
// `liftoff sweep`: one scene solved for every combination of values of some of its keys
// (`--set foundation.nondimensional_k=10,100,1e3`), the cases run in parallel on the machine's cores.

#include <functional>
#include <string>
#include <vector>

#include "app/solve_command.hpp"
#include "io/report.hpp"

namespace liftoff::app {

struct SweepParameter {
  std::string key;  // a scene key: "foundation.modulus", "loads[0].value"
  std::vector<double> values;
};

// "KEY=VALUES" with VALUES "a,b,c", "lin:a:b:n" (n values from a to b) or "log:a:b:n"
// (n values from a to b, evenly spaced in log). Throws InputError naming the option.
SweepParameter parse_sweep_parameter(const std::string& text);

// The most cases one sweep runs (each keeps its scene and its report in memory until the end).
inline constexpr std::size_t max_sweep_cases = 100'000;

// A sweep's cases before any work: every combination of the parameters' values (the last
// parameter varies fastest) in cases[i].values, and each case's scene, edited and validated, in
// scenes[i]. Throws InputError (a key given twice, no values, more than max_sweep_cases cases, a
// bad key or value) before anything is solved.
struct SweepGrid {
  std::vector<io::SweepCase> cases;
  std::vector<scene::Scene> scenes;
};
SweepGrid make_sweep_grid(const scene::Scene& scene, const std::vector<SweepParameter>& parameters);

// Whether the request (or else the scene) asks for every method (Method::all).
bool solves_every_method(const scene::Scene& scene, const SolveRequest& request);

// Solves case i of the grid into grid.cases[i]: its reports (every method when `all`), or the
// one-line error that stopped it. Never throws for the case's own failure.
void solve_sweep_case(SweepGrid& grid, std::size_t i, const SolveRequest& request, bool all);

// Every combination of the parameters' values (the last parameter varies fastest), solved
// with `request` (Method::all gives every method per case). A case that fails carries its
// one-line error. A grid of more than max_sweep_cases cases is refused (InputError) before any
// work. `progress(done, total)` is called after each case, from any thread.
std::vector<io::SweepCase> run_sweep(const scene::Scene& scene, const std::vector<SweepParameter>& parameters,
                                     const SolveRequest& request, int jobs,
                                     const std::function<void(int, int)>& progress = {});

}  // namespace liftoff::app
