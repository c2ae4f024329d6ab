#pragma once
// The random models' generator: xoshiro256** seeded through SplitMix64, and
// the uniform and normal draws written out here rather than taken from
// <random>, whose distributions differ between standard libraries. So a
// seed names the same track with GCC or Clang, libstdc++ or libc++.
#include <cmath>
#include <cstdint>
#include <numbers>

namespace rfsitl::position::mobility::detail {

class MobilityRandom {
 public:
  explicit MobilityRandom(std::uint64_t seed) {
    // SplitMix64 spreads any seed, 0 included, over the whole state.
    for (std::uint64_t& word : s_) {
      seed += 0x9e3779b97f4a7c15ULL;
      std::uint64_t z = seed;
      z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
      z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
      word = z ^ (z >> 31);
    }
  }

  std::uint64_t next_u64() {
    const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }

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
  static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

  std::uint64_t s_[4];
};

}  // namespace rfsitl::position::mobility::detail
