#include "frame_receiver.hpp"

#include <algorithm>
#include <cmath>

#include "crc.hpp"

namespace rfsitl::phy::gmsk {

FrameReceiver::FrameReceiver(const GmskPulse& pulse, std::size_t max_payload_bytes)
    : k_(pulse.samples_per_symbol),
      max_payload_(max_payload_bytes),
      c0_(pulse.c0),
      period_samples_(static_cast<unsigned>(kPreamblePeriodSymbols) * k_),
      // A detection can come late (low SNR, or the window just filled after a
      // reset): look again at the last 16 symbols plus the sync word.
      replay_samples_((kSyncSymbols + 16) * k_),
      // The detector fires while its window is in the preamble, at most one
      // period after the preamble's end; the sync peak is a sync word later.
      search_horizon_((kSyncSymbols + 2 * kPreamblePeriodSymbols) * k_ + pulse.c0.size()),
      ring_(replay_samples_ + pulse.c0.size() + period_samples_ + 4 * k_),
      delayed_(period_samples_),
      detector_(k_),
      sync_(k_),
      payload_(max_payload_bytes + kPayloadCrcBytes),
      soft_(8 * (kHeaderBytes + max_payload_bytes + kPayloadCrcBytes)) {}

void FrameReceiver::reset() {
  state_ = State::kIdle;
  ring_.clear();
  detector_.reset();
  sync_.reset();
  candidate_ = false;
}

void FrameReceiver::push(std::span<const cf32> in, RxHandler& handler) {
  std::size_t i = 0;
  while (i < in.size()) {
    switch (state_) {
      case State::kIdle:
        i = scan_idle(in, i, handler);
        break;
      case State::kHeader:
      case State::kPayload:
        i = scan_frame(in, i, handler);
        break;
      case State::kSearch: {
        const cf32 x = in[i++];
        const std::uint64_t t = now_++;
        ring_.put(t, x);
        step(t, detector_.push(x, ring_.at(t - period_samples_)), handler);
        break;
      }
    }
  }
}

std::size_t FrameReceiver::scan_frame(std::span<const cf32> in, std::size_t i, RxHandler& handler) {
  // Inside a frame: store the samples up to the next symbol's matched-filter
  // time, then decide that symbol. During the header the detector keeps
  // running (the lock may be false); during the payload it rests.
  const State state = state_;
  const std::size_t n = in.size();
  while (i < n) {
    const auto take =
        static_cast<std::size_t>(std::min<std::uint64_t>(next_symbol_time_ + 1 - now_, n - i));
    const cf32* x = in.data() + i;
    if (state == State::kHeader) {
      for (std::size_t j = 0; j < take; ++j) {
        const std::uint64_t t = now_ + j;
        ring_.put(t, x[j]);
        if (detector_.push(x[j], ring_.at(t - period_samples_))) {
          preamble_during_header_ = true;
          last_preamble_ = t;
        }
      }
    } else {
      ring_.put_block(now_, x, take);
    }
    now_ += take;
    i += take;
    if (now_ <= next_symbol_time_) break;  // the block ended first
    demodulate_symbol(handler);
    if (state_ != state) break;
  }
  return i;
}

std::size_t FrameReceiver::scan_idle(std::span<const cf32> in, std::size_t i, RxHandler& handler) {
  // The hot path on noise: the detector alone, then the samples go to the ring
  // in one copy. The delayed samples come from the ring for the first D
  // samples and from the input itself after that.
  const std::size_t d = period_samples_;
  const std::size_t n = in.size() - i;
  const cf32* x = in.data() + i;
  for (std::size_t j = 0; j < d; ++j) delayed_[j] = ring_.at(now_ + j - d);
  bool detected = false;
  std::size_t used = detector_.scan(x, delayed_.data(), std::min(n, d), &detected);
  if (!detected && n > d) used += detector_.scan(x + d, x, n - d, &detected);
  ring_.put_block(now_, x, used);
  now_ += used;
  if (detected) start_search(now_ - 1, now_ - 1 + search_horizon_, handler);
  return i + used;
}

void FrameReceiver::start_search(std::uint64_t t, std::uint64_t deadline, RxHandler& handler) {
  state_ = State::kSearch;
  deadline_ = deadline;
  candidate_ = false;
  sync_.reset();
  // Replay the recent past through the search (and, if it locks there, the
  // demodulator); the ring still holds it.
  const std::uint64_t from = t + 1 >= replay_samples_ ? t + 1 - replay_samples_ : 0;
  for (std::uint64_t u = from; u <= t && state_ != State::kIdle; ++u) step(u, false, handler);
}

void FrameReceiver::step(std::uint64_t t, bool preamble_seen, RxHandler& handler) {
  switch (state_) {
    case State::kSearch: {
      if (preamble_seen) deadline_ = std::max(deadline_, t + search_horizon_);
      const float rho = sync_.push(ring_.filter(t, c0_.data(), c0_.size()));
      if (!candidate_) {
        if (rho >= kSyncThreshold) {
          candidate_ = true;
          best_rho_ = rho;
          best_gain_ = sync_.gain();
          best_preamble_gain_ = sync_.preamble_gain();
          best_time_ = t;
          candidate_end_ = t + k_;
        } else if (t >= deadline_) {
          state_ = State::kIdle;  // the detector has kept running: no reset
        }
      } else {
        if (rho > best_rho_) {
          best_rho_ = rho;
          best_gain_ = sync_.gain();
          best_preamble_gain_ = sync_.preamble_gain();
          best_time_ = t;
        }
        if (t >= candidate_end_) lock(t, handler);
      }
      break;
    }
    case State::kHeader:
      if (preamble_seen) {
        preamble_during_header_ = true;
        last_preamble_ = t;
      }
      demodulate_until(t, handler);
      break;
    case State::kPayload:
      demodulate_until(t, handler);
      break;
    case State::kIdle:
      break;
  }
}

void FrameReceiver::lock(std::uint64_t t, RxHandler& handler) {
  state_ = State::kHeader;
  candidate_ = false;
  // Carrier frequency: the phase turn from the preamble's last 32 symbols to
  // the sync word, 32 symbols later. G is the sync word's mean gain, i.e. its
  // phase at the word's middle (symbol 15.5); the first header symbol is
  // symbol 32, 16.5 symbols on.
  const float per_symbol =
      std::arg(best_gain_ * std::conj(best_preamble_gain_)) / static_cast<float>(kSyncSymbols);
  const cf32 gain = best_gain_ * std::polar(1.0F, per_symbol * (kSyncSymbols / 2.0F + 0.5F));
  coherent_.start(gain, kSyncSymbols, per_symbol);
  next_symbol_time_ = best_time_ + k_;
  preamble_during_header_ = false;
  whitener_ = Whitener{};
  bit_in_byte_ = 0;
  byte_ = 0;
  bytes_done_ = 0;
  symbols_done_ = 0;
  error_energy_ = 0.0F;
  demodulate_until(t, handler);
}

void FrameReceiver::demodulate_until(std::uint64_t t, RxHandler& handler) {
  while (next_symbol_time_ <= t && (state_ == State::kHeader || state_ == State::kPayload)) {
    demodulate_symbol(handler);
  }
}

void FrameReceiver::demodulate_symbol(RxHandler& handler) {
  cf32 z;
  const unsigned bit = coherent_.decide(ring_.filter(next_symbol_time_, c0_.data(), c0_.size()), z);
  soft_[symbols_done_++] = z;
  const float e = std::abs(z.real()) - 1.0F;
  error_energy_ += e * e;
  next_symbol_time_ += k_;
  on_bit(bit, handler);
}

void FrameReceiver::on_bit(unsigned bit, RxHandler& handler) {
  byte_ = static_cast<std::uint8_t>(byte_ | (bit << bit_in_byte_));
  if (++bit_in_byte_ < 8) return;
  const auto b = static_cast<std::uint8_t>(byte_ ^ whitener_.next());
  bit_in_byte_ = 0;
  byte_ = 0;
  if (state_ == State::kHeader) {
    header_[bytes_done_++] = b;
    if (bytes_done_ == kHeaderBytes) finish_header(handler);
  } else {
    payload_[bytes_done_++] = b;
    if (bytes_done_ == frame_header_.payload_bytes + kPayloadCrcBytes) finish_payload(handler);
  }
}

void FrameReceiver::finish_header(RxHandler& handler) {
  const auto header = decode_header(header_);
  if (!header) {
    report(FrameTag{}, false, false, {}, handler);
    // A false lock; if a preamble showed up meanwhile, go and find its sync word.
    if (preamble_during_header_) {
      start_search(now_ - 1, last_preamble_ + search_horizon_, handler);
    } else {
      state_ = State::kIdle;
    }
    return;
  }
  frame_header_ = *header;
  if (header->payload_bytes > max_payload_) {
    report(header->tag, true, false, {}, handler);
    state_ = State::kIdle;
    return;
  }
  state_ = State::kPayload;
  bytes_done_ = 0;
}

void FrameReceiver::finish_payload(RxHandler& handler) {
  const std::size_t n = frame_header_.payload_bytes;
  const std::span<const std::uint8_t> payload(payload_.data(), n);
  std::uint32_t sent = 0;
  for (unsigned i = 0; i < kPayloadCrcBytes; ++i) {
    sent |= static_cast<std::uint32_t>(payload_[n + i]) << (8 * i);
  }
  report(frame_header_.tag, true, crc32(payload) == sent, payload, handler);
  // The detector rested during the payload: its sums are stale.
  detector_.reset();
  state_ = State::kIdle;
}

void FrameReceiver::report(const FrameTag& tag, bool header_valid, bool payload_valid,
                           std::span<const std::uint8_t> payload, RxHandler& handler) {
  RxEvent ev;
  ev.tag = tag;
  ev.header_valid = header_valid;
  ev.payload_valid = payload_valid;
  ev.payload = payload;
  // |G|^2 ~ k times the signal power per sample (C0 has unit energy and holds
  // almost all of the signal's).
  ev.rssi_db = 10.0F * std::log10(std::max(std::norm(best_gain_) / static_cast<float>(k_), 1e-30F));
  ev.evm_db =
      10.0F *
      std::log10(std::max(
          error_energy_ / static_cast<float>(std::max<std::size_t>(symbols_done_, 1)), 1e-30F));
  ev.symbols = {soft_.data(), symbols_done_};
  handler.on_rx(ev);
}

}  // namespace rfsitl::phy::gmsk
