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

}  // namespace

WorkerTuner::WorkerTuner(std::size_t pool, bool fixed, Clock clock)
    : pool_(std::max<std::size_t>(1, pool)),
      tuned_(!fixed && pool_ > 1),
      clock_(clock ? std::move(clock) : Clock(steady_ns)),
      current_(pool_) {
  if (tuned_) start_probe();
}

void WorkerTuner::start_probe() {
  step_ = 0;
  probe_ns_[0] = probe_ns_[1] = 0.0;
  probe_work_[0] = probe_work_[1] = 0.0;
  current_ = 1;
  ticks_ = 0;
  epoch_work_ = 0.0;
  epoch_start_ns_ = clock_();
}

void WorkerTuner::tick_done(double work) {
  if (!tuned_) return;
  epoch_work_ += work;
  if (++ticks_ < kEpochTicks) return;
  ticks_ = 0;
  end_epoch();
}

void WorkerTuner::end_epoch() {
  if (!probing()) {
    if (--epochs_left_ == 0) start_probe();
    return;
  }
  const std::int64_t now = clock_();
  const std::size_t arm = current_ == 1 ? 0 : 1;
  probe_ns_[arm] += static_cast<double>(now - epoch_start_ns_);
  probe_work_[arm] += epoch_work_;
  epoch_work_ = 0.0;
  epoch_start_ns_ = now;
  ++step_;
  if (probing()) {
    current_ = step_ == 1 || step_ == 2 ? pool_ : 1;
    return;
  }
  // Cost per unit of work of each arm; the pool must win by kMinGain.
  const double one = probe_ns_[0] / std::max(probe_work_[0], 1e-9);
  const double all = probe_ns_[1] / std::max(probe_work_[1], 1e-9);
  const std::size_t chosen = all < one * (1.0 - kMinGain) ? pool_ : 1;
  exploit_epochs_ = chosen == last_choice_ ? std::min(2 * exploit_epochs_, kMaxExploitEpochs)
                                           : kFirstExploitEpochs;
  last_choice_ = chosen;
  current_ = chosen;
  epochs_left_ = exploit_epochs_;
}

}  // namespace rfsitl::engine
