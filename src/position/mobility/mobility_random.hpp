#pragma once
// The random models' generator: the project's xoshiro256**
// (rfsitl/common/xoshiro256.hpp), and the uniform and normal draws written out
// here rather than taken from <random>, whose distributions differ between
// standard libraries. So a seed names the same track with GCC or Clang,
// libstdc++ or libc++.
#include <cmath>
#include <cstdint>
#include <numbers>

#include "rfsitl/common/xoshiro256.hpp"

namespace rfsitl::position::mobility::detail {

class MobilityRandom {
 public:
  explicit MobilityRandom(std::uint64_t seed) : rng_(seed) {}

  std::uint64_t next_u64() { return rng_.next(); }

  /// Uniform in [0, 1): the top 53 bits as a fraction.
  double unit() { return static_cast<double>(next_u64() >> 11) * 0x1.0p-53; }

  /// Uniform in [lo, hi] (lo when lo == hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * unit(); }

  /// Standard normal (Box-Muller, one of the pair: simpler state, same law).
  double normal() {
    const double u1 = 1.0 - unit();  // (0, 1]: the logarithm stays finite
    const double u2 = unit();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
  }

 private:
  Xoshiro256 rng_;
};

}  // namespace rfsitl::position::mobility::detail
