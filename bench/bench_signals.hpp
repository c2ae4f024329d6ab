#pragma once
/// Test signals shared by the receiver benchmarks: complex Gaussian noise and
/// back-to-back frames of one transceiver on top of it, and an RX handler that
/// counts valid decodes.
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "rfsitl/phy/transceiver.hpp"

namespace rfsitl::bench {

struct CountingHandler : phy::RxHandler {
  std::size_t valid = 0;
  void on_rx(const phy::RxEvent& ev) override { valid += ev.payload_valid ? 1 : 0; }
};

/// n samples of circular complex Gaussian noise of total power `variance`.
inline std::vector<cf32> noise(std::size_t n, float variance, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> g(0.0F, std::sqrt(variance / 2.0F));
  std::vector<cf32> v(n);
  for (auto& s : v) s = {g(rng), g(rng)};
  return v;
}

/// n samples of noise (`noise_variance`) with 80-byte frames of `tx` added back
/// to back, `gap` samples apart; *count is the number of frames.
inline std::vector<cf32> frames(phy::Transceiver& tx, std::size_t n, float noise_variance,
                                std::size_t gap, std::size_t* count) {
  std::vector<cf32> v = noise(n, noise_variance, 7);
  const std::vector<std::uint8_t> payload(80, 0x5A);
  const std::size_t len = tx.frame_samples(payload.size());
  std::vector<cf32> f(len);
  *count = 0;
  for (std::size_t pos = gap; pos + len <= n; pos += len + gap) {
    tx.start_frame({1, 2, static_cast<std::uint32_t>(*count)}, payload);
    tx.transmit(f);
    for (std::size_t i = 0; i < len; ++i) v[pos + i] += f[i];
    ++*count;
  }
  return v;
}

}  // namespace rfsitl::bench
