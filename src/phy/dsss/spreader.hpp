#pragma once
/// The TX half of direct-sequence spreading: every symbol multiplies one whole
/// period of the code, and every chip lasts samples_per_chip samples
/// (rectangular chips). With unit-magnitude symbols every output sample has
/// magnitude 1, so the mean output power is exactly 1.
#include <cstddef>
#include <span>
#include <vector>

#include "codes.hpp"
#include "rfsitl/common/types.hpp"

namespace rfsitl::phy::dsss {

/// Produces a frame's samples on demand, so that a long frame never needs a
/// sample buffer (symbols are 1/(L*S) of the samples).
class Spreader {
 public:
  /// Starts a new frame, abandoning any unfinished one.
  /// Preconditions: chips not empty, samples_per_chip >= 1.
  void start(std::span<const Chip> chips, unsigned samples_per_chip, std::vector<cf32> symbols);

  /// Writes min(out.size(), remaining()) samples to the front of `out` and returns that count.
  std::size_t write(std::span<cf32> out);

  std::size_t remaining() const { return total_ - position_; }

 private:
  std::vector<Chip> chips_;
  std::vector<cf32> symbols_;
  std::size_t samples_per_chip_ = 1;
  std::size_t total_ = 0;
  std::size_t position_ = 0;
};

/// All samples of `symbols` spread by `chips`, samples_per_chip samples per chip.
std::vector<cf32> spread(std::span<const cf32> symbols, std::span<const Chip> chips,
                         unsigned samples_per_chip);

}  // namespace rfsitl::phy::dsss
