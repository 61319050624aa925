#pragma once
// The command line run in-process, as a user would run `liftoff <args>`: exit status and what
// it wrote to stdout and stderr.

#include <sstream>
#include <string>
#include <vector>

#include "app/cli.hpp"

namespace liftoff::test {

struct Run {
  int status;
  std::string out, err;
};

// `args` without the program's name.
inline Run run_cli(std::vector<std::string> args) {
  args.insert(args.begin(), "liftoff");
  std::vector<const char*> argv;
  for (const auto& a : args) argv.push_back(a.c_str());
  std::ostringstream out, err;
  const int status = app::run_cli(static_cast<int>(argv.size()), argv.data(), out, err);
  return {status, out.str(), err.str()};
}

// A one-line message: not empty, and its only newline is the last character.
inline bool one_line(const std::string& s) { return !s.empty() && s.find('\n') == s.size() - 1; }

}  // namespace liftoff::test
