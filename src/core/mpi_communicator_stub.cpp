// proprio::core_mpi of a build without MPI (CMake found none): the local world only.
#include <string>

#include "proprio/core/error.hpp"
#include "proprio/core/mpi_communicator.hpp"

namespace proprio::core {

bool built_with_mpi() { return false; }

std::unique_ptr<Communicator> world_communicator() {
  const int n = launched_mpi_world_size();
  if (n > 1) {
    throw CollectiveError("launched as one of " + std::to_string(n) +
                          " MPI processes, but this proprio was built without MPI (install "
                          "libopenmpi-dev and rebuild, or run it without mpirun)");
  }
  return std::make_unique<LocalCommunicator>();
}

void abort_world(int) {}

}  // namespace proprio::core
