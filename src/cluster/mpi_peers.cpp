#include <mpi.h>

#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <string>

#include "rfsitl/cluster/mpi_launch.hpp"

namespace rfsitl::cluster {
namespace {

void check(int rc, const char* what) {
  if (rc == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int len = 0;
  MPI_Error_string(rc, text, &len);
  throw std::runtime_error(std::string("MPI: ") + what + " failed: " + std::string(text, len));
}

class MpiPeers final : public Peers {
 public:
  MpiPeers() {
    // A rank waiting in an exchange yields its core instead of spinning (unless
    // the user chose otherwise): the ranks share their hosts' cores with each
    // other's worker threads, and on a busy or oversubscribed host a spinning
    // rank made each exchange take milliseconds instead of microseconds.
    setenv("OMPI_MCA_mpi_yield_when_idle", "1", 0);
    // A tick's message is a few kB to a few hundred kB (the samples of the
    // rank's transmitters). Over the shared-memory transport's 4 kB eager
    // limit each message takes a rendezvous, which on the development machine
    // (a container) cost about 0.4 s per tick at 128 nodes; 128 kB keeps
    // the common messages eager (bench/mpi_exchange.py).
    setenv("OMPI_MCA_btl_vader_eager_limit", "131072", 0);
    int provided = 0;
    check(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided), "MPI_Init_thread");
    if (provided < MPI_THREAD_SERIALIZED) {
      MPI_Finalize();
      throw std::runtime_error(
          "MPI: this MPI library cannot be called from more than one thread "
          "(MPI_THREAD_SERIALIZED), which the engine's thread needs");
    }
    // Errors come back as codes (check() turns them into exceptions) instead
    // of aborting the job from inside the library.
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
    int r = 0;
    int n = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &r);
    MPI_Comm_size(MPI_COMM_WORLD, &n);
    rank_ = static_cast<std::size_t>(r);
    size_ = static_cast<std::size_t>(n);
    counts_.resize(size_);
    displacements_.resize(size_);
  }
  ~MpiPeers() override { MPI_Finalize(); }
  MpiPeers(const MpiPeers&) = delete;
  MpiPeers& operator=(const MpiPeers&) = delete;

  std::size_t rank() const override { return rank_; }
  std::size_t size() const override { return size_; }

  void all_gather(std::span<const std::uint8_t> mine, Gathered& out) override {
    if (mine.size() > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
      throw std::runtime_error("MPI: one rank's exchange is over 2 GiB");
    }
    int my_count = static_cast<int>(mine.size());
    check(MPI_Allgather(&my_count, 1, MPI_INT, counts_.data(), 1, MPI_INT, MPI_COMM_WORLD),
          "MPI_Allgather");
    out.offsets.assign(size_ + 1, 0);
    for (std::size_t r = 0; r < size_; ++r) {
      displacements_[r] = static_cast<int>(out.offsets[r]);
      out.offsets[r + 1] = out.offsets[r] + static_cast<std::size_t>(counts_[r]);
    }
    if (out.offsets[size_] > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
      throw std::runtime_error("MPI: one exchange is over 2 GiB");
    }
    out.bytes.resize(out.offsets[size_]);
    check(MPI_Allgatherv(mine.data(), my_count, MPI_BYTE, out.bytes.data(), counts_.data(),
                         displacements_.data(), MPI_BYTE, MPI_COMM_WORLD),
          "MPI_Allgatherv");
  }

 private:
  std::size_t rank_ = 0;
  std::size_t size_ = 1;
  std::vector<int> counts_;
  std::vector<int> displacements_;
};

}  // namespace

bool mpi_available() {
  return true;
}

std::unique_ptr<Peers> start_mpi() {
  return std::make_unique<MpiPeers>();
}

std::string host_name() {
  char name[MPI_MAX_PROCESSOR_NAME];
  int len = 0;
  if (MPI_Get_processor_name(name, &len) != MPI_SUCCESS) return "?";
  return {name, static_cast<std::size_t>(len)};
}

}  // namespace rfsitl::cluster
