#pragma once
/// What the dashboard shows that the engine does not keep itself: outcomes per
/// link, the spectrum of the nodes someone is watching, and the constellation
/// of each node's last decoded frame. An engine observer; every method is
/// thread-safe.
#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "rfsitl/engine/engine_observer.hpp"
#include "rfsitl/monitor/spectrum.hpp"

namespace rfsitl::monitor {

struct Constellation {
  SampleTime time = 0;  ///< tick of the decode
  NodeId src = 0;
  NodeId dst = 0;
  std::uint32_t serial = 0;
  bool payload_valid = false;
  std::vector<cf32> points;  ///< at most kMaxConstellationPoints, evenly picked
};

class LiveView final : public engine::EngineObserver {
 public:
  static constexpr std::size_t kSpectrumBins = 256;
  static constexpr std::size_t kMaxConstellationPoints = 512;
  static constexpr std::size_t kSpectrumTickPeriod = 16;
  static constexpr std::size_t kSpectrumTicksTaken = 4;

  explicit LiveView(std::vector<NodeId> ids);

  void on_frame_event(const engine::FrameEvent& e) override;
  void on_rx_samples(std::size_t node, SampleTime time, std::span<const cf32> samples) override;
  /// A watched node's samples in 4 consecutive ticks of every 16: plenty for a
  /// spectrum four times a second, a quarter of the cost of every tick.
  bool wants_samples(std::size_t node, SampleTime tick_start,
                     std::size_t tick_samples) const override;
  void on_decode(std::size_t node, SampleTime time, const phy::RxEvent& ev) override;

  /// A viewer starts (+1) or stops (-1) watching node `node`'s spectrum.
  void watch(std::size_t node, int delta);

  /// Frames decoded (received) and lost, per link, row-major [tx * N + rx].
  struct LinkOutcomes {
    std::vector<std::uint32_t> received;
    std::vector<std::uint32_t> lost;
  };
  LinkOutcomes link_outcomes() const;

  /// Moves the averages of every watched node into their published spectra
  /// (call periodically, e.g. per dashboard push); spectrum() reads them.
  void publish_spectra();
  /// dB per bin, DC in the middle; empty if nothing was published.
  std::vector<float> spectrum(std::size_t node) const;

  std::optional<Constellation> constellation(std::size_t node) const;

  /// Distributed runs (EngineObserver::share): the live views of every rank
  /// swap what they saw, so that rank 0's dashboard shows every rank's nodes:
  /// link outcomes (each cell is counted on one rank only: the receiver's for
  /// decodes, the sender's for losses; the cells that changed, and every tenth
  /// share all of them) and, for a node watched on another rank, its new
  /// constellations and its spectrum (the watching rank's share names the
  /// node; the owner's receiver then keeps its samples).
  std::string_view share_key() const override { return "live_view"; }
  std::vector<std::uint8_t> share() override;
  void take_share(std::size_t rank, std::span<const std::uint8_t> bytes) override;
  /// Shares from other ranks that were dropped as malformed.
  std::uint64_t bad_shares() const { return bad_shares_.load(); }

 private:
  std::optional<std::size_t> index_of(NodeId id) const;

  std::vector<NodeId> ids_;
  std::size_t n_;
  mutable std::mutex links_mutex_;
  LinkOutcomes links_;
  std::unique_ptr<std::atomic<int>[]> watchers_;
  mutable std::mutex spectra_mutex_;
  std::vector<std::unique_ptr<SpectrumAverager>> averagers_;
  std::vector<std::vector<float>> published_;
  std::vector<SampleTime> next_time_;  // where each node's samples continue
  mutable std::mutex constellation_mutex_;
  std::vector<std::optional<Constellation>> constellations_;
  std::vector<SampleTime> shared_until_;  // the newest constellation shared, per node
  LinkOutcomes shared_links_;             // links_ as last shared (under links_mutex_)
  std::uint64_t shares_ = 0;              // share() calls
  // What other ranks shared (engine thread writes; the link sums are read by
  // the dashboard's thread under links_mutex_).
  std::vector<LinkOutcomes> remote_links_;                  // by rank
  std::vector<std::vector<std::uint32_t>> remote_watched_;  // by rank
  std::unique_ptr<std::atomic<int>[]> remote_watchers_;     // ranks watching each node
  std::atomic<std::uint64_t> bad_shares_{0};
};

}  // namespace rfsitl::monitor
