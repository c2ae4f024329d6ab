#pragma once
/// Test doubles for the position pipeline: a PositionSource that reports a
/// script of states at given virtual times, and the observer that drives it
/// from the engine's own clock, so an engine test sees exactly when a report
/// arrives and when the engine applies it.
#include <cstddef>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "rfsitl/engine/engine_observer.hpp"
#include "rfsitl/position/source/position_source.hpp"

namespace rfsitl::testing {

class ScriptedPositionSource final : public position::PositionSource {
 public:
  struct Step {
    double t_s;        ///< virtual time it is reported at
    std::size_t node;  ///< node index
    position::StateReport report;
  };

  /// `script` in time order.
  explicit ScriptedPositionSource(std::vector<Step> script) : script_(std::move(script)) {}

  void start(position::PositionSink& sink) override { sink_ = &sink; }
  void stop() override { sink_ = nullptr; }

  /// Reports every step due by `t_s` not reported yet; returns how many.
  std::size_t advance(double t_s) {
    std::size_t n = 0;
    for (; next_ < script_.size() && script_[next_].t_s <= t_s; ++next_, ++n) {
      if (sink_ == nullptr) continue;
      sink_->report(script_[next_].node, script_[next_].report);
      ++updates_[script_[next_].node];
    }
    return n;
  }

  std::optional<position::SourceCounters> counters(std::size_t index) const override {
    position::SourceCounters c;
    const auto it = updates_.find(index);
    c.updates = it == updates_.end() ? 0 : it->second;
    c.connected = sink_ != nullptr;
    return c;
  }
  std::string where(std::size_t) const override { return "script"; }

 private:
  std::vector<Step> script_;
  std::size_t next_ = 0;
  position::PositionSink* sink_ = nullptr;
  std::map<std::size_t, std::uint64_t> updates_;
};

/// Calls `tick(t_s)` once per engine tick, on the engine thread, with the
/// tick's start in virtual seconds (during the tick's receive phase: whatever
/// it reports is applied at the next tick). Wants no samples.
class TickHook final : public engine::EngineObserver {
 public:
  TickHook(double sample_rate_hz, std::function<void(double)> tick)
      : sample_rate_hz_(sample_rate_hz), tick_(std::move(tick)) {}
  void on_frame_event(const engine::FrameEvent&) override {}
  bool wants_samples(std::size_t node, SampleTime tick_start, std::size_t) const override {
    if (node == 0) tick_(static_cast<double>(tick_start) / sample_rate_hz_);
    return false;
  }

 private:
  double sample_rate_hz_;
  std::function<void(double)> tick_;
};

}  // namespace rfsitl::testing
