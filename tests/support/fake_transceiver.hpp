#pragma once
/// A phy::Transceiver test double for tests of the engine's own logic: it keeps
/// the Transceiver contract but does no DSP, so engine tests neither wait for
/// a real receiver nor depend on one's behaviour.
///
/// TX: a frame is header_samples + samples_per_byte * payload bytes of a
/// unit-power pseudo-random waveform, registered in the shared FakeAir with its
/// virtual start time, tag and payload.
///
/// RX: the receiver tracks every frame (from another sender) whose first sample
/// it receives. It measures, block by block of the frame, the frame's own power
/// (the received samples correlated with its waveform) against everything else
/// in them (noise, other frames): the SINR. A block below sensitivity_snr_db is
/// lost. If every header block was received and good, the decode is reported
/// (header_valid) rx_latency_samples after the frame's last sample, with
/// payload_valid iff every payload block was too (else a CRC failure). So a
/// weak link, an overlapping frame of similar power or a gap in reception (own
/// transmission, reset_receiver) loses a frame just as a real receiver would,
/// decided from the samples the engine actually delivered; a much stronger frame
/// captures the receiver over a weak one.
///
/// Limits: time comes from begin_tick() (both paths; without it, from counting
/// samples), so transmit() must be called in every tick while tx_busy(), and
/// receive() gets only the samples after the own transmission of the tick (the
/// T/R switch), which is what the engine does. In noise alone a block's SINR
/// estimate exceeds a linear ratio x with probability about exp(-x *
/// block_samples), so keep the threshold near 0 dB or above (at 32 samples).
/// RxEvent::symbols is always empty.
///
/// Threads: one thread at a time per instance (the engine's worker for the
/// node); read calls()/decodes() after the run or from the thread driving it.
#include <complex>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "fake_air.hpp"
#include "rfsitl/phy/transceiver.hpp"

namespace rfsitl::testing {

struct FakeConfig {
  std::size_t header_samples = 100;  ///< samples of a frame before its payload's
  std::size_t samples_per_byte = 8;  ///< samples per payload byte
  std::size_t max_payload = 1500;    ///< bytes
  /// dB: every block of a frame must reach this SINR to be decoded.
  double sensitivity_snr_db = 10.0;
  /// dB: what sensitivity_snr_db() tells the engine, when it should differ from
  /// the real threshold (a PHY that claims more than it does).
  std::optional<double> claimed_sensitivity_snr_db;
  std::size_t rx_latency_samples = 0;  ///< after a frame's last sample, before its decode
  std::size_t block_samples = 32;      ///< SINR resolution (a shorter tail joins the last block)
};

/// How often each Transceiver call was made, and contract breaches seen.
struct FakeCalls {
  std::uint64_t begin_tick = 0;
  std::uint64_t start_frame = 0;
  std::uint64_t transmit = 0;
  std::uint64_t receive = 0;
  std::uint64_t reset_receiver = 0;
  std::uint64_t samples_received = 0;
  /// start_frame while busy or with an oversized payload, time running
  /// backwards, a tick without transmit() while busy.
  std::uint64_t contract_violations = 0;
};

/// One decode the receiver reported (header valid).
struct FakeDecode {
  phy::FrameTag tag;
  bool payload_valid = false;
  SampleTime frame_start = 0;  ///< virtual time of the frame's first sample
  SampleTime reported_at = 0;  ///< virtual time of the sample after which it was reported
  double min_sinr_db = 0.0;    ///< worst block of the frame
};

class FakeTransceiver final : public phy::Transceiver {
 public:
  /// `air` is shared by every fake of one engine (one medium per run).
  FakeTransceiver(FakeConfig config, std::shared_ptr<FakeAir> air);

  std::size_t max_payload() const override { return config_.max_payload; }
  std::size_t frame_samples(std::size_t payload_bytes) const override;
  double sensitivity_snr_db() const override;
  bool tx_busy() const override { return tx_frame_ != nullptr; }
  std::size_t start_frame(const phy::FrameTag& tag, std::span<const std::uint8_t> payload) override;
  std::size_t transmit(std::span<cf32> out) override;
  void receive(std::span<const cf32> in, phy::RxHandler& handler) override;
  void reset_receiver() override;
  bool rx_busy() const override;
  std::size_t rx_latency_samples() const override { return config_.rx_latency_samples; }
  void begin_tick(std::uint64_t tick, SampleTime time) override;

  const FakeConfig& config() const { return config_; }
  const FakeCalls& calls() const { return calls_; }
  /// Every decode reported, in order.
  const std::vector<FakeDecode>& decodes() const { return decodes_; }

 private:
  /// A frame the receiver saw begin, and its measurement so far.
  struct Acquisition {
    std::shared_ptr<const AirFrame> frame;
    std::size_t next = 0;   ///< next frame sample expected
    bool detected = false;  ///< a first header block was good
    bool lost_header = false;
    bool payload_ok = true;
    std::complex<double> block_corr{};  ///< sum of y * conj(waveform) over the block
    double block_power = 0.0;           ///< sum of |y|^2 over the block
    std::size_t block_len = 0;
    std::complex<double> total_corr{};
    double min_sinr_db = 0.0;
  };

  void measure(Acquisition& a, std::span<const cf32> in, SampleTime t0) const;
  void close_block(Acquisition& a, std::size_t last_sample) const;
  bool block_ends_at(const AirFrame& f, std::size_t j) const;
  void report(const Acquisition& a, phy::RxHandler& handler);

  FakeConfig config_;
  std::shared_ptr<FakeAir> air_;
  FakeCalls calls_;
  std::vector<FakeDecode> decodes_;

  std::shared_ptr<const AirFrame> tx_frame_;  // while on the air
  std::size_t tx_next_ = 0;                   // next sample of tx_frame_ to send
  SampleTime tx_clock_ = 0;                   // virtual time of the next transmit() sample
  SampleTime rx_clock_ = 0;                   // virtual time of the next receive() sample
  SampleTime rx_deaf_until_ = 0;              // end of the own signal (T/R switch)
  std::optional<SampleTime> last_tick_time_;
  std::vector<Acquisition> acquisitions_;
};

}  // namespace rfsitl::testing
