#include "rfsitl/channel/noise_source.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace rfsitl::channel {

NoiseSource::NoiseSource(std::uint64_t seed, std::uint64_t stream, float variance)
    : key_{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32)},
      stream_{static_cast<std::uint32_t>(stream), static_cast<std::uint32_t>(stream >> 32)},
      variance_(variance),
      sigma_per_dim_(0.0) {
  if (!(variance >= 0.0f) || !std::isfinite(variance)) {
    throw std::invalid_argument("NoiseSource: variance must be finite and >= 0");
  }
  // E|eta|^2 = E[I^2] + E[Q^2], split evenly for circular noise.
  sigma_per_dim_ = std::sqrt(static_cast<double>(variance) / 2.0);
}

// One Philox block per pair of samples: counter = (t / 2, stream); sample t
// takes words 0-1 when t is even, 2-3 when odd. Box-Muller: from two
// independent uniforms, r = sqrt(-2 ln u1) and theta = 2 pi u2 give two
// independent N(0, 1) variates r cos(theta) and r sin(theta), which are exactly
// one circular complex sample. u1 is in (0, 1] (never log 0); its 32 bits put
// the largest radius at 6.66 sigma, beyond which a Gaussian has 2e-10 of its
// samples. Single precision: the samples are floats anyway.
namespace {

cf32 gaussian(std::uint32_t a, std::uint32_t b, float sigma) {
  const float u1 = (static_cast<float>(a) + 1.0f) * 0x1.0p-32f;
  const float theta = static_cast<float>(b) * (2.0f * std::numbers::pi_v<float> * 0x1.0p-32f);
  const float r = sigma * std::sqrt(-2.0f * std::log(u1));
  return {r * std::cos(theta), r * std::sin(theta)};
}

}  // namespace

void NoiseSource::add_to(std::span<cf32> buf, std::uint64_t first_sample) const {
  if (variance_ == 0.0f) return;
  const auto sigma = static_cast<float>(sigma_per_dim_);
  std::size_t i = 0;
  while (i < buf.size()) {
    const std::uint64_t t = first_sample + i;
    const std::uint64_t pair = t >> 1;
    const PhiloxCounter w =
        philox4x32({static_cast<std::uint32_t>(pair), static_cast<std::uint32_t>(pair >> 32),
                    stream_[0], stream_[1]},
                   key_);
    if ((t & 1) == 0) buf[i++] += gaussian(w[0], w[1], sigma);
    if (i < buf.size()) buf[i++] += gaussian(w[2], w[3], sigma);
  }
}

void NoiseSource::fill(std::span<cf32> buf, std::uint64_t first_sample) const {
  std::fill(buf.begin(), buf.end(), cf32{0.0f, 0.0f});
  add_to(buf, first_sample);
}

}  // namespace rfsitl::channel
