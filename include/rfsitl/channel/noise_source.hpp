#pragma once
/// Zero-mean circular complex white Gaussian noise, reproducible from a seed.
#include <cstdint>
#include <span>

#include "rfsitl/common/types.hpp"
#include "rfsitl/common/xoshiro256.hpp"

namespace rfsitl::channel {

class NoiseSource {
 public:
  /// variance: E|eta|^2 (each of I and Q carries variance/2). Precondition: variance >= 0.
  NoiseSource(std::uint64_t seed, float variance);

  float variance() const { return variance_; }

  /// Adds one noise sample to every element of `buf`.
  void add_to(std::span<cf32> buf);

  /// Overwrites `buf` with noise.
  void fill(std::span<cf32> buf);

 private:
  double next_unit();  // uniform in (0, 1]

  Xoshiro256 rng_;
  float variance_;
  float sigma_per_dim_;
};

}  // namespace rfsitl::channel
