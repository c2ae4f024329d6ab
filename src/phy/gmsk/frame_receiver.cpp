#include "frame_receiver.hpp"

#include <algorithm>
#include <cmath>

#include "crc.hpp"

namespace rfsitl::phy::gmsk {

FrameReceiver::FrameReceiver(const GmskPulse& pulse, std::size_t max_payload_bytes,
                             const ReceiverKernels& kernels)
    : kernels_(&kernels),
      k_(pulse.samples_per_symbol),
      max_payload_(max_payload_bytes),
      c0_(pulse.c0),
      period_samples_(static_cast<unsigned>(kPreamblePeriodSymbols) * k_),
      // A detection can come late (low SNR, or the window just filled after a
      // reset): look again at the last 16 symbols plus the sync word.
      replay_samples_((kSyncSymbols + 16) * k_),
      // The detector fires while its window is in the preamble, at most one
      // period after the preamble's end; the sync peak is a sync word later.
      search_horizon_((kSyncSymbols + 2 * kPreamblePeriodSymbols) * k_ + pulse.c0.size()),
      // The ring holds what the replay, the filter and the detector look back
      // on, and a block of symbols that demodulate_symbols() filters at once.
      ring_(std::max(replay_samples_ + pulse.c0.size() + period_samples_ + 4 * k_,
                     kSymbolBlock * k_ + pulse.c0.size())),
      delayed_(period_samples_),
      window_(SyncCorrelator::kMaxBlock + pulse.c0.size() - 1),
      mf_(SyncCorrelator::kMaxBlock),
      bits_(kSymbolBlock),
      detector_(k_),
      sync_(k_, kernels),
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
      case State::kSearch:
        i = scan_search(in, i, handler);
        break;
    }
  }
}

std::size_t FrameReceiver::scan_frame(std::span<const cf32> in, std::size_t i, RxHandler& handler) {
  // Inside a frame: store the samples up to the last symbol whose
  // matched-filter time the block reaches (not past the header's or the
  // payload's end), then decide those symbols. During the header the detector
  // keeps running (the lock may be false); during the payload it rests.
  const std::size_t n = in.size();
  while (i < n && (state_ == State::kHeader || state_ == State::kPayload)) {
    const std::uint64_t last = now_ + (n - i) - 1;
    std::size_t count = 0;
    if (next_symbol_time_ <= last) {
      count = static_cast<std::size_t>(std::min<std::uint64_t>(
          (last - next_symbol_time_) / k_ + 1, std::min(symbols_to_boundary(), kSymbolBlock)));
    }
    const std::size_t take =
        count > 0 ? static_cast<std::size_t>(next_symbol_time_ + (count - 1) * k_ + 1 - now_)
                  : n - i;
    const cf32* x = in.data() + i;
    if (state_ == State::kHeader) {
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
    if (count > 0) demodulate_symbols(count, handler);
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

std::size_t FrameReceiver::scan_search(std::span<const cf32> in, std::size_t i,
                                       RxHandler& handler) {
  const std::size_t n = std::min(in.size() - i, SyncCorrelator::kMaxBlock);
  return i + search(now_, n, in.data() + i, handler);
}

void FrameReceiver::start_search(std::uint64_t t, std::uint64_t deadline, RxHandler& handler) {
  state_ = State::kSearch;
  deadline_ = deadline;
  candidate_ = false;
  sync_.reset();
  // Replay the recent past through the search (and, if it locks there, the
  // demodulator, up to t); the ring still holds it.
  const std::uint64_t from = t + 1 >= replay_samples_ ? t + 1 - replay_samples_ : 0;
  search(from, static_cast<std::size_t>(t + 1 - from), nullptr, handler);
  demodulate_until(t, handler);
}

std::size_t FrameReceiver::search(std::uint64_t first, std::size_t n, const cf32* fresh,
                                  RxHandler& handler) {
  // The samples of times first .. first + n - 1 through the search, block by
  // block: from the ring in a replay (fresh null), else new input (fresh[0 ..
  // n)), which also goes to the ring and the detector as it is used. Returns
  // the samples used: all of them, or those up to the one at which the
  // search ended.
  for (std::size_t done = 0; done < n;) {
    const std::size_t m = std::min(n - done, SyncCorrelator::kMaxBlock);
    const std::uint64_t t0 = first + done;
    filter_search_block(t0, m, fresh != nullptr ? fresh + done : nullptr);
    sync_.push({mf_.data(), m});
    for (std::size_t j = 0; j < m; ++j) {
      const std::uint64_t t = t0 + j;
      bool preamble_seen = false;
      if (fresh != nullptr) {
        now_ = t + 1;
        ring_.put(t, fresh[done + j]);
        preamble_seen = detector_.push(fresh[done + j], ring_.at(t - period_samples_));
      }
      if (!search_step(t, j, preamble_seen, handler)) return done + j + 1;
    }
    done += m;
  }
  return n;
}

void FrameReceiver::filter_search_block(std::uint64_t first, std::size_t n, const cf32* fresh) {
  // Output q is the filter over the len samples ending at time first + q: the
  // len - 1 before `first` from the ring, then the block's own.
  const std::size_t len = c0_.size();
  if (fresh != nullptr) {
    ring_.copy_out(first + 1 - len, len - 1, window_.data());
    std::copy_n(fresh, n, window_.data() + (len - 1));
  } else {
    ring_.copy_out(first + 1 - len, n + len - 1, window_.data());
  }
  kernels_->matched_filter(reinterpret_cast<const float*>(window_.data()), c0_.data(), len, 2 * n,
                           reinterpret_cast<float*>(mf_.data()));
}

bool FrameReceiver::search_step(std::uint64_t t, std::size_t j, bool preamble_seen,
                                RxHandler& handler) {
  if (preamble_seen) deadline_ = std::max(deadline_, t + search_horizon_);
  const float rho = sync_.rho(j);
  if (!candidate_) {
    if (rho >= kSyncThreshold) {
      candidate_ = true;
      best_rho_ = rho;
      best_gain_ = sync_.gain(j);
      best_preamble_gain_ = sync_.preamble_gain(j);
      best_time_ = t;
      candidate_end_ = t + k_;
    } else if (t >= deadline_) {
      state_ = State::kIdle;  // the detector has kept running: no reset
    }
  } else {
    if (rho > best_rho_) {
      best_rho_ = rho;
      best_gain_ = sync_.gain(j);
      best_preamble_gain_ = sync_.preamble_gain(j);
      best_time_ = t;
    }
    if (t >= candidate_end_) lock(t, handler);
  }
  return state_ == State::kSearch;
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

std::size_t FrameReceiver::symbols_to_boundary() const {
  const std::size_t bytes =
      state_ == State::kHeader ? kHeaderBytes : frame_header_.payload_bytes + kPayloadCrcBytes;
  return (bytes - bytes_done_) * 8 - bit_in_byte_;
}

void FrameReceiver::demodulate_until(std::uint64_t t, RxHandler& handler) {
  while (next_symbol_time_ <= t && (state_ == State::kHeader || state_ == State::kPayload)) {
    demodulate_symbols(
        static_cast<std::size_t>(std::min<std::uint64_t>(
            (t - next_symbol_time_) / k_ + 1, std::min(symbols_to_boundary(), kSymbolBlock))),
        handler);
  }
}

void FrameReceiver::demodulate_symbols(std::size_t count, RxHandler& handler) {
  // The filter (independent of the decisions) inside the decision loop, so
  // that it runs in the shadow of the loop's dependency chain; then the bits.
  // Precondition: count <= symbols_to_boundary(), so that only the last bit
  // can end the header or payload.
  const std::uint64_t t0 = next_symbol_time_;
  cf32* soft = soft_.data() + symbols_done_;
  coherent_.decide(
      count, [&](std::size_t q) { return ring_.filter(t0 + q * k_, c0_.data(), c0_.size()); }, soft,
      bits_.data());
  for (std::size_t q = 0; q < count; ++q) {
    const float e = std::abs(soft[q].real()) - 1.0F;
    error_energy_ += e * e;
    ++symbols_done_;
    next_symbol_time_ += k_;
    on_bit(bits_[q], handler);
  }
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
