#pragma once
// The accuracy targets of issue 11, measured in one run (liftoff_bench --sections targets): on
// every shipped scene with a closed form (a beam on a foundation along its whole length, no
// interior supports; the two seed beams and five engineering members) and on a weightless free
// beam under a central load (beta L = 6, written to the scratch folder), the time each method
// needs to bring its contact limits within 1e-6, 1e-8 and 1e-10 of the member's length of the
// exact closed-form limits, with its peak memory there.
//
// Each method refines by doubling (elements, or modes) until the error is below 1e-10 or its
// size or time limit ends the sequence; the time to a target is that of the first size whose
// error is below it (not interpolated, not cumulative: one solve at the size that reaches it),
// the median of repeats in a child process whose peak RSS is the memory figure. Methods: dual
// and primal Lemke, fast (node-based, through contact::solve_contact, as `liftoff solve`), the
// limit-fitted solve (fast on the same mesh for the topology, then
// contact::solve_fitted_limits), Ritz (fixed modes, started from fast at 100 elements) and
// the dolfinx penalty reference (penalty_reference.py --refine, its solve time per mesh, one run
// each). Fitted exponents: time ~ n^a over the larger half of the sizes, error ~ n^-b over the
// sizes whose error is above 1e-13 (round-off).

#include <string>
#include <vector>

#include "closed_form/beam_on_foundation.hpp"
#include "model/member_model.hpp"
#include "scene/scene.hpp"

namespace liftoff::bench {

// A scene with a closed form and its exact tensionless solution (the closed form's Newton started
// from fast's regions at 4000 elements; throws if it does not converge).
struct ClosedFormScene {
  std::string name, file;
  scene::Scene scene;
  model::MemberModel model;
  std::vector<double> exact;                // interior contact limits, s
  closed_form::TensionlessResult solution;  // from the member's begin (s - s_begin), nondimensional
};

// The scenes both sections measure, in order: the two seed beams, the engineering scenes with a
// closed form (the others are named and skipped) and the free beam, written to `scratch`; scenes
// without an interior contact limit are skipped too. `only`: comma-separated names (empty: all).
std::vector<ClosedFormScene> closed_form_scenes(const std::string& source_dir, const std::string& scratch,
                                                const std::string& only);

struct TargetOptions {
  std::string out;         // folder for targets.csv
  std::string scratch;     // folder for the free beam's scene and dolfinx's JSON
  std::string source_dir;  // liftoff's source tree
  std::string python;      // interpreter with dolfinx
  bool dolfinx = true;
  bool full = false;  // larger size limits
  int repeats = 5;    // runs per measurement below 0.5 s (the median is reported)
  std::string only;   // comma-separated scene names (empty: all)
};

void run_targets(const TargetOptions& options);

}  // namespace liftoff::bench
