// The worker tuner on a fake clock: what each tick costs is the test's cost
// model, so the choice it should make is known. It picks the cheaper of one
// thread and the pool, needs the pool to win by kMinGain, sees a change of
// load at its next probe, and never tunes a fixed number or a pool of one.
#include "worker_tuner.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <functional>

namespace rfsitl::engine {
namespace {

/// Runs `ticks` ticks of work 1 each, the fake clock advancing by what the
/// tick costs with the tuner's current choice; returns the ticks spent on the
/// pool.
struct FakeMachine {
  std::int64_t now_ns = 0;
  std::function<std::int64_t(std::size_t workers)> tick_ns;

  std::size_t run(WorkerTuner& t, std::size_t ticks) {
    std::size_t on_pool = 0;
    for (std::size_t i = 0; i < ticks; ++i) {
      now_ns += tick_ns(t.workers());
      on_pool += t.workers() > 1 ? 1 : 0;
      t.tick_done(1.0);
    }
    return on_pool;
  }
};

WorkerTuner tuner_on(FakeMachine& m, std::size_t pool = 2, bool fixed = false) {
  return WorkerTuner(pool, fixed, [&m] { return m.now_ns; });
}

/// Ticks of 1 us enough for many probes: 200 epochs.
constexpr std::size_t kLong = 200 * WorkerTuner::kEpochNs / 1000;

TEST(WorkerTuner, ChoosesThePoolWhereItIsFaster) {
  FakeMachine m{0, [](std::size_t w) { return w > 1 ? 600 : 1000; }};
  WorkerTuner t = tuner_on(m);
  m.run(t, kLong);
  EXPECT_EQ(t.workers(), 2U);
  EXPECT_FALSE(t.probing());
}

TEST(WorkerTuner, ChoosesOneThreadWhereThePoolIsSlowerOrBarelyFaster) {
  for (const std::int64_t pool_ns : {2000, 980}) {  // twice as slow; 2 % faster only
    FakeMachine m{0, [pool_ns](std::size_t w) { return w > 1 ? pool_ns : 1000; }};
    WorkerTuner t = tuner_on(m);
    m.run(t, kLong);
    EXPECT_EQ(t.workers(), 1U) << pool_ns;
    // What the probes cost: the run against the same ticks on one thread.
    const double lost = static_cast<double>(m.now_ns) / (1000.0 * kLong) - 1.0;
    EXPECT_LT(lost, 0.05) << pool_ns;
  }
}

TEST(WorkerTuner, FollowsAChangeOfLoadAtItsNextProbe) {
  bool crowded = false;  // another process takes the second core
  FakeMachine m{0, [&crowded](std::size_t w) { return w > 1 ? (crowded ? 2500 : 600) : 1000; }};
  WorkerTuner t = tuner_on(m);
  m.run(t, kLong);
  ASSERT_EQ(t.workers(), 2U);
  crowded = true;
  // The exploit stretch is at most kMaxExploitEpochs, then a probe of eight
  // (ticks of at least 1 us: the count is enough time).
  m.run(t, (WorkerTuner::kMaxExploitEpochs + 10) * WorkerTuner::kEpochNs / 1000);
  EXPECT_EQ(t.workers(), 1U);
}

TEST(WorkerTuner, NormalizesByTheWorkEachEpochHad) {
  // The pool is faster per unit of work, but the one-thread epochs happen to
  // be quiet: raw times would favour one thread.
  FakeMachine m;
  WorkerTuner t = tuner_on(m);
  for (std::size_t i = 0; i < kLong; ++i) {
    const double work = t.workers() > 1 ? 10.0 : 1.0;
    m.now_ns += static_cast<std::int64_t>(work * (t.workers() > 1 ? 600.0 : 1000.0));
    t.tick_done(work);
  }
  EXPECT_EQ(t.workers(), 2U);
}

TEST(WorkerTuner, InRealTimeLeavesTheWaitsForTheClockOut) {
  // Every tick lasts 250 us of wall time (the clock paces it); the pool
  // computes it in 60 us, one thread in 100 us. Told of the waits, the tuner
  // sees the pool's gain; its epochs' wall times alone are all alike.
  FakeMachine m;
  WorkerTuner t = tuner_on(m);
  for (std::size_t i = 0; i < 4000; ++i) {  // a second of ticks
    const std::int64_t busy = t.workers() > 1 ? 60'000 : 100'000;
    m.now_ns += 250'000;
    t.idle(250'000 - busy);
    t.tick_done(1.0);
  }
  EXPECT_EQ(t.workers(), 2U);
}

TEST(WorkerTuner, NeverTunesAFixedNumberOrAPoolOfOne) {
  FakeMachine m{0, [](std::size_t w) { return w > 1 ? 5000 : 1000; }};
  WorkerTuner fixed = tuner_on(m, 2, true);
  m.run(fixed, kLong);
  EXPECT_EQ(fixed.workers(), 2U);
  EXPECT_FALSE(fixed.probing());
  WorkerTuner single = tuner_on(m, 1, false);
  m.run(single, kLong);
  EXPECT_EQ(single.workers(), 1U);
}

}  // namespace
}  // namespace rfsitl::engine
