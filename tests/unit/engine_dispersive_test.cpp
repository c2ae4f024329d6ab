// Dispersive channels through the engine and the real GMSK transceivers: a
// frame 30 km away arrives 100 samples late across tick boundaries and is
// delivered (its tail is mixed after its transmitter fell silent; the ledger
// waits for it); a TDL fading channel gives the same outcome whatever the
// thread count.
#include <gtest/gtest.h>

#include <string>

#include "engine_run.hpp"
#include "rfsitl/engine/engine_observer.hpp"
#include "rfsitl/scenario/scenario_loader.hpp"

namespace rfsitl::testing {
namespace {

/// 40 dBm, NF 7 dB, 1 Msps: the noise is -107 dBm; at 30 km free space
/// loses 129.6 dB at 2.4 GHz, an SNR of 17 dB. Ticks of 250 samples.
scenario::Scenario far_pair(const std::string& stages, unsigned threads,
                            const std::string& impairments = "") {
  const std::string yaml =
      "time: {mode: virtual, duration_s: 0.2, sample_rate_hz: 1e6, tick_samples: 250}\n"
      "radio: {carrier_hz: 2.4e9, tx_power_dbm: 40, noise_figure_db: 7}\n"
      "channel:\n  stages: [{type: path_loss, model: free_space}" +
      stages + "]\n" + impairments + "engine: {threads: " + std::to_string(threads) +
      "}\n"
      "nodes:\n  - {id: 1, position: {x: 0, y: 0, z: 10}}\n"
      "  - {id: 2, position: {x: 30000, y: 0, z: 10}}\n"
      "  - {id: 3, mobility: {type: orbit, radius_m: 200, speed_mps: 15, altitude_m: 10}}\n"
      "traffic:\n"
      "  - {at_s: 0.002, src: 1, dst: 2, size_bytes: 60, repeat: 10, interval_s: 0.015}\n"
      "  - {at_s: 0.006, src: 3, dst: 1, size_bytes: 40, repeat: 10, interval_s: 0.015}\n"
      "  - {at_s: 0.010, src: 2, dst: 255, size_bytes: 40, repeat: 10, interval_s: 0.015}\n";
  return scenario::parse_scenario(yaml, "dispersive.yaml");
}

TEST(EngineDelay, AFrameLateByTheDistanceIsDeliveredAndNothingIsLate) {
  const RunResult flat = run_engine(far_pair("", 2));
  const RunResult late = run_engine(far_pair(", {type: delay}", 2));
  EXPECT_EQ(flat.counters[1].received, 10U);
  EXPECT_EQ(late.counters[1].received, 10U);
  EXPECT_EQ(late.counters[0].received, flat.counters[0].received);
  EXPECT_EQ(late.status.late_decodes, 0U);
  // 100 us late: a frame that ended near a tick's end is decoded a tick later.
  ASSERT_FALSE(late.deliveries.empty());
  SampleTime flat_sum = 0;
  SampleTime late_sum = 0;
  for (const Delivery& d : flat.deliveries) {
    if (d.node == 1) flat_sum += d.tick_start;
  }
  for (const Delivery& d : late.deliveries) {
    if (d.node == 1) late_sum += d.tick_start;
  }
  EXPECT_GE(late_sum, flat_sum);
}

TEST(EngineMultipath, ATdlFadingChannelGivesTheSameOutcomeWithAnyThreadCount) {
  const std::string tdl =
      ", {type: delay}, {type: multipath, profile: tdl_c, delay_spread_ns: 300},"
      " {type: fading, model: rician, k_db: 6}";
  const RunResult one = run_engine(far_pair(tdl, 1));
  const RunResult two = run_engine(far_pair(tdl, 2));
  expect_same_outcome(one, two);
  // Near links survive the fading; most of the far link's frames do too.
  EXPECT_GE(one.counters[0].received, 5U);
  EXPECT_EQ(one.status.late_decodes, 0U);
}

/// Wants every node's samples in every tick (as the dashboard or SigMF would).
class WatchAll final : public engine::EngineObserver {
 public:
  void on_frame_event(const engine::FrameEvent&) override {}
  bool wants_samples(std::size_t, SampleTime, std::size_t) const override { return true; }
  void on_rx_samples(std::size_t, SampleTime, std::span<const cf32>) override { ++ticks; }
  std::uint64_t ticks = 0;
};

TEST(EngineMultipath, WatchingAndThreadsChangeNoOutcomeWithTailsAndImpairments) {
  const std::string stages =
      ", {type: delay}, {type: multipath, profile: tdl_a, delay_spread_ns: 1000},"
      " {type: fading, model: rayleigh}";
  const std::string impairments =
      "  impairments:\n"
      "    tx: {cfo_spread_hz: 300, iq_imbalance_db: 0.3, dc_offset: 0.02}\n"
      "    rx: {phase_noise_dbc_hz: -85, iq_imbalance_deg: 2, dc_offset: 0.1}\n";
  scenario::Scenario s = far_pair(stages, 2, impairments);
  const RunResult plain = run_engine(s);
  WatchAll watcher;
  const RunResult watched = run_engine(s, {.observers = {&watcher}});
  expect_same_outcome(plain, watched);
  EXPECT_GT(watcher.ticks, 0U);
  s.engine.threads = 1;
  expect_same_outcome(plain, run_engine(s));
  EXPECT_GE(plain.counters[0].received, 5U);
}

TEST(EngineMultipath, TheShippedWifiScenarioDeliversMostFramesThroughItsImpairedChannel) {
  scenario::Scenario s = scenario::load_scenario_file(std::string(RFSITL_SOURCE_DIR) +
                                                      "/scenarios/wifi_multipath.yaml");
  s.timing.duration_s = 0.25;  // 12 frames from each UAV
  const RunResult r = run_engine(s);
  // Node 1 (the ground station) hears the near UAVs' frames; the far one's
  // may fade. Nothing is late, and every handed-in frame is accounted for.
  EXPECT_GE(r.counters[0].received, 24U);
  EXPECT_EQ(r.status.late_decodes, 0U);
  for (const auto& c : r.counters) {
    EXPECT_LE(c.delivered + c.lost_total() + c.queue_dropped, c.handed_in);
  }
}

}  // namespace
}  // namespace rfsitl::testing
