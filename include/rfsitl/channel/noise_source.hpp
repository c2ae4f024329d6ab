#pragma once
/// Zero-mean circular complex white Gaussian noise, counter-based: sample t of
/// stream s under seed k is a pure function of (k, s, t) (Philox4x32-10, then
/// Box-Muller). So a receiver's noise does not depend on which ticks it ran,
/// which thread drew it, or whether anyone watched: outcomes of a seeded run
/// are the same with observers, any thread count, and in the split architecture.
#include <cstdint>
#include <span>

#include "rfsitl/common/philox.hpp"
#include "rfsitl/common/types.hpp"

namespace rfsitl::channel {

class NoiseSource {
 public:
  /// variance: E|eta|^2 (each of I and Q carries variance/2); stream: which of
  /// the seed's independent streams (the engine: the receiver's index).
  /// Throws std::invalid_argument unless variance is finite and >= 0.
  NoiseSource(std::uint64_t seed, std::uint64_t stream, float variance);

  float variance() const { return variance_; }

  /// Adds samples first_sample, first_sample + 1, ... of the stream to `buf`.
  /// Thread-safe (const, no state).
  void add_to(std::span<cf32> buf, std::uint64_t first_sample) const;

  /// Overwrites `buf` with samples first_sample, ... of the stream.
  void fill(std::span<cf32> buf, std::uint64_t first_sample) const;

 private:
  PhiloxKey key_;            // the seed
  std::uint32_t stream_[2];  // counter words 2 and 3
  float variance_;
  double sigma_per_dim_;
};

}  // namespace rfsitl::channel
