#pragma once
// Runs a program as a user would (its own process, stdin empty, a working directory of its own)
// and reports how it ended: exit code or signal, stdout and stderr, and whether it outlived its
// time limit (then it is killed). The fuzzer's view of liftoff: nothing in-process, so a crash,
// a sanitizer report or a stray write reaches the test exactly as it would reach a user.

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace liftoff::fuzz {

struct Ended {
  bool timed_out = false;
  int signal = 0;      // the signal that ended it, 0 if it exited
  int exit_code = -1;  // when it exited
  std::string out, err;
  double seconds = 0.0;
};

inline std::string read_all(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Runs `program args...` in `directory` with stdout and stderr captured through files in
// `capture` (outside `directory`, so the program's own files are all that appear there).
inline Ended run_program(const std::string& program, const std::vector<std::string>& args,
                         const std::filesystem::path& directory, const std::filesystem::path& capture,
                         double timeout_seconds) {
  const std::string out_path = (capture / "stdout").string(), err_path = (capture / "stderr").string();
  std::vector<std::string> words{program};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);

  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = ::fork();
  if (pid == 0) {  // child: only async-signal-safe calls until exec
    const int in = ::open("/dev/null", O_RDONLY);
    const int out = ::open(out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err = ::open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (in < 0 || out < 0 || err < 0 || ::chdir(directory.c_str()) != 0) ::_exit(127);
    ::dup2(in, 0);
    ::dup2(out, 1);
    ::dup2(err, 2);
    ::execv(program.c_str(), argv.data());
    ::_exit(127);
  }
  Ended ended;
  if (pid < 0) {
    ended.exit_code = 127;
    ended.err = "fork failed";
    return ended;
  }
  int status = 0;
  while (true) {
    const pid_t done = ::waitpid(pid, &status, WNOHANG);
    if (done == pid) break;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (elapsed > timeout_seconds) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      ended.timed_out = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  ended.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (WIFEXITED(status)) ended.exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) ended.signal = WTERMSIG(status);
  ended.out = read_all(out_path);
  ended.err = read_all(err_path);
  return ended;
}

}  // namespace liftoff::fuzz
