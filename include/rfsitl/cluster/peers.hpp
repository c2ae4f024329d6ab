#pragma once
/// The processes of one distributed run (`mpirun -n K rfsitl run ...`), as the
/// engine sees them: K ranks, each owning some of the nodes, that swap what
/// the others need once or twice per tick. A run in one process has no Peers.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace rfsitl::cluster {

/// Every rank's bytes of one exchange, in rank order.
struct Gathered {
  std::vector<std::uint8_t> bytes;   ///< all ranks' bytes, concatenated
  std::vector<std::size_t> offsets;  ///< rank r's bytes are [offsets[r], offsets[r + 1])

  std::span<const std::uint8_t> of(std::size_t rank) const {
    return {bytes.data() + offsets[rank], offsets[rank + 1] - offsets[rank]};
  }
  std::size_t ranks() const { return offsets.empty() ? 0 : offsets.size() - 1; }
};

/// Contract: every call except rank() and size() is collective: every rank
/// makes the same calls in the same order, one thread at a time per rank
/// (not necessarily the thread that made the object). A call blocks until
/// every rank has made it. Failures throw std::runtime_error; a rank that
/// died is not survived (Open MPI ends the job).
class Peers {
 public:
  virtual ~Peers() = default;

  /// This process's rank, 0..size()-1; rank 0 speaks for the run (summary,
  /// dashboard).
  virtual std::size_t rank() const = 0;
  virtual std::size_t size() const = 0;

  /// Collective: `out` gets every rank's `mine` (this rank's too), in rank
  /// order. `out` is reused between calls to spare allocations.
  virtual void all_gather(std::span<const std::uint8_t> mine, Gathered& out) = 0;
};

}  // namespace rfsitl::cluster
