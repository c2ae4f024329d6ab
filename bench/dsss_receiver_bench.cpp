/// DSSS receiver throughput on one core: complex samples per second consumed on
/// pure noise (listening on one code and on two) and on a stream of 80-byte
/// DBPSK frames (10 dB per-sample SNR, 500-sample gaps), fed in 250-sample
/// ticks as the engine does. Median of 5 runs. A benchmark: prints, asserts nothing.
///
///   g++ -std=c++20 -O2 -Iinclude bench/dsss_receiver_bench.cpp src/phy/dsss/*.cpp
///       -lliquid -pthread -o dsss_receiver_bench
///   ./dsss_receiver_bench [samples per measurement, default 4000000]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench_signals.hpp"
#include "phy/dsss/dsss_transceiver.hpp"

namespace {

using namespace rfsitl;

using bench::CountingHandler;
using bench::noise;

/// Noise 10 dB below unit power with back-to-back frames; *count: frames in it.
std::vector<cf32> frames(const phy::DsssSettings& s, std::size_t n, std::size_t* count) {
  auto tx = phy::make_dsss_transceiver(s);
  return bench::frames(*tx, n, 0.1F, 500, count);
}

/// Median samples/s of a fresh receiver listening on `listen` codes.
double rate(const phy::DsssSettings& s, const std::vector<cf32>& input, std::size_t listen,
            std::size_t* valid) {
  std::vector<double> rates;
  for (int run = 0; run < 5; ++run) {
    auto rx = phy::make_code_agile_dsss_transceiver(s);
    std::vector<std::size_t> codes = {0};
    if (listen > 1) {
      // Another member of the code's Gold family when there is one; Barker-11
      // and mseq255 have no partner, so they listen twice on the same code
      // (a correlator costs the same whichever code it holds).
      const std::string length = s.code.substr(s.code.find_first_of("0123456789"));
      try {
        codes.push_back(rx->add_code("gold" + length.substr(0, length.find(':')) + ":1"));
      } catch (const std::invalid_argument&) {
        codes.push_back(0);
      }
    }
    rx->set_listen_codes(codes);
    CountingHandler h;
    const auto t0 = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < input.size(); i += 250) {
      rx->receive(std::span(input).subspan(i, std::min<std::size_t>(250, input.size() - i)), h);
    }
    const auto t1 = std::chrono::steady_clock::now();
    rates.push_back(static_cast<double>(input.size()) /
                    std::chrono::duration<double>(t1 - t0).count());
    *valid = h.valid;
  }
  std::sort(rates.begin(), rates.end());
  return rates[2];
}

}  // namespace

int main(int argc, char** argv) {
  const std::size_t n = argc > 1 ? std::strtoul(argv[1], nullptr, 10) : 4'000'000;
  const std::vector<cf32> pure = noise(n, 1.0F, 3);
  std::printf("Msps on one core, %zu samples per run, 250-sample ticks\n", n);
  std::printf("%-10s %4s %12s %12s %12s %14s %8s\n", "code", "sps", "noise", "noise 2code",
              "frames", "decoded/sent", "noise fp");
  for (const char* code :
       {"barker11", "mseq31", "gold63", "mseq127", "gold127", "mseq255", "gold511", "gold1023"}) {
    for (const unsigned sps : {1U, 2U}) {
      phy::DsssSettings s;
      s.code = code;
      s.samples_per_chip = sps;
      std::size_t sent = 0;
      std::size_t decoded = 0;
      std::size_t noise_decodes = 0;
      std::size_t unused = 0;
      const auto stream = frames(s, n, &sent);
      const double r1 = rate(s, pure, 1, &noise_decodes);
      const double r2 = rate(s, pure, 2, &unused);
      const double rf = rate(s, stream, 1, &decoded);
      std::printf("%-10s %4u %12.1f %12.1f %12.1f %8zu/%-5zu %8zu\n", code, sps, r1 / 1e6, r2 / 1e6,
                  rf / 1e6, decoded, sent, noise_decodes);
    }
  }
  return 0;
}
