#include "code_channel.hpp"

namespace rfsitl::phy::dsss::detail {
namespace {

// Symbols over which the early-late gate sums powers before moving the timing.
constexpr std::size_t kTrackSymbols = 8;

}  // namespace

void CodeChannel::configure(const ListenCode& code, const ReceiverSettings& settings,
                            std::size_t max_block, std::int64_t start) {
  searcher_.configure(code.chips, settings.samples_per_chip, max_block,
                      settings.detection_threshold, start);
  period_ = searcher_.correlator().period();
  demod_.configure(settings.max_payload_bytes, period_);
  code_ = code;
  track_ = settings.samples_per_chip >= 2;
  demod_active_ = false;
  pending_.reset();
}

void CodeChannel::process(const FrontEnd& fe, std::int64_t b, std::span<CodeChannel> others,
                          FrameSink& sink) {
  for (;;) {
    if (demod_active_ && demod_.committed()) {
      // Inside a frame: this code's search rests until the frame is over.
      if (run_demod(fe, b, b, sink) != DemodResult::kFinished) return;
      demod_active_ = false;
      // The filter still holds the frame's last period, at neighbouring code
      // phases, for one period: keep the search from seeing it.
      const std::int64_t from = last_symbol_ + 1;
      searcher_.restart(from, from + static_cast<std::int64_t>(period_));
      continue;
    }
    if (!pending_) pending_ = searcher_.advance(fe, b);
    const std::int64_t limit = pending_ ? pending_->decided_at : b;
    if (demod_active_) {
      const DemodResult r = run_demod(fe, limit, b, sink);
      if (r == DemodResult::kFinished) demod_active_ = false;
      if (r == DemodResult::kCommitted) {
        pending_.reset();
        continue;
      }
    }
    if (!pending_) return;
    consider(*pending_, others);
    pending_.reset();
  }
}

bool CodeChannel::same_signal(std::int64_t timing) const {
  const auto p = static_cast<std::int64_t>(period_);
  const std::int64_t offset = ((timing - next_symbol_) % p + p) % p;
  return offset <= 1 || offset >= p - 1;
}

void CodeChannel::consider(const Candidate& c, std::span<CodeChannel> others) {
  // The same preamble found again while its SFD is being searched for.
  if (demod_active_ && same_signal(c.timing)) return;
  // The same frame seen on two codes at once (a strong frame leaks into other
  // codes of its family): the stronger code keeps it.
  for (CodeChannel& o : others) {
    if (&o == this || !o.demod_active_ || !o.same_signal(c.timing)) continue;
    if (o.strength_ >= c.strength) return;
    if (!o.demod_.committed()) o.demod_active_ = false;
  }
  demod_.start(c.reference, code_.id);
  demod_active_ = true;
  strength_ = c.strength;
  next_symbol_ = c.timing + static_cast<std::int64_t>(period_);
  early_ = on_time_ = late_ = 0.0F;
  tracked_ = 0;
}

CodeChannel::DemodResult CodeChannel::run_demod(const FrontEnd& fe, std::int64_t limit,
                                                std::int64_t b, FrameSink& sink) {
  const CodeCorrelator& corr = searcher_.correlator();
  const std::int64_t ahead = track_ ? 1 : 0;  // the late tap needs one more sample
  while (next_symbol_ < limit && next_symbol_ + ahead < b) {
    const std::int64_t t = next_symbol_;
    const cf32 z = corr.correlate(fe.y(t));
    std::int64_t step = static_cast<std::int64_t>(period_);
    if (track_) step += track_timing(fe, t, z);
    const bool was_committed = demod_.committed();
    last_symbol_ = t;
    next_symbol_ = t + step;
    if (demod_.push(z, sink)) return DemodResult::kFinished;
    if (!was_committed && demod_.committed()) return DemodResult::kCommitted;
  }
  return DemodResult::kRunning;
}

std::int64_t CodeChannel::track_timing(const FrontEnd& fe, std::int64_t t, cf32 z) {
  const CodeCorrelator& corr = searcher_.correlator();
  early_ += std::norm(corr.correlate(fe.y(t - 1)));
  late_ += std::norm(corr.correlate(fe.y(t + 1)));
  on_time_ += std::norm(z);
  if (++tracked_ < kTrackSymbols) return 0;
  std::int64_t shift = 0;
  if (late_ > on_time_ && late_ >= early_) {
    shift = 1;
  } else if (early_ > on_time_) {
    shift = -1;
  }
  early_ = on_time_ = late_ = 0.0F;
  tracked_ = 0;
  return shift;
}

}  // namespace rfsitl::phy::dsss::detail
