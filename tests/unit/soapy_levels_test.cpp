// What a SoapySDR program hears in scenarios/soapy_pair.yaml at the module's
// default RX gain (signal_path.hpp), from the scenario's own link budget:
// every other node's burst at a Soapy node (a built-in one's, or the other
// Soapy node's at full scale) fits CS16 without clipping and stands clear of
// the noise, as on a real SDR at its default gain.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <variant>

#include "rfsitl/scenario/link_budget_of.hpp"
#include "rfsitl/scenario/scenario_loader.hpp"
#include "signal_path.hpp"

namespace rfsitl::soapy {
namespace {

constexpr double kCs16FullScale = 32767.0;

bool external(const scenario::Scenario& s, std::size_t i) {
  return s.phy_of(i).type == "external";
}

channel::LinkEnd end_of(const scenario::Scenario& s, std::size_t i) {
  channel::LinkEnd e;
  e.index = i;
  e.local = std::get<LocalPosition>(*s.nodes[i].initial_position);
  return e;
}

TEST(SoapyLevels, SoapyPairBurstsFitCs16AtTheDefaultRxGain) {
  const scenario::Scenario s =
      scenario::load_scenario_file(std::string(RFSITL_SOURCE_DIR) + "/scenarios/soapy_pair.yaml");
  const auto budget = scenario::make_link_budget(s);
  // Native units: the receiver noise has unit power (the channel divides by
  // its standard deviation); a built-in transmitter, and a Soapy one at full
  // scale and its default gain, send unit power.
  const double native_per_coefficient = 1.0 / std::sqrt(s.channel.noise_variance);
  const double to_lsb =
      amplitude_of({true, 0.0, kRxGain.scale_db(kRxGain.default_db)}) * kCs16FullScale;
  const double noise_lsb = std::sqrt(0.5) * to_lsb;  // RMS of I (or Q) of unit-power noise
  int links = 0;
  double loudest = 0.0;
  for (std::size_t tx = 0; tx < s.nodes.size(); ++tx) {
    for (std::size_t rx = 0; rx < s.nodes.size(); ++rx) {
      if (tx == rx || !external(s, rx)) continue;
      channel::LinkGeometry g;
      g.tx = end_of(s, tx);
      g.rx = end_of(s, rx);
      g.distance_m = g.horizontal_m =
          std::hypot(g.tx.local.x_m - g.rx.local.x_m, g.tx.local.y_m - g.rx.local.y_m);
      const double burst_lsb = std::abs(budget->coefficient(g)) * native_per_coefficient * to_lsb;
      const std::string link = std::to_string(tx + 1) + " -> " + std::to_string(rx + 1);
      EXPECT_GT(burst_lsb, 10.0 * noise_lsb) << link << ": 20 dB above the noise";
      ++links;
      loudest = std::max(loudest, burst_lsb);
    }
  }
  EXPECT_EQ(links, 6) << "each Soapy node hears the other three";
  // A constant-envelope burst peaks (in I or Q) at its amplitude, plus the
  // noise's few sigma: the loudest leaves 6 dB of headroom for them.
  EXPECT_LT(loudest, 0.5 * kCs16FullScale);
}

}  // namespace
}  // namespace rfsitl::soapy
