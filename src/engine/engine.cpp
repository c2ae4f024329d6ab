#include "rfsitl/engine/engine.hpp"

#include <algorithm>
#include <array>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>

#include "engine_node.hpp"
#include "event_reporter.hpp"
#include "frame_kind.hpp"
#include "link_snapshots.hpp"
#include "mobility_driver.hpp"
#include "node_macs.hpp"
#include "node_state_inbox.hpp"
#include "node_tx_report.hpp"
#include "rank_link.hpp"
#include "rfsitl/channel/channel.hpp"
#include "rfsitl/channel/channel_matrix.hpp"
#include "rfsitl/channel/geodesy.hpp"
#include "rfsitl/common/spsc_ring.hpp"
#include "rfsitl/engine/frame_ledger.hpp"
#include "rfsitl/engine/tick_clock.hpp"
#include "rfsitl/engine/traffic_schedule.hpp"
#include "rfsitl/engine/worker_pool.hpp"
#include "rfsitl/registry/phy_registry.hpp"
#include "rfsitl/scenario/link_budget_of.hpp"

namespace rfsitl::engine {
namespace {

class LockStepEngine final : public Engine {
 public:
  LockStepEngine(const scenario::Scenario& s, FrameSink& sink, const TransceiverFactory& factory,
                 Distribution distribution)
      : scenario_(s),
        sink_(sink),
        block_(s.timing.tick_samples),
        air_(s.nodes.size(), scenario::make_link_budget(s), s.channel.origin,
             channel::ChannelConfig{s.channel.noise_variance, s.channel.shared_noise, s.seed,
                                    s.timing.sample_rate_hz, s.timing.tick_samples,
                                    s.channel.tx_impairments, s.channel.rx_impairments}),
        channel_(air_.matrix()),
        counters_(s.nodes.size()),
        clock_(s.timing.sample_rate_hz, s.timing.tick_samples, s.timing.speed,
               s.timing.mode == scenario::TimeMode::kRealTime),
        pool_(worker_count(s, std::max<std::size_t>(1, distribution.ranks_on_host))),
        traffic_(s.traffic, s.timing.sample_rate_hz),
        mobility_(s),
        reporter_(scenario_, channel_),
        inbox_(s.nodes.size(), s.channel.origin) {
    const std::size_t n = s.nodes.size();
    owned_.assign(n, true);
    if (distribution.peers != nullptr) {
      if (distribution.owner.size() != n) {
        throw std::invalid_argument("distributed run: an owner rank is needed for every node");
      }
      link_.emplace(*distribution.peers, n, block_);
      for (std::size_t i = 0; i < n; ++i) owned_[i] = distribution.owner[i] == link_->rank();
      // Counters of other ranks' nodes are gathered every 0.1 s of virtual time.
      merge_every_ = std::max<std::uint64_t>(
          1,
          static_cast<std::uint64_t>(0.1 * s.timing.sample_rate_hz / static_cast<double>(block_)));
    }
    nodes_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      Node& node = nodes_[i];
      node.id = s.nodes[i].id;
      node.index = i;
      node.reporter = &reporter_;
      ids_.push_back(node.id);
      const scenario::PhyChoice& phy = s.phy_of(i);
      if (factory) {
        node.radio = factory(i, phy, counters_[i]);
      } else if (s.runs_externally(i)) {
        throw std::invalid_argument("node " + std::to_string(node.id) +
                                    " runs in another process, but no external hub was set up");
      } else {
        node.radio = phy::make_transceiver(phy.type, phy.settings);
      }
      if (node.radio->remote()) ++remote_count_;
      node.queue = std::make_unique<SpscRing<QueuedFrame>>(phy.tx_queue_frames);
      node.producers = std::make_unique<std::mutex>();
      node.tx.assign(block_, cf32{});
      node.rx.assign(block_, cf32{});
      node.scratch.inputs.reserve(n);
      node.scratch.coeffs.reserve(n * channel::Channel::kMaxTogether);
      active_.reserve(n);
      active_tx_.reserve(n);
      runnable_.reserve(n);
      rx_groups_.reserve(n);
      node.decoded.reserve(8);
      if (s.nodes[i].initial_position) {
        channel_.set_position(i, channel::to_ecef(*s.nodes[i].initial_position, s.channel.origin));
      }
    }
    std::vector<double> sensitivity;
    std::size_t latency = 0;
    for (const Node& node : nodes_) {
      sensitivity.push_back(node.radio->sensitivity_snr_db());
      latency = std::max(latency, node.radio->rx_latency_samples());
    }
    make_macs(nodes_, counters_, scenario_, block_, latency, air_.front_end_gain());
    // Remote transceivers come first in the TX dealing order so that each gets
    // a worker of its own (the pool has at least as many workers as remotes).
    for (std::size_t i = 0; i < n; ++i) {
      if (nodes_[i].radio->remote()) tx_order_.push_back(i);
    }
    for (std::size_t i = 0; i < n; ++i) {
      if (!nodes_[i].radio->remote()) tx_order_.push_back(i);
    }
    ledger_.emplace(LedgerConfig{s.channel.noise_variance, std::move(sensitivity),
                                 static_cast<SampleTime>(2 * latency + block_)},
                    counters_, [this](NodeId id) { return index_of(id); });
    ledger_->set_outcome_callback([this](const LedgerOutcome& o) {
      // A unicast frame is delivered by the decode that receives it: report the
      // receiver's event first, then the outcome (see replay). A rank reports
      // the outcomes of its own nodes' frames.
      if (!owned_[o.tx]) return;
      if (defer_outcomes_) {
        deferred_outcomes_.push_back(o);
      } else {
        reporter_.outcome(o, now_);
      }
    });
  }

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

  bool submit(std::size_t node, NetFrame&& frame) override {
    // Producers (the net ports' I/O thread, an IP node's TAP reader) take
    // turns; the engine thread pops without a lock.
    std::lock_guard producers(*nodes_[node].producers);
    NodeCounters& c = counters_[node];
    NodeCounters::bump(c.handed_in);
    QueuedFrame item{std::move(frame), clock_.wall_now_samples()};
    // In virtual time the wall clock says nothing: the event is stamped with
    // the tick the engine is at.
    const SampleTime at = scenario_.timing.mode == scenario::TimeMode::kRealTime
                              ? item.not_before
                              : status_.virtual_samples.load(std::memory_order_relaxed);
    reporter_.handed_in(node, item.frame, at);
    if (!nodes_[node].queue->try_push(item)) {
      NodeCounters::bump(c.queue_dropped);
      reporter_.queue_dropped(node, item.frame, at);
      return false;
    }
    return true;
  }

  void add_observer(EngineObserver& observer) override { reporter_.add(observer); }

  std::size_t queue_depth(std::size_t node) const override { return nodes_[node].queue->size(); }

  std::vector<std::optional<Ecef>> positions() const override { return snapshots_.positions(); }

  std::vector<float> link_gains() const override {
    return snapshots_.link_gains(status_.virtual_samples.load(std::memory_order_relaxed));
  }

  void set_position(std::size_t node, std::optional<Ecef> position) override {
    inbox_.move(node, position, false);
  }

  void report(std::size_t node, const position::StateReport& r) override {
    if (r.position) {
      inbox_.move(node, channel::to_ecef(*r.position, scenario_.channel.origin),
                  r.velocity.has_value());
    }
    inbox_.set_motion(node, {r.velocity, r.attitude});
  }

  std::vector<position::NodeMotion> motions() const override { return inbox_.motions(); }

  NodeCounters& counters(std::size_t node) override { return counters_[node]; }

  EngineStatus status() const override {
    EngineStatus st;
    const auto rd = [](const auto& a) { return a.load(std::memory_order_relaxed); };
    st.virtual_samples = rd(status_.virtual_samples);
    st.virtual_s = static_cast<double>(st.virtual_samples) / scenario_.timing.sample_rate_hz;
    st.wall_s = clock_.elapsed_wall_s();
    st.lag_s = rd(status_.lag_s);
    st.max_lag_s = rd(status_.max_lag_s);
    st.late_ticks = rd(status_.late_ticks);
    st.late_decodes = rd(status_.late_decodes);
    st.receiver_ticks_run = rd(status_.receiver_ticks_run);
    st.receiver_ticks_skipped = rd(status_.receiver_ticks_skipped);
    st.receiver_ticks_blanked = rd(status_.receiver_ticks_blanked);
    st.mobility_wall_s = rd(status_.mobility_wall_s);
    st.exchanged_bytes = rd(status_.exchanged_bytes);
    st.exchange_wall_s = rd(status_.exchange_wall_s);
    return st;
  }

  bool owns(std::size_t node) const override { return owned_[node]; }

  std::vector<RankStatus> ranks() const override {
    std::lock_guard lock(snapshot_mutex_);
    return ranks_snapshot_;
  }

  void run(const std::atomic<bool>& stop) override {
    const auto duration =
        static_cast<SampleTime>(scenario_.timing.duration_s * scenario_.timing.sample_rate_hz);
    // Ranks start their clocks together (and are told to stop together, by
    // the exchange of the tick where any one of them was).
    if (link_) link_->barrier();
    clock_.start();
    for (std::uint64_t k = 0; !stop_agreed_; ++k) {
      if (duration > 0 && now_ >= duration) break;
      clock_.wait_for_tick(k);
      local_stop_ = stop.load(std::memory_order_relaxed);
      if (!link_ && local_stop_) break;
      run_tick();
      publish_status();
    }
    if (link_) merge_counters();
    publish_status();
  }

 private:
  /// One per core (or as set), and at least one per remote transceiver: those
  /// workers mostly wait on a socket, and their waits must overlap.
  static std::size_t worker_count(const scenario::Scenario& s, std::size_t ranks_on_host) {
    const std::size_t cores = std::max(1U, std::thread::hardware_concurrency());
    const std::size_t wanted =
        s.engine.threads != 0 ? s.engine.threads : std::max<std::size_t>(1, cores / ranks_on_host);
    std::size_t remote = 0;
    for (std::size_t i = 0; i < s.nodes.size(); ++i) remote += s.runs_externally(i) ? 1 : 0;
    return std::clamp<std::size_t>(std::max(wanted, remote), 1, s.nodes.size());
  }

  /// Scenario traffic enters its node's queue at the first tick boundary at or
  /// after its scheduled time.
  void inject_traffic() {
    while (const auto t = traffic_.pop_due(now_)) {
      const auto node = index_of(t->src);
      if (!node || !owned_[*node]) continue;  // validated scenarios name only known sources
      NetFrame frame{t->src, t->dst, std::vector<std::uint8_t>(t->size, 0)};
      for (std::size_t b = 0; b < t->size; ++b) {
        frame.payload[b] = static_cast<std::uint8_t>((t->repeat_index + b) & 0xFF);
      }
      NodeCounters::bump(counters_[*node].handed_in);
      reporter_.handed_in(*node, frame, now_);
      nodes_[*node].injected.push_back(std::move(frame));
    }
  }

  void apply_positions() {
    const double now_s = static_cast<double>(now_) / scenario_.timing.sample_rate_hz;
    channel_.set_clock(now_s);
    // A distributed run applies what every rank took at the previous tick.
    if (!link_) peer_updates_ = inbox_.take();
    bool moved = inbox_.apply(peer_updates_, now_s, channel_);
    peer_updates_.clear();
    // After the feeds: a modelled node follows its model again at each update.
    moved = mobility_.update(now_, channel_, [this](std::size_t node, const position::Velocity& v) {
      inbox_.set_motion_now(node, {v, std::nullopt});
    }) || moved;
    const bool turned = inbox_.motion_changed();
    if (moved || turned) {
      snapshots_.mark_stale();
      // Fading follows each node along its velocity between updates; antennas
      // turn with their bodies.
      if (channel_.time_varying() || channel_.depends_on_attitude()) copy_motions();
    }
    snapshots_.maybe_copy(channel_, now_);
  }

  void copy_motions() {
    const std::vector<position::NodeMotion> motions = inbox_.motions();
    for (std::size_t i = 0; i < motions.size(); ++i) {
      const position::Velocity v = motions[i].velocity.value_or(position::Velocity{});
      channel_.set_velocity(i, {v.vx_mps, v.vy_mps, v.vz_mps});
      std::optional<channel::Orientation> attitude;
      if (const auto& a = motions[i].attitude) {
        attitude = channel::Orientation{a->roll_rad, a->pitch_rad, a->yaw_rad};
      }
      channel_.set_attitude(i, attitude);
    }
  }

  void run_tick() {
    apply_positions();
    inject_traffic();
    // Waking the workers costs more than an idle transmitter's zero fill, so
    // the TX phase runs in parallel only when several nodes were on the air
    // (or a remote transceiver may make a round trip).
    if (active_.size() > kSerialTxLimit || remote_count_ > 0) {
      pool_.run([this](std::size_t w) {
        for (std::size_t j = w; j < tx_order_.size(); j += pool_.size()) tx_phase(tx_order_[j]);
      });
    } else {
      for (std::size_t i = 0; i < nodes_.size(); ++i) tx_phase(i);
    }
    if (link_) exchange_transmissions();
    record_transmissions();
    air_.on_air(now_, active_tx_);
    plan_receivers();
    air_.begin_tick(now_, !runnable_.empty());
    // Receivers that run are dealt round-robin to the workers: balanced whatever
    // their indices are. A few receivers that only hear noise (run because
    // skipping is off or someone watches them) cost less than waking the workers.
    group_receivers();
    if (busy_receivers_ > 1 || runnable_.size() >= kSerialNoiseOnlyLimit) {
      pool_.run([this](std::size_t w) {
        for (std::size_t j = w; j < rx_groups_.size(); j += pool_.size()) rx_group(rx_groups_[j]);
      });
    } else {
      for (const RxGroup& group : rx_groups_) rx_group(group);
    }
    handle_decodes();
    now_ += block_;
    ledger_->settle(now_, channel_);
    if (link_ && ++ticks_since_merge_ >= merge_every_) merge_counters();
  }

  /// Per node, in parallel: the MAC may start a frame, then B samples. A
  /// node's MAC is called by one worker at a time, and only here and in
  /// handle_decodes().
  void tx_phase(std::size_t i) {
    Node& node = nodes_[i];
    if (!owned_[i]) {
      // Another rank's node: what it sends comes in exchange_transmissions().
      node.tx_samples = 0;
      node.active = false;
      return;
    }
    node.radio->begin_tick(static_cast<std::uint64_t>(now_) / block_, now_);
    node.queue_now = now_;
    const std::uint32_t frame_before = node.mac_frame;
    const std::optional<mac::MacTransmission> send =
        node.mac->on_tick(now_, node.radio->tx_busy(), node);
    if (const auto v = node.mac->take_verdict()) node.verdict = PendingVerdict{frame_before, *v};
    if (send) start(node, *send);
    // An idle transmitter's samples are never read (only active ones are
    // mixed), so it produces none: no zero fill for silence.
    node.tx_samples = node.radio->tx_busy() ? node.radio->transmit(node.tx) : 0;
    node.active = node.tx_samples > 0;
  }

  /// Starts the transmission the MAC asked for (the TX phase, node's worker).
  void start(Node& node, const mac::MacTransmission& send) {
    // Sender index in the top byte; the count from 1, so that 0 never names a frame.
    const std::uint32_t serial =
        (static_cast<std::uint32_t>(node.index) << 24) | (node.frames_started++ % 0xFFFFFFU + 1U);
    NetFrame frame = send.frame != nullptr ? *send.frame
                                           : NetFrame{node.id,
                                                      send.dst,
                                                      {send.header.begin(), send.header.end()},
                                                      FrameKind::kMacControl};
    std::span<const std::uint8_t> on_air = frame.payload;
    if (typed_) {
      on_air = with_kind(frame.kind,
                         send.frame != nullptr ? send.header : std::span<const std::uint8_t>{},
                         on_air, node.typed_payload);
    }
    node.started_len = node.radio->start_frame(phy::FrameTag{frame.src, frame.dst, serial}, on_air);
    node.mac->on_sent(now_, now_ + static_cast<SampleTime>(node.started_len));
    node.started_awaits_verdict = send.awaits_verdict;
    node.started_first_attempt = !send.retry;
    if (send.awaits_verdict && !send.retry) node.mac_frame = serial;
    node.started.emplace(serial, std::move(frame));
  }

  /// Serially after the TX phase: the ledger learns of new frames, and active_
  /// lists this tick's transmitters (in index order, so mixing order is fixed).
  void record_transmissions() {
    active_.clear();
    active_tx_.clear();
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
      Node& node = nodes_[i];
      if (node.active) {
        active_.push_back(i);
        active_tx_.push_back({i, node.tx.data()});
      }
      if (node.verdict) {
        ledger_->on_frame_done(node.verdict->frame, node.verdict->verdict == mac::Verdict::kGaveUp);
        node.verdict.reset();
      }
      if (node.started) {
        const auto& [serial, frame] = *node.started;
        node.frame_end = now_ + static_cast<SampleTime>(node.started_len);
        if (frame.kind == FrameKind::kMacControl) {
          // The MAC's own frame: never counted, but it occupies the air.
          ledger_->on_activity(i, now_, node.frame_end);
        } else {
          ledger_->on_transmit(serial, i, frame.dst, now_, node.frame_end,
                               node.started_awaits_verdict ? node.mac_frame : 0);
        }
        const TxRole role = frame.kind == FrameKind::kMacControl ? TxRole::kControl
                            : node.started_first_attempt         ? TxRole::kFirst
                                                                 : TxRole::kRepeat;
        if (owned_[i]) reporter_.transmitted(i, serial, frame, now_, node.started_len, role);
        node.started.reset();
      } else if (node.active && now_ >= node.frame_end) {
        // Signal that no frame of ours explains: an external program transmits.
        ledger_->on_activity(i, now_, now_ + static_cast<SampleTime>(node.tx_samples));
      }
    }
  }

  /// Half-duplex, the T/R switch: y_m contains c_mm x_m exactly as in the paper,
  /// but a real receiver front end is switched off (or saturated) while its own
  /// radio transmits, and liquid's detectors would need milliseconds to recover
  /// from a self-signal 100+ dB above the noise floor. So the receiver of a
  /// transmitting node does not run during the samples it transmits, and it
  /// restarts (reset_receiver) at the first sample after its transmission. Any
  /// frame that overlaps the node's own transmission is therefore lost.
  std::size_t first_receive_sample(const Node& node) const { return node.tx_samples; }
  bool blanked_whole_tick(const Node& node) const { return node.tx_samples >= block_; }

  /// Skipping silence, exact condition: receiver m runs in a tick iff some sample
  /// is left after its own transmission and (it is inside a frame, or it has just
  /// finished transmitting, or some other transmitter's signal reaches it: an
  /// active one with c_nm != 0, or through a delayed path the tail of an
  /// earlier transmission). Otherwise its input is pure noise, from which it cannot decode
  /// anything. skip_idle_receivers = false runs every receiver every tick.
  /// Observers do not count: a watched idle receiver's input is computed for
  /// them (RxTick::kWatched) without running it.
  bool receiver_must_run(std::size_t m) const {
    const Node& node = nodes_[m];
    if (blanked_whole_tick(node)) return false;
    if (!scenario_.engine.skip_idle_receivers) return true;
    return hears_more_than_noise(m);
  }

  /// Whether receiver m has work beyond noise this tick (the skip condition's
  /// second half); also how the RX phase judges whether parallelism pays.
  bool hears_more_than_noise(std::size_t m) const {
    const Node& node = nodes_[m];
    if (node.receiver_blanked || node.radio->rx_busy()) return true;
    return air_.hears_signal(m);
  }

  /// Serially: which receivers run this tick (runnable_, remote ones first so
  /// that they are dealt to different workers), and why the others do not.
  void plan_receivers() {
    runnable_.clear();
    busy_receivers_ = 0;
    for (const std::size_t m : tx_order_) {
      Node& node = nodes_[m];
      if (!owned_[m]) {
        node.rx_tick = Node::RxTick::kElsewhere;
        continue;
      }
      node.watched = reporter_.active() && reporter_.wants_samples(m, now_, block_);
      node.tick_time = now_;
      if (node.tx_samples > 0) node.receiver_blanked = true;
      // Carrier sense: a node that transmits hears its own signal; whether
      // anyone else's reaches it, its input will tell (sense()).
      node.sensed_busy = node.tx_samples > 0;
      node.hears_others = node.busy_power.has_value() && air_.hears_signal(m);
      if (receiver_must_run(m)) {
        node.rx_tick = Node::RxTick::kRan;
        runnable_.push_back(m);
        if (node.radio->remote() || hears_more_than_noise(m)) ++busy_receivers_;
      } else if (node.watched && !blanked_whole_tick(node)) {
        node.rx_tick = Node::RxTick::kWatched;
        runnable_.push_back(m);
      } else {
        node.rx_tick = blanked_whole_tick(node) ? Node::RxTick::kBlanked : Node::RxTick::kSkipped;
      }
    }
  }

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
  void group_receivers() {
    rx_groups_.clear();
    const bool together = air_.mixes_together(kMixTogetherMinInputs);
    RxGroup open;
    for (const std::size_t m : runnable_) {
      if (!together || first_receive_sample(nodes_[m]) != 0) {
        rx_groups_.push_back(RxGroup{{m}, 1});
        continue;
      }
      open.receivers[open.size++] = m;
      if (open.size == open.receivers.size()) {
        rx_groups_.push_back(open);
        open.size = 0;
      }
    }
    if (open.size > 0) rx_groups_.push_back(open);
  }

  /// Per group, in parallel: y_m = g (sum_{n != m} c_nm x_n + eta_m) over the
  /// samples after m's own transmission, then m decodes.
  void rx_group(const RxGroup& group) {
    if (group.size == 1) {
      const std::size_t m = group.receivers[0];
      Node& node = nodes_[m];
      const std::size_t first = first_receive_sample(node);
      if (node.watched) std::fill_n(node.rx.begin(), first, cf32{});  // blanked: zeros
      const std::span<cf32> y(node.rx.data() + first, block_ - first);
      air_.receive(m, first, y, node.scratch);
      decode(m, y);
      sense(node, y);
      return;
    }
    std::array<cf32*, channel::Channel::kMaxTogether> ys{};
    for (std::size_t j = 0; j < group.size; ++j) ys[j] = nodes_[group.receivers[j]].rx.data();
    const std::span<const std::size_t> ms(group.receivers.data(), group.size);
    air_.receive_together(ms, {ys.data(), group.size}, nodes_[ms[0]].scratch);
    for (const std::size_t m : ms) {
      decode(m, nodes_[m].rx);
      sense(nodes_[m], nodes_[m].rx);
    }
  }

  /// Carrier sense over the input y of a receiver that ran (or was watched):
  /// busy when its receiver is inside a frame it detected, or when some other
  /// transmitter reaches it and the tick's mean power exceeds the MAC's
  /// threshold. An input that is noise alone is idle by definition, so that
  /// watching a receiver (which computes its noise) changes no outcome.
  static void sense(Node& node, std::span<const cf32> y) {
    if (!node.busy_power || node.sensed_busy) return;
    if (node.radio->rx_busy()) {
      node.sensed_busy = true;
      return;
    }
    if (!node.hears_others || y.empty()) return;
    float power = 0.0F;
    for (const cf32 v : y) power += std::norm(v);
    node.sensed_busy = power > *node.busy_power * static_cast<float>(y.size());
  }

  /// Receiver m decodes its input y, if it runs this tick.
  void decode(std::size_t m, std::span<cf32> y) {
    Node& node = nodes_[m];
    if (node.rx_tick != Node::RxTick::kRan) return;
    if (node.receiver_blanked) {
      node.radio->reset_receiver();
      node.receiver_blanked = false;
    }
    node.radio->receive(y, node);
  }

  /// Serially, after the RX phase: each own receiver's decodes go to its MAC
  /// now (classify), and to the ledger and the agent in replay(); in a
  /// distributed run every rank replays every rank's ledger ops, in node order,
  /// so that every rank's ledger is the same.
  void handle_decodes() {
    ops_.clear();
    deliveries_.clear();
    for (std::size_t m = 0; m < nodes_.size(); ++m) {
      Node& node = nodes_[m];
      if (node.rx_tick == Node::RxTick::kElsewhere) continue;
      if (node.rx_tick == Node::RxTick::kSkipped || node.rx_tick == Node::RxTick::kWatched) {
        ++skipped_ticks_;
      }
      if (node.rx_tick == Node::RxTick::kRan) ++run_ticks_;
      if (node.rx_tick == Node::RxTick::kBlanked) ++blanked_ticks_;
      if (node.watched) {
        if (node.rx_tick == Node::RxTick::kBlanked)
          std::fill(node.rx.begin(), node.rx.end(), cf32{});
        reporter_.rx_samples(m, now_, node.rx);
      }
      if (node.busy_power) node.mac->on_sensed(node.sensed_busy);
      for (Decoded& d : node.decoded) classify(node, d);
      node.decoded.clear();
    }
    if (link_) link_->exchange_ops(ops_);
    for (const LedgerOp& op : ops_) replay(op);
  }

  /// One decode of receiver `node`: the MAC's control frames go to the MAC,
  /// data frames to the MAC (repeats, ACKs) and, through replay(), to the
  /// ledger and the agent.
  void classify(Node& node, Decoded& d) {
    const auto m = static_cast<std::uint32_t>(node.index);
    // A kind byte this build does not know, or a frame too short for its
    // header, passed the CRC only if a transceiver garbled it: counted with
    // the failed decodes.
    const std::size_t header = typed_ ? kKindBytes + node.mac->header_bytes() : 0;
    if (!d.payload_valid || (typed_ && !has_known_kind(d.payload))) {
      NodeCounters::bump(counters_[m].rx_crc_failures);
      return;
    }
    if (typed_ && static_cast<FrameKind>(d.payload[0]) == FrameKind::kMacControl) {
      if (d.tag.dst != node.id) return;  // overheard
      node.mac->on_control(d.tag.src, std::span(d.payload).subspan(kKindBytes), now_);
      if (const auto v = node.mac->take_verdict()) {
        ops_.push_back(
            {m, LedgerOp::Kind::kFrameDone, *v == mac::Verdict::kGaveUp, node.mac_frame});
      }
      return;
    }
    if (d.payload.size() < header) {
      NodeCounters::bump(counters_[m].rx_crc_failures);
      return;
    }
    // The MAC judges by what its receiver decoded (the frame's own addresses),
    // the ledger only keeps the books.
    const bool to_me = d.tag.dst == node.id;
    mac::RxDecision decision;
    if ((to_me || d.tag.dst == kBroadcastId) && d.tag.src != node.id) {
      const std::span<const std::uint8_t> mac_header =
          typed_ ? std::span<const std::uint8_t>(d.payload).subspan(kKindBytes, header - kKindBytes)
                 : std::span<const std::uint8_t>();
      decision = node.mac->on_data(d.tag.src, mac_header, to_me, now_);
    }
    const std::uint32_t serial = d.tag.serial;
    deliveries_.push_back(Delivery{std::move(d), header, decision.deliver});
    ops_.push_back({m, LedgerOp::Kind::kDecoded, false, serial, deliveries_.size() - 1});
  }

  /// What the ledger learns, in the same order on every rank; a decode of an
  /// own receiver that the ledger finds addressed to it, and its MAC lets
  /// through, goes to the agent.
  void replay(const LedgerOp& op) {
    if (op.kind == LedgerOp::Kind::kFrameDone) {
      ledger_->on_frame_done(op.id, op.gave_up);
      return;
    }
    defer_outcomes_ = true;
    const bool for_this_node = ledger_->on_decoded(op.id, op.node);
    defer_outcomes_ = false;
    if (op.delivery != LedgerOp::kNoDelivery && for_this_node && deliveries_[op.delivery].deliver) {
      Delivery& delivery = deliveries_[op.delivery];
      Decoded& d = delivery.decoded;
      NodeCounters::bump(counters_[op.node].received);
      NetFrame frame{d.tag.src, d.tag.dst, std::move(d.payload)};
      if (typed_) strip_header(frame, delivery.header);
      reporter_.received(op.node, d.tag, frame, now_);
      sink_.deliver(op.node, std::move(frame));
    }
    for (const LedgerOutcome& o : deferred_outcomes_) reporter_.outcome(o, now_);
    deferred_outcomes_.clear();
  }

  /// Distributed run, after the TX phase: tells the other ranks what this
  /// rank's nodes did (verdicts, frames started, samples) and the positions
  /// it was told, and takes theirs into the nodes they own.
  void exchange_transmissions() {
    TxMessage& mine = tx_out_;  // reused: its vectors keep their capacity
    mine.stop = local_stop_;
    mine.reports.clear();
    mine.samples.clear();
    mine.updates = inbox_.take();
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
      const Node& node = nodes_[i];
      if (!owned_[i] || !has_tx_report(node)) continue;
      mine.reports.push_back(tx_report_of(node));
      mine.samples.emplace_back(node.tx.data(), node.tx_samples);
    }
    const std::vector<TxMessageView>& all = link_->exchange_tx(mine);
    for (std::size_t r = 0; r < all.size(); ++r) {
      stop_agreed_ = stop_agreed_ || all[r].stop;
      peer_updates_.insert(peer_updates_.end(), all[r].updates.begin(), all[r].updates.end());
      if (r == link_->rank()) continue;
      for (std::size_t k = 0; k < all[r].reports.size(); ++k) take_report(r, k, all[r].reports[k]);
    }
  }

  /// Another rank's node `t.node` as this tick's TX phase left it there.
  void take_report(std::size_t rank, std::size_t k, const TxReport& t) {
    Node& node = nodes_[t.node];
    if (owned_[t.node]) {
      throw std::runtime_error("tick exchange: rank " + std::to_string(rank) +
                               " reports node index " + std::to_string(t.node) + ", owned here");
    }
    link_->copy_samples(rank, k, node.tx.data());
    take_tx_report(node, t);
  }

  /// Distributed run: every rank takes the owners' counters of the nodes it
  /// does not own (collective), and every rank's figures.
  void merge_counters() {
    ticks_since_merge_ = 0;
    std::vector<std::pair<std::uint32_t, NodeCountersSnapshot>> own;
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
      if (owned_[i]) own.emplace_back(static_cast<std::uint32_t>(i), counters_[i].snapshot());
    }
    const RankFigures mine{clock_.max_lag_s(), clock_.late_ticks(), link_->bytes_sent(),
                           link_->wall_s(), clock_.elapsed_wall_s()};
    std::vector<RankFigures> figures;
    std::vector<std::pair<std::uint32_t, NodeCountersSnapshot>> all;
    std::vector<std::vector<ObserverShare>> shares;
    link_->exchange_counters(mine, own, reporter_.shares(), figures, all, shares);
    for (const auto& [node, snapshot] : all) {
      if (!owned_[node]) counters_[node].assign(snapshot);
    }
    for (std::size_t r = 0; r < shares.size(); ++r) {
      if (r != link_->rank()) reporter_.take_shares(r, shares[r]);
    }
    std::vector<RankStatus> ranks;
    for (const RankFigures& f : figures) {
      ranks.push_back({f.max_lag_s, f.late_ticks, f.exchanged_bytes, f.exchange_wall_s, f.wall_s});
    }
    std::lock_guard lock(snapshot_mutex_);
    ranks_snapshot_ = std::move(ranks);
  }

  /// Once per tick, lock-free: relaxed atomic stores that any thread may read
  /// (each field is consistent on its own, which is all a stats line needs).
  void publish_status() {
    const auto wr = [](auto& a, auto v) { a.store(v, std::memory_order_relaxed); };
    wr(status_.virtual_samples, now_);
    wr(status_.lag_s, clock_.lag_s());
    wr(status_.max_lag_s, clock_.max_lag_s());
    wr(status_.late_ticks, clock_.late_ticks());
    wr(status_.late_decodes, ledger_->late_decodes());
    wr(status_.mobility_wall_s, mobility_.wall_s());
    wr(status_.receiver_ticks_run, run_ticks_);
    wr(status_.receiver_ticks_skipped, skipped_ticks_);
    wr(status_.receiver_ticks_blanked, blanked_ticks_);
    if (link_) {
      wr(status_.exchanged_bytes, link_->bytes_sent());
      wr(status_.exchange_wall_s, link_->wall_s());
    }
  }

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
  } status_;

  // Distributed run (make_engine's Distribution); in one process link_ is
  // empty and every node is owned.
  std::vector<bool> owned_;
  std::optional<RankLink> link_;
  bool local_stop_ = false;                // this rank was told to stop
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

}  // namespace

std::unique_ptr<Engine> make_engine(const scenario::Scenario& scenario, FrameSink& sink,
                                    TransceiverFactory factory, Distribution distribution) {
  return std::make_unique<LockStepEngine>(scenario, sink, factory, std::move(distribution));
}

}  // namespace rfsitl::engine
