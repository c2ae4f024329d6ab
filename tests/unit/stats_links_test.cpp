// The link matrix of /api/stats and --summary-json: every link's power gain
// and SNR of the moment, fading included, row-major [tx * n + rx].
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>

#include "monitor_test_scenario.hpp"
#include "rfsitl/monitor/stats_report.hpp"
#include "rfsitl/scenario/scenario_loader.hpp"

namespace rfsitl::monitor {
namespace {

using test::NullSink;

/// Three nodes, a 20 dBm radio through free space and Rician fading, node 3
/// placed by its location feed (unknown here: no link).
scenario::Scenario faded_trio() {
  return scenario::parse_scenario(
      "name: links\n"
      "time: {mode: virtual, duration_s: 0.25}\n"
      "radio: {carrier_hz: 2.4e9, tx_power_dbm: 20, noise_figure_db: 7}\n"
      "channel:\n"
      "  stages:\n"
      "    - {type: path_loss, model: free_space}\n"
      "    - {type: fading, model: rician, k_db: 3}\n"
      "nodes:\n"
      "  - {id: 1, position: {x: 0, y: 0, z: 10}}\n"
      "  - {id: 2, position: {x: 100, y: 0, z: 10}}\n"
      "  - {id: 3}\n",
      "links.yaml");
}

TEST(StatsLinks, GainAndSnrOfEveryLinkAreTheEnginesGainsOfTheMoment) {
  const auto s = faded_trio();
  NullSink sink;
  auto e = engine::make_engine(s, sink);
  const std::atomic<bool> stop{false};
  e->run(stop);
  const auto j = stats_with_links_json(s, *e);
  const auto gains = e->link_gains();
  ASSERT_EQ(j.at("links").at("n"), 3);
  const auto& gain_db = j.at("links").at("gain_db");
  const auto& snr_db = j.at("links").at("snr_db");
  ASSERT_EQ(gain_db.size(), 9U);
  ASSERT_EQ(snr_db.size(), 9U);
  const double noise_db = 10.0 * std::log10(s.channel.noise_variance);
  for (std::size_t tx = 0; tx < 3; ++tx) {
    for (std::size_t rx = 0; rx < 3; ++rx) {
      const std::size_t k = tx * 3 + rx;
      if (tx == rx || tx == 2 || rx == 2) {  // itself, or node 3 without a position
        EXPECT_TRUE(gain_db[k].is_null()) << k;
        EXPECT_TRUE(snr_db[k].is_null()) << k;
        continue;
      }
      const double want = 10.0 * std::log10(gains[k]);
      EXPECT_NEAR(gain_db[k].get<double>(), want, 0.051) << k;
      EXPECT_NEAR(snr_db[k].get<double>(), want - noise_db, 0.051) << k;
    }
  }
  // 100 m of free space at 2.4 GHz is 80.1 dB; 20 dBm in, so about -60 dBm
  // around which the Rician fade moves it (a fade this deep in 0.25 s at K = 3
  // dB and no Doppler would be a broken stage).
  EXPECT_NEAR(gain_db[1].get<double>(), 20.0 - 80.05, 15.0);
  // The plain stats document has no matrix: it is not computed for it.
  EXPECT_FALSE(stats_json(s, *e).contains("links"));
}

}  // namespace
}  // namespace rfsitl::monitor
