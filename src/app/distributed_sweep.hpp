#pragma once
// `mpirun -np N liftoff sweep ...`: a sweep's cases spread over MPI ranks. The only code that
// talks to MPI (the numerics never do); built from distributed_sweep.cpp when CMake finds MPI
// (LIFTOFF_MPI), otherwise from distributed_sweep_off.cpp, where the process is never distributed.
//
// Contract:
// - MPI is initialised only when the process was started by a launcher (mpirun, mpiexec, srun:
//   their environment variables); `liftoff` run by itself is the single-process program, unchanged.
// - Dynamic load balancing: a shared counter on rank 0 (MPI_Fetch_and_op, passive target) hands
//   out the next case index to whichever rank (or thread of a rank) asks; rank 0 works too.
// - Every case is solved exactly as the serial sweep solves it (solve_sweep_case); a case that
//   fails is recorded as the serial sweep records it (its error, its termination) and the ranks
//   go on. Rank 0 gathers every case and writes the one HDF5 file (io::write_sweep_hdf5 from the
//   cases' in-memory images) and the CSV: the same content as the serial sweep's.
// - Only rank 0 prints; every rank exits with rank 0's exit code (Session::agreed_exit_code).
//   A failure of the distribution itself (not of a case) aborts every rank (MPI_Abort, exit 1).
// - Threads per rank: `--jobs` (default 1 under MPI, so `-np 2` on 2 cores is not oversubscribed).

#include <functional>
#include <string>
#include <vector>

#include "app/sweep_command.hpp"
#include "io/report.hpp"

namespace liftoff::app::mpi {

// MPI for the life of the process: MPI_Init_thread (serialized) when started by a launcher,
// MPI_Finalize at the end; nothing otherwise.
class Session {
 public:
  Session(int& argc, char**& argv);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
  // Rank 0's exit code on every rank (a broadcast); `code` itself when not distributed.
  int agreed_exit_code(int code) const;
};

bool active();  // MPI initialised by Session
int rank();     // 0 when not active
int size();     // 1 when not active

// Whether every rank got through the start of a command (`ok` here): true when not active.
// Called by every rank before the sweep's collective work, so that a rank that could not read
// the scene makes the others stop instead of waiting for it.
bool all_ready(bool ok);

// What rank 0 needs of a distributed sweep (empty on the other ranks): cases with their values,
// error and, per report, what the front end reads (scene_name, warnings, termination, usable,
// outcome, units); the CSV (header and rows, io::sweep_csv's text); each case's HDF5 image
// (io::sweep_case_image) when `images` was asked for.
struct DistributedSweep {
  std::vector<io::SweepCase> cases;
  std::string csv;
  std::vector<std::vector<char>> images;
};

// Every rank calls it with the same grid (make_sweep_grid of the same scene and parameters).
// `progress(done, total)` on rank 0: cases handed out so far, then the total at the end.
DistributedSweep run_distributed_sweep(SweepGrid grid, const std::vector<std::string>& keys,
                                       const SolveRequest& request, bool all, int threads, bool images,
                                       const std::function<void(int, int)>& progress);

}  // namespace liftoff::app::mpi
