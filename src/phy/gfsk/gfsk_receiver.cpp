#include "gfsk_receiver.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "rfsitl/common/crc.hpp"

namespace rfsitl::phy::gfsk {
namespace {

constexpr std::uint64_t kPatternMask = (std::uint64_t{1} << kSyncPatternBits) - 1;

/// True if `diff` has at most kSyncErrors bits set. With at most 3 errors one
/// of the four 12-bit quarters is clean (pigeonhole): that cheap test rejects
/// all but 1 in 1000 noise samples before the (software) popcount.
bool near_pattern(std::uint64_t diff) {
  static_assert(GfskFrameReceiver::kSyncErrors < 4 && kSyncPatternBits == 48);
  constexpr std::uint64_t kQuarter = 0xFFF;
  const bool clean_quarter = (diff & kQuarter) == 0 || (diff & (kQuarter << 12)) == 0 ||
                             (diff & (kQuarter << 24)) == 0 || (diff & (kQuarter << 36)) == 0;
  return clean_quarter && std::popcount(diff) <= static_cast<int>(GfskFrameReceiver::kSyncErrors);
}

}  // namespace

GfskFrameReceiver::GfskFrameReceiver(const GfskSettings& s)
    : k_(s.samples_per_symbol),
      kind_(s.receiver),
      whitening_(s.whitening),
      offset_symbols_(
          static_cast<unsigned>(std::min<std::size_t>(kOffsetSymbols, 8 * s.preamble_bytes - 2)) &
          ~1U),
      max_payload_(s.max_payload_bytes),
      energy_(s.samples_per_symbol, s.modulation_index),
      discriminator_(s.samples_per_symbol, s.modulation_index),
      // The alignment looks back over the pattern, the offset estimate's
      // preamble symbols and one more symbol of candidate timings.
      ring_(std::bit_ceil(std::size_t{k_} * (kSyncPatternBits + kOffsetSymbols + 2))),
      ring_mask_(ring_.size() - 1),
      history_(k_, 0) {
  soft_.reserve(8 * (kHeaderBytes + max_payload_ + kPayloadCrcBytes));
  payload_.reserve(max_payload_ + kPayloadCrcBytes);
}

void GfskFrameReceiver::reset() {
  energy_.reset();
  discriminator_.reset();
  std::fill(ring_.begin(), ring_.end(), 0.0F);
  std::fill(history_.begin(), history_.end(), 0);
  phase_ = 0;
  t_ = 0;
  state_ = State::kSearch;
}

void GfskFrameReceiver::push(std::span<const cf32> in, RxHandler& handler) {
  if (kind_ == GfskReceiver::kEnergy) {
    run(energy_, in, handler);
  } else {
    run(discriminator_, in, handler);
  }
}

template <class Metric>
void GfskFrameReceiver::run(Metric& metric, std::span<const cf32> in, RxHandler& handler) {
  for (const cf32 y : in) {
    const float m = metric.step(y);
    ring_[t_ & ring_mask_] = m;
    std::uint64_t& h = history_[phase_];
    h = (h << 1) | (m > 0.0F ? 1U : 0U);
    switch (state_) {
      case State::kSearch:
        if (near_pattern((h ^ kSyncPattern) & kPatternMask)) {
          hit_time_ = t_;
          state_ = State::kAlign;
        }
        break;
      case State::kAlign:
        break;
      case State::kHeader:
      case State::kPayload:
        power_ += std::norm(y);
        ++power_samples_;
        if (t_ == next_symbol_time_) {
          next_symbol_time_ += k_;
          on_symbol(m - offset_, handler);
        }
        break;
    }
    if (state_ == State::kAlign && t_ == hit_time_ + k_ / 2) lock();
    if (++phase_ == k_) phase_ = 0;
    ++t_;
  }
}

void GfskFrameReceiver::lock() {
  // Candidate timings: the k samples ending now, so that the first header
  // symbol (k after the sync word's last) is still to come.
  float best = -std::numeric_limits<float>::infinity();
  std::uint64_t best_time = t_;
  for (std::uint64_t c = t_ + 1 - k_; c <= t_; ++c) {
    float score = 0.0F;
    for (unsigned i = 0; i < kSyncPatternBits; ++i) {
      const float m = metric_at(c - std::uint64_t{i} * k_);
      score += ((kSyncPattern >> i) & 1U) != 0 ? m : -m;
    }
    if (score > best) {
      best = score;
      best_time = c;
    }
  }
  offset_ = 0.0F;
  if (kind_ == GfskReceiver::kDiscriminator) {
    // Preamble symbols alternate, so their mean is the carrier offset's bias.
    float sum = 0.0F;
    for (unsigned j = 0; j < offset_symbols_; ++j) {
      sum += metric_at(best_time - std::uint64_t{kSyncBits + j} * k_);
    }
    offset_ = sum / static_cast<float>(offset_symbols_);
  }
  next_symbol_time_ = best_time + k_;
  state_ = State::kHeader;
  whitener_ = gmsk::Whitener{};
  octet_ = 0;
  bits_in_octet_ = 0;
  octets_done_ = 0;
  octets_wanted_ = kHeaderBytes;
  soft_.clear();
  power_ = 0.0;
  power_samples_ = 0;
}

void GfskFrameReceiver::on_symbol(float m, RxHandler& handler) {
  soft_.push_back(m);
  octet_ = static_cast<std::uint8_t>((octet_ << 1) | (m > 0.0F ? 1U : 0U));
  if (++bits_in_octet_ < 8) return;
  bits_in_octet_ = 0;
  const std::uint8_t b = whitening_ ? static_cast<std::uint8_t>(octet_ ^ whitener_.next()) : octet_;
  if (state_ == State::kHeader) {
    header_[octets_done_++] = b;
    if (octets_done_ == kHeaderBytes) finish_header(handler);
  } else {
    payload_[octets_done_++] = b;
    if (octets_done_ == octets_wanted_) finish_payload(handler);
  }
}

void GfskFrameReceiver::finish_header(RxHandler& handler) {
  const auto h = gmsk::decode_header(header_);
  state_ = State::kSearch;
  if (!h) {
    tag_ = FrameTag{};
    report(false, false, {}, handler);
    return;
  }
  tag_ = h->tag;
  if (h->payload_bytes > max_payload_) {
    report(true, false, {}, handler);
    return;
  }
  octets_wanted_ = h->payload_bytes + kPayloadCrcBytes;
  payload_.resize(octets_wanted_);
  octets_done_ = 0;
  state_ = State::kPayload;
}

void GfskFrameReceiver::finish_payload(RxHandler& handler) {
  const std::size_t n = payload_.size() - kPayloadCrcBytes;
  const auto sent = static_cast<std::uint16_t>((payload_[n] << 8) | payload_[n + 1]);
  const std::span<const std::uint8_t> payload = std::span(payload_).first(n);
  state_ = State::kSearch;
  report(true, crc16(payload) == sent, payload, handler);
}

void GfskFrameReceiver::report(bool header_valid, bool payload_valid,
                               std::span<const std::uint8_t> payload, RxHandler& handler) {
  double mean_abs = 0.0;
  for (const float v : soft_) mean_abs += std::fabs(v);
  mean_abs /= static_cast<double>(std::max<std::size_t>(soft_.size(), 1));
  const float scale = mean_abs > 0.0 ? static_cast<float>(1.0 / mean_abs) : 0.0F;
  symbols_.resize(soft_.size());
  double spread = 0.0;
  for (std::size_t i = 0; i < soft_.size(); ++i) {
    const float z = soft_[i] * scale;
    symbols_[i] = cf32{z, 0.0F};
    spread += (std::fabs(z) - 1.0) * (std::fabs(z) - 1.0);
  }
  spread /= static_cast<double>(std::max<std::size_t>(soft_.size(), 1));

  RxEvent ev;
  ev.tag = tag_;
  ev.header_valid = header_valid;
  ev.payload_valid = payload_valid;
  ev.payload = payload;
  const double power = power_ / static_cast<double>(std::max<std::uint64_t>(power_samples_, 1));
  ev.rssi_db = static_cast<float>(10.0 * std::log10(std::max(power, 1e-30)));
  ev.evm_db = static_cast<float>(10.0 * std::log10(std::max(spread, 1e-30)));
  ev.symbols = symbols_;
  handler.on_rx(ev);
}

}  // namespace rfsitl::phy::gfsk
