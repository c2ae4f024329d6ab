/// The air-time floor of a ping: one frame plus one acknowledgement on the air,
/// as the transceiver itself counts them (no queueing, ticks or processing).
///
///   rfsitl_airtime [--phy gmsk] [--size 80] [--ack-size 8] [--sample-rate 1e6]
///
/// Prints one CSV row (with a header): phy, sizes, samples, fs and the floor in ms.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <string>

#include "rfsitl/registry/phy_registry.hpp"
#include "rfsitl/scenario/scenario.hpp"

int main(int argc, char** argv) {
  CLI::App app{"Air-time floor of a frame plus its acknowledgement"};
  std::string type = "gmsk";
  unsigned rate_mbps = 6;
  std::size_t size = 80;
  std::size_t ack_size = 8;
  double fs = 1e6;
  app.add_option("--phy", type, "Transceiver type")->capture_default_str();
  app.add_option("--rate-mbps", rate_mbps, "ofdm: 802.11 rate")->capture_default_str();
  app.add_option("--size", size, "Frame payload bytes")->capture_default_str();
  app.add_option("--ack-size", ack_size, "Acknowledgement payload bytes")->capture_default_str();
  app.add_option("--sample-rate", fs, "Sample rate fs in Hz")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  try {
    auto phy = rfsitl::scenario::PhyChoice::of(type);
    if (type == "ofdm") phy = phy.with("rate_mbps", rate_mbps);
    const auto t = rfsitl::phy::make_transceiver(phy.type, phy.settings);
    const std::size_t frame = t->frame_samples(size);
    const std::size_t ack = t->frame_samples(ack_size);
    std::printf("phy,size_bytes,ack_bytes,frame_samples,ack_samples,sample_rate_hz,floor_ms\n");
    std::printf("%s,%zu,%zu,%zu,%zu,%.0f,%.4f\n", type.c_str(), size, ack_size, frame, ack, fs,
                1e3 * static_cast<double>(frame + ack) / fs);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "airtime: %s\n", e.what());
    return 2;
  }
  return 0;
}
