#pragma once
/// Open MPI, used only when the process was started by mpirun: a run in one
/// process initialises nothing and pays nothing.
#include <memory>
#include <string>

#include "rfsitl/cluster/peers.hpp"

namespace rfsitl::cluster {

/// True when mpirun (Open MPI's launcher, or another PMIx one) started this
/// process: it sets OMPI_COMM_WORLD_SIZE or PMIX_RANK in the environment.
bool launched_by_mpirun();

/// Whether this build can run under MPI (Open MPI's development files were
/// found when it was configured).
bool mpi_available();

/// Initialises MPI (thread level serialized: the engine's thread makes the
/// exchanges, the main thread starts and ends) and returns the run's peers
/// over MPI_COMM_WORLD; MPI is finalised when the object is destroyed.
/// Call once per process. Throws std::runtime_error when MPI cannot start or
/// this build has no MPI (naming the package to install).
std::unique_ptr<Peers> start_mpi();

/// How many ranks of the run share this host (OMPI_COMM_WORLD_LOCAL_SIZE;
/// 1 when not told).
std::size_t ranks_on_this_host();

/// This rank's place among those on its host, 0..ranks_on_this_host()-1
/// (OMPI_COMM_WORLD_LOCAL_RANK; 0 when not told): host-wide chores (claiming
/// the IP namespaces' prefix) fall to local rank 0.
std::size_t local_rank();

/// The host this rank runs on (MPI_Get_processor_name), for messages.
std::string host_name();

}  // namespace rfsitl::cluster
