#pragma once
// Commands that run as one process or as the ranks of an MPI job (`mpirun -np N proprio lda
// train ...`, `... vocab build ...`; issue 23): the world is MPI's when the launcher's environment
// says so. Bad input that every rank saw alike (core::CollectiveError) is printed once, by rank 0,
// and every rank leaves MPI and exits 2 (under mpirun); anything else on one rank of several ends
// the whole job (MPI_Abort), so that no rank waits for it.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <functional>
#include <memory>

#include "proprio/core/communicator.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/mpi_communicator.hpp"

namespace proprio::app {

inline void run_on_world(const std::function<void(core::Communicator&)>& body) {
  std::unique_ptr<core::Communicator> comm = core::world_communicator();
  const int rank = comm->rank();
  const bool several = comm->size() > 1;
  try {
    body(*comm);
  } catch (const core::CollectiveError& e) {
    if (!several) throw;  // main prints it and exits 2
    // Printed before MPI_Finalize, which every rank enters: no rank's exit (on which mpirun
    // ends the job) comes before the line.
    if (rank == 0) std::fprintf(stderr, "proprio: %s\n", e.what());
    std::fflush(stdout);
    std::fflush(stderr);
    comm.reset();
    std::exit(2);  // NOLINT(concurrency-mt-unsafe): every rank's exit, after MPI_Finalize
  } catch (const std::exception& e) {
    if (!several) throw;
    std::fprintf(stderr, "proprio: rank %d: %s; ending the MPI job\n", rank, e.what());
    std::fflush(stderr);
    core::abort_world(dynamic_cast<const Error*>(&e) != nullptr ? 2 : 1);
    throw;
  }
}

}  // namespace proprio::app
