#include "run_log.hpp"

#include <algorithm>

namespace rfsitl::python {

RunLog::RunLog(std::size_t nodes, bool record_events, std::size_t max_events,
               std::size_t max_tap_samples)
    : record_events_(record_events),
      max_events_(max_events),
      max_tap_samples_(max_tap_samples),
      taps_(nodes) {}

void RunLog::set_tap(std::size_t node, bool on) {
  taps_[node].on = on;
  if (!on) taps_[node] = TapBuffer{};
}

void RunLog::begin_step() {
  for (TapBuffer& t : taps_) {
    t.samples.clear();
    t.first = 0;
    t.cut = 0;
  }
}

std::vector<engine::FrameEvent> RunLog::take_events() {
  std::lock_guard lock(events_mutex_);
  std::vector<engine::FrameEvent> out;
  out.swap(events_);
  return out;
}

std::uint64_t RunLog::events_dropped() const {
  std::lock_guard lock(events_mutex_);
  return events_dropped_;
}

TapBuffer RunLog::take_tap(std::size_t node) {
  TapBuffer& t = taps_[node];
  if (t.samples.size() > max_tap_samples_) {
    const std::size_t cut = t.samples.size() - max_tap_samples_;
    t.samples.erase(t.samples.begin(), t.samples.begin() + static_cast<std::ptrdiff_t>(cut));
    t.first += static_cast<SampleTime>(cut);
    t.cut += cut;
  }
  TapBuffer out;
  out.on = t.on;
  out.first = t.first;
  out.cut = t.cut;
  out.samples.swap(t.samples);
  t.cut = 0;
  return out;
}

void RunLog::on_frame_event(const engine::FrameEvent& event) {
  if (!record_events_) return;
  std::lock_guard lock(events_mutex_);
  if (events_.size() >= max_events_) {
    // The oldest half goes at once (not one by one: that would be quadratic);
    // every one is counted.
    const std::size_t drop = std::max<std::size_t>(1, events_.size() / 2);
    events_.erase(events_.begin(), events_.begin() + static_cast<std::ptrdiff_t>(drop));
    events_dropped_ += drop;
  }
  events_.push_back(event);
}

void RunLog::on_rx_samples(std::size_t node, SampleTime time, std::span<const cf32> samples) {
  TapBuffer& t = taps_[node];
  if (t.samples.empty()) t.first = time;
  t.samples.insert(t.samples.end(), samples.begin(), samples.end());
  if (t.samples.size() > 2 * max_tap_samples_) {
    // Keep the latest max_tap_samples_ (amortized: at most every cap samples).
    const std::size_t cut = t.samples.size() - max_tap_samples_;
    t.samples.erase(t.samples.begin(), t.samples.begin() + static_cast<std::ptrdiff_t>(cut));
    t.first += static_cast<SampleTime>(cut);
    t.cut += cut;
  }
}

}  // namespace rfsitl::python
