#include "stream_buffers.hpp"

#include <SoapySDR/Errors.h>

#include <algorithm>
#include <chrono>

namespace rfsitl::soapy {
namespace {

/// TX events kept for readStreamStatus. An application that never asks (GNU
/// Radio's sink, which writes without END_BURST: one underflow per packet)
/// must not grow the queue forever; the oldest go first.
constexpr std::size_t kMaxTxEvents = 1024;
/// How long read() waits before it repeats SOAPY_SDR_STREAM_ERROR.
constexpr std::chrono::microseconds kErrorRepeat{100'000};

std::chrono::microseconds micros(long timeout_us) {
  return std::chrono::microseconds(std::max(timeout_us, 0L));
}

}  // namespace

StreamBuffers::StreamBuffers(double sample_rate_hz, std::size_t rx_capacity,
                             std::size_t tx_capacity)
    : sample_rate_hz_(sample_rate_hz), rx_capacity_(rx_capacity), tx_capacity_(tx_capacity) {}

void StreamBuffers::set_rx_tuning(const PathTuning& t) {
  std::lock_guard lock(mutex_);
  rx_tuning_ = t;
}

void StreamBuffers::set_tx_tuning(const PathTuning& t) {
  std::lock_guard lock(mutex_);
  tx_tuning_ = t;
}

void StreamBuffers::set_rx_active(bool active) {
  std::lock_guard lock(mutex_);
  rx_active_ = active;
  rx_.clear();
  rx_buffered_ = 0;
  overflow_pending_ = false;
}

SampleTime StreamBuffers::now() const {
  std::lock_guard lock(mutex_);
  return now_;
}

bool StreamBuffers::now_after_first_tick(SampleTime& t, long timeout_us) {
  std::unique_lock lock(mutex_);
  changed_.wait_for(lock, micros(timeout_us), [&] { return ticked_ || closed_; });
  if (!ticked_) return false;
  t = now_;
  return true;
}

bool StreamBuffers::connected() const {
  std::lock_guard lock(mutex_);
  return !closed_;
}

int StreamBuffers::read(std::span<cf32> out, SampleTime& time, long timeout_us) {
  std::unique_lock lock(mutex_);
  changed_.wait_for(lock, micros(timeout_us),
                    [&] { return !rx_.empty() || overflow_pending_ || closed_; });
  if (overflow_pending_) {
    overflow_pending_ = false;
    return SOAPY_SDR_OVERFLOW;
  }
  if (rx_.empty() && closed_) {
    // Once said, the error comes after the timeout (at most kErrorRepeat): an
    // application that retries on errors (GNU Radio's source logs and calls
    // again) must not spin, nor starve its other threads of the device.
    if (error_reported_) changed_.wait_for(lock, std::min(micros(timeout_us), kErrorRepeat));
    error_reported_ = true;
    return SOAPY_SDR_STREAM_ERROR;
  }
  if (rx_.empty()) return SOAPY_SDR_TIMEOUT;
  Chunk& c = rx_.front();
  const std::size_t n = std::min(out.size(), c.samples.size() - c.used);
  std::copy_n(c.samples.begin() + static_cast<std::ptrdiff_t>(c.used), n, out.begin());
  time = c.time + static_cast<SampleTime>(c.used);
  c.used += n;
  rx_buffered_ -= n;
  if (c.used == c.samples.size()) rx_.pop_front();
  return static_cast<int>(n);
}

int StreamBuffers::write(std::span<const cf32> in, const SampleTime* time, bool end_burst,
                         long timeout_us) {
  std::unique_lock lock(mutex_);
  changed_.wait_for(lock, micros(timeout_us), [&] { return tx_queued_ < tx_capacity_ || closed_; });
  if (closed_) return SOAPY_SDR_STREAM_ERROR;
  if (tx_queued_ >= tx_capacity_) return SOAPY_SDR_TIMEOUT;
  if (time != nullptr && *time < tx_floor_) {
    // Its first samples would belong to a tick already answered.
    late_bursts_.fetch_add(1);
    push_event({SOAPY_SDR_TIME_ERROR, *time});
    in_burst_ = false;
    changed_.notify_all();
    return static_cast<int>(in.size());
  }
  const std::size_t n = std::min(in.size(), tx_capacity_ - tx_queued_);
  Chunk b;
  // Untimed samples follow the previous write's (bursts written back to back
  // must not overlap), or start with the next tick when those are gone.
  b.time = time != nullptr ? *time : std::max(tx_next_, tx_floor_);
  b.samples.assign(in.begin(), in.begin() + static_cast<std::ptrdiff_t>(n));
  shift_and_scale(b.samples, b.time, tx_tuning_.offset_hz / sample_rate_hz_,
                  amplitude_of(tx_tuning_));
  tx_next_ = b.time + static_cast<SampleTime>(n);
  // A partial write leaves the burst open: the caller writes the rest next.
  in_burst_ = !(end_burst && n == in.size());
  tx_queued_ += n;
  const auto at = std::upper_bound(tx_.begin(), tx_.end(), b.time,
                                   [](SampleTime t, const Chunk& x) { return t < x.time; });
  tx_.insert(at, std::move(b));
  return static_cast<int>(n);
}

int StreamBuffers::read_event(TxEvent& event, long timeout_us) {
  std::unique_lock lock(mutex_);
  changed_.wait_for(lock, micros(timeout_us), [&] { return !events_.empty() || closed_; });
  if (events_.empty()) return closed_ ? SOAPY_SDR_STREAM_ERROR : SOAPY_SDR_TIMEOUT;
  event = events_.front();
  events_.pop_front();
  return 0;
}

void StreamBuffers::on_tick(SampleTime t, std::span<const cf32> rx, std::span<cf32> tx) {
  {
    std::lock_guard lock(mutex_);
    take_rx(t, rx);
    build_tx(t, tx);
    now_ = t;
    ticked_ = true;
  }
  changed_.notify_all();
}

void StreamBuffers::close() {
  {
    std::lock_guard lock(mutex_);
    closed_ = true;
  }
  changed_.notify_all();
}

void StreamBuffers::reopen(SampleTime t) {
  {
    std::lock_guard lock(mutex_);
    rx_.clear();
    rx_buffered_ = 0;
    overflow_pending_ = false;
    tx_.clear();
    tx_queued_ = 0;
    tx_floor_ = tx_next_ = now_ = t;
    ticked_ = true;  // t is the new emulator's first tick
    in_burst_ = false;
    closed_ = false;
    error_reported_ = false;
  }
  changed_.notify_all();  // a writer waiting for room has it now
}

void StreamBuffers::take_rx(SampleTime t, std::span<const cf32> rx) {
  if (!rx_active_ || rx.empty()) return;
  Chunk c;
  c.time = t - static_cast<SampleTime>(rx.size());
  c.samples.assign(rx.begin(), rx.end());
  // Received at the carrier, heard by an application tuned `offset` above it.
  shift_and_scale(c.samples, c.time, -rx_tuning_.offset_hz / sample_rate_hz_,
                  amplitude_of(rx_tuning_));
  rx_buffered_ += c.samples.size();
  rx_.push_back(std::move(c));
  while (rx_buffered_ > rx_capacity_ && rx_.size() > 1) {
    // The application reads too slowly: the oldest samples go.
    rx_buffered_ -= rx_.front().samples.size() - rx_.front().used;
    rx_.pop_front();
    if (!overflow_pending_) overflows_.fetch_add(1);
    overflow_pending_ = true;
  }
}

void StreamBuffers::build_tx(SampleTime t, std::span<cf32> out) {
  std::fill(out.begin(), out.end(), cf32{});
  const SampleTime end = t + static_cast<SampleTime>(out.size());
  // Bursts are in start order: stop at the first one that starts later.
  for (auto it = tx_.begin(); it != tx_.end() && it->time < end;) {
    const std::size_t left = it->samples.size() - it->used;
    const auto from = static_cast<std::size_t>(std::max<SampleTime>(it->time - t, 0));
    const std::size_t n = std::min(left, out.size() - from);
    for (std::size_t i = 0; i < n; ++i) out[from + i] += it->samples[it->used + i];
    it->used += n;
    it->time += static_cast<SampleTime>(n);
    tx_queued_ -= n;
    it = it->used == it->samples.size() ? tx_.erase(it) : std::next(it);
  }
  if (in_burst_ && tx_next_ < end) {
    // The application promised more samples and did not deliver in time.
    underflows_.fetch_add(1);
    push_event({SOAPY_SDR_UNDERFLOW, std::max(tx_next_, t)});
    in_burst_ = false;
  }
  tx_floor_ = end;
}

void StreamBuffers::push_event(const TxEvent& e) {
  if (events_.size() >= kMaxTxEvents) events_.pop_front();
  events_.push_back(e);
}

}  // namespace rfsitl::soapy
