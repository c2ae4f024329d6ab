#pragma once
/// How many of the pool's workers the engine's parallel phases use, chosen
/// while it runs from what this machine and this scenario cost. Waking a
/// worker and meeting it at the barrier pays only when a phase has enough
/// work, and on a shared or virtual machine (another process, a hypervisor's
/// steal) a second thread can make a tick slower, not faster. So the tuner
/// measures both: the engine thread alone (one) and the whole pool (all), in
/// epochs of kEpochNs of wall time each (long against the scheduler's time
/// slices, which would otherwise decide an epoch alone), in the order one,
/// all, all, one, twice (so that a trend in the load weighs on both alike;
/// once when the first four differ by more than kClearCut), each arm's wall
/// time over the work its ticks had. The pool must be at
/// least kMinGain cheaper to be chosen, since a second busy thread costs the
/// machine even when the engine breaks even. The choice then holds for a
/// stretch of epochs that doubles (up to kMaxExploitEpochs, 10 s) while the
/// same choice keeps winning and starts short again when it changes: the
/// probes cost about one percent of a long run, and a changed load is seen
/// within seconds.
///
/// Only the engine thread calls it. The clock is read every kClockTicks
/// ticks, never per tick.
#include <cstddef>
#include <cstdint>
#include <functional>

namespace rfsitl::engine {

class WorkerTuner {
 public:
  static constexpr std::int64_t kEpochNs = 10'000'000;
  static constexpr std::size_t kClockTicks = 16;
  static constexpr std::size_t kFirstExploitEpochs = 32;
  static constexpr std::size_t kMaxExploitEpochs = 1024;
  static constexpr double kMinGain = 0.05;
  static constexpr double kClearCut = 0.15;

  /// Monotonic time in nanoseconds (tests give a fake one).
  using Clock = std::function<std::int64_t()>;

  /// `pool`: the pool's size; `fixed`: the number is not to be tuned (the
  /// user gave --threads, or remote transceivers need a worker each), so
  /// workers() is always `pool`. A pool of one has nothing to tune either.
  WorkerTuner(std::size_t pool, bool fixed, Clock clock = {});

  /// Workers the next tick's parallel phases use: 1 or the pool's size.
  std::size_t workers() const { return current_; }

  /// True while it measures (the choice may change at every epoch).
  bool probing() const { return step_ < kProbeEpochs; }

  /// After each tick: the work it had, in any unit that grows with what the
  /// parallel phases did (the engine: receivers run and transmitters on air).
  /// Must be > 0 (an idle tick still costs its loop).
  void tick_done(double work);

  /// Time the engine spent waiting rather than working (real time: for the
  /// wall clock to reach the next tick), left out of the epoch's time: in
  /// real time an epoch lasts its wall time whatever the threads do, and only
  /// the rest tells the arms apart.
  void idle(std::int64_t ns) { epoch_idle_ns_ += ns; }

 private:
  static constexpr std::size_t kProbeEpochs = 8;  // one, all, all, one, twice
  void start_probe(std::int64_t now);
  void end_epoch(std::int64_t now);
  void decide();
  /// Cost per unit of work of arm 0 (one) or 1 (all) in this probe so far.
  double cost(std::size_t arm) const;
  bool clear_cut() const;

  std::size_t pool_;
  bool tuned_;
  Clock clock_;
  std::size_t current_;
  std::size_t step_ = kProbeEpochs;  // probe epoch 0..7, or kProbeEpochs while exploiting
  std::size_t ticks_ = 0;            // since the clock was last read
  std::size_t epochs_left_ = 0;      // of the exploit stretch
  std::size_t exploit_epochs_ = kFirstExploitEpochs;
  std::size_t last_choice_ = 0;  // the previous probe's verdict (0: none yet)
  std::int64_t epoch_start_ns_ = 0;
  std::int64_t epoch_idle_ns_ = 0;
  double epoch_work_ = 0.0;
  double probe_ns_[2] = {0.0, 0.0};  // [one, all]
  double probe_work_[2] = {0.0, 0.0};
};

}  // namespace rfsitl::engine
