#pragma once
/// Zero-mean circular complex white Gaussian noise, counter-based: sample t of
/// stream s under seed k is a pure function of (k, s, t) (Philox4x32-10, then
/// Box-Muller, in groups of 32 samples: noise_source.cpp). So a receiver's noise does not depend on
/// which ticks it ran, which thread drew it, or whether anyone watched: outcomes of a seeded run
/// are the same with observers, any thread count, and in the split architecture.
#include <cstdint>
#include <span>

#include "rfsitl/common/philox.hpp"
#include "rfsitl/common/types.hpp"

namespace rfsitl::channel {

/// The instruction sets the noise can be made with. Every kernel computes the
/// same IEEE operations, so all give the same bits (a seed names the same
/// noise on any x86-64 CPU); kBest is the fastest this CPU runs.
enum class NoiseKernel { kBest, kScalar, kAvx2, kAvx512 };

/// True when this CPU runs `kernel` (kBest and kScalar always).
bool noise_kernel_supported(NoiseKernel kernel);

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

  /// The same with a given kernel (tests and benchmarks). Throws
  /// std::invalid_argument when !noise_kernel_supported(kernel).
  void add_to(std::span<cf32> buf, std::uint64_t first_sample, NoiseKernel kernel) const;

  /// Overwrites `buf` with samples first_sample, ... of the stream.
  void fill(std::span<cf32> buf, std::uint64_t first_sample) const;

 private:
  PhiloxKey key_;            // the seed
  std::uint32_t stream_[2];  // counter words 2 and 3
  float variance_;
  double sigma_per_dim_;
};

}  // namespace rfsitl::channel
