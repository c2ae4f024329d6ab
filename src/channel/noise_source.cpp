#include "rfsitl/channel/noise_source.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace rfsitl::channel {
namespace {

constexpr std::uint64_t rotl(std::uint64_t x, int k) {
  return (x << k) | (x >> (64 - k));
}

/// SplitMix64 (Steele, Lea, Flood 2014): a 64-bit state advanced by the golden
/// ratio increment and passed through a mixing finaliser. Used only to expand
/// one seed into xoshiro's 256-bit state, as the xoshiro authors recommend, so
/// that similar seeds (0, 1, 2, ...) still give unrelated streams.
std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

}  // namespace

NoiseSource::NoiseSource(std::uint64_t seed, float variance)
    : s_{}, variance_(variance), sigma_per_dim_(0.0f) {
  if (!(variance >= 0.0f) || !std::isfinite(variance)) {
    throw std::invalid_argument("NoiseSource: variance must be finite and >= 0");
  }
  // E|eta|^2 = E[I^2] + E[Q^2], split evenly for circular noise.
  sigma_per_dim_ = static_cast<float>(std::sqrt(static_cast<double>(variance) / 2.0));
  std::uint64_t sm = seed;
  for (auto& word : s_) {
    word = splitmix64(sm);
  }
  // SplitMix64 is a bijection on successive states, so four outputs cannot all
  // be zero; xoshiro's only forbidden state is therefore unreachable.
}

/// xoshiro256** 1.0 (Blackman and Vigna 2018): period 2^256 - 1, passes
/// BigCrush, and costs a handful of shifts and xors per 64-bit output.
std::uint64_t NoiseSource::next_u64() {
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

double NoiseSource::next_unit() {
  // Top 53 bits give every multiple of 2^-53; the +1 shifts the range from
  // [0, 1) to (0, 1] so that log(u) below is always finite.
  return static_cast<double>((next_u64() >> 11) + 1) * 0x1.0p-53;
}

// Box-Muller: from two independent uniforms, r = sqrt(-2 ln u1) and
// theta = 2 pi u2 give two independent N(0, 1) variates r cos(theta) and
// r sin(theta), which are exactly one circular complex sample. Each sample
// consumes exactly two RNG outputs and nothing is cached between calls, so the
// stream does not depend on how a caller splits its buffers.
void NoiseSource::add_to(std::span<cf32> buf) {
  if (variance_ == 0.0f) {
    return;
  }
  const double sigma = sigma_per_dim_;
  for (cf32& v : buf) {
    const double r = sigma * std::sqrt(-2.0 * std::log(next_unit()));
    const double theta = 2.0 * std::numbers::pi * next_unit();
    v += cf32{static_cast<float>(r * std::cos(theta)), static_cast<float>(r * std::sin(theta))};
  }
}

void NoiseSource::fill(std::span<cf32> buf) {
  std::fill(buf.begin(), buf.end(), cf32{0.0f, 0.0f});
  add_to(buf);
}

}  // namespace rfsitl::channel
