// Built instead of mpi_peers.cpp when Open MPI's development files were not
// found: a run under mpirun is refused with what to install.
#include <stdexcept>

#include "rfsitl/cluster/mpi_launch.hpp"

namespace rfsitl::cluster {

bool mpi_available() {
  return false;
}

std::unique_ptr<Peers> start_mpi() {
  throw std::runtime_error(
      "started by mpirun, but this build has no MPI: install libopenmpi-dev (scripts/setup.sh "
      "does) and build again");
}

std::string host_name() {
  return "?";
}

}  // namespace rfsitl::cluster
