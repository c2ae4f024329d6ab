#pragma once
/// An EngineObserver test double that records every callback with its
/// arguments and a global sequence number (the order in which the engine made
/// the calls), with helpers to query them.
#include <algorithm>
#include <complex>
#include <cstdint>
#include <iterator>
#include <mutex>
#include <set>
#include <span>
#include <vector>

#include "rfsitl/engine/engine_observer.hpp"

namespace rfsitl::testing {

class SpyObserver final : public engine::EngineObserver {
 public:
  using Kind = engine::FrameEventKind;

  struct Event : engine::FrameEvent {
    std::uint64_t seq = 0;
  };
  struct Samples {
    std::uint64_t seq = 0;
    std::size_t node = 0;
    SampleTime time = 0;
    std::vector<cf32> samples;
    double mean_power() const {
      double p = 0.0;
      for (const cf32 v : samples) p += std::norm(v);
      return samples.empty() ? 0.0 : p / static_cast<double>(samples.size());
    }
  };
  struct Decode {
    std::uint64_t seq = 0;
    std::size_t node = 0;
    SampleTime time = 0;
    phy::FrameTag tag;
    bool header_valid = false;
    bool payload_valid = false;
    std::vector<std::uint8_t> payload;
    std::size_t symbols = 0;
  };

  /// Wants the samples of the nodes in `watched` (every tick), of none by default.
  explicit SpyObserver(std::set<std::size_t> watched = {}) : watched_(std::move(watched)) {}

  // EngineObserver: any thread (the engine's, its workers', the I/O thread).
  void on_frame_event(const engine::FrameEvent& event) override {
    std::lock_guard lock(mutex_);
    events_.push_back(Event{event, next_seq()});
  }
  bool wants_samples(std::size_t node, SampleTime, std::size_t) const override {
    return watched_.contains(node);
  }
  void on_rx_samples(std::size_t node, SampleTime time, std::span<const cf32> samples) override {
    std::lock_guard lock(mutex_);
    samples_.push_back(Samples{next_seq(), node, time, {samples.begin(), samples.end()}});
  }
  void on_decode(std::size_t node, SampleTime time, const phy::RxEvent& ev) override {
    std::lock_guard lock(mutex_);
    decodes_.push_back(Decode{next_seq(),
                              node,
                              time,
                              ev.tag,
                              ev.header_valid,
                              ev.payload_valid,
                              {ev.payload.begin(), ev.payload.end()},
                              ev.symbols.size()});
  }

  // Queries: copies, safe while the engine runs.
  std::vector<Event> events() const {
    std::lock_guard lock(mutex_);
    return events_;
  }
  std::vector<Event> events(Kind kind) const {
    return filter([&](const Event& e) { return e.kind == kind; });
  }
  /// The events of one transmission (serial != 0), in order.
  std::vector<Event> of_serial(std::uint32_t serial) const {
    return filter([&](const Event& e) { return e.serial == serial; });
  }
  /// How many events of `kind` happened at node id `node`.
  std::size_t count(Kind kind, NodeId node) const {
    return filter([&](const Event& e) { return e.kind == kind && e.node == node; }).size();
  }
  std::vector<Samples> samples() const {
    std::lock_guard lock(mutex_);
    return samples_;
  }
  std::vector<Decode> decodes() const {
    std::lock_guard lock(mutex_);
    return decodes_;
  }

 private:
  template <typename Pred>
  std::vector<Event> filter(Pred pred) const {
    std::lock_guard lock(mutex_);
    std::vector<Event> out;
    std::copy_if(events_.begin(), events_.end(), std::back_inserter(out), pred);
    return out;
  }
  std::uint64_t next_seq() { return seq_++; }  // under mutex_

  std::set<std::size_t> watched_;
  mutable std::mutex mutex_;
  std::uint64_t seq_ = 0;
  std::vector<Event> events_;
  std::vector<Samples> samples_;
  std::vector<Decode> decodes_;
};

}  // namespace rfsitl::testing
