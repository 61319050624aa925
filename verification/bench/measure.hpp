#pragma once
// How the benchmark measures: in-process wall time as the median of several runs, a child
// process's wall time and peak memory (wait4's ru_maxrss), and exponents fitted by least
// squares on log-log data. Nothing here knows about beams.

#include <functional>
#include <string>
#include <vector>

namespace liftoff::bench {

struct Timing {
  double median_s = -1.0;
  double min_s = -1.0;
  int runs = 0;
};

// Runs `work` `repeats` times (at least once) and returns the median and the fastest.
Timing time_median(const std::function<void()>& work, int repeats);

double median(std::vector<double> values);

struct ProcessRun {
  int exit_code = -1;         // the child's exit status; -1 if it could not run or was killed
  double wall_s = -1.0;       // fork to reap
  double peak_rss_mb = -1.0;  // ru_maxrss of the child (MiB)
  std::string out;            // its stdout
};

// Spawns argv[0] with the arguments (no shell), captures stdout (stderr is discarded), waits
// with wait4.
ProcessRun run_process(const std::vector<std::string>& argv);

// Least-squares slope of log(y) against log(x): the exponent p of y ~ C x^p. NaN for fewer than
// two usable points (x, y > 0).
double fitted_exponent(const std::vector<double>& x, const std::vector<double>& y);

// Log-log interpolation: the y where the piecewise-linear curve (log x_i, log y_i), taken in
// order, first reaches x = target (x decreasing along the curve, as errors do when a mesh is
// refined). NaN if the curve never reaches it; the first y if the first x is already below.
double interpolate_loglog(const std::vector<double>& x, const std::vector<double>& y, double target);

}  // namespace liftoff::bench
