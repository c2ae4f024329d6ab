#include <cstdlib>

#include "rfsitl/cluster/mpi_launch.hpp"

namespace rfsitl::cluster {

bool launched_by_mpirun() {
  // Open MPI's mpirun sets the first; PMIx launchers (Open MPI 5, prterun,
  // srun with PMIx) the second.
  return std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr || std::getenv("PMIX_RANK") != nullptr;
}

std::size_t ranks_on_this_host() {
  const char* v = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
  if (v == nullptr) return 1;
  const long n = std::strtol(v, nullptr, 10);
  return n > 0 ? static_cast<std::size_t>(n) : 1;
}

}  // namespace rfsitl::cluster
