#pragma once
/// The engine behind make_engine(): lock-step ticks of B samples in which
/// every node's MAC and transmitter run (TX phase), the channel mixes what is
/// on the air, and every receiver that can hear more than noise decodes (RX
/// phase). Its definitions are split by phase: lock_step_engine.cpp (set-up,
/// the Engine interface, the tick and its TX phase), receive_phase.cpp (the
/// RX phase and the ledger's books), distributed_tick.cpp (what ranks swap).
#include <algorithm>
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "engine_node.hpp"
#include "event_reporter.hpp"
#include "frame_kind.hpp"
#include "link_snapshots.hpp"
#include "mobility_driver.hpp"
#include "node_state_inbox.hpp"
#include "node_tx_report.hpp"
#include "rank_link.hpp"
#include "rfsitl/channel/channel.hpp"
#include "rfsitl/channel/channel_matrix.hpp"
#include "rfsitl/engine/engine.hpp"
#include "rfsitl/engine/frame_ledger.hpp"
#include "rfsitl/engine/tick_clock.hpp"
#include "rfsitl/engine/traffic_schedule.hpp"
#include "rfsitl/engine/worker_pool.hpp"
#include "worker_tuner.hpp"

namespace rfsitl::engine {

class LockStepEngine final : public Engine {
 public:
  LockStepEngine(const scenario::Scenario& s, FrameSink& sink, const TransceiverFactory& factory,
                 Distribution distribution);

  const std::vector<NodeId>& node_ids() const override { return ids_; }

  std::optional<std::size_t> index_of(NodeId id) const override {
    const auto it = std::find(ids_.begin(), ids_.end(), id);
    if (it == ids_.end()) return std::nullopt;
    return static_cast<std::size_t>(it - ids_.begin());
  }

  std::size_t max_payload(std::size_t node) const override {
    const Node& n = nodes_[node];
    return n.mac->max_radio_payload() - (typed_ ? kKindBytes + n.mac->header_bytes() : 0);
  }

  std::string mac_description(std::size_t node) const override {
    return nodes_[node].mac->describe();
  }

  bool submit(std::size_t node, NetFrame&& frame) override;

  void add_observer(EngineObserver& observer) override { reporter_.add(observer); }

  std::size_t queue_depth(std::size_t node) const override { return nodes_[node].queue->size(); }

  std::vector<std::optional<Ecef>> positions() const override { return snapshots_.positions(); }

  std::vector<float> link_gains() const override {
    return snapshots_.link_gains(status_.virtual_samples.load(std::memory_order_relaxed));
  }

  void set_position(std::size_t node, std::optional<Ecef> position) override {
    inbox_.move(node, position, false);
  }

  void retune(std::size_t node, double tx_hz, double rx_hz) override;

  void report(std::size_t node, const position::StateReport& r) override;

  std::vector<position::NodeMotion> motions() const override { return inbox_.motions(); }

  NodeCounters& counters(std::size_t node) override { return counters_[node]; }

  EngineStatus status() const override;

  bool owns(std::size_t node) const override { return owned_[node]; }

  std::vector<RankStatus> ranks() const override {
    std::lock_guard lock(snapshot_mutex_);
    return ranks_snapshot_;
  }

  void run(const std::atomic<bool>& stop) override;
  SampleTime advance(SampleTime until, const std::atomic<bool>& stop) override;

 private:
  /// One per core (or as set), and at least one per remote transceiver: those
  /// workers mostly wait on a socket, and their waits must overlap.
  static std::size_t worker_count(const scenario::Scenario& s, std::size_t ranks_on_host);

  /// Scenario traffic enters its node's queue at the first tick boundary at or
  /// after its scheduled time.
  void inject_traffic();

  /// At each tick's start: the positions reported (in a distributed run,
  /// every rank's, swapped at the previous tick) and the mobility models'
  /// into the channel.
  void apply_positions();

  /// Every node's velocity and attitude into the channel (fading, antennas).
  void copy_motions();

  /// One tick of B samples: positions, traffic, the TX phase, (the ranks'
  /// exchange), the RX phase, the decodes; then the ledger settles.
  void run_tick();

  /// Per node, in parallel: the MAC may start a frame, then B samples. A
  /// node's MAC is called by one worker at a time, and only here and in
  /// handle_decodes().
  void tx_phase(std::size_t i);

  /// Starts the transmission the MAC asked for (the TX phase, node's worker).
  void start(Node& node, const mac::MacTransmission& send);

  /// Serially after the TX phase: the ledger learns of new frames, and active_
  /// lists this tick's transmitters (in index order, so mixing order is fixed).
  void record_transmissions();

  /// Half-duplex, the T/R switch: y_m contains c_mm x_m exactly as in the paper,
  /// but a real receiver front end is switched off (or saturated) while its own
  /// radio transmits, and liquid's detectors would need milliseconds to recover
  /// from a self-signal 100+ dB above the noise floor. So the receiver of a
  /// transmitting node does not run during the samples it transmits, and it
  /// restarts (reset_receiver) at the first sample after its transmission. Any
  /// frame that overlaps the node's own transmission is therefore lost.
  std::size_t first_receive_sample(const Node& node) const {
    return node.full_duplex ? 0 : node.tx_samples;
  }
  bool blanked_whole_tick(const Node& node) const {
    return !node.full_duplex && node.tx_samples >= block_;
  }

  /// Skipping silence, exact condition: receiver m runs in a tick iff some sample
  /// is left after its own transmission and (it is inside a frame, or it has just
  /// finished transmitting, or some other transmitter's signal reaches it: an
  /// active one with c_nm != 0, or through a delayed path the tail of an
  /// earlier transmission). Otherwise its input is pure noise, from which it cannot decode
  /// anything. skip_idle_receivers = false, or a receive stage that makes
  /// skipping inexact (Channel::skipping_exact), runs every receiver every tick.
  /// Observers do not count: a watched idle receiver's input is computed for
  /// them (RxTick::kWatched) without running it.
  bool receiver_must_run(std::size_t m) const;
  /// The scenario's duration in samples (0: none), and the loop both run()
  /// and advance() drive: ticks while the virtual time is before `end` and
  /// neither `stop` nor (distributed) another rank said stop.
  SampleTime duration_samples() const;
  void tick_until(SampleTime end, const std::atomic<bool>& stop);

  /// Whether receiver m has work beyond noise this tick (the skip condition's
  /// second half); also how the RX phase judges whether parallelism pays.
  bool hears_more_than_noise(std::size_t m) const;

  /// Serially: which receivers run this tick (runnable_, remote ones first so
  /// that they are dealt to different workers), and why the others do not.
  void plan_receivers();

  /// Receivers whose inputs are mixed together (channel::mix_rows): with many
  /// transmitters on the air each transmitter's samples are then read once per
  /// group instead of once per receiver. Bit for bit the same inputs.
  struct RxGroup {
    std::array<std::size_t, channel::Channel::kMaxTogether> receivers{};
    std::size_t size = 0;
  };
  /// Below this many transmitters on the air their samples fit in L1 and one
  /// receiver at a time mixes as fast (rfsitl_mix_bench: mix against mix_rows).
  static constexpr std::size_t kMixTogetherMinInputs = 24;

  /// Serially: runnable_ as groups, in its order. Receivers that hear the
  /// whole tick are grouped when the channel allows it; the rest alone.
  void group_receivers();

  /// Per group, in parallel: y_m = g (sum_{n != m} c_nm x_n + eta_m) over the
  /// samples after m's own transmission, then m decodes.
  void rx_group(const RxGroup& group);

  /// Carrier sense over the input y of a receiver that ran (or was watched):
  /// busy when its receiver is inside a frame it detected, or when some other
  /// transmitter reaches it and the tick's mean power exceeds the MAC's
  /// threshold. An input that is noise alone is idle by definition, so that
  /// watching a receiver (which computes its noise) changes no outcome.
  static void sense(Node& node, std::span<const cf32> y);

  /// Receiver m decodes its input y, if it runs this tick.
  void decode(std::size_t m, std::span<cf32> y);

  /// Serially, after the RX phase: each own receiver's decodes go to its MAC
  /// now (classify), and to the ledger and the agent in replay(); in a
  /// distributed run every rank replays every rank's ledger ops, in node order,
  /// so that every rank's ledger is the same.
  void handle_decodes();

  /// One decode of receiver `node`: the MAC's control frames go to the MAC,
  /// data frames to the MAC (repeats, ACKs) and, through replay(), to the
  /// ledger and the agent.
  void classify(Node& node, Decoded& d);

  /// What the ledger learns, in the same order on every rank; a decode of an
  /// own receiver that the ledger finds addressed to it, and its MAC lets
  /// through, goes to the agent.
  void replay(const LedgerOp& op);

  /// Distributed run, after the TX phase: tells the other ranks what this
  /// rank's nodes did (verdicts, frames started, samples) and the positions
  /// it was told, and takes theirs into the nodes they own.
  void exchange_transmissions();

  /// Another rank's node `t.node` as this tick's TX phase left it there.
  void take_report(std::size_t rank, std::size_t k, const TxReport& t);

  /// Distributed run: every rank takes the owners' counters of the nodes it
  /// does not own (collective), and every rank's figures.
  void merge_counters();

  /// Once per tick, lock-free: relaxed atomic stores that any thread may read
  /// (each field is consistent on its own, which is all a stats line needs).
  void publish_status();

  scenario::Scenario scenario_;
  bool typed_ = scenario_.typed_framing();  // frames carry their kind on the air
  FrameSink& sink_;
  std::size_t block_;
  channel::Channel air_;
  channel::ChannelMatrix& channel_;  // air_'s links
  std::vector<NodeCounters> counters_;
  std::vector<Node> nodes_;
  std::vector<std::size_t> active_;               // transmitters of the current tick
  std::vector<channel::Transmission> active_tx_;  // the same, with their samples
  std::vector<std::size_t> runnable_;             // receivers that run in the current tick
  std::vector<RxGroup> rx_groups_;                // the same, as groups (group_receivers)
  std::size_t busy_receivers_ = 0;                // of those, the ones with more than noise to do
  static constexpr std::size_t kSerialTxLimit = 2;
  static constexpr std::size_t kSerialNoiseOnlyLimit = 8;
  std::vector<std::size_t> tx_order_;  // remote transceivers first, then the others
  std::size_t remote_count_ = 0;
  std::vector<NodeId> ids_;
  std::optional<FrameLedger> ledger_;
  TickClock clock_;
  WorkerPool pool_;
  std::optional<WorkerTuner> tuner_;  // how many of pool_'s workers a tick uses
  TrafficSchedule traffic_;
  MobilityDriver mobility_;
  SampleTime now_ = 0;
  std::uint64_t run_ticks_ = 0;
  std::uint64_t skipped_ticks_ = 0;
  std::uint64_t blanked_ticks_ = 0;

  EventReporter reporter_;
  bool defer_outcomes_ = false;  // replay(): outcomes wait until the decode is reported
  std::vector<LedgerOutcome> deferred_outcomes_;
  LinkSnapshots snapshots_{scenario_.timing.sample_rate_hz};
  mutable std::mutex snapshot_mutex_;  // ranks_snapshot_
  NodeStateInbox inbox_;

  // Engine::retune: asked for by any thread, applied by the engine thread at
  // the start of the next tick (apply_retunes). tunings_ holds every node's
  // radio once the first retune came (empty before: the scenario's).
  struct Retune {
    std::size_t node;
    double tx_hz;
    double rx_hz;
  };
  std::mutex retune_mutex_;
  std::vector<Retune> retunes_;  // under retune_mutex_
  std::atomic<bool> retune_pending_{false};
  std::vector<channel::RadioTuning> tunings_;
  void apply_retunes();

  struct AtomicStatus {
    std::atomic<SampleTime> virtual_samples{0};
    std::atomic<double> lag_s{0.0};
    std::atomic<double> max_lag_s{0.0};
    std::atomic<std::uint64_t> late_ticks{0};
    std::atomic<std::uint64_t> late_decodes{0};
    std::atomic<std::uint64_t> receiver_ticks_run{0};
    std::atomic<std::uint64_t> receiver_ticks_skipped{0};
    std::atomic<std::uint64_t> receiver_ticks_blanked{0};
    std::atomic<double> mobility_wall_s{0.0};
    std::atomic<std::uint64_t> exchanged_bytes{0};
    std::atomic<double> exchange_wall_s{0.0};
    std::atomic<std::size_t> workers{1};
  } status_;

  // Distributed run (make_engine's Distribution); in one process link_ is
  // empty and every node is owned.
  std::vector<bool> owned_;
  std::optional<RankLink> link_;
  bool local_stop_ = false;                // this rank was told to stop
  bool clock_started_ = false;             // run() or the first advance() started it
  bool ran_ = false;                       // run() was called: advance() may not go on
  std::uint64_t tick_index_ = 0;           // ticks run so far (the clock's k)
  bool stop_agreed_ = false;               // some rank was: every rank stops after this tick
  std::vector<StateUpdate> peer_updates_;  // applied at the next tick's start
  TxMessage tx_out_;                       // this rank's message A, built every tick
  std::uint64_t merge_every_ = 0;          // ticks between counter merges
  std::uint64_t ticks_since_merge_ = 0;
  std::vector<RankStatus> ranks_snapshot_;  // under snapshot_mutex_
  /// A decode handed to the ledger by replay(), and to the agent if addressed.
  struct Delivery {
    Decoded decoded;
    std::size_t header;  // bytes of kind and MAC header before the payload
    bool deliver;        // the MAC lets it through (not a duplicate)
  };
  std::vector<Delivery> deliveries_;
  std::vector<LedgerOp> ops_;
};

}  // namespace rfsitl::engine
