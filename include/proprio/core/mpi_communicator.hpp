#pragma once
// The world communicator of a program that may be launched by `mpirun` (library
// proprio::core_mpi). Built with Open MPI when CMake finds it (PROPRIO_MPI); built without it,
// the same call gives the local world, and throws Error when the launcher's environment says the
// program runs as one of several MPI processes (each would otherwise train alone).

#include <memory>

#include "proprio/core/communicator.hpp"

namespace proprio::core {

/// Whether this build has MPI.
bool built_with_mpi();

/// MPI's world (MPI_Init on the first call; MPI_Finalize when the returned object is destroyed)
/// when launched under an MPI launcher, else a LocalCommunicator. MPI errors are returned, not
/// fatal, and become InternalError naming the operation. Throws Error when launched under MPI by a
/// build without it.
std::unique_ptr<Communicator> world_communicator();

/// Ends the whole MPI job now with `code` (MPI_Abort), e.g. after a failure that the other ranks
/// cannot learn of; a no-op without MPI.
void abort_world(int code);

}  // namespace proprio::core
