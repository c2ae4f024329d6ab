/// A digest of every decision the fast GMSK receiver makes on a fixed random
/// workload (frames of random sizes, gaps, carrier phases and frequency
/// offsets in noise at several SNRs, k = 2, 3, 4, 8, fed in 250-sample ticks):
/// tags, CRC outcomes, payload bytes, soft symbols, RSSI and EVM, and the busy
/// state after every tick, hashed bit for bit. Two builds whose digests match
/// decided alike; this is how an optimisation of the receiver is checked
/// against the code before it (the unit tests compare the kernel versions of
/// one build).
///
///   rfsitl_gmsk_decision_digest [--frames N]
///
/// For a checkout without this target (an older commit), by hand from this
/// file and that checkout's sources, leaving out the registry's part (one line):
///   g++ -std=c++20 -O3 -I<old>/include -I<old>/src bench/gmsk_decision_digest.cpp
///       $(ls <old>/src/phy/gmsk/*.cpp | grep -v gmsk_component) -o old_digest
#include <bit>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "phy/gmsk/fast_gmsk_transceiver.hpp"

namespace {

using namespace rfsitl;

/// FNV-1a, 64 bits.
class Digest final : public phy::RxHandler {
 public:
  void add(const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) h_ = (h_ ^ b[i]) * 0x100000001b3ULL;
  }
  template <class T>
  void add(const T& v) {
    add(&v, sizeof v);
  }
  void on_rx(const phy::RxEvent& ev) override {
    add(ev.tag.src);
    add(ev.tag.dst);
    add(ev.tag.serial);
    add(ev.header_valid);
    add(ev.payload_valid);
    add(ev.payload.data(), ev.payload.size());
    add(std::bit_cast<std::uint32_t>(ev.rssi_db));
    add(std::bit_cast<std::uint32_t>(ev.evm_db));
    for (const cf32 z : ev.symbols) add(std::bit_cast<std::uint64_t>(z));
    ++events;
    valid += ev.payload_valid ? 1 : 0;
  }
  std::uint64_t value() const { return h_; }
  std::size_t events = 0;
  std::size_t valid = 0;

 private:
  std::uint64_t h_ = 0xcbf29ce484222325ULL;
};

/// `frames` random frames at unit power in noise of `noise_power`.
std::vector<cf32> workload(unsigned k, std::size_t frames, double noise_power, std::uint32_t seed) {
  std::mt19937 rng(seed);
  phy::FastGmskSettings s;
  s.samples_per_symbol = k;
  auto tx = phy::make_fast_gmsk_transceiver(s);
  std::vector<cf32> air(std::uniform_int_distribution<std::size_t>(0, 500)(rng));
  for (std::size_t f = 0; f < frames; ++f) {
    std::vector<std::uint8_t> payload(std::uniform_int_distribution<std::size_t>(0, 200)(rng));
    for (auto& b : payload) b = static_cast<std::uint8_t>(rng());
    const std::size_t len =
        tx->start_frame(phy::FrameTag{1, 2, static_cast<std::uint32_t>(f)}, payload);
    std::vector<cf32> frame(len);
    tx->transmit(frame);
    const float phase = std::uniform_real_distribution<float>(0.0F, 6.28F)(rng);
    const float offset = std::uniform_real_distribution<float>(-2e-3F, 2e-3F)(rng);
    for (std::size_t i = 0; i < len; ++i) {
      air.push_back(frame[i] * std::polar(1.0F, phase + offset * static_cast<float>(i)));
    }
    air.resize(air.size() + std::uniform_int_distribution<std::size_t>(0, 600)(rng));
  }
  std::normal_distribution<float> g(0.0F, static_cast<float>(std::sqrt(noise_power / 2.0)));
  for (cf32& v : air) v += cf32{g(rng), g(rng)};
  return air;
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t frames = 200;
  if (argc == 3 && std::string(argv[1]) == "--frames") {
    frames = std::strtoul(argv[2], nullptr, 10);
  } else if (argc != 1) {
    std::fprintf(stderr, "usage: %s [--frames N]\n", argv[0]);
    return 2;
  }
  Digest total;
  for (const unsigned k : {2U, 3U, 4U, 8U}) {
    Digest d;
    for (const double snr_db : {-4.0, 0.0, 3.0, 6.0, 20.0}) {
      const auto seed = static_cast<std::uint32_t>(1000 * k + 10 * (snr_db + 10));
      const std::vector<cf32> air = workload(k, frames, std::pow(10.0, -snr_db / 10.0), seed);
      phy::FastGmskSettings s;
      s.samples_per_symbol = k;
      auto rx = phy::make_fast_gmsk_transceiver(s);
      for (std::size_t off = 0; off < air.size(); off += 250) {
        rx->receive(std::span(air).subspan(off, std::min<std::size_t>(250, air.size() - off)), d);
        d.add(rx->rx_busy());
      }
    }
    std::printf("k=%u decodes %zu valid %zu digest %016" PRIx64 "\n", k, d.events, d.valid,
                d.value());
    total.add(d.value());
  }
  std::printf("all %016" PRIx64 "\n", total.value());
  return 0;
}
