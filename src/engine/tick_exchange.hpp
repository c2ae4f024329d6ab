#pragma once
// Internal to the engine: what the ranks of a distributed run tell each other
// in a tick, as bytes (cluster::Peers carries them). Ranks run the same build,
// so records are copied as they lie in memory; a reader still checks every
// length, and names the rank whose message is short or inconsistent.
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "rfsitl/common/position.hpp"
#include "rfsitl/common/types.hpp"
#include "rfsitl/engine/node_counters.hpp"
#include "rfsitl/position/source/node_state.hpp"

namespace rfsitl::engine {

/// After the TX phase, for each node of the rank that has anything to say:
/// its MAC's verdict, the frame it started, and its samples on the air.
struct TxReport {
  std::uint32_t node = 0;
  std::uint32_t tx_samples = 0;  ///< leading samples of the tick that carry signal
  bool has_verdict = false;
  bool gave_up = false;
  std::uint32_t verdict_frame = 0;
  bool started = false;  ///< a frame started this tick: the fields below
  bool awaits_verdict = false;
  bool first_attempt = true;
  std::uint8_t kind = 0;  ///< FrameKind
  std::uint32_t serial = 0;
  NodeId dst = 0;
  std::uint32_t started_len = 0;
  std::uint32_t mac_frame = 0;
};

/// A position or motion that a live source (or the dashboard) reported to one
/// rank, for every rank to apply at the same tick.
struct StateUpdate {
  std::uint32_t node = 0;
  bool moves = false;          ///< `position` replaces the node's (nullopt: unknown)
  bool with_velocity = false;  ///< ... and its source reports the velocity itself
  std::optional<Ecef> position;
  position::NodeMotion motion;  ///< the parts set replace the node's
};

/// After the receivers ran: what the ledger must learn, in the order the
/// node's owner learnt it.
struct LedgerOp {
  enum class Kind : std::uint8_t { kDecoded, kFrameDone };
  std::uint32_t node = 0;
  Kind kind = Kind::kDecoded;
  bool gave_up = false;  ///< kFrameDone
  std::uint32_t id = 0;  ///< kDecoded: the frame's serial; kFrameDone: its first serial
  std::size_t delivery = kNoDelivery;  ///< on the owner: its pending delivery (not sent)
  static constexpr std::size_t kNoDelivery = ~std::size_t{0};
};

/// Message A of a tick: whether the rank was told to stop, its nodes' TX
/// reports with their samples, and the state updates it received.
struct TxMessage {
  bool stop = false;
  std::vector<TxReport> reports;
  std::vector<std::span<const cf32>> samples;  ///< per report, tx_samples long
  std::vector<StateUpdate> updates;
};

void write_tx_message(const TxMessage& m, std::vector<std::uint8_t>& out);

/// Reads rank `rank`'s message A; report k's samples are copied into
/// `samples_out(k)` (tx_samples of them). Throws std::runtime_error naming the
/// rank when the bytes are short, or a node index is >= `nodes`, or a report
/// carries more than `tick_samples` samples.
struct TxMessageView {
  bool stop = false;
  std::vector<TxReport> reports;
  std::vector<std::size_t> sample_offsets;  ///< byte offset of report k's samples
  std::vector<StateUpdate> updates;
};
TxMessageView read_tx_message(std::span<const std::uint8_t> bytes, std::size_t rank,
                              std::size_t nodes, std::size_t tick_samples);
/// The same into `out`, whose vectors keep their capacity (once per rank and tick).
void read_tx_message(std::span<const std::uint8_t> bytes, std::size_t rank, std::size_t nodes,
                     std::size_t tick_samples, TxMessageView& out);

void write_ledger_ops(std::span<const LedgerOp> ops, std::vector<std::uint8_t>& out);
/// Appends rank `rank`'s ops to `out` (delivery = kNoDelivery). Throws like
/// read_tx_message.
void read_ledger_ops(std::span<const std::uint8_t> bytes, std::size_t rank, std::size_t nodes,
                     std::vector<LedgerOp>& out);

/// A rank's figures, gathered with the counters.
struct RankFigures {
  double max_lag_s = 0.0;
  std::uint64_t late_ticks = 0;
  std::uint64_t exchanged_bytes = 0;  ///< sent by this rank
  double exchange_wall_s = 0.0;       ///< wall time spent in the exchanges
  double wall_s = 0.0;
};

/// What one of a rank's observers shares (EngineObserver::share), by its key.
struct ObserverShare {
  std::string key;
  std::vector<std::uint8_t> bytes;
};

/// The counters of a rank's own nodes, its figures and its observers' shares.
void write_counters(const RankFigures& figures,
                    std::span<const std::pair<std::uint32_t, NodeCountersSnapshot>> nodes,
                    std::span<const ObserverShare> shares, std::vector<std::uint8_t>& out);
/// Appends the nodes' counters to `out` and the shares to `shares`.
void read_counters(std::span<const std::uint8_t> bytes, std::size_t rank, std::size_t nodes,
                   RankFigures& figures,
                   std::vector<std::pair<std::uint32_t, NodeCountersSnapshot>>& out,
                   std::vector<ObserverShare>& shares);

}  // namespace rfsitl::engine
