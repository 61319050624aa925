#!/usr/bin/env bash
# Installs what is missing (Debian 12 packages), then configures and builds liftoff in Release
# under ./build. Safe to run again: installed packages are skipped, the build is incremental.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  cmake make g++ pkg-config        # toolchain
  libeigen3-dev                    # dense and sparse linear algebra
  liblapack-dev                    # reference of the banded LU (tests/linalg)
  libsundials-dev                  # KINSOL (Newton solver of the Ritz model)
  libhdf5-dev hdf5-tools           # result files; h5dump
  catch2                           # unit tests
  libtomlplusplus-dev              # scene files
  libcli11-dev                     # command line
  nlohmann-json3-dev               # --json output
  libfmt-dev                       # formatting
  libudunits2-dev                  # UDUNITS-2: scene values with their units ("30 MN/m^2"), src/scene/unit_library.hpp
  python3-h5py                     # tests read the HDF5 output as a user would
  python3-matplotlib               # verification/plots (figures of sweeps)
  python3-dolfinx                  # verification only: the independent penalty-contact reference
  pybind11-dev python3-dev         # the Python module (src/python/): pybind11 and Python's headers
  python3-numpy                    # the Python module's arrays
  libopenmpi-dev openmpi-bin       # distributed sweeps (`mpirun -np N liftoff sweep`); optional, built when found
)
source .ci/install_missing.sh
install_missing "${packages[@]}"

cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)"

# `import liftoff` for Debian's python from any directory: a .pth file in its site directory names the
# build tree's package (build/python), so python imports what was just built, with no copy that could
# go stale (`cmake --install build` installs a copy instead, which then comes first).
if [ -d build/python/liftoff ]; then
  site=$(/usr/bin/python3 -c 'import site; print(site.getsitepackages()[0])')
  mkdir -p "$site" && echo "$PWD/build/python" >"$site/liftoff.pth"
fi
