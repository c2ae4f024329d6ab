// The MAC "csma": 802.11's distributed coordination function (DCF) on the
// engine's ticks. A node listens with its own receiver (the engine reports,
// every tick, whether its receiver was inside a frame or heard energy over the
// threshold), waits until the channel has been idle for DIFS, then counts down
// a random backoff of idle slots, frozen while the channel is busy. As in
// 802.11's DCF, a frame that arrives to an idle channel (idle for DIFS at
// least, no backoff pending) goes at once; one that finds the channel busy, or
// idle for less than DIFS, draws a backoff first, so nodes whose frames queued
// up during the same busy period do not all start when it ends. The first frame
// after start draws one too: interfaces that come up together (IPv6 duplicate
// address detection, router solicitations) would otherwise send together.
// Unicast frames are acknowledged after SIFS; without an ACK the frame is sent
// again with the contention window doubled, up to the retry limit. Receivers
// drop repeats by sequence number (and acknowledge them again). Broadcasts are
// sent once, without ACK. Every transmission is followed by a fresh backoff
// (the "post-backoff"), so a saturated node contends for every frame, as in
// Bianchi's model. RTS/CTS is not implemented.
#include <algorithm>
#include <array>
#include <cstdio>
#include <memory>
#include <optional>
#include <unordered_map>
#include <utility>

#include "../mac_timing.hpp"
#include "csma_settings.hpp"
#include "rfsitl/common/xoshiro256.hpp"
#include "rfsitl/config/fields.hpp"
#include "rfsitl/mac/mac.hpp"

namespace rfsitl::mac {
namespace {

const config::Fields<CsmaSettings>& csma_fields() {
  using S = CsmaSettings;
  static const auto f =
      config::Fields<S>()
          .real("slot_us", &S::slot_us, "us", {0.0, 1e6},
                "backoff slot; rounded up to whole ticks (at least one): the engine senses "
                "the channel once per tick")
          .real("sifs_us", &S::sifs_us, "us", {0.0, 1e6},
                "gap before an ACK, counted from the tick the data frame was decoded in; "
                "rounded up to whole ticks (at least one). DIFS = SIFS + 2 slots")
          .integer("cw_min", &S::cw_min, "slots", 1, 65535,
                   "contention window of a first attempt: backoff drawn from 0..cw_min")
          .integer("cw_max", &S::cw_max, "slots", 1, 65535,
                   "largest contention window; each retry doubles the window (2 cw + 1) up "
                   "to this")
          .integer("retry_limit", &S::retry_limit, "", 0, 255,
                   "retransmissions of a unicast frame without ACK before it is given up "
                   "(lost: retry_limit)")
          .real("cca_threshold_db", &S::cca_threshold_db, "dB", {0.5, 60.0},
                "energy detection: the channel is busy when a tick's received power exceeds "
                "the noise power by this much (a frame the receiver has detected makes it "
                "busy at any level)")
          .rule([](const S& s) {
            if (s.cw_max < s.cw_min) {
              throw config::SettingError("cw_max", "must be at least cw_min (" +
                                                       std::to_string(s.cw_min) + "), got " +
                                                       std::to_string(s.cw_max));
            }
          });
  return f;
}

constexpr std::uint8_t kAck = 1;  // control frame type: [kAck][seq hi][seq lo]
constexpr std::size_t kAckBytes = 3;
constexpr std::size_t kHeaderBytes = 2;  // data frame header: [seq hi][seq lo]

class CsmaMac final : public Mac {
 public:
  CsmaMac(const CsmaSettings& s, const MacContext& c)
      : s_(s),
        c_(c),
        slot_(detail::ticks_of_us(s.slot_us, c)),
        sifs_(detail::ticks_of_us(s.sifs_us, c)),
        difs_(sifs_ + 2 * slot_),
        ack_samples_(c.frame_samples(1 + kAckBytes)),
        cw_(s.cw_min),
        rng_(c.seed) {}

  std::size_t header_bytes() const override { return kHeaderBytes; }
  std::size_t max_radio_payload() const override { return c_.radio_max_payload; }
  std::optional<double> carrier_sense_db() const override { return s_.cca_threshold_db; }

  std::optional<MacTransmission> on_tick(SampleTime now, bool tx_busy, FrameQueue& queue) override {
    if (ack_due_ && now >= ack_due_->at) {
      const PendingAck ack = *ack_due_;
      ack_due_.reset();
      // An ACK that cannot go now (the transmitter is busy) would come too late.
      if (!tx_busy) {
        control_ = {kAck, static_cast<std::uint8_t>(ack.seq >> 8),
                    static_cast<std::uint8_t>(ack.seq & 0xFF)};
        MacCounters::bump(c_.counters->control_sent);
        sending_ = Sending::kControl;
        return MacTransmission{FrameKind::kMacControl, ack.to, nullptr, control_, false, false};
      }
    }
    if (ack_deadline_ && now >= *ack_deadline_) ack_timed_out();
    if (tx_busy || ack_deadline_) return std::nullopt;
    if (!current_) {
      if (queue.peek() == nullptr) return std::nullopt;
      current_ = queue.take();
      attempts_ = 0;
      ++seq_;
      if (backoff_ == 0 && (!sent_any_ || idle_ticks_ < difs_)) draw_backoff();
      sent_any_ = true;
    }
    if (backoff_ > 0 || idle_ticks_ < difs_) return std::nullopt;
    ++attempts_;
    header_ = {static_cast<std::uint8_t>(seq_ >> 8), static_cast<std::uint8_t>(seq_ & 0xFF)};
    const bool unicast = current_->dst != kBroadcastId;
    sending_ = unicast ? Sending::kUnicast : Sending::kBroadcast;
    if (attempts_ > 1) MacCounters::bump(c_.counters->retries);
    return MacTransmission{current_->kind, current_->dst, &*current_,
                           header_,        attempts_ > 1, unicast};
  }

  void on_sent(SampleTime, SampleTime end) override {
    switch (sending_) {
      case Sending::kUnicast:
        ack_deadline_ = ack_deadline(end);
        break;
      case Sending::kBroadcast:
        current_.reset();
        draw_backoff();
        break;
      case Sending::kControl:
        break;
    }
  }

  std::optional<Verdict> take_verdict() override { return std::exchange(verdict_, std::nullopt); }

  void on_sensed(bool busy) override {
    MacCounters::bump(c_.counters->sensed_ticks);
    if (busy) {
      MacCounters::bump(c_.counters->busy_ticks);
      idle_ticks_ = 0;
      return;
    }
    ++idle_ticks_;
    // After DIFS of idle channel, one backoff slot ends every slot_ ticks.
    if (backoff_ > 0 && idle_ticks_ > difs_ && (idle_ticks_ - difs_) % slot_ == 0) {
      --backoff_;
      MacCounters::bump(c_.counters->backoff_slots);
    }
  }

  RxDecision on_data(NodeId src, std::span<const std::uint8_t> header, bool to_me,
                     SampleTime now) override {
    const auto seq = static_cast<std::uint16_t>((header[0] << 8) | header[1]);
    // Acknowledge every unicast decode, repeats too: the sender repeats
    // because it missed the ACK.
    if (to_me) ack_due_ = PendingAck{src, seq, now + static_cast<SampleTime>(sifs_ * tick())};
    const auto [last, first_from_src] = last_seq_.try_emplace(src, seq);
    if (!first_from_src && last->second == seq) {
      MacCounters::bump(c_.counters->duplicates);
      return {false};
    }
    last->second = seq;
    return {true};
  }

  void on_control(NodeId src, std::span<const std::uint8_t> content, SampleTime) override {
    if (content.size() != kAckBytes || content[0] != kAck) return;
    const auto seq = static_cast<std::uint16_t>((content[1] << 8) | content[2]);
    // Only the ACK of the frame awaiting one counts; a late one is ignored.
    if (!ack_deadline_ || !current_ || current_->dst != src || seq != seq_) return;
    ack_deadline_.reset();
    finish(Verdict::kAcknowledged);
  }

  std::string describe() const override {
    char line[200];
    std::snprintf(line, sizeof line,
                  "csma: slot %.0f us (%zu tick%s), SIFS %.0f us, DIFS %.0f us, CW %u..%u, "
                  "retry limit %u, CCA %.1f dB over the noise",
                  detail::us_of_ticks(slot_, c_), slot_, slot_ == 1 ? "" : "s",
                  detail::us_of_ticks(sifs_, c_), detail::us_of_ticks(difs_, c_), s_.cw_min,
                  s_.cw_max, s_.retry_limit, s_.cca_threshold_db);
    return line;
  }

 private:
  enum class Sending : std::uint8_t { kUnicast, kBroadcast, kControl };
  struct PendingAck {
    NodeId to;
    std::uint16_t seq;
    SampleTime at;
  };

  SampleTime tick() const { return static_cast<SampleTime>(c_.tick_samples); }

  /// When to give up waiting for the ACK of a frame that ended at `end`: the
  /// receiver decodes it in the tick holding its last sample plus the latency,
  /// answers SIFS ticks later, and this node decodes that ACK the same way;
  /// one slot more of slack.
  SampleTime ack_deadline(SampleTime end) const {
    const auto lat = static_cast<SampleTime>(c_.rx_latency_samples);
    const SampleTime data_decoded = (end - 1 + lat) / tick();
    const SampleTime ack_start = (data_decoded + static_cast<SampleTime>(sifs_)) * tick();
    const SampleTime ack_end = ack_start + static_cast<SampleTime>(ack_samples_);
    const SampleTime ack_decoded = (ack_end - 1 + lat) / tick();
    return (ack_decoded + 1 + static_cast<SampleTime>(slot_)) * tick();
  }

  void ack_timed_out() {
    ack_deadline_.reset();
    MacCounters::bump(c_.counters->ack_timeouts);
    if (attempts_ > s_.retry_limit) {
      MacCounters::bump(c_.counters->retry_drops);
      finish(Verdict::kGaveUp);
      return;
    }
    cw_ = std::min(2 * cw_ + 1, s_.cw_max);
    draw_backoff();
  }

  void finish(Verdict v) {
    verdict_ = v;
    current_.reset();
    cw_ = s_.cw_min;
    draw_backoff();
  }

  void draw_backoff() { backoff_ = static_cast<std::uint32_t>(rng_.next() % (cw_ + 1ULL)); }

  CsmaSettings s_;
  MacContext c_;
  std::size_t slot_;  // ticks
  std::size_t sifs_;  // ticks
  std::size_t difs_;  // ticks
  std::size_t ack_samples_;
  std::uint32_t cw_;
  std::uint32_t backoff_ = 0;  // slots left
  bool sent_any_ = false;      // a frame was taken since start (the first draws a backoff)
  std::size_t idle_ticks_ = 0;
  Xoshiro256 rng_;

  std::optional<NetFrame> current_;  // the frame being sent, until its verdict
  std::uint32_t attempts_ = 0;
  std::uint16_t seq_ = 0;
  std::array<std::uint8_t, kHeaderBytes> header_{};
  std::array<std::uint8_t, kAckBytes> control_{};
  Sending sending_ = Sending::kControl;
  std::optional<SampleTime> ack_deadline_;
  std::optional<Verdict> verdict_;
  std::optional<PendingAck> ack_due_;
  std::unordered_map<NodeId, std::uint16_t> last_seq_;  // per sender, for repeats
};

}  // namespace

MacComponent csma_component() {
  return {csma_fields().info("mac", "csma",
                             "802.11 DCF-like CSMA/CA: carrier sense on the node's own received "
                             "samples, DIFS, binary exponential backoff, ACKs and retries for "
                             "unicast, broadcast sent once"),
          [](const config::Settings& settings, const MacContext& c) -> std::unique_ptr<Mac> {
            return std::make_unique<CsmaMac>(csma_fields().build(settings), c);
          }};
}

}  // namespace rfsitl::mac
