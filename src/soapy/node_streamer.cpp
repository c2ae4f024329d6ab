#include "node_streamer.hpp"

#include <SoapySDR/Errors.h>
#include <SoapySDR/Logger.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <numbers>

namespace rfsitl::soapy {
namespace {

/// How long the pump waits for a tick before it looks at stopping_ again.
constexpr int kPumpPollMs = 100;

/// Multiplies s[i] by amplitude * exp(j 2 pi f (t0 + i)), f = offset / fs in
/// cycles per sample. The phase follows the absolute virtual time, so that
/// chunks written or received separately join without a phase jump.
void shift_and_scale(std::span<cf32> s, SampleTime t0, double cycles_per_sample, double amplitude) {
  if (cycles_per_sample == 0.0) {
    for (auto& x : s) x *= static_cast<float>(amplitude);
    return;
  }
  // The start phase from the absolute time (fmod keeps it small), then a
  // rotator: a chunk is at most a few ticks, far too short to drift.
  const double start = std::fmod(cycles_per_sample * static_cast<double>(t0), 1.0);
  std::complex<double> rot = std::polar(amplitude, 2.0 * std::numbers::pi * start);
  const std::complex<double> step = std::polar(1.0, 2.0 * std::numbers::pi * cycles_per_sample);
  for (auto& x : s) {
    x = cf32(std::complex<double>(x) * rot);
    rot *= step;
  }
}

double amplitude_of(const PathTuning& t) {
  return t.in_band ? std::pow(10.0, t.gain_db / 20.0) : 0.0;
}

std::chrono::microseconds micros(long timeout_us) {
  return std::chrono::microseconds(std::max(timeout_us, 0L));
}

}  // namespace

NodeStreamer::NodeStreamer(Settings settings)
    : settings_(std::move(settings)),
      client_({settings_.socket_path, settings_.node_id, "samples", settings_.program, 5000}) {
  welcome_ = client_.connect();
  const auto b = static_cast<std::size_t>(welcome_.tick_samples);
  // At least two ticks, so that the pump can queue one while the reader takes another.
  rx_capacity_ = std::max<std::size_t>(
      2 * b, static_cast<std::size_t>(settings_.rx_buffer_s * welcome_.sample_rate_hz));
  tx_capacity_ = std::max<std::size_t>(2, settings_.tx_queue_ticks) * b;
  thread_ = std::thread([this] { pump(); });
}

NodeStreamer::~NodeStreamer() {
  stopping_.store(true);
  thread_.join();
  client_.disconnect();
}

long long NodeStreamer::to_ns(SampleTime t) const {
  return std::llround(static_cast<double>(t) * 1e9 / welcome_.sample_rate_hz);
}

SampleTime NodeStreamer::to_samples(long long ns) const {
  return std::llround(static_cast<double>(ns) * welcome_.sample_rate_hz / 1e9);
}

void NodeStreamer::set_rx_tuning(const PathTuning& t) {
  std::lock_guard lock(mutex_);
  rx_tuning_ = t;
}

void NodeStreamer::set_tx_tuning(const PathTuning& t) {
  std::lock_guard lock(mutex_);
  tx_tuning_ = t;
}

void NodeStreamer::set_rx_active(bool active) {
  std::lock_guard lock(mutex_);
  rx_active_ = active;
  rx_.clear();
  rx_buffered_ = 0;
  overflow_pending_ = false;
}

SampleTime NodeStreamer::now() const {
  std::lock_guard lock(mutex_);
  return now_;
}

bool NodeStreamer::connected() const {
  std::lock_guard lock(mutex_);
  return !closed_;
}

int NodeStreamer::read(std::span<cf32> out, SampleTime& time, long timeout_us) {
  std::unique_lock lock(mutex_);
  changed_.wait_for(lock, micros(timeout_us),
                    [&] { return !rx_.empty() || overflow_pending_ || closed_; });
  if (overflow_pending_) {
    overflow_pending_ = false;
    return SOAPY_SDR_OVERFLOW;
  }
  if (rx_.empty()) return closed_ ? SOAPY_SDR_STREAM_ERROR : SOAPY_SDR_TIMEOUT;
  Chunk& c = rx_.front();
  const std::size_t n = std::min(out.size(), c.samples.size() - c.used);
  std::copy_n(c.samples.begin() + static_cast<std::ptrdiff_t>(c.used), n, out.begin());
  time = c.time + static_cast<SampleTime>(c.used);
  c.used += n;
  rx_buffered_ -= n;
  if (c.used == c.samples.size()) rx_.pop_front();
  return static_cast<int>(n);
}

int NodeStreamer::write(std::span<const cf32> in, const SampleTime* time, bool end_burst,
                        long timeout_us) {
  std::unique_lock lock(mutex_);
  changed_.wait_for(lock, micros(timeout_us), [&] { return tx_queued_ < tx_capacity_ || closed_; });
  if (closed_) return SOAPY_SDR_STREAM_ERROR;
  if (tx_queued_ >= tx_capacity_) return SOAPY_SDR_TIMEOUT;
  if (time != nullptr && *time < tx_floor_) {
    // Its first samples would belong to a tick already answered.
    late_bursts_.fetch_add(1);
    events_.push_back({SOAPY_SDR_TIME_ERROR, *time});
    in_burst_ = false;
    changed_.notify_all();
    return static_cast<int>(in.size());
  }
  const std::size_t n = std::min(in.size(), tx_capacity_ - tx_queued_);
  Burst b;
  // Untimed samples follow the previous write's (bursts written back to back
  // must not overlap), or start with the next tick when those are gone.
  b.start = time != nullptr ? *time : std::max(tx_next_, tx_floor_);
  b.samples.assign(in.begin(), in.begin() + static_cast<std::ptrdiff_t>(n));
  shift_and_scale(b.samples, b.start, tx_tuning_.offset_hz / welcome_.sample_rate_hz,
                  amplitude_of(tx_tuning_));
  tx_next_ = b.start + static_cast<SampleTime>(n);
  // A partial write leaves the burst open: the caller writes the rest next.
  in_burst_ = !(end_burst && n == in.size());
  tx_queued_ += n;
  const auto at = std::upper_bound(tx_.begin(), tx_.end(), b.start,
                                   [](SampleTime t, const Burst& x) { return t < x.start; });
  tx_.insert(at, std::move(b));
  return static_cast<int>(n);
}

int NodeStreamer::read_event(TxEvent& event, long timeout_us) {
  std::unique_lock lock(mutex_);
  changed_.wait_for(lock, micros(timeout_us), [&] { return !events_.empty() || closed_; });
  if (events_.empty()) return closed_ ? SOAPY_SDR_STREAM_ERROR : SOAPY_SDR_TIMEOUT;
  event = events_.front();
  events_.pop_front();
  return 0;
}

void NodeStreamer::pump() {
  std::vector<cf32> tx(welcome_.tick_samples);
  while (!stopping_.load()) {
    const external::RecvStatus st = client_.wait_tick(kPumpPollMs);
    if (st == external::RecvStatus::kTimeout) continue;
    if (st != external::RecvStatus::kOk) {
      return close_with(st == external::RecvStatus::kClosed
                            ? "the emulator closed the connection"
                            : "unexpected message from the emulator");
    }
    const external::Tick& tick = client_.tick();
    const auto t = static_cast<SampleTime>(tick.time);
    {
      std::lock_guard lock(mutex_);
      take_rx(tick);
      build_tx(t, tx);
      now_ = t;
    }
    changed_.notify_all();
    if (!client_.send_tx(tx)) return close_with("the emulator closed the connection");
  }
}

void NodeStreamer::take_rx(const external::Tick& tick) {
  if (!rx_active_ || tick.rx.empty()) return;
  Chunk c;
  c.time = static_cast<SampleTime>(tick.time) - static_cast<SampleTime>(tick.rx.size());
  c.samples.assign(tick.rx.begin(), tick.rx.end());
  // Received at the carrier, heard by an application tuned `offset` above it.
  shift_and_scale(c.samples, c.time, -rx_tuning_.offset_hz / welcome_.sample_rate_hz,
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

void NodeStreamer::build_tx(SampleTime t, std::span<cf32> out) {
  std::fill(out.begin(), out.end(), cf32{});
  const SampleTime end = t + static_cast<SampleTime>(out.size());
  // Bursts are in start order: stop at the first one that starts later.
  for (auto it = tx_.begin(); it != tx_.end() && it->start < end;) {
    const std::size_t left = it->samples.size() - it->used;
    const auto from = static_cast<std::size_t>(std::max<SampleTime>(it->start - t, 0));
    const std::size_t n = std::min(left, out.size() - from);
    for (std::size_t i = 0; i < n; ++i) out[from + i] += it->samples[it->used + i];
    it->used += n;
    it->start += static_cast<SampleTime>(n);
    tx_queued_ -= n;
    it = it->used == it->samples.size() ? tx_.erase(it) : std::next(it);
  }
  if (in_burst_ && tx_next_ < end) {
    // The application promised more samples and did not deliver in time.
    underflows_.fetch_add(1);
    events_.push_back({SOAPY_SDR_UNDERFLOW, std::max(tx_next_, t)});
    in_burst_ = false;
  }
  tx_floor_ = end;
}

void NodeStreamer::close_with(const std::string& why) {
  SoapySDR::logf(SOAPY_SDR_WARNING, "rfsitl node %u: %s", unsigned{settings_.node_id}, why.c_str());
  {
    std::lock_guard lock(mutex_);
    closed_ = true;
  }
  changed_.notify_all();
}

}  // namespace rfsitl::soapy
