/// Packet error rate versus SNR for every PHY, through the emulator's own code
/// path: an Engine in virtual time with two nodes at distance 0 (path gain 1),
/// the noise variance set to give each SNR, and scheduled 80-byte frames.
///
///   rfsitl_per_sweep [--frames N] [--csv FILE] [--from DB --to DB --step DB]
///
/// SNR is per sample: transmit power (1) over the noise variance in the whole
/// sample bandwidth fs. (An OFDM signal fills 52 of 64 subcarriers, so its SNR
/// per occupied subcarrier is 0.9 dB higher; GMSK at k = 2 has Eb/N0 = SNR + 3 dB.)
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <tuple>
#include <vector>

#include "rfsitl/engine/engine.hpp"
#include "rfsitl/registry/phy_registry.hpp"
#include "rfsitl/session/session.hpp"

namespace {

using namespace rfsitl;

struct Point {
  std::string phy;
  double snr_db;
  unsigned frames;
  std::uint64_t delivered;
};

Point measure(const scenario::PhyChoice& phy, const std::string& label, double snr_db,
              unsigned frames, std::size_t payload, std::uint64_t seed) {
  scenario::Scenario s;
  s.name = "per-sweep";
  s.seed = seed;
  s.phy = phy;
  s.timing.mode = scenario::TimeMode::kVirtual;
  s.channel.noise_variance = std::pow(10.0, -snr_db / 10.0);
  s.nodes = {scenario::NodeConfig::at(1, LocalPosition{0, 0, 10}),
             scenario::NodeConfig::at(2, LocalPosition{0, 0, 10})};
  const double frame_s =
      static_cast<double>(phy::make_transceiver(phy.type, phy.settings)->frame_samples(payload)) /
      s.timing.sample_rate_hz;
  const double interval = 1.5 * frame_s + 0.001;
  s.traffic = {{0.001, 1, 2, payload, frames, interval}};
  s.timing.duration_s = 0.001 + interval * frames + 0.01;
  return {label, snr_db, frames, session::run_portless(s).counters[0].delivered};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Packet error rate versus SNR of every PHY, through the emulator's code path"};
  unsigned frames = 200;
  double from = -2.0;
  double to = 30.0;
  double step = 1.0;
  std::size_t payload = 80;
  std::string csv = "per_vs_snr.csv";
  std::vector<std::string> only;
  app.add_option("--frames", frames, "Frames per point")->capture_default_str();
  app.add_option("--from", from, "First SNR (dB)")->capture_default_str();
  app.add_option("--to", to, "Last SNR (dB)")->capture_default_str();
  app.add_option("--step", step, "SNR step (dB)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--size", payload, "Net payload bytes per frame")->capture_default_str();
  app.add_option("--csv", csv, "Output CSV")->capture_default_str();
  app.add_option(
      "--only", only,
      "Measure only these curves (gmsk, gmsk-liquid, ofdm6 ... ofdm54, dsss-barker11-dbpsk, "
      "dsss-barker11-dqpsk, dsss-mseq31-dbpsk, dsss-mseq127-dbpsk, gfsk-energy-h1, gfsk-sik)");
  CLI11_PARSE(app, argc, argv);

  struct Curve {
    std::string label;
    scenario::PhyChoice phy;
    double from_db;  // where the curve starts to matter
  };
  std::vector<Curve> curves;
  curves.push_back({"gmsk", scenario::PhyChoice::of("gmsk"), from});
  curves.push_back({"gmsk-liquid", scenario::PhyChoice::of("gmsk-liquid"), from});
  for (unsigned rate : {6U, 9U, 12U, 18U, 24U, 36U, 48U, 54U}) {
    curves.push_back({"ofdm" + std::to_string(rate),
                      scenario::PhyChoice::of("ofdm").with("rate_mbps", rate), from});
  }
  // DSSS at 1 sample per chip: the processing gain moves the curves left.
  for (const auto& [code, modulation, start] :
       {std::tuple{"barker11", "dbpsk", -6.0}, std::tuple{"barker11", "dqpsk", -2.0},
        std::tuple{"mseq31", "dbpsk", -10.0}, std::tuple{"mseq127", "dbpsk", -16.0}}) {
    const auto p = scenario::PhyChoice::of("dsss")
                       .with("code", std::string(code))
                       .with("modulation", std::string(modulation));
    curves.push_back({std::string("dsss-") + code + "-" + modulation, p, std::min(from, start)});
  }
  // GFSK at 8 samples per bit: the energy detector with orthogonal tones (h = 1,
  // no shaping), which is the non-coherent BFSK theory's detector, and the
  // SiK-like defaults (h = 2, BT = 0.5, FM discriminator).
  curves.push_back({"gfsk-energy-h1",
                    scenario::PhyChoice::of("gfsk")
                        .with("receiver", std::string("energy"))
                        .with("modulation_index", 1.0)
                        .with("bandwidth_time", 0.0),
                    from});
  curves.push_back({"gfsk-sik", scenario::PhyChoice::of("gfsk"), from});
  std::ofstream out(csv);
  out << "phy,snr_db,frames,delivered,per\n";
  for (const auto& [label, phy, start] : curves) {
    if (!only.empty() && std::find(only.begin(), only.end(), label) == only.end()) continue;
    unsigned clean = 0;  // stop a curve after three points without a single error
    for (double snr = start; snr <= to + 1e-9 && clean < 3; snr += step) {
      const auto seed = static_cast<std::uint64_t>(std::llround((snr + 100.0) * 10.0));
      const Point p = measure(phy, label, snr, frames, payload, seed);
      const double per = 1.0 - static_cast<double>(p.delivered) / p.frames;
      out << p.phy << "," << p.snr_db << "," << p.frames << "," << p.delivered << "," << per
          << "\n";
      std::printf("%-7s snr %5.1f dB  per %.4f  (%llu/%u delivered)\n", label.c_str(), snr, per,
                  static_cast<unsigned long long>(p.delivered), p.frames);
      std::fflush(stdout);
      clean = p.delivered == p.frames ? clean + 1 : 0;
    }
  }
  std::printf("per_sweep: wrote %s\n", csv.c_str());
  return 0;
}
