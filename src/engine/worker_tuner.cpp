#include "worker_tuner.hpp"

#include <algorithm>
#include <chrono>
#include <utility>

namespace rfsitl::engine {
namespace {

std::int64_t steady_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

/// The arm of probe epoch `step`: one, all, all, one, one, all, all, one.
bool pool_arm(std::size_t step) {
  const std::size_t k = step % 4;
  return k == 1 || k == 2;
}

}  // namespace

WorkerTuner::WorkerTuner(std::size_t pool, bool fixed, Clock clock)
    : pool_(std::max<std::size_t>(1, pool)),
      tuned_(!fixed && pool_ > 1),
      clock_(clock ? std::move(clock) : Clock(steady_ns)),
      current_(pool_) {
  if (tuned_) start_probe(clock_());
}

void WorkerTuner::start_probe(std::int64_t now) {
  step_ = 0;
  probe_ns_[0] = probe_ns_[1] = 0.0;
  probe_work_[0] = probe_work_[1] = 0.0;
  current_ = pool_arm(0) ? pool_ : 1;
  epoch_work_ = 0.0;
  epoch_start_ns_ = now;
  epoch_idle_ns_ = 0;
}

void WorkerTuner::tick_done(double work) {
  if (!tuned_) return;
  epoch_work_ += work;
  if (++ticks_ < kClockTicks) return;
  ticks_ = 0;
  const std::int64_t now = clock_();
  if (now - epoch_start_ns_ >= kEpochNs) end_epoch(now);
}

void WorkerTuner::end_epoch(std::int64_t now) {
  if (!probing()) {
    epoch_start_ns_ = now;
    epoch_idle_ns_ = 0;
    if (--epochs_left_ == 0) start_probe(now);
    return;
  }
  const std::size_t arm = current_ == 1 ? 0 : 1;
  probe_ns_[arm] +=
      static_cast<double>(std::max<std::int64_t>(0, now - epoch_start_ns_ - epoch_idle_ns_));
  probe_work_[arm] += epoch_work_;
  epoch_work_ = 0.0;
  epoch_start_ns_ = now;
  epoch_idle_ns_ = 0;
  ++step_;
  if (step_ == kProbeEpochs / 2 && clear_cut()) step_ = kProbeEpochs;
  if (probing()) {
    current_ = pool_arm(step_) ? pool_ : 1;
    return;
  }
  decide();
}

bool WorkerTuner::clear_cut() const {
  const double ratio = cost(1) / cost(0);
  return ratio < 1.0 - kClearCut || ratio > 1.0 + kClearCut;
}

double WorkerTuner::cost(std::size_t arm) const {
  return probe_ns_[arm] / std::max(probe_work_[arm], 1e-9);
}

void WorkerTuner::decide() {
  // The pool must win by kMinGain.
  const std::size_t chosen = cost(1) < cost(0) * (1.0 - kMinGain) ? pool_ : 1;
  exploit_epochs_ = chosen == last_choice_ ? std::min(2 * exploit_epochs_, kMaxExploitEpochs)
                                           : kFirstExploitEpochs;
  last_choice_ = chosen;
  current_ = chosen;
  epochs_left_ = exploit_epochs_;
}

}  // namespace rfsitl::engine
