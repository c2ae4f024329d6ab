#pragma once
/// What a Python caller reads of a run between two steps: every frame event
/// (received frames with their payloads: what each node decoded) and the
/// received samples of the nodes it taps. An engine observer; the engine
/// calls it on its threads while a step runs, Python reads it between steps.
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <span>
#include <vector>

#include "rfsitl/common/types.hpp"
#include "rfsitl/engine/engine_observer.hpp"
#include "rfsitl/engine/frame_event.hpp"

namespace rfsitl::python {

/// One tapped node's samples: those of the latest step, at most a cap (the
/// latest ones are kept), from virtual sample time `first`.
struct TapBuffer {
  bool on = false;
  SampleTime first = 0;
  std::vector<cf32> samples;
  std::uint64_t cut = 0;  ///< samples of the step left out (over the cap)
};

class RunLog final : public engine::EngineObserver {
 public:
  /// `max_events`: events kept until taken (older ones beyond it are dropped
  /// and counted); `max_tap_samples`: per node and step.
  RunLog(std::size_t nodes, bool record_events, std::size_t max_events,
         std::size_t max_tap_samples);

  /// Between steps. The taps' samples are those of the step after this call.
  void set_tap(std::size_t node, bool on);
  /// Called before every step: empties the taps.
  void begin_step();
  /// The events since the last call, oldest first.
  std::vector<engine::FrameEvent> take_events();
  std::uint64_t events_dropped() const;
  /// Node `node`'s samples of the latest step, at most the cap (the latest
  /// ones), moved out: a second call gives none.
  TapBuffer take_tap(std::size_t node);

  // engine::EngineObserver
  void on_frame_event(const engine::FrameEvent& event) override;
  void on_rx_samples(std::size_t node, SampleTime time, std::span<const cf32> samples) override;
  bool wants_samples(std::size_t node, SampleTime, std::size_t) const override {
    return taps_[node].on;
  }

 private:
  const bool record_events_;
  const std::size_t max_events_;
  const std::size_t max_tap_samples_;
  mutable std::mutex events_mutex_;  // handed-in events may come from the caller's thread
  std::vector<engine::FrameEvent> events_;
  std::uint64_t events_dropped_ = 0;
  std::vector<TapBuffer> taps_;
};

}  // namespace rfsitl::python
