#include "lock_step_engine.hpp"

#include <algorithm>
#include <chrono>
#include <limits>
#include <stdexcept>
#include <string>
#include <thread>

#include "node_macs.hpp"
#include "rfsitl/common/geodesy.hpp"
#include "rfsitl/common/spsc_ring.hpp"
#include "rfsitl/registry/phy_registry.hpp"
#include "rfsitl/scenario/link_budget_of.hpp"
#include "rfsitl/scenario/radio_tuning_of.hpp"
#include "rfsitl/scenario/sample_chain_of.hpp"

namespace rfsitl::engine {

LockStepEngine::LockStepEngine(const scenario::Scenario& s, FrameSink& sink,
                               const TransceiverFactory& factory, Distribution distribution)
    : scenario_(s),
      sink_(sink),
      block_(s.timing.tick_samples),
      air_(s.nodes.size(), scenario::make_link_budget(s), s.channel.origin,
           channel::ChannelConfig{s.channel.noise_variance, s.channel.shared_noise, s.seed,
                                  s.timing.sample_rate_hz, s.timing.tick_samples, s.carrier_hz()},
           scenario::make_sample_chain(s, channel::SampleSide::kTransmit),
           scenario::make_sample_chain(s, channel::SampleSide::kReceive)),
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
        1, static_cast<std::uint64_t>(0.1 * s.timing.sample_rate_hz / static_cast<double>(block_)));
  }
  nodes_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    Node& node = nodes_[i];
    node.id = s.nodes[i].id;
    node.index = i;
    node.reporter = &reporter_;
    node.full_duplex = s.band_of(i).duplex == scenario::Duplex::kFull;
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
      channel_.set_position(i, to_ecef(*s.nodes[i].initial_position, s.channel.origin));
    }
  }
  // Radios on their own frequencies; without any, the channel keeps the one
  // shared band (and its exact arithmetic).
  if (s.tuned()) {
    for (std::size_t i = 0; i < n; ++i) air_.tune(i, scenario::radio_tuning_of(s, i));
  }
  // Remote transceivers mostly wait on a socket: each needs its worker.
  tuner_.emplace(pool_.size(), s.engine.threads != 0 || remote_count_ > 0);
  std::vector<double> sensitivity;
  std::vector<bool> full_duplex;
  std::size_t latency = 0;
  for (const Node& node : nodes_) {
    full_duplex.push_back(node.full_duplex);
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
  ledger_.emplace(
      LedgerConfig{s.channel.noise_variance, std::move(sensitivity),
                   static_cast<SampleTime>(2 * latency + block_), std::move(full_duplex)},
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

bool LockStepEngine::submit(std::size_t node, NetFrame&& frame) {
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

void LockStepEngine::report(std::size_t node, const position::StateReport& r) {
  if (r.position) {
    inbox_.move(node, to_ecef(*r.position, scenario_.channel.origin), r.velocity.has_value());
  }
  inbox_.set_motion(node, {r.velocity, r.attitude});
}

EngineStatus LockStepEngine::status() const {
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
  st.workers = rd(status_.workers);
  return st;
}

SampleTime LockStepEngine::duration_samples() const {
  return static_cast<SampleTime>(scenario_.timing.duration_s * scenario_.timing.sample_rate_hz);
}

void LockStepEngine::run(const std::atomic<bool>& stop) {
  if (clock_started_) throw std::logic_error("engine: run() after advance() or a second run()");
  ran_ = true;
  // Ranks start their clocks together (and are told to stop together, by
  // the exchange of the tick where any one of them was).
  if (link_) link_->barrier();
  clock_.start();
  clock_started_ = true;
  const SampleTime duration = duration_samples();
  tick_until(duration > 0 ? duration : std::numeric_limits<SampleTime>::max(), stop);
  if (link_) merge_counters();
  publish_status();
}

SampleTime LockStepEngine::advance(SampleTime until, const std::atomic<bool>& stop) {
  if (link_) throw std::logic_error("engine: a distributed run cannot advance in parts");
  if (ran_) throw std::logic_error("engine: advance() after run()");
  if (!clock_started_) {
    clock_.start();
    clock_started_ = true;
  }
  const SampleTime duration = duration_samples();
  tick_until(duration > 0 ? std::min(until, duration) : until, stop);
  // The caller reads between the parts: what it moved is in the views now,
  // not at the next period (a copy: no outcome changes).
  snapshots_.copy_if_stale(channel_, now_);
  publish_status();
  return now_;
}

void LockStepEngine::tick_until(SampleTime end, const std::atomic<bool>& stop) {
  // In real time the tuner is told how long each wait for the wall clock took
  // (two clock reads a tick, against a tick's hundreds of microseconds); in
  // virtual time there is no wait, and no read.
  const bool paced = scenario_.timing.mode == scenario::TimeMode::kRealTime;
  while (!stop_agreed_ && now_ < end) {
    const std::uint64_t k = tick_index_;
    if (paced) {
      const auto before = std::chrono::steady_clock::now();
      clock_.wait_for_tick(k);
      tuner_->idle(std::chrono::duration_cast<std::chrono::nanoseconds>(
                       std::chrono::steady_clock::now() - before)
                       .count());
    } else {
      clock_.wait_for_tick(k);
    }
    local_stop_ = stop.load(std::memory_order_relaxed);
    if (!link_ && local_stop_) break;
    run_tick();
    ++tick_index_;
    publish_status();
  }
}

std::size_t LockStepEngine::worker_count(const scenario::Scenario& s, std::size_t ranks_on_host) {
  const std::size_t cores = std::max(1U, std::thread::hardware_concurrency());
  const std::size_t wanted =
      s.engine.threads != 0 ? s.engine.threads : std::max<std::size_t>(1, cores / ranks_on_host);
  std::size_t remote = 0;
  for (std::size_t i = 0; i < s.nodes.size(); ++i) remote += s.runs_externally(i) ? 1 : 0;
  return std::clamp<std::size_t>(std::max(wanted, remote), 1, s.nodes.size());
}

void LockStepEngine::inject_traffic() {
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

void LockStepEngine::retune(std::size_t node, double tx_hz, double rx_hz) {
  std::lock_guard lock(retune_mutex_);
  retunes_.push_back({node, tx_hz, rx_hz});
  retune_pending_.store(true, std::memory_order_release);
}

void LockStepEngine::apply_retunes() {
  std::vector<Retune> due;
  {
    std::lock_guard lock(retune_mutex_);
    due.swap(retunes_);
    retune_pending_.store(false, std::memory_order_relaxed);
  }
  if (tunings_.empty()) {
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
      tunings_.push_back(scenario::radio_tuning_of(scenario_, i));
      air_.tune(i, tunings_.back());
    }
  }
  for (const Retune& r : due) {
    channel::RadioTuning& t = tunings_.at(r.node);
    t.tx_hz = r.tx_hz;
    t.rx_hz = r.rx_hz;
    air_.tune(r.node, t);
    reporter_.retuned(r.node, now_, r.tx_hz, r.rx_hz);
  }
  snapshots_.mark_stale();
}

void LockStepEngine::apply_positions() {
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

void LockStepEngine::copy_motions() {
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

void LockStepEngine::run_tick() {
  if (retune_pending_.load(std::memory_order_acquire)) apply_retunes();
  apply_positions();
  inject_traffic();
  // Waking the workers costs more than an idle transmitter's zero fill, so
  // the TX phase runs in parallel only when several nodes were on the air
  // (or a remote transceiver may make a round trip).
  const std::size_t workers = tuner_->workers();
  if (active_.size() > kSerialTxLimit || remote_count_ > 0) {
    pool_.for_each(tx_order_.size(), workers, [this](std::size_t j) { tx_phase(tx_order_[j]); });
  } else {
    for (std::size_t i = 0; i < nodes_.size(); ++i) tx_phase(i);
  }
  if (link_) exchange_transmissions();
  record_transmissions();
  air_.on_air(now_, active_tx_);
  plan_receivers();
  air_.begin_tick(now_, !runnable_.empty());
  // Receivers that run are taken by the workers one group at a time: balanced
  // whatever their indices are and however the OS holds a worker up. A few
  // receivers that only hear noise (run because skipping is off or someone
  // watches them) cost less than waking the workers.
  group_receivers();
  if (busy_receivers_ > 1 || runnable_.size() >= kSerialNoiseOnlyLimit) {
    pool_.for_each(rx_groups_.size(), workers, [this](std::size_t j) { rx_group(rx_groups_[j]); });
  } else {
    for (const RxGroup& group : rx_groups_) rx_group(group);
  }
  // What the parallel phases had to do: a receiver with more than noise costs
  // far more than one that only runs on noise, a transmitter in between.
  tuner_->tick_done(1.0 + static_cast<double>(busy_receivers_) +
                    0.1 * static_cast<double>(runnable_.size() - busy_receivers_) +
                    0.5 * static_cast<double>(active_tx_.size()));
  handle_decodes();
  now_ += block_;
  ledger_->settle(now_, channel_);
  if (link_ && ++ticks_since_merge_ >= merge_every_) merge_counters();
}

void LockStepEngine::tx_phase(std::size_t i) {
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

void LockStepEngine::start(Node& node, const mac::MacTransmission& send) {
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
    on_air =
        with_kind(frame.kind, send.frame != nullptr ? send.header : std::span<const std::uint8_t>{},
                  on_air, node.typed_payload);
  }
  node.started_len = node.radio->start_frame(phy::FrameTag{frame.src, frame.dst, serial}, on_air);
  node.mac->on_sent(now_, now_ + static_cast<SampleTime>(node.started_len));
  node.started_awaits_verdict = send.awaits_verdict;
  node.started_first_attempt = !send.retry;
  if (send.awaits_verdict && !send.retry) node.mac_frame = serial;
  node.started.emplace(serial, std::move(frame));
}

void LockStepEngine::record_transmissions() {
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

void LockStepEngine::publish_status() {
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
  wr(status_.workers, tuner_->workers());
  if (link_) {
    wr(status_.exchanged_bytes, link_->bytes_sent());
    wr(status_.exchange_wall_s, link_->wall_s());
  }
}

std::unique_ptr<Engine> make_engine(const scenario::Scenario& scenario, FrameSink& sink,
                                    TransceiverFactory factory, Distribution distribution) {
  return std::make_unique<LockStepEngine>(scenario, sink, factory, std::move(distribution));
}

}  // namespace rfsitl::engine
