#include "frame_demodulator.hpp"

#include <algorithm>
#include <cmath>

#include "differential_psk.hpp"

namespace rfsitl::phy::dsss::detail {
namespace {

// The preamble plus the SFD: if the SFD has not shown up within that many
// symbols of the detection, the detection was noise or a frame's middle.
constexpr std::size_t kSfdSearchSymbols = kPreambleSymbols + kSfdBits;
// Before the SFD is complete a frame shows its 9 ones and, the preamble being
// all zeros, only bit errors besides; more ones than this mean data, not a
// preamble, and the search gives up early (random data gets there in ~22 symbols).
constexpr std::size_t kMaxOnesBeforeSfd = 9 + 2;

}  // namespace

void FrameDemodulator::configure(std::size_t max_payload_bytes, std::size_t period) {
  max_payload_ = max_payload_bytes;
  period_ = period;
  body_.reserve(max_payload_bytes + kCrc32Bytes);
  products_.reserve(8 * (max_payload_bytes + kCrc32Bytes));
}

void FrameDemodulator::start(cf32 z, std::size_t code_id) {
  stage_ = Stage::kSfd;
  code_id_ = code_id;
  previous_ = z;
  symbols_seen_ = 0;
  sfd_register_ = 0;
  ones_before_sfd_ = 0;
  bit_count_ = 0;
  header_bytes_.fill(0);
  body_.clear();
  products_.clear();
  amplitude_sum_ = 0.0;
  power_sum_ = 0.0;
  measured_ = 0;
}

void FrameDemodulator::take_bit(std::uint8_t bit, std::uint8_t* bytes) {
  bytes[bit_count_ / 8] =
      static_cast<std::uint8_t>(bytes[bit_count_ / 8] | (bit << (bit_count_ % 8)));
  ++bit_count_;
}

void FrameDemodulator::measure(cf32 z) {
  const double a = std::abs(z);
  amplitude_sum_ += a;
  power_sum_ += a * a;
  ++measured_;
}

bool FrameDemodulator::push(cf32 z, FrameSink& sink) {
  const cf32 d = z * std::conj(previous_);
  previous_ = z;
  switch (stage_) {
    case Stage::kSfd: {
      ++symbols_seen_;
      const std::uint8_t bit = dbpsk_decide(d);
      ones_before_sfd_ += bit;
      sfd_register_ = static_cast<std::uint16_t>((sfd_register_ >> 1) | (bit << 15));
      if (symbols_seen_ >= kSfdBits && sfd_register_ == kSfd) {
        stage_ = Stage::kHeader;
        bit_count_ = 0;
        return false;
      }
      return symbols_seen_ >= kSfdSearchSymbols || ones_before_sfd_ > kMaxOnesBeforeSfd;
    }
    case Stage::kHeader: {
      measure(z);
      take_bit(dbpsk_decide(d), header_bytes_.data());
      if (bit_count_ < kHeaderBits) return false;
      const auto h = decode_header(header_bytes_);
      if (!h) {
        report(false, false, {}, sink);
        return true;
      }
      header_ = *h;
      if (header_.length > max_payload_) {
        report(true, false, {}, sink);
        return true;
      }
      stage_ = Stage::kPayload;
      bit_count_ = 0;
      bits_wanted_ = 8 * (header_.length + kCrc32Bytes);
      body_.assign(header_.length + kCrc32Bytes, 0);
      return false;
    }
    case Stage::kPayload: {
      measure(z);
      products_.push_back(d);
      if (header_.modulation == Modulation::kDbpsk) {
        take_bit(dbpsk_decide(d), body_.data());
      } else {
        const std::uint8_t dibit = dqpsk_decide(d);
        take_bit(dibit & 1U, body_.data());
        take_bit(static_cast<std::uint8_t>(dibit >> 1), body_.data());
      }
      if (bit_count_ < bits_wanted_) return false;
      report(true, payload_crc_valid(body_),
             std::span<const std::uint8_t>(body_).first(header_.length), sink);
      return true;
    }
  }
  return true;
}

void FrameDemodulator::report(bool header_valid, bool payload_valid,
                              std::span<const std::uint8_t> payload, FrameSink& sink) {
  ReceivedFrame f;
  f.header_valid = header_valid;
  f.payload_valid = payload_valid;
  f.code_id = code_id_;
  if (header_valid) f.header = header_;
  f.payload = payload;
  // Moments of |z|: with signal amplitude A and complex noise of variance s2,
  // E|z|^2 = A^2 + s2 and, well above the noise, E|z| ~ A, so
  // A^2 ~ mean(|z|)^2 and s2 ~ 2 * (mean(|z|^2) - mean(|z|)^2) (|z| carries half the noise).
  if (measured_ > 1) {
    const double mean_a = amplitude_sum_ / static_cast<double>(measured_);
    const double mean_p = power_sum_ / static_cast<double>(measured_);
    const double signal = mean_a * mean_a;
    const double noise = std::max(2.0 * (mean_p - signal), 1e-12 * signal + 1e-30);
    const auto period = static_cast<double>(period_);
    const double per_sample = signal / (period * period);
    f.rssi_db = static_cast<float>(10.0 * std::log10(per_sample + 1e-30));
    f.despread_snr_db = static_cast<float>(10.0 * std::log10(signal / noise));
    const auto scale = static_cast<float>(1.0 / std::max(signal, 1e-30));
    for (cf32& p : products_) p *= scale;
  }
  f.symbols = products_;
  sink.on_frame(f);
}

}  // namespace rfsitl::phy::dsss::detail
