#pragma once
// `liftoff plot FILE.h5`: the pictures of a result file (solve, trace, sweep or envelope), drawn by one
// Python script, verification/plots/plot.py, run with the interpreter fixed at configure time
// (CMake cache variable LIFTOFF_PYTHON, Debian's /usr/bin/python3: it has matplotlib and h5py).
// The script prints each PNG it wrote on stdout and a one-line error on stderr; its exit code
// is liftoff's (2 the file is not a liftoff result, 4 a picture could not be written or a
// Python module is missing) and is returned as it is. A missing interpreter or script is exit 4
// (nothing can be drawn), a crash of the script exit 1 (a bug).

#include <string>
#include <vector>

namespace liftoff::app {

struct PlotRequest {
  std::string file;        // the HDF5 file
  std::string out;         // prefix of the PNG files (empty: the file's name without .h5)
  bool normalise = false;  // sweeps: each case's curve divided by its own largest magnitude
};

// The interpreter and script `liftoff plot` runs.
std::string plot_python();
std::string plot_script();

// The command line of the script for `request` (argv[0] the interpreter).
std::vector<std::string> plot_command_line(const PlotRequest& request);

// Runs the script; returns liftoff's exit code. Throws OutputError if the interpreter or the
// script is missing.
int run_plot(const PlotRequest& request);

}  // namespace liftoff::app
