// A build without MPI: the process is never distributed (app/distributed_sweep.hpp).
#include "app/distributed_sweep.hpp"
#include "core/error.hpp"

namespace liftoff::app::mpi {

Session::Session(int&, char**&) {}
Session::~Session() = default;
int Session::agreed_exit_code(int code) const { return code; }

bool active() { return false; }
int rank() { return 0; }
int size() { return 1; }
bool all_ready(bool ok) { return ok; }

DistributedSweep run_distributed_sweep(SweepGrid, const std::vector<std::string>&, const SolveRequest&, bool, int, bool,
                                       const std::function<void(int, int)>&) {
  throw std::logic_error("run_distributed_sweep: liftoff was built without MPI");
}

}  // namespace liftoff::app::mpi
