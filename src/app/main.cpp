#include <iostream>

#include "app/cli.hpp"
#include "core/allocator.hpp"

int main(int argc, char** argv) {
  liftoff::tune_allocator();
  return liftoff::app::run_cli(argc, argv, std::cout, std::cerr);
}
