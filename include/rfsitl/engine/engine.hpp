#pragma once
/// The lock-step emulator: every tick each transceiver produces B samples, the
/// channel mixes them into every receiver's input, and every receiver consumes
/// them. Transceivers of different nodes run in parallel on worker threads.
#include <atomic>
#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rfsitl/cluster/peers.hpp"
#include "rfsitl/common/net_frame.hpp"
#include "rfsitl/common/position.hpp"
#include "rfsitl/engine/engine_observer.hpp"
#include "rfsitl/engine/node_counters.hpp"
#include "rfsitl/phy/transceiver.hpp"
#include "rfsitl/position/source/position_source.hpp"
#include "rfsitl/scenario/scenario.hpp"

namespace rfsitl::engine {

/// Where decoded frames go (the net ports). Called on the engine thread, in node
/// order; an implementation must return quickly (hand off, never block).
class FrameSink {
 public:
  virtual ~FrameSink() = default;
  virtual void deliver(std::size_t node, NetFrame&& frame) = 0;
};

/// Progress of the run, readable from any thread.
struct EngineStatus {
  SampleTime virtual_samples = 0;  ///< samples emulated per node so far
  double virtual_s = 0.0;
  double wall_s = 0.0;
  double lag_s = 0.0;                    ///< real time: how late the latest tick started
  double max_lag_s = 0.0;                ///< real time: worst lag so far
  std::uint64_t late_ticks = 0;          ///< real time: ticks started more than a tick late
  std::uint64_t late_decodes = 0;        ///< decodes after their verdict was due (not delivered)
  std::uint64_t receiver_ticks_run = 0;  ///< receiver-ticks processed
  std::uint64_t receiver_ticks_skipped = 0;  ///< receiver-ticks skipped as silent
  std::uint64_t receiver_ticks_blanked = 0;  ///< receiver-ticks wholly blanked by own TX
  double mobility_wall_s = 0.0;              ///< wall seconds spent evaluating mobility models
  std::uint64_t exchanged_bytes = 0;  ///< distributed run: bytes this rank sent to the others
  double exchange_wall_s = 0.0;       ///< distributed run: wall seconds in the exchanges
  /// Threads the parallel phases use now: chosen while running from what they
  /// cost on this machine (1 or all of the pool's), or the --threads given.
  std::size_t workers = 1;
};

/// A rank of a distributed run, as its figures were last gathered.
struct RankStatus {
  double max_lag_s = 0.0;
  std::uint64_t late_ticks = 0;
  std::uint64_t exchanged_bytes = 0;
  double exchange_wall_s = 0.0;
  double wall_s = 0.0;
};

/// How a distributed run shares its nodes (cluster/node_assignment.hpp). Each
/// rank runs an engine for the whole scenario that transmits and receives
/// only for its own nodes and exchanges the rest with its peers every tick;
/// every rank keeps the whole channel, positions and frame ledger, so that the
/// outcomes are those of one process. The counters of other ranks' nodes are
/// gathered every 0.1 s of virtual time and at the end.
struct Distribution {
  cluster::Peers* peers = nullptr;  ///< nullptr: one process, every node its own
  std::vector<std::size_t> owner;   ///< owner rank of each node, by index
  /// Ranks sharing this host's cores: with engine.threads 0 each rank takes
  /// its share of the cores for its workers, not all of them.
  std::size_t ranks_on_host = 1;
};

/// Also the sink of the live position sources (position_source.hpp): a report
/// moves its node at the next tick, like set_position().
class Engine : public position::PositionSink {
 public:
  virtual ~Engine() = default;

  std::size_t num_nodes() const { return node_ids().size(); }
  /// Node ids in index order.
  virtual const std::vector<NodeId>& node_ids() const = 0;
  virtual std::optional<std::size_t> index_of(NodeId id) const = 0;

  /// Hands a frame from node `node`'s agent (net port or TAP interface) to its
  /// TX queue; false (and counted as queue_dropped) when the queue is full.
  /// Oversized payloads must have been refused by the caller. Thread-safe: the
  /// producers of one node (the net ports' I/O thread, the TAP reader) take
  /// turns on a lock of that node; the engine thread never waits for it.
  virtual bool submit(std::size_t node, NetFrame&& frame) = 0;

  /// Largest payload a frame from node `node` may carry (with IP on, one byte
  /// less than its transceiver's: the frame's kind travels on the air).
  virtual std::size_t max_payload(std::size_t node) const = 0;

  /// Node `node`'s MAC and its times as really used (one line, for the banner).
  virtual std::string mac_description(std::size_t node) const = 0;

  /// Moves node `node` (nullopt: position unknown, no links). Thread-safe; takes
  /// effect at the next tick. Its velocity is then estimated from its successive
  /// positions (position/source/velocity_estimator.hpp) on the engine's clock.
  virtual void set_position(std::size_t node, std::optional<Ecef> position) = 0;

  /// Retunes node `node`'s radio to transmit on tx_hz and receive on rx_hz
  /// (its bandwidth and duplex stay). Thread-safe; takes effect at the next
  /// tick, from which on the channel treats its links by the new offsets
  /// (channel/radio_tuning.hpp), and observers are told (on_retune: the pcap
  /// trace's comment). Precondition: both in (0, 1e11] Hz.
  virtual void retune(std::size_t node, double tx_hz, double rx_hz) = 0;

  /// A live source's report: the position (WGS84 or local, converted with the
  /// scenario's origin) as set_position(); velocity and attitude as motions()
  /// shows them. Thread-safe.
  void report(std::size_t node, const position::StateReport& report) override = 0;

  /// Thread-safe copy of every node's last reported velocity and attitude, by
  /// index (a mobility model's velocity at its latest update).
  virtual std::vector<position::NodeMotion> motions() const = 0;

  /// Adds an observer of frame events and samples (traces, recordings, the
  /// dashboard). Before run() and before anything calls submit() (frames handed
  /// in reach the observers on the caller's thread); the observer must outlive
  /// the engine's run.
  /// Watching a node's samples changes no outcome: in a tick where its receiver
  /// would be skipped (silence), the samples are computed and the receiver does
  /// not run; the noise is counter-based (channel/noise_source.hpp).
  virtual void add_observer(EngineObserver& observer) = 0;

  /// Thread-safe copy of the current positions (nullopt: unknown), by index.
  virtual std::vector<std::optional<Ecef>> positions() const = 0;

  /// Thread-safe copy of the link power gains, row-major [tx * N + rx]: |c_nm|^2,
  /// or with time-varying stages the gains of the moment (fading included, on a
  /// 100 ms grid of virtual time, computed by the caller's thread).
  virtual std::vector<float> link_gains() const = 0;

  /// Runs ticks on the calling thread until `stop` is set or the scenario's
  /// duration has been emulated. Call once, and not with advance().
  virtual void run(const std::atomic<bool>& stop) = 0;

  /// Runs ticks on the calling thread until the virtual time reaches `until`
  /// samples (a whole number of ticks: the first tick boundary at or after
  /// it), the scenario's duration (when it has one), or `stop` is set; then
  /// returns the virtual time reached. Called again, it goes on from there, so
  /// a caller can act between two calls (move nodes, hand in frames, read the
  /// counters) and the outcomes are those of one run() with the same acts at
  /// the same ticks. On return positions() and link_gains() show the
  /// channel as it is now. One process only: throws std::logic_error in a
  /// distributed run (its ticks are collective) and after run().
  virtual SampleTime advance(SampleTime until, const std::atomic<bool>& stop) = 0;

  /// Frames waiting in node `node`'s TX queue (thread-safe, approximate while
  /// the queue changes).
  virtual std::size_t queue_depth(std::size_t node) const = 0;

  /// Thread-safe views of the accounting and progress.
  virtual NodeCounters& counters(std::size_t node) = 0;
  virtual EngineStatus status() const = 0;

  /// Distributed run: whether this rank owns node `node` (its ports, source,
  /// MAC and transceiver run here). Always true in one process.
  virtual bool owns(std::size_t node) const = 0;

  /// Distributed run: every rank's figures as last gathered (empty in one
  /// process). Thread-safe.
  virtual std::vector<RankStatus> ranks() const = 0;
};

/// Builds node `index`'s transceiver from its PHY settings (the split
/// architecture substitutes proxies for transceivers in other processes, which
/// count their stalls in `counters`; the counters outlive the transceiver).
using TransceiverFactory = std::function<std::unique_ptr<phy::Transceiver>(
    std::size_t index, const scenario::PhyChoice& phy, NodeCounters& counters)>;

/// Builds the engine for a validated scenario. Transceivers come from `factory`,
/// or from the PHY registry when it is empty. Throws std::invalid_argument on
/// settings the PHY rejects (and for external nodes without a factory).
/// `distribution`: this process is one rank of a distributed run; run() is
/// then collective (every rank calls it, and every rank stops at the tick
/// where any one of them was told to).
std::unique_ptr<Engine> make_engine(const scenario::Scenario& scenario, FrameSink& sink,
                                    TransceiverFactory factory = {},
                                    Distribution distribution = {});

}  // namespace rfsitl::engine
