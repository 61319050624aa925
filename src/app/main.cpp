#include <iostream>
#include <sstream>

#include "app/cli.hpp"
#include "app/distributed_sweep.hpp"
#include "core/allocator.hpp"

int main(int argc, char** argv) {
  liftoff::tune_allocator();
  // Under mpirun (app/distributed_sweep.hpp) rank 0 alone prints, and every rank exits with its code.
  const liftoff::app::mpi::Session mpi(argc, argv);
  std::ostringstream discarded;
  const bool prints = liftoff::app::mpi::rank() == 0;
  const int code = liftoff::app::run_cli(argc, argv, prints ? std::cout : discarded, prints ? std::cerr : discarded);
  return mpi.agreed_exit_code(code);
}
