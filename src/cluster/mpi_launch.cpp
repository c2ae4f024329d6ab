#include <cstdlib>

#include "rfsitl/cluster/mpi_launch.hpp"

namespace rfsitl::cluster {

bool launched_by_mpirun() {
  // Open MPI's mpirun sets the first; PMIx launchers (Open MPI 5, prterun,
  // srun with PMIx) the second.
  return std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr || std::getenv("PMIX_RANK") != nullptr;
}

namespace {

/// A non-negative count from the environment, or `otherwise`.
std::size_t count_from_env(const char* name, std::size_t otherwise) {
  const char* v = std::getenv(name);
  if (v == nullptr) return otherwise;
  char* end = nullptr;
  const long n = std::strtol(v, &end, 10);
  return end != v && *end == '\0' && n >= 0 ? static_cast<std::size_t>(n) : otherwise;
}

}  // namespace

std::size_t ranks_on_this_host() {
  const std::size_t n = count_from_env("OMPI_COMM_WORLD_LOCAL_SIZE", 1);
  return n > 0 ? n : 1;
}

std::size_t local_rank() {
  return count_from_env("OMPI_COMM_WORLD_LOCAL_RANK", 0);
}

}  // namespace rfsitl::cluster
