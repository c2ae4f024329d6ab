#pragma once
/// Follows every frame from the moment it goes on the air to its outcome, and
/// names the reason of each loss. The ledger only explains outcomes: whether a
/// frame arrives is decided by the real receiver, never here.
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <unordered_map>
#include <vector>

#include "rfsitl/channel/channel_matrix.hpp"
#include "rfsitl/common/types.hpp"
#include "rfsitl/engine/node_counters.hpp"

namespace rfsitl::engine {

struct LedgerConfig {
  double noise_variance = 0.0;  ///< sigma^2 at every receiver
  /// Sensitivity (dB) of each node's PHY, by node index: a frame is named
  /// below_sensitivity when its SNR is under its transmitter's figure.
  std::vector<double> sensitivity_snr_db;
  SampleTime grace_samples = 0;  ///< receiver latency allowed after a frame ends
  /// By node index: receives while it transmits (no half_duplex losses);
  /// empty or shorter: half duplex.
  std::vector<bool> full_duplex;
};

/// A frame's final outcome, for observers.
struct LedgerOutcome {
  bool delivered = false;
  std::uint32_t serial = 0;
  std::size_t tx = 0;
  NodeId dst = 0;
  std::optional<std::size_t> rx;  ///< lost: the receiver the reason was named at
  std::optional<LossReason> reason;
  SampleTime start = 0;
  SampleTime end = 0;
};

/// Engine-thread only (not thread-safe). Node indices are 0..N-1.
class FrameLedger {
 public:
  /// `index_of_id(id)` maps a node id to its index, or nullopt if no such node.
  FrameLedger(LedgerConfig config, std::span<NodeCounters> counters,
              std::function<std::optional<std::size_t>(NodeId)> index_of_id);

  /// A frame with `serial` from node index `tx` to node id `dst` occupies the air
  /// during [start, end). `frame` != 0: this transmission is an attempt of the
  /// frame whose first attempt had serial `frame` (== serial for the first),
  /// and the frame's outcome waits for on_frame_done(): it is counted once,
  /// delivered if any attempt was decoded by its destination.
  void on_transmit(std::uint32_t serial, std::size_t tx, NodeId dst, SampleTime start,
                   SampleTime end, std::uint32_t frame = 0);

  /// The MAC's verdict on the frame whose first attempt had serial `frame`: no
  /// more attempts will come. Lost (once its attempts are settled, and if
  /// none was decoded) with the last attempt's reason, or kRetryLimit when the
  /// MAC `gave_up`.
  void on_frame_done(std::uint32_t frame, bool gave_up);

  /// Node `tx` put signal on the air during [start, end) that is no frame the
  /// emulator started (an external program's transmission). It is never
  /// counted, but it explains other frames' losses (collision, half-duplex).
  /// Activity adjoining the node's previous activity extends it.
  void on_activity(std::size_t tx, SampleTime start, SampleTime end);

  /// Receiver `rx` decoded the frame `serial` with a valid CRC. Returns true if the
  /// frame is addressed to rx (unicast to it, or broadcast): hand it to its agent.
  bool on_decoded(std::uint32_t serial, std::size_t rx);

  /// Resolves every frame whose receivers' verdict is due by `now` (end + grace),
  /// naming the loss reason from `channel` and the overlap history; forgets
  /// records no longer needed for overlap checks.
  void settle(SampleTime now, const channel::ChannelMatrix& channel);

  /// Called with every final outcome (delivered or lost), when it is decided.
  void set_outcome_callback(std::function<void(const LedgerOutcome&)> callback) {
    on_outcome_ = std::move(callback);
  }

  /// Frames on the air or awaiting a verdict.
  std::size_t in_flight() const;

  /// Valid decodes that came after their frame had been settled as lost.
  std::uint64_t late_decodes() const { return late_decodes_; }

 private:
  struct Record {
    std::uint32_t serial;
    std::size_t tx;
    NodeId dst;
    SampleTime start;
    SampleTime end;
    std::uint32_t decodes = 0;  // receivers addressed by this frame that decoded it
    bool settled = false;
    bool activity = false;    // on_activity(): not a frame, never counted
    std::uint32_t frame = 0;  // an attempt of this MAC frame (its first serial); 0: none
  };

  /// A frame sent in attempts (on_transmit with `frame`), until it is counted.
  struct AttemptedFrame {
    bool delivered = false;
    bool done = false;  // the MAC's verdict came
    bool gave_up = false;
    std::uint32_t unsettled = 0;  // attempts awaiting their verdict
    LossReason last_reason = LossReason::kDecodeFailure;
    std::optional<std::size_t> rx;
    Record last;  // the latest attempt, for the outcome report
  };
  void resolve_if_done(std::uint32_t frame);
  std::unordered_map<std::uint32_t, AttemptedFrame> attempted_;

  LossReason loss_reason(const Record& r, std::size_t rx,
                         const channel::ChannelMatrix& channel) const;
  void settle_record(Record& r, const channel::ChannelMatrix& channel);

  LedgerConfig config_;
  std::span<NodeCounters> counters_;
  std::function<std::optional<std::size_t>(NodeId)> index_of_id_;
  std::vector<Record> records_;  // in start order
  SampleTime longest_frame_ = 0;
  std::uint64_t late_decodes_ = 0;
  std::function<void(const LedgerOutcome&)> on_outcome_;

  void report(const Record& r, bool delivered, std::optional<std::size_t> rx,
              std::optional<LossReason> reason) const;
};

}  // namespace rfsitl::engine
