// The link budget end to end: a radio and a free-space channel decide, through
// the real GMSK transceivers, which frames arrive; and the frame ledger names
// the same cause for a loss that the budget predicts.
#include <gtest/gtest.h>

#include <string>

#include "engine_run.hpp"
#include "rfsitl/scenario/scenario_loader.hpp"

namespace rfsitl::testing {
namespace {

/// Node 2 at `d` metres from node 1; 20 dBm, NF 7 dB, 1 Msps: the noise is
/// -107 dBm, so the SNR is 127 dB - FSPL(d) at 2.4 GHz.
scenario::Scenario pair_at(double d) {
  const std::string yaml =
      "time: {mode: virtual, duration_s: 0.1, sample_rate_hz: 1e6, tick_samples: 1000}\n"
      "radio: {carrier_hz: 2.4e9, tx_power_dbm: 20, noise_figure_db: 7}\n"
      "channel:\n  stages: [{type: path_loss, model: free_space}]\n"
      "engine: {threads: 2}\n"
      "nodes:\n  - {id: 1, position: {x: 0, y: 0, z: 10}}\n"
      "  - {id: 2, position: {x: " +
      std::to_string(d) +
      ", y: 0, z: 10}}\n"
      "traffic:\n  - {at_s: 0.002, src: 1, dst: 2, size_bytes: 60, repeat: 5, interval_s: 0.015}\n";
  return scenario::parse_scenario(yaml, "budget.yaml");
}

TEST(EngineLinkBudget, ANearLinkDeliversEveryFrame) {
  // 100 m: FSPL 80 dB, SNR 47 dB.
  const RunResult r = run_engine(pair_at(100.0));
  EXPECT_EQ(r.counters[1].received, 5U);
  EXPECT_EQ(r.deliveries.size(), 5U);
}

TEST(EngineLinkBudget, AFarLinkLosesEveryFrameBelowSensitivity) {
  // 40 km: FSPL 132 dB, SNR -5 dB: under GMSK's sensitivity, and the ledger
  // says so from the same gains the receiver saw.
  const RunResult r = run_engine(pair_at(40000.0));
  EXPECT_EQ(r.counters[1].received, 0U);
  EXPECT_EQ(r.lost(0, engine::LossReason::kBelowSensitivity), 5U);  // counted at the sender
}

/// Node 2 circles node 1 at 4 km and 20 m/s (a 160 Hz Doppler at 2.4 GHz):
/// a mean SNR of 14.9 dB, 10 dB above GMSK's sensitivity, with 200 frames.
scenario::Scenario orbiting_pair(const std::string& extra_stage, unsigned threads) {
  const std::string yaml =
      "time: {mode: virtual, duration_s: 2.1, sample_rate_hz: 1e6, tick_samples: 1000}\n"
      "radio: {carrier_hz: 2.4e9, tx_power_dbm: 20, noise_figure_db: 7}\n"
      "channel:\n  stages: [{type: path_loss, model: free_space}" +
      extra_stage +
      "]\n"
      "engine: {threads: " +
      std::to_string(threads) +
      "}\n"
      "nodes:\n  - {id: 1, position: {x: 0, y: 0, z: 10}}\n"
      "  - {id: 2, mobility: {type: orbit, radius_m: 4000, speed_mps: 20, altitude_m: 10}}\n"
      "traffic:\n  - {at_s: 0.002, src: 1, dst: 2, size_bytes: 60, repeat: 200, interval_s: "
      "0.01}\n";
  return scenario::parse_scenario(yaml, "fading.yaml");
}

TEST(EngineFading, RayleighFadingLosesFramesThatTheSameMeanSnrWouldDeliver) {
  const RunResult flat = run_engine(orbiting_pair("", 2));
  EXPECT_EQ(flat.counters[1].received, 200U);
  // In Rayleigh fading the SNR is below the mean by 10 dB or more a tenth of
  // the time (1 - exp(-0.1)): frames are lost, but most arrive.
  const RunResult faded = run_engine(orbiting_pair(", {type: fading, model: rayleigh}", 2));
  const std::uint64_t got = faded.counters[1].received;
  EXPECT_GT(got, 120U);
  EXPECT_LT(got, 199U);
  // A loss in a fade is the receiver's, not the mean budget's.
  EXPECT_EQ(faded.lost(0, engine::LossReason::kBelowSensitivity), 0U);
  EXPECT_EQ(faded.lost(0, engine::LossReason::kDecodeFailure), 200U - got);
}

TEST(EngineFading, TheOutcomeIsTheSameWithAnyThreadCount) {
  const std::string rician = ", {type: fading, model: rician, k_db: 3}";
  const RunResult one = run_engine(orbiting_pair(rician, 1));
  const RunResult three = run_engine(orbiting_pair(rician, 3));
  expect_same_outcome(one, three);
}

}  // namespace
}  // namespace rfsitl::testing
