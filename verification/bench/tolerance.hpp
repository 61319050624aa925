#pragma once
// The honesty of accuracy on demand (liftoff_bench --sections tolerance): on every scene the
// targets section measures (targets.hpp: the closed-form scenes), every method (auto, fast, dual,
// primal, ritz) and tolerances 1e-6, 1e-8, 1e-10 (full: 1e-12 too), the tolerance path exactly as
// `liftoff solve SCENE --tolerance T --method M --json` takes it (app::solve_scene in process,
// no sampled fields, as --json without --output), against the closed form:
//  - the true contact-limit error max_k |t_k - t_k exact| / L beside the answer's
//    estimated_limit_error / L, and their ratio estimate / true (honest: not far below 1);
//  - the true error of w on the answer's sampled fields (FE: 16 points per element, from a second,
//    untimed solve with fields; Ritz: its grid) relative to max |w exact|, and of the reaction
//    k max(w, 0) relative to its exact largest, beside estimated_w_error and
//    estimated_reaction_error (FE only; Ritz estimates only its limits);
//  - the observed order, the elements (or modes) used, the termination, and the solve time
//    (report.time_s: set-up to report, median of --repeats runs when a run is under 0.5 s).
// A refusal (an exception, or an answer not usable) prints its termination and reason instead,
// and, when the refused answer has limits and an estimate (a failed certificate), their figures.
// Per method, the honesty floor (smallest estimate / true) and ceiling over every scene and
// tolerance; every answer whose estimate (limits, w or r) is below a third of its true error, or
// whose true error of the limits, w or r is above the tolerance, is listed with what is wrong.
// Rows go to tolerance.csv in `out`.

#include <string>

namespace liftoff::bench {

struct ToleranceBenchOptions {
  std::string out;         // folder for tolerance.csv
  std::string scratch;     // folder for the free beam's scene
  std::string source_dir;  // liftoff's source tree
  bool full = false;       // adds the tolerance 1e-12
  int repeats = 5;         // runs per cheap measurement (the median is reported)
  std::string only;        // comma-separated scene names (empty: all)
};

void run_tolerance(const ToleranceBenchOptions& options);

}  // namespace liftoff::bench
