#include <cstdlib>

#include "rfsitl/cluster/mpi_launch.hpp"

namespace rfsitl::cluster {

bool launched_by_mpirun() {
  // Open MPI's mpirun sets the first; PMIx launchers (Open MPI 5, prterun,
  // srun with PMIx) the second.
  return std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr || std::getenv("PMIX_RANK") != nullptr;
}

}  // namespace rfsitl::cluster
