// The MAC "tdma" alone: frames start only in the node's own slot and end a
// guard before it does; a slot too short for any frame is refused.
#include <gtest/gtest.h>

#include <stdexcept>

#include "fake_frame_queue.hpp"
#include "rfsitl/registry/mac_registry.hpp"

namespace rfsitl::mac {
namespace {

constexpr std::size_t kTick = 100;

using FakeQueue = testing::FakeFrameQueue;

/// 1 Msps, 100-sample ticks, a frame of b radio bytes lasts 200 + 10 b samples.
std::unique_ptr<Mac> tdma(std::size_t index, double slot_ms, double guard_us, MacCounters& counters,
                          std::size_t nodes = 3) {
  config::Settings s = find_mac("tdma")->info.defaults();
  s.set("slot_ms", slot_ms);
  s.set("guard_us", guard_us);
  MacContext c;
  c.id = static_cast<NodeId>(index + 1);
  c.index = index;
  c.num_nodes = nodes;
  c.sample_rate_hz = 1e6;
  c.tick_samples = kTick;
  c.radio_max_payload = 2048;
  c.frame_samples = [](std::size_t bytes) { return 200 + 10 * bytes; };
  c.counters = &counters;
  return find_mac("tdma")->make(s, c);
}

TEST(TdmaMac, SendsOnlyInItsOwnSlotAndOnlyWhatEndsBeforeTheGuard) {
  MacCounters counters;
  // Slots of 1 ms = 1000 samples; node index 1 owns [1000, 2000) of every
  // 3000; a 50-byte payload (51 radio bytes) lasts 710 samples and must end
  // by 1900, so it may start at 1000 or 1100 but not at 1200.
  auto mac = tdma(1, 1.0, 100.0, counters);
  FakeQueue q;
  std::vector<SampleTime> starts;
  SampleTime tx_end = 0;
  for (SampleTime now = 0; now < 30000; now += kTick) {
    if (q.frames.empty() && now % 3000 == 0) {
      for (int i = 0; i < 3; ++i) q.frames.push_back(NetFrame{2, 1, std::vector<std::uint8_t>(50)});
    }
    if (auto send = mac->on_tick(now, now < tx_end, q)) {
      tx_end = now + 710;
      starts.push_back(now);
    }
  }
  ASSERT_FALSE(starts.empty());
  for (const SampleTime t : starts) {
    EXPECT_EQ(t % 3000, 1000) << "a start at " << t;  // one frame per slot fits
  }
  EXPECT_EQ(starts.size(), 10U);             // one per TDMA frame
  EXPECT_EQ(mac->max_radio_payload(), 70U);  // 200 + 10 * 70 = 900 = the slot less its guard
  EXPECT_FALSE(mac->carrier_sense_db());
}

TEST(TdmaMac, SlotsDefaultToOnePerNodeInTheScenariosOrder) {
  MacCounters counters;
  std::vector<std::unique_ptr<Mac>> macs;
  for (std::size_t i = 0; i < 4; ++i) macs.push_back(tdma(i, 1.0, 0.0, counters, 4));
  for (std::size_t i = 0; i < 4; ++i) {
    FakeQueue q;
    q.frames.push_back(NetFrame{static_cast<NodeId>(i + 1), kBroadcastId, {1}});
    SampleTime first = -1;
    for (SampleTime now = 0; now < 8000 && first < 0; now += kTick) {
      if (macs[i]->on_tick(now, false, q)) first = now;
    }
    EXPECT_EQ(first, static_cast<SampleTime>(1000 * i));
  }
}

TEST(TdmaMac, ASlotThatHoldsNoFrameIsRefused) {
  MacCounters counters;
  // An empty frame lasts 200 samples; a 0.2 ms slot less a 50 us guard holds 150.
  try {
    tdma(0, 0.2, 50.0, counters);
    FAIL() << "expected a refusal";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("mac.slot_ms"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rfsitl::mac
