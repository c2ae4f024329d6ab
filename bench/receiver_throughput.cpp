/// Receiver throughput on one core: complex samples per second of CPU time (the
/// thread's own, so that other work on a shared machine does not count) that a
/// PHY's RX path consumes, on pure noise and on a stream full of frames (80-byte
/// frames back to back with 200-sample gaps, 30 dB SNR). Median of 5 runs.
///
///   rfsitl_receiver_throughput [--seconds S] [--only NAME] [--csv FILE]
///   (e.g. --only ofdm24, for perf; --csv writes the table as CSV, for bench/run_benchmarks.sh)
#include <time.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "bench_signals.hpp"
#include "rfsitl/registry/phy_registry.hpp"
#include "rfsitl/scenario/scenario.hpp"

namespace {

using namespace rfsitl;

using bench::CountingHandler;
using bench::noise;

std::vector<cf32> frames(const scenario::PhyChoice& phy, std::size_t n, std::size_t* count) {
  auto tx = phy::make_transceiver(phy.type, phy.settings);
  return bench::frames(*tx, n, 1e-3F, 200, count);  // 30 dB below the unit-power signal
}

double thread_cpu_s() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

/// Median samples/s of feeding `input` in 250-sample ticks to a fresh receiver.
double rate(const scenario::PhyChoice& phy, const std::vector<cf32>& input, std::size_t* valid) {
  std::vector<double> rates;
  for (int run = 0; run < 5; ++run) {
    auto rx = phy::make_transceiver(phy.type, phy.settings);
    CountingHandler h;
    const double t0 = thread_cpu_s();
    for (std::size_t i = 0; i < input.size(); i += 250) {
      rx->receive(std::span(input).subspan(i, std::min<std::size_t>(250, input.size() - i)), h);
    }
    const double s = thread_cpu_s() - t0;
    rates.push_back(static_cast<double>(input.size()) / s);
    *valid = h.valid;
  }
  std::sort(rates.begin(), rates.end());
  return rates[2];
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Receiver throughput of every PHY on one core"};
  double seconds = 1.0;
  app.add_option("--seconds", seconds, "Signal length per measurement, at 1 Msps")
      ->capture_default_str();
  std::string only;
  app.add_option("--only", only, "Measure only this row (gmsk, ofdm24, dsss-barker11, ...)");
  std::string csv;
  app.add_option("--csv", csv, "Also write the table to this CSV file");
  CLI11_PARSE(app, argc, argv);
  std::ofstream table;
  if (!csv.empty()) {
    table.open(csv);
    if (!table) {
      std::fprintf(stderr, "rfsitl_receiver_throughput: cannot write %s\n", csv.c_str());
      return 1;
    }
    table << "phy,noise_msps,frames_msps,decoded,sent\n";
  }
  const auto n = static_cast<std::size_t>(seconds * 1e6);

  std::vector<std::pair<std::string, scenario::PhyChoice>> phys;
  phys.emplace_back("gmsk", scenario::PhyChoice::of("gmsk"));
  phys.emplace_back("gmsk-liquid", scenario::PhyChoice::of("gmsk-liquid"));
  for (unsigned r : {6U, 24U, 54U}) {
    phys.emplace_back("ofdm" + std::to_string(r),
                      scenario::PhyChoice::of("ofdm").with("rate_mbps", r));
  }
  for (const char* code : {"barker11", "mseq127"}) {
    phys.emplace_back(std::string("dsss-") + code,
                      scenario::PhyChoice::of("dsss").with("code", std::string(code)));
  }
  const std::vector<cf32> quiet = noise(n, 1.0F, 3);
  std::printf("%-13s %16s %22s %10s\n", "phy", "noise [Msps]", "with frames [Msps]", "decoded");
  for (const auto& [name, phy] : phys) {
    if (!only.empty() && name != only) continue;
    std::size_t sent = 0;
    std::size_t valid = 0;
    const std::vector<cf32> busy = frames(phy, n, &sent);
    const double on_noise = rate(phy, quiet, &valid);
    const double on_frames = rate(phy, busy, &valid);
    std::printf("%-13s %16.2f %22.2f %5zu/%-5zu\n", name.c_str(), on_noise / 1e6, on_frames / 1e6,
                valid, sent);
    if (table.is_open()) {
      table << name << "," << on_noise / 1e6 << "," << on_frames / 1e6 << "," << valid << ","
            << sent << "\n";
    }
  }
  return 0;
}
