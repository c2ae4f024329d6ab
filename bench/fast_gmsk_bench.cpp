/// The fast GMSK transceiver beside the liquid-dsp one, in one run:
/// receiver throughput on one core (pure noise; 80-byte frames back to back)
/// and packet success rate against per-sample SNR.
///
/// Build by hand (or through bench/CMakeLists.txt once it lists this file), in
/// one line:
///   g++ -std=c++20 -O2 -Iinclude bench/fast_gmsk_bench.cpp src/phy/gmsk/*.cpp
///       src/phy/gmsk_transceiver.cpp -lliquid -pthread -o fast_gmsk_bench
///   ./fast_gmsk_bench [--seconds S] [--frames N] [--k K]
///
/// Throughput: a fresh receiver is fed S seconds of 1 Msps input in 250-sample
/// ticks (the emulator's), median of 5 runs. "noise" is unit-power complex
/// AWGN (the emulator scales every receiver's noise floor to 1); "frames" is
/// 80-byte frames back to back with 200-sample gaps at 20 dB SNR over that noise.
/// PER: N 80-byte frames per point, each with random payload, carrier phase and
/// start offset, in its own noise, fed in 250-sample ticks; a frame counts if
/// its exact tag and payload are reported valid.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "phy/gmsk/fast_gmsk_transceiver.hpp"
#include "phy/gmsk_liquid/gmsk_transceiver.hpp"

namespace {

using namespace rfsitl;

constexpr std::size_t kTick = 250;
constexpr std::size_t kPayloadBytes = 80;

struct Phy {
  const char* name;
  std::unique_ptr<phy::Transceiver> (*make)(unsigned k);
};

std::unique_ptr<phy::Transceiver> make_fast(unsigned k) {
  phy::FastGmskSettings s;
  s.samples_per_symbol = k;
  return phy::make_fast_gmsk_transceiver(s);
}

std::unique_ptr<phy::Transceiver> make_liquid(unsigned k) {
  phy::GmskSettings s;
  s.samples_per_symbol = k;
  return phy::make_gmsk_transceiver(s);
}

struct Counter final : phy::RxHandler {
  std::size_t valid = 0;
  std::uint32_t last_serial = 0;
  std::vector<std::uint8_t> last_payload;
  void on_rx(const phy::RxEvent& ev) override {
    if (!ev.payload_valid) return;
    ++valid;
    last_serial = ev.tag.serial;
    last_payload.assign(ev.payload.begin(), ev.payload.end());
  }
};

void add_noise(std::vector<cf32>& v, float variance, std::mt19937& rng) {
  std::normal_distribution<float> g(0.0F, std::sqrt(variance / 2.0F));
  for (auto& s : v) s += cf32{g(rng), g(rng)};
}

std::vector<cf32> frame_stream(const Phy& p, unsigned k, std::size_t n, std::size_t* count) {
  auto tx = p.make(k);
  std::vector<cf32> v(n);
  std::mt19937 rng(7);
  std::vector<std::uint8_t> payload(kPayloadBytes);
  const float amplitude = 10.0F;  // 20 dB over the unit noise
  std::size_t pos = 200;
  *count = 0;
  for (std::uint32_t serial = 0;; ++serial) {
    const std::size_t len = tx->frame_samples(payload.size());
    if (pos + len > n) break;
    for (auto& b : payload) b = static_cast<std::uint8_t>(rng());
    tx->start_frame({1, 2, serial}, payload);
    tx->transmit(std::span(v).subspan(pos, len));
    for (std::size_t i = pos; i < pos + len; ++i) v[i] *= amplitude;
    pos += len + 200;
    ++*count;
  }
  add_noise(v, 1.0F, rng);
  return v;
}

/// Median input samples per second over 5 runs; `valid` gets the decodes.
double throughput(const Phy& p, unsigned k, const std::vector<cf32>& input, std::size_t* valid) {
  std::vector<double> rates;
  for (int run = 0; run < 5; ++run) {
    auto rx = p.make(k);
    Counter c;
    const auto t0 = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < input.size(); i += kTick) {
      rx->receive(std::span(input).subspan(i, std::min(kTick, input.size() - i)), c);
    }
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    rates.push_back(static_cast<double>(input.size()) / s);
    *valid = c.valid;
  }
  std::sort(rates.begin(), rates.end());
  return rates[2];
}

double success_rate(const Phy& p, unsigned k, double snr_db, int frames, std::uint32_t seed) {
  auto tx = p.make(k);
  auto rx = p.make(k);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> phase(0.0F, 6.2831853F);
  int ok = 0;
  std::vector<std::uint8_t> payload(kPayloadBytes);
  for (int f = 0; f < frames; ++f) {
    for (auto& b : payload) b = static_cast<std::uint8_t>(rng());
    const auto serial = static_cast<std::uint32_t>(f);
    const std::size_t len = tx->start_frame({1, 2, serial}, payload);
    const std::size_t start = 300 + rng() % 100;
    std::vector<cf32> air(start + len + 600);
    tx->transmit(std::span(air).subspan(start, len));
    const cf32 rot = std::polar(1.0F, phase(rng));
    for (auto& s : air) s *= rot;
    add_noise(air, static_cast<float>(std::pow(10.0, -snr_db / 10.0)), rng);
    Counter c;
    for (std::size_t i = 0; i < air.size(); i += kTick) {
      rx->receive(std::span(air).subspan(i, std::min(kTick, air.size() - i)), c);
    }
    ok += static_cast<int>(c.valid == 1 && c.last_serial == serial && c.last_payload == payload);
  }
  return static_cast<double>(ok) / frames;
}

}  // namespace

int main(int argc, char** argv) {
  double seconds = 2.0;
  int frames = 500;
  unsigned k = 2;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (std::strcmp(argv[i], "--seconds") == 0) {
      seconds = std::atof(argv[i + 1]);
    } else if (std::strcmp(argv[i], "--frames") == 0) {
      frames = std::atoi(argv[i + 1]);
    } else if (std::strcmp(argv[i], "--k") == 0) {
      k = static_cast<unsigned>(std::atoi(argv[i + 1]));
    } else {
      std::fprintf(stderr, "usage: %s [--seconds S] [--frames N] [--k K]\n", argv[0]);
      return 2;
    }
  }
  const Phy phys[] = {{"fast", make_fast}, {"liquid", make_liquid}};
  const auto n = static_cast<std::size_t>(seconds * 1e6);
  std::vector<cf32> noise(n);
  std::mt19937 rng(1);
  add_noise(noise, 1.0F, rng);

  std::printf("GMSK k=%u BT=0.5, one core, 250-sample ticks, %.1f s of 1 Msps input\n", k, seconds);
  std::printf("%-8s %14s %14s %10s %12s\n", "phy", "noise_Msps", "frames_Msps", "frames",
              "decoded");
  for (const Phy& p : phys) {
    std::size_t count = 0;
    std::size_t valid = 0;
    const std::vector<cf32> stream = frame_stream(p, k, n, &count);
    const double noise_rate = throughput(p, k, noise, &valid);
    const std::size_t noise_valid = valid;
    const double frame_rate = throughput(p, k, stream, &valid);
    std::printf("%-8s %14.2f %14.2f %10zu %12zu   (noise decodes: %zu)\n", p.name, noise_rate / 1e6,
                frame_rate / 1e6, count, valid, noise_valid);
  }

  std::printf("\npacket success rate, %zu-byte frames, %d frames per point\n", kPayloadBytes,
              frames);
  std::printf("%8s %10s %10s\n", "snr_db", "fast", "liquid");
  const double offset = -10.0 * std::log10(k / 2.0);
  for (double snr = 3.0; snr <= 12.01; snr += 1.0) {
    const double s = snr + offset;
    std::printf("%8.2f %10.3f %10.3f\n", s, success_rate(phys[0], k, s, frames, 11),
                success_rate(phys[1], k, s, frames, 11));
    std::fflush(stdout);
  }
  return 0;
}
