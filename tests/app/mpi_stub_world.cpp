// A program linked with the build-without-MPI world (src/core/mpi_communicator_stub.cpp), as
// `proprio` is when CMake finds no MPI: under mpirun it prints one line and exits 2 on every rank
// (tests/app/mpi_cli_test.cpp runs it); alone, it has the local world.
#include <cstdio>

#include "proprio/core/mpi_communicator.hpp"

int main() {
  try {
    const auto world = proprio::core::world_communicator();
    std::printf("%s world of %d\n", world->name().c_str(), world->size());
    return 0;
  } catch (const proprio::Error& e) {
    std::fprintf(stderr, "proprio: %s\n", e.what());
    return 2;
  }
}
