#include "fake_transceiver.hpp"

#include <algorithm>
#include <cmath>

namespace rfsitl::testing {
namespace {

/// dB reported for "no signal at all" and "nothing but the signal", so that
/// RxEvent's floats stay finite.
constexpr double kSinrCapDb = 200.0;

double sinr_db(double signal, double rest) {
  if (signal <= 0.0) return -kSinrCapDb;
  if (rest <= signal * 1e-20) return kSinrCapDb;
  return std::clamp(10.0 * std::log10(signal / rest), -kSinrCapDb, kSinrCapDb);
}

}  // namespace

FakeTransceiver::FakeTransceiver(FakeConfig config, std::shared_ptr<FakeAir> air)
    : config_(config), air_(std::move(air)) {}

std::size_t FakeTransceiver::frame_samples(std::size_t payload_bytes) const {
  return config_.header_samples + config_.samples_per_byte * payload_bytes;
}

double FakeTransceiver::sensitivity_snr_db() const {
  return config_.claimed_sensitivity_snr_db.value_or(config_.sensitivity_snr_db);
}

void FakeTransceiver::begin_tick(std::uint64_t /*tick*/, SampleTime time) {
  ++calls_.begin_tick;
  const bool backwards = last_tick_time_ && time <= *last_tick_time_;
  // The waveform is registered at virtual times: a busy transmitter that
  // skipped a tick would put it on the air later than registered.
  const bool tx_out_of_step = tx_busy() && tx_clock_ != time;
  if (backwards || tx_out_of_step || rx_clock_ > time) ++calls_.contract_violations;
  last_tick_time_ = time;
  tx_clock_ = time;
  rx_clock_ = time;
}

std::size_t FakeTransceiver::start_frame(const phy::FrameTag& tag,
                                         std::span<const std::uint8_t> payload) {
  ++calls_.start_frame;
  if (tx_busy() || payload.size() > config_.max_payload) ++calls_.contract_violations;
  AirFrame f;
  f.sender = this;
  f.tag = tag;
  f.payload.assign(payload.begin(), payload.end());
  f.start = tx_clock_;  // the next sample transmit() writes
  f.header_samples = config_.header_samples;
  f.length = frame_samples(payload.size());
  tx_frame_ = f.length > 0 ? air_->add(std::move(f)) : nullptr;
  tx_next_ = 0;
  return frame_samples(payload.size());
}

std::size_t FakeTransceiver::transmit(std::span<cf32> out) {
  ++calls_.transmit;
  std::size_t signal = 0;
  for (cf32& s : out) {
    if (tx_frame_ && tx_next_ < tx_frame_->length) {
      s = tx_frame_->sample(tx_next_++);
      ++signal;
    } else {
      s = cf32{};
    }
  }
  if (tx_frame_ && tx_next_ == tx_frame_->length) tx_frame_.reset();
  if (signal > 0) rx_deaf_until_ = tx_clock_ + static_cast<SampleTime>(signal);
  tx_clock_ += static_cast<SampleTime>(out.size());
  return signal;
}

bool FakeTransceiver::block_ends_at(const AirFrame& f, std::size_t j) const {
  // Header and payload are judged apart: a block never spans both, and a
  // region's short tail joins its last block rather than being judged on a
  // handful of noisy samples.
  const bool in_header = j < f.header_samples;
  const std::size_t region_start = in_header ? 0 : f.header_samples;
  const std::size_t region_len = in_header ? f.header_samples : f.length - f.header_samples;
  const std::size_t done = j - region_start + 1;
  const std::size_t b = std::max<std::size_t>(config_.block_samples, 1);
  return done == region_len || (done % b == 0 && region_len - done >= b);
}

void FakeTransceiver::close_block(Acquisition& a, std::size_t last_sample) const {
  const double n = static_cast<double>(a.block_len);
  const double signal = std::norm(a.block_corr / n);  // the waveform has unit power
  const double sinr = sinr_db(signal, a.block_power / n - signal);
  a.min_sinr_db = std::min(a.min_sinr_db, sinr);
  const bool good = sinr >= config_.sensitivity_snr_db;
  if (last_sample < a.frame->header_samples) {
    a.lost_header = a.lost_header || !good;
  } else {
    a.payload_ok = a.payload_ok && good;
  }
  a.detected = a.detected || good;
  a.block_corr = {};
  a.block_power = 0.0;
  a.block_len = 0;
}

void FakeTransceiver::measure(Acquisition& a, std::span<const cf32> in, SampleTime t0) const {
  const AirFrame& f = *a.frame;
  const SampleTime expected = f.start + static_cast<SampleTime>(a.next);
  if (a.next < f.length && expected < t0) {
    // Samples of the frame never reached this receiver (it transmitted, or
    // was not run): what they carried is lost.
    if (a.next < f.header_samples) {
      a.lost_header = true;
      return;
    }
    a.payload_ok = false;
    a.next = std::min(f.length, static_cast<std::size_t>(t0 - f.start));
    a.block_corr = {};
    a.block_power = 0.0;
    a.block_len = 0;
  }
  const SampleTime t1 = t0 + static_cast<SampleTime>(in.size());
  for (; a.next < f.length && f.start + static_cast<SampleTime>(a.next) < t1; ++a.next) {
    const std::complex<double> y =
        in[static_cast<std::size_t>(f.start + static_cast<SampleTime>(a.next) - t0)];
    const std::complex<double> w = f.sample(a.next);
    a.block_corr += y * std::conj(w);
    a.total_corr += y * std::conj(w);
    a.block_power += std::norm(y);
    ++a.block_len;
    if (block_ends_at(f, a.next)) close_block(a, a.next);
  }
}

void FakeTransceiver::receive(std::span<const cf32> in, phy::RxHandler& handler) {
  ++calls_.receive;
  calls_.samples_received += in.size();
  // The T/R switch: the input starts after the own transmission of the tick.
  const SampleTime t0 = std::max(rx_clock_, rx_deaf_until_);
  const SampleTime t1 = t0 + static_cast<SampleTime>(in.size());
  for (auto& f : air_->starting_in(t0, t1, this)) {
    Acquisition a;
    a.frame = std::move(f);
    a.min_sinr_db = kSinrCapDb;
    acquisitions_.push_back(std::move(a));
  }
  for (Acquisition& a : acquisitions_) measure(a, in, t0);
  std::erase_if(acquisitions_, [](const Acquisition& a) { return a.lost_header; });

  // Decodes fall due rx_latency_samples after their frame; several due in one
  // call are reported in the order of their due times, as smaller calls would.
  const auto due = [&](const Acquisition& a) {
    return a.frame->end() + static_cast<SampleTime>(config_.rx_latency_samples);
  };
  std::stable_sort(acquisitions_.begin(), acquisitions_.end(),
                   [&](const Acquisition& a, const Acquisition& b) { return due(a) < due(b); });
  while (!acquisitions_.empty() && due(acquisitions_.front()) <= t1) {
    report(acquisitions_.front(), handler);
    acquisitions_.erase(acquisitions_.begin());
  }
  rx_clock_ = t1;
}

void FakeTransceiver::report(const Acquisition& a, phy::RxHandler& handler) {
  const AirFrame& f = *a.frame;
  phy::RxEvent ev;
  ev.tag = f.tag;
  ev.payload = f.payload;
  ev.header_valid = true;
  ev.payload_valid = a.payload_ok;
  const double amplitude = std::abs(a.total_corr) / static_cast<double>(f.length);
  ev.rssi_db = static_cast<float>(amplitude > 0.0 ? 20.0 * std::log10(amplitude) : -kSinrCapDb);
  ev.evm_db = static_cast<float>(-a.min_sinr_db);
  decodes_.push_back(FakeDecode{f.tag, a.payload_ok, f.start,
                                f.end() + static_cast<SampleTime>(config_.rx_latency_samples),
                                a.min_sinr_db});
  handler.on_rx(ev);
}

void FakeTransceiver::reset_receiver() {
  ++calls_.reset_receiver;
  acquisitions_.clear();
}

bool FakeTransceiver::rx_busy() const {
  // Inside a frame it has detected (a good first block), or waiting out the
  // latency after one; a frame start it has not judged yet does not count.
  return std::any_of(acquisitions_.begin(), acquisitions_.end(),
                     [](const Acquisition& a) { return a.detected; });
}

}  // namespace rfsitl::testing
