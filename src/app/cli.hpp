#pragma once
// The command line: `liftoff solve [SCENE] [--method M] [--elements N] [--json] [--output F]`.
// Returns the process exit code (core/error.hpp); writes results to `out` and one-line errors
// to `err`, so tests can run it in-process.

#include <ostream>

namespace liftoff::app {

int run_cli(int argc, const char* const* argv, std::ostream& out, std::ostream& err);

}  // namespace liftoff::app
