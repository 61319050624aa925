#pragma once
// Errors that cross the library boundary, and the process exit codes they map to.
//
// Outcomes of an algorithm (a Lemke ray, an iteration limit) live in each solver's Summary.
// Misuse (a bad scene, a meaningless parameter) and failures the user must act on are thrown
// as one of these, with a one-line message that already names the file, the key and what was
// expected. The front end prints the message and exits with the code below.

#include <stdexcept>
#include <string>

namespace liftoff {

enum class ExitCode : int {
  success = 0,
  internal_error = 1,        // a bug: an invariant of ours was broken
  bad_input = 2,             // malformed or meaningless scene or command line
  solver_failure = 3,        // no equilibrium (Lemke ray), iteration limit, refused formulation
  output_error = 4,          // the result could not be written
  unstable_equilibrium = 5,  // the axial force exceeds the critical load of the configuration found
};

// A scene or command-line problem. Message format: "FILE:LINE: key 'a.b': expected ..., got ...".
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The structure is a mechanism that the loads drive: no equilibrium exists whatever the
// foundation does. Raised by the discretisation without a file name; the front end adds it.
class MechanismError : public InputError {
 public:
  using InputError::InputError;
};

// The problem is well posed as input but the chosen method cannot deliver an answer
// (no equilibrium, dual form refused for a mechanism, iteration limit). Message in words.
class SolverFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A solver found the axial force beyond the critical load of the configuration (exit code
// unstable_equilibrium, not solver_failure): thrown where no report carries that termination.
class UnstableEquilibrium : public SolverFailure {
 public:
  using SolverFailure::SolverFailure;
};

// Writing a result file failed; nothing half-written is left behind.
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace liftoff
