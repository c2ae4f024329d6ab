/// DSSS sensitivity: packet error rate of 80-byte frames versus per-sample SNR
/// for each code and modulation, and the SNR at which the PER crosses 10%
/// (linear interpolation between the 1 dB steps). Frames go through a random
/// constant phase and AWGN, 300-sample gaps, fed in 250-sample ticks. Prints,
/// asserts nothing.
///
///   g++ -std=c++20 -O2 -Iinclude bench/dsss_per_bench.cpp src/phy/dsss/*.cpp
///       -lliquid -pthread -o dsss_per_bench
///   ./dsss_per_bench [frames per point, default 100]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "phy/dsss/codes.hpp"
#include "phy/dsss/dsss_transceiver.hpp"

namespace {

using namespace rfsitl;

struct Counter : phy::RxHandler {
  std::size_t valid = 0;
  void on_rx(const phy::RxEvent& ev) override { valid += ev.payload_valid ? 1 : 0; }
};

/// PER of `frames` 80-byte frames at `snr_db`.
double per(const phy::DsssSettings& s, std::size_t frames, double snr_db, std::uint32_t seed) {
  auto tx = phy::make_dsss_transceiver(s);
  auto rx = phy::make_dsss_transceiver(s);
  std::mt19937 rng(seed);
  std::normal_distribution<float> g(
      0.0F, static_cast<float>(std::sqrt(0.5 * std::pow(10.0, -snr_db / 10.0))));
  std::uniform_real_distribution<float> phase(0.0F, 6.2831853F);
  const std::size_t gap = 300;
  const std::size_t len = tx->frame_samples(80);
  std::vector<cf32> x(len + 2 * gap);
  std::vector<std::uint8_t> payload(80);
  Counter c;
  for (std::size_t k = 0; k < frames; ++k) {
    for (auto& b : payload) b = static_cast<std::uint8_t>(rng());
    tx->start_frame({1, 2, static_cast<std::uint32_t>(k)}, payload);
    std::fill(x.begin(), x.end(), cf32{});
    tx->transmit(std::span(x).subspan(gap, len));
    const cf32 rot = std::polar(1.0F, phase(rng));
    for (cf32& v : x) v = v * rot + cf32{g(rng), g(rng)};
    for (std::size_t i = 0; i < x.size(); i += 250) {
      rx->receive(std::span(x).subspan(i, std::min<std::size_t>(250, x.size() - i)), c);
    }
  }
  return 1.0 - static_cast<double>(c.valid) / static_cast<double>(frames);
}

}  // namespace

/// The SNR at which the PER crosses 10%, interpolated; NaN if it never does.
double crossing(const std::vector<std::pair<double, double>>& curve) {
  for (std::size_t i = 1; i < curve.size(); ++i) {
    const auto [s0, p0] = curve[i - 1];  // higher SNR
    const auto [s1, p1] = curve[i];
    if (p0 <= 0.1 && p1 > 0.1) return s0 + (s1 - s0) * (0.1 - p0) / (p1 - p0);
  }
  return std::nan("");
}

int main(int argc, char** argv) {
  const std::size_t frames = argc > 1 ? std::strtoul(argv[1], nullptr, 10) : 100;
  std::printf("80-byte frames, %zu per point, 1 sample per chip\n", frames);
  std::printf("%-9s %-6s %8s   PER at per-sample SNR (dB)\n", "code", "mod", "10% PER");
  for (const char* modulation : {"dbpsk", "dqpsk"}) {
    for (const char* code :
         {"barker11", "mseq31", "gold63", "mseq127", "gold127", "mseq255", "gold511", "gold1023"}) {
      phy::DsssSettings s;
      s.code = code;
      s.modulation = modulation;
      const auto length = static_cast<double>(phy::dsss::code_by_name(code).chips.size());
      // Start a few dB above the expected threshold and walk down.
      double snr = std::round(14.0 - 10.0 * std::log10(length)) + (s.modulation == "dqpsk" ? 3 : 0);
      std::vector<std::pair<double, double>> curve;
      std::string row;
      // Fewer frames for long codes keep each point at a few seconds.
      const auto chips = static_cast<std::size_t>(length);
      const std::size_t n =
          std::max<std::size_t>(20, frames * 127 / std::max<std::size_t>(127, chips));
      for (int step = 0; step < 12; ++step, snr -= 1.0) {
        const double p = per(s, n, snr, 1000 + static_cast<std::uint32_t>(step));
        curve.emplace_back(snr, p);
        char cell[32];
        std::snprintf(cell, sizeof cell, " %+.0f:%.2f", snr, p);
        row += cell;
        if (p >= 0.95) break;
      }
      std::printf("%-9s %-6s %8.1f  %s\n", code, modulation, crossing(curve), row.c_str());
      std::fflush(stdout);
    }
  }
  return 0;
}
