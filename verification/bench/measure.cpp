#include "measure.hpp"

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace liftoff::bench {

double median(std::vector<double> values) {
  if (values.empty()) return NAN;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

Timing time_median(const std::function<void()>& work, int repeats) {
  std::vector<double> times;
  for (int i = 0; i < std::max(1, repeats); ++i) {
    const auto start = std::chrono::steady_clock::now();
    work();
    times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return {median(times), *std::min_element(times.begin(), times.end()), static_cast<int>(times.size())};
}

ProcessRun run_process(const std::vector<std::string>& argv) {
  ProcessRun run;
  int pipe_fds[2];
  if (argv.empty() || ::pipe(pipe_fds) != 0) return run;
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);

  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = ::fork();
  if (pid < 0) return run;
  if (pid == 0) {
    ::dup2(pipe_fds[1], STDOUT_FILENO);
    // Its messages would interleave with the benchmark's tables: the exit code says it.
    const int null = ::open("/dev/null", O_WRONLY);
    if (null >= 0) ::dup2(null, STDERR_FILENO);
    ::close(pipe_fds[0]);
    ::close(pipe_fds[1]);
    ::execv(args[0], args.data());
    ::_exit(127);
  }
  ::close(pipe_fds[1]);
  char buffer[65536];
  for (ssize_t got; (got = ::read(pipe_fds[0], buffer, sizeof buffer)) > 0;)
    run.out.append(buffer, static_cast<std::size_t>(got));
  ::close(pipe_fds[0]);
  int status = 0;
  struct rusage usage {};
  if (::wait4(pid, &status, 0, &usage) != pid) return run;
  run.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  run.peak_rss_mb = usage.ru_maxrss / 1024.0;  // Linux: KiB
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

double fitted_exponent(const std::vector<double>& x, const std::vector<double>& y) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  for (std::size_t i = 0; i < x.size() && i < y.size(); ++i) {
    if (!(x[i] > 0 && y[i] > 0)) continue;
    const double lx = std::log(x[i]), ly = std::log(y[i]);
    sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly, ++n;
  }
  if (n < 2) return NAN;
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

double interpolate_loglog(const std::vector<double>& x, const std::vector<double>& y, double target) {
  if (x.empty() || x.size() != y.size()) return NAN;
  if (x[0] <= target) return y[0];
  for (std::size_t i = 1; i < x.size(); ++i) {
    if (!(x[i] > 0 && x[i - 1] > 0 && y[i] > 0 && y[i - 1] > 0)) continue;
    if (x[i] <= target) {
      const double f = (std::log(target) - std::log(x[i - 1])) / (std::log(x[i]) - std::log(x[i - 1]));
      return std::exp(std::log(y[i - 1]) + f * (std::log(y[i]) - std::log(y[i - 1])));
    }
  }
  return NAN;
}

}  // namespace liftoff::bench
