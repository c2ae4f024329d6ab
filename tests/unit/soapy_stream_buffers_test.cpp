// The SoapySDR module's buffers between the application and the emulator's
// ticks (stream_buffers.hpp), fed tick by tick without an emulator: RX
// timestamps and overflow, TX timed and untimed placement, late bursts,
// underflows, timeouts, closing and reopening after a restart.
#include <SoapySDR/Errors.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <thread>
#include <vector>

#include "stream_buffers.hpp"

namespace rfsitl::soapy {
namespace {

constexpr std::size_t kTick = 100;
constexpr double kFs = 1e6;

/// The emulator's side: ticks at 0, kTick, 2 kTick, ... with RX samples
/// numbered by their time, so that a read shows which samples it got.
struct FakeEmulator {
  explicit FakeEmulator(StreamBuffers& b) : buffers(b) {}
  /// One tick; returns what the node transmitted in it.
  std::vector<cf32> tick() {
    std::vector<cf32> rx(kTick), tx(kTick);
    for (std::size_t i = 0; i < kTick; ++i) {
      rx[i] = {static_cast<float>(t - static_cast<SampleTime>(kTick) + static_cast<SampleTime>(i)),
               0.0F};
    }
    buffers.on_tick(t, rx, tx);
    t += static_cast<SampleTime>(kTick);
    return tx;
  }
  StreamBuffers& buffers;
  SampleTime t = 0;
};

TEST(SoapyStreamBuffers, RxChunksCarryTheirVirtualTime) {
  StreamBuffers b(kFs, 10 * kTick, 10 * kTick);
  FakeEmulator emu(b);
  emu.tick();  // before activation: not kept
  b.set_rx_active(true);
  emu.tick();  // t = 100: samples [0, 100)
  emu.tick();  // t = 200: samples [100, 200)
  std::vector<cf32> out(60);
  SampleTime t = -1;
  ASSERT_EQ(b.read(out, t, 0), 60);
  EXPECT_EQ(t, 0);
  EXPECT_EQ(out[59].real(), 59.0F);
  ASSERT_EQ(b.read(out, t, 0), 40);  // the rest of the chunk: reads never span chunks
  EXPECT_EQ(t, 60);
  ASSERT_EQ(b.read(out, t, 0), 60);
  EXPECT_EQ(t, 100);
  EXPECT_EQ(out[0].real(), 100.0F);
}

TEST(SoapyStreamBuffers, SlowReaderLosesTheOldestAndSeesOneOverflow) {
  StreamBuffers b(kFs, 3 * kTick, 10 * kTick);
  FakeEmulator emu(b);
  b.set_rx_active(true);
  for (int i = 0; i < 6; ++i) emu.tick();  // 6 chunks into room for 3
  EXPECT_EQ(b.overflows(), 1U);            // one episode, however many chunks went
  std::vector<cf32> out(kTick);
  SampleTime t = 0;
  EXPECT_EQ(b.read(out, t, 0), SOAPY_SDR_OVERFLOW);
  ASSERT_EQ(b.read(out, t, 0), static_cast<int>(kTick));
  EXPECT_EQ(t, 200);  // the newest three remain: [200, 500)
  EXPECT_EQ(out[0].real(), 200.0F);
}

TEST(SoapyStreamBuffers, ReadTimesOutInTimeAndFailsOnceClosed) {
  StreamBuffers b(kFs, 10 * kTick, 10 * kTick);
  b.set_rx_active(true);
  std::vector<cf32> out(kTick);
  SampleTime t = 0;
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(b.read(out, t, 20'000), SOAPY_SDR_TIMEOUT);
  EXPECT_GE(std::chrono::steady_clock::now() - start, std::chrono::milliseconds(19));
  // A reader waiting without end returns when the emulator goes.
  std::thread closer([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    b.close();
  });
  EXPECT_EQ(b.read(out, t, 60'000'000), SOAPY_SDR_STREAM_ERROR);
  closer.join();
  // Repeated, the error waits its timeout, so that a caller retrying in a
  // loop does not spin.
  const auto again = std::chrono::steady_clock::now();
  EXPECT_EQ(b.read(out, t, 20'000), SOAPY_SDR_STREAM_ERROR);
  EXPECT_GE(std::chrono::steady_clock::now() - again, std::chrono::milliseconds(19));
  EXPECT_FALSE(b.connected());
  const std::vector<cf32> burst(10, cf32{1.0F, 0.0F});
  EXPECT_EQ(b.write(burst, nullptr, true, 0), SOAPY_SDR_STREAM_ERROR);
  TxEvent e;
  EXPECT_EQ(b.read_event(e, 0), SOAPY_SDR_STREAM_ERROR);
}

TEST(SoapyStreamBuffers, TimeWaitsForTheFirstTickInsteadOfReadingZero) {
  StreamBuffers b(kFs, 10 * kTick, 10 * kTick);
  FakeEmulator emu(b);
  emu.t = 30'280'000;  // an emulator that has run for a while before the device joined
  SampleTime t = -1;
  const auto start = std::chrono::steady_clock::now();
  EXPECT_FALSE(b.now_after_first_tick(t, 20'000)) << "no tick yet: no time";
  EXPECT_GE(std::chrono::steady_clock::now() - start, std::chrono::milliseconds(19));
  EXPECT_EQ(t, -1);
  // A reader waiting without end gets the first tick's time, not 0.
  const SampleTime first = emu.t;
  std::thread ticker([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    emu.tick();
  });
  const bool got = b.now_after_first_tick(t, 60'000'000);
  ticker.join();
  ASSERT_TRUE(got);
  EXPECT_EQ(t, first);
  emu.tick();
  ASSERT_TRUE(b.now_after_first_tick(t, 0)) << "after the first tick: at once";
  EXPECT_EQ(t, emu.t - static_cast<SampleTime>(kTick));
  EXPECT_EQ(t, b.now());
}

TEST(SoapyStreamBuffers, TimeWaitEndsWhenTheEmulatorGoesBeforeItsFirstTick) {
  StreamBuffers b(kFs, 10 * kTick, 10 * kTick);
  std::thread closer([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    b.close();
  });
  SampleTime t = -1;
  const bool got = b.now_after_first_tick(t, 60'000'000);
  closer.join();
  EXPECT_FALSE(got);
  EXPECT_EQ(t, -1);
  b.reopen(4000);  // a new emulator's first tick: its time is known
  ASSERT_TRUE(b.now_after_first_tick(t, 0));
  EXPECT_EQ(t, 4000);
}

TEST(SoapyStreamBuffers, ReopenedAfterARestartTheBuffersFollowTheNewVirtualTime) {
  StreamBuffers b(kFs, 3 * kTick, 10 * kTick);
  FakeEmulator old_emu(b);
  b.set_rx_active(true);
  for (int i = 0; i < 40; ++i) old_emu.tick();  // far ahead in virtual time, overflowing
  const SampleTime old_time = 40 * static_cast<SampleTime>(kTick);
  const std::vector<cf32> burst(10, cf32{1.0F, 0.0F});
  const SampleTime later = old_time + 5 * static_cast<SampleTime>(kTick);
  ASSERT_EQ(b.write(burst, &later, true, 0), 10);  // for the old emulator's time
  b.close();
  std::vector<cf32> out(kTick);
  SampleTime t = 0;
  EXPECT_EQ(b.read(out, t, 0), SOAPY_SDR_OVERFLOW);  // still said, before the error
  ASSERT_EQ(b.read(out, t, 0), static_cast<int>(kTick));

  b.reopen(0);  // a new emulator, from virtual time 0
  EXPECT_TRUE(b.connected());
  EXPECT_EQ(b.now(), 0);
  EXPECT_EQ(b.read(out, t, 0), SOAPY_SDR_TIMEOUT) << "nothing of the old emulator is left";
  FakeEmulator new_emu(b);
  std::vector<cf32> sent;
  for (int i = 0; i < 8; ++i) {
    const std::vector<cf32> tx = new_emu.tick();
    sent.insert(sent.end(), tx.begin(), tx.end());
  }
  EXPECT_TRUE(std::all_of(sent.begin(), sent.end(), [](cf32 v) { return v == cf32{}; }))
      << "the old emulator's burst must not go out";
  ASSERT_EQ(b.read(out, t, 0), SOAPY_SDR_OVERFLOW);  // 8 new ticks into room for 3
  ASSERT_EQ(b.read(out, t, 0), static_cast<int>(kTick));
  EXPECT_EQ(t, 400);  // the new emulator's times
  EXPECT_EQ(out[0].real(), 400.0F);
  EXPECT_EQ(b.overflows(), 2U) << "the counters span connections";
  const SampleTime soon = new_emu.t;
  ASSERT_EQ(b.write(burst, &soon, true, 0), 10);
  EXPECT_EQ(new_emu.tick()[0], (cf32{1.0F, 0.0F}));
}

TEST(SoapyStreamBuffers, TimedBurstGoesOutAtItsTimeAcrossTicks) {
  StreamBuffers b(kFs, 10 * kTick, 10 * kTick);
  FakeEmulator emu(b);
  emu.tick();  // answered [0, 100)
  const SampleTime at = 250;
  const std::vector<cf32> burst(120, cf32{0.5F, 0.0F});
  ASSERT_EQ(b.write(burst, &at, true, 0), 120);
  EXPECT_EQ(emu.tick()[99], cf32{});  // [100, 200): silent
  const auto a = emu.tick();          // [200, 300): from 250 on
  EXPECT_EQ(a[49], cf32{});
  EXPECT_EQ(a[50], cf32(0.5F, 0.0F));
  const auto c = emu.tick();  // [300, 400): the last 70 samples, then silence
  EXPECT_EQ(c[69], cf32(0.5F, 0.0F));
  EXPECT_EQ(c[70], cf32{});
  TxEvent e;
  EXPECT_EQ(b.read_event(e, 0), SOAPY_SDR_TIMEOUT);  // ended with END_BURST: no underflow
}

TEST(SoapyStreamBuffers, LateBurstIsDroppedAndReported) {
  StreamBuffers b(kFs, 10 * kTick, 10 * kTick);
  FakeEmulator emu(b);
  emu.tick();
  emu.tick();  // answered up to 200
  const SampleTime at = 150;
  const std::vector<cf32> burst(30, cf32{1.0F, 0.0F});
  EXPECT_EQ(b.write(burst, &at, true, 0), 30);  // taken, not sent
  TxEvent e;
  ASSERT_EQ(b.read_event(e, 0), 0);
  EXPECT_EQ(e.code, SOAPY_SDR_TIME_ERROR);
  EXPECT_EQ(e.time, 150);
  EXPECT_EQ(b.late_bursts(), 1U);
  for (const auto& x : emu.tick()) ASSERT_EQ(x, cf32{});
}

TEST(SoapyStreamBuffers, UntimedWritesFollowEachOtherAndAnOpenBurstUnderflows) {
  StreamBuffers b(kFs, 10 * kTick, 10 * kTick);
  FakeEmulator emu(b);
  emu.tick();  // answered [0, 100): untimed samples start at 100
  const std::vector<cf32> one(60, cf32{1.0F, 0.0F}), two(60, cf32{0.0F, 1.0F});
  ASSERT_EQ(b.write(one, nullptr, false, 0), 60);
  ASSERT_EQ(b.write(two, nullptr, false, 0), 60);  // still no END_BURST
  const auto a = emu.tick();                       // [100, 200)
  EXPECT_EQ(a[59], cf32(1.0F, 0.0F));
  EXPECT_EQ(a[60], cf32(0.0F, 1.0F));  // right after, no gap, no overlap
  TxEvent e;
  EXPECT_EQ(b.read_event(e, 0), SOAPY_SDR_TIMEOUT);
  emu.tick();  // [200, 300): the last 20, then the promised rest is missing
  ASSERT_EQ(b.read_event(e, 0), 0);
  EXPECT_EQ(e.code, SOAPY_SDR_UNDERFLOW);
  EXPECT_EQ(e.time, 220);
  EXPECT_EQ(b.underflows(), 1U);
  // The next untimed write starts at the next tick, not back at 220.
  ASSERT_EQ(b.write(one, nullptr, true, 0), 60);
  EXPECT_EQ(emu.tick()[0], cf32(1.0F, 0.0F));
}

TEST(SoapyStreamBuffers, FullTxQueueTimesOutAndTheEventQueueIsBounded) {
  StreamBuffers b(kFs, 10 * kTick, 2 * kTick);
  FakeEmulator emu(b);
  const std::vector<cf32> big(2 * kTick, cf32{1.0F, 0.0F});
  ASSERT_EQ(b.write(big, nullptr, true, 0), static_cast<int>(2 * kTick));
  EXPECT_EQ(b.write(big, nullptr, true, 1000), SOAPY_SDR_TIMEOUT);
  emu.tick();  // one tick's worth leaves the queue: room for a partial write
  EXPECT_EQ(b.write(big, nullptr, true, 0), static_cast<int>(kTick));
  emu.tick();
  emu.tick();  // the queue is empty again
  // An application that never reads the status (GNU Radio's sink) keeps at
  // most 1024 events.
  for (int i = 0; i < 2000; ++i) {
    const SampleTime late = 0;
    b.write(std::span(big).first(1), &late, true, 0);
  }
  int events = 0;
  TxEvent e;
  while (b.read_event(e, 0) == 0) ++events;
  EXPECT_EQ(events, 1024);
  EXPECT_EQ(b.late_bursts(), 2000U);
}

TEST(SoapyStreamBuffers, TuningShiftsAndScalesBothDirections) {
  StreamBuffers b(kFs, 10 * kTick, 10 * kTick);
  FakeEmulator emu(b);
  b.set_tx_tuning({true, 0.0, -20.0});
  b.set_rx_tuning({false, 0.0, 0.0});  // tuned out of band: hears nothing
  b.set_rx_active(true);
  emu.tick();
  const std::vector<cf32> one(kTick, cf32{1.0F, 0.0F});
  ASSERT_EQ(b.write(one, nullptr, true, 0), static_cast<int>(kTick));
  EXPECT_NEAR(emu.tick()[10].real(), 0.1F, 1e-6F);
  std::vector<cf32> out(kTick);
  SampleTime t = 0;
  ASSERT_EQ(b.read(out, t, 0), static_cast<int>(kTick));
  for (const auto& x : out) ASSERT_EQ(x, cf32{});
}

}  // namespace
}  // namespace rfsitl::soapy
