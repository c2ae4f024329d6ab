#pragma once
/// The project's one pseudo-random generator, written out here so that a seed
/// names the same stream with any compiler and standard library: xoshiro256**
/// 1.0 (Blackman and Vigna 2018; period 2^256 - 1, passes BigCrush, a handful
/// of shifts and xors per 64-bit output), its state expanded from one seed by
/// SplitMix64 as its authors recommend, so that similar seeds (0, 1, 2, ...)
/// give unrelated streams. Header-only: the noise source calls it per sample.
#include <cstdint>

namespace rfsitl {

/// SplitMix64 (Steele, Lea, Flood 2014): advances `state` by the golden-ratio
/// increment and returns it through a mixing finaliser.
constexpr std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

class Xoshiro256 {
 public:
  /// SplitMix64 is a bijection on successive states, so its four outputs are
  /// never all zero: xoshiro's one forbidden state cannot be reached.
  explicit Xoshiro256(std::uint64_t seed) {
    for (std::uint64_t& word : s_) word = splitmix64(seed);
  }

  std::uint64_t next() {
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

 private:
  static constexpr std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

  std::uint64_t s_[4];
};

}  // namespace rfsitl
