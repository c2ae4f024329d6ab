#pragma once
/// Builds FrameEvents from what the engine and the ledger know and hands them
/// to the observers. Internal to the engine.
#include <mutex>
#include <unordered_map>
#include <vector>

#include "rfsitl/channel/channel_matrix.hpp"
#include "rfsitl/common/net_frame.hpp"
#include "rfsitl/engine/engine_observer.hpp"
#include "rfsitl/engine/frame_ledger.hpp"
#include "rfsitl/scenario/scenario.hpp"
#include "tick_exchange.hpp"

namespace rfsitl::engine {

/// What a transmission is to the reports: a frame's first (or only) attempt,
/// a repeat of it (its outcome is reported once, under the first attempt's
/// serial), or the MAC's own frame (no outcome).
enum class TxRole : std::uint8_t { kFirst, kRepeat, kControl };

class EventReporter {
 public:
  EventReporter(const scenario::Scenario& s, const channel::ChannelMatrix& channel);

  /// Before the run only.
  void add(EngineObserver& observer) { observers_.push_back(&observer); }
  bool active() const { return !observers_.empty(); }

  // I/O or engine thread.
  void handed_in(std::size_t node, const NetFrame& f, SampleTime t) const;
  void queue_dropped(std::size_t node, const NetFrame& f, SampleTime t) const;

  // Engine thread.
  void transmitted(std::size_t node, std::uint32_t serial, const NetFrame& f, SampleTime start,
                   std::size_t length, TxRole role);
  void received(std::size_t rx, const phy::FrameTag& tag, const NetFrame& frame,
                SampleTime t) const;
  void outcome(const LedgerOutcome& o, SampleTime now);
  bool wants_samples(std::size_t node, SampleTime tick_start, std::size_t tick_samples) const;
  void rx_samples(std::size_t node, SampleTime t, std::span<const cf32> samples) const;

  // Worker threads.
  /// Node `node`'s radio moved to tx_hz/rx_hz from the tick at t.
  void retuned(std::size_t node, SampleTime t, double tx_hz, double rx_hz) const;
  void decoded(std::size_t node, SampleTime t, const phy::RxEvent& ev) const;

  // Engine thread, distributed runs: what the observers share with the other
  // ranks' (EngineObserver::share_key), and what they shared.
  std::vector<ObserverShare> shares() const;
  void take_shares(std::size_t rank, std::span<const ObserverShare> shares) const;

 private:
  FrameEvent make(FrameEventKind kind, std::size_t sender, NodeId src, NodeId dst,
                  SampleTime t) const;
  std::optional<double> snr_db(std::size_t tx, std::optional<std::size_t> rx) const;
  std::optional<std::size_t> receiver_of(std::size_t tx, NodeId dst) const;
  void emit(const FrameEvent& e) const;

  const scenario::Scenario& scenario_;
  const channel::ChannelMatrix& channel_;
  std::vector<EngineObserver*> observers_;
  struct InFlight {
    NodeId src = 0;  // as the agent wrote it
    std::vector<std::uint8_t> payload;
    FrameKind kind = FrameKind::kAgent;
  };
  std::unordered_map<std::uint32_t, InFlight> in_flight_;  // by serial
};

}  // namespace rfsitl::engine
