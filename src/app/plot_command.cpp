#include "app/plot_command.hpp"

#include <fmt/format.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <iostream>

#include "core/error.hpp"

extern char** environ;

namespace liftoff::app {

std::string plot_python() { return LIFTOFF_PYTHON; }
std::string plot_script() { return LIFTOFF_PLOT_SCRIPT; }

std::vector<std::string> plot_command_line(const PlotRequest& request) {
  std::vector<std::string> argv{plot_python(), plot_script(), request.file};
  if (!request.out.empty()) argv.insert(argv.end(), {"--out", request.out});
  if (request.normalise) argv.emplace_back("--normalise");
  return argv;
}

int run_plot(const PlotRequest& request) {
  const std::string python = plot_python(), script = plot_script();
  if (::access(python.c_str(), X_OK) != 0)
    throw OutputError(
        fmt::format("plot: cannot draw: the Python interpreter '{}' is missing ({}); expected Debian's python3 with "
                    "python3-matplotlib and python3-h5py (or configure with -DLIFTOFF_PYTHON=...)",
                    python, std::strerror(errno)));
  if (::access(script.c_str(), R_OK) != 0)
    throw OutputError(
        fmt::format("plot: cannot draw: the script '{}' is missing ({}); liftoff plot runs it from the "
                    "source tree it was built from",
                    script, std::strerror(errno)));
  const std::vector<std::string> arguments = plot_command_line(request);
  std::vector<char*> argv;
  for (const std::string& a : arguments) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  std::cout.flush();  // the script writes to the same stdout and stderr
  std::cerr.flush();
  // A trace with an axial force draws the perfect member's branch from verification/closed_form's
  // program; the one built beside this liftoff unless the caller names another.
  ::setenv("LIFTOFF_CLOSED_FORM", LIFTOFF_CLOSED_FORM, 0);
  pid_t child = 0;
  const int spawned = ::posix_spawn(&child, python.c_str(), nullptr, nullptr, argv.data(), environ);
  if (spawned != 0) throw OutputError(fmt::format("plot: cannot run '{}': {}", python, std::strerror(spawned)));
  int status = 0;
  while (::waitpid(child, &status, 0) < 0)
    if (errno != EINTR) throw OutputError(fmt::format("plot: cannot wait for '{}': {}", python, std::strerror(errno)));
  if (!WIFEXITED(status))
    throw std::runtime_error(fmt::format("plot: '{}' ended by signal {}", script, WTERMSIG(status)));
  const int code = WEXITSTATUS(status);
  // The script's own codes pass through; anything else (a Python traceback is 1) is a bug.
  if (code == 0 || code == static_cast<int>(ExitCode::bad_input) || code == static_cast<int>(ExitCode::output_error))
    return code;
  return static_cast<int>(ExitCode::internal_error);
}

}  // namespace liftoff::app
