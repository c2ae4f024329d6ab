#include "rfsitl/channel/noise_source.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace rfsitl::channel {

NoiseSource::NoiseSource(std::uint64_t seed, float variance)
    : rng_(seed), variance_(variance), sigma_per_dim_(0.0f) {
  if (!(variance >= 0.0f) || !std::isfinite(variance)) {
    throw std::invalid_argument("NoiseSource: variance must be finite and >= 0");
  }
  // E|eta|^2 = E[I^2] + E[Q^2], split evenly for circular noise.
  sigma_per_dim_ = static_cast<float>(std::sqrt(static_cast<double>(variance) / 2.0));
}

double NoiseSource::next_unit() {
  // Top 53 bits give every multiple of 2^-53; the +1 shifts the range from
  // [0, 1) to (0, 1] so that log(u) below is always finite.
  return static_cast<double>((rng_.next() >> 11) + 1) * 0x1.0p-53;
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
