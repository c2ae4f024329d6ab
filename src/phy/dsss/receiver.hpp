#pragma once
/// The DSSS RX path: acquisition on one or more codes at once, chip timing,
/// differential demodulation, SFD search, header and payload checks. Each
/// listened code has its own search and its own demodulator on the shared
/// front end, so the receiver decodes frames on different codes even when they
/// overlap in time, and a frame (or a false lock) on one code never blinds it
/// to another.
///
/// Acquisition. For every listened code the receiver computes, at every sample,
/// the code-matched filter output z[n] (CodeCorrelator) and its power
/// P[n] = |z[n]|^2, and tests the non-coherent sum over the last M = 8 code
/// periods at the same code phase,
///   D[n] = sum_{m < 8} P[n - m L S]   against   threshold * 8 L S * pbar[n],
/// where pbar[n] is the mean received power per sample over the last 8 to 9
/// periods, so that the right side is D's mean on noise. On noise D / (8 L S
/// pbar) follows Gamma(8)/8 whatever the code and noise level: P(> 4) ~ 1e-7
/// per sample and code (higher thresholds, from the Gamma(m) quantiles, hold
/// during the first 8 periods after a reset). A frame gives ~1 + L S rho / (1 + rho)
/// (rho: per-sample SINR): detection reaches down to rho ~ 3 / (L S), below where
/// frames decode (~8 / (L S)). The test is on |z|^2, so it needs neither the
/// data nor the carrier phase, and it normalizes by the total power, so a strong
/// interferer raises the bar as it should.
///
/// Chip timing and verification. After a detection at n0 the code's search
/// waits 6 periods (so that everything it then looks at is preamble), takes as
/// symbol timing the sample that maximizes sum_{m<6} P over one period (the best
/// of the L S code phases, hence the best sample phase when S > 1), and keeps it
/// only if there its despread power is again 4 times its noise mean and the 6
/// periods add up coherently (the preamble repeats one symbol; frame data rarely
/// does). While demodulating with S >= 2 an early-late gate (one sample either
/// side, power summed over 8 symbols) moves the timing by one sample when a
/// neighbour is stronger than the on-time point, which follows slow drift; the
/// emulator itself keeps exact sample timing.
///
/// Carrier. Decisions are differential (z[k] z*[k-1]), so a constant phase and
/// a carrier offset that turns the phase by much less than 90 degrees (DBPSK) or
/// 45 degrees (DQPSK) per code period do not matter.
///
/// Code isolation. A frame on code A despreads on code B of the same family at
/// (R/L)^2 of its power, R the cross-correlation (|R| <= t(n) for Gold codes over
/// the constant preamble): -17.5 dB for gold127. With S = 1 the verification
/// rejects such leaks of gold31, gold127 and gold511 frames at any SNR (see
/// frame_format.hpp); otherwise a frame strong enough that its leak despreads
/// above ~9 dB can decode on the wrong code as well (CRC-valid: it is the same
/// frame). When two listened codes lock on the same frame, the stronger keeps it.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "codes.hpp"
#include "frame_format.hpp"
#include "rfsitl/common/types.hpp"

namespace rfsitl::phy::dsss {

/// Codes one receiver can listen on at once.
inline constexpr std::size_t kMaxListenCodes = 4;

/// A code to listen on, with the caller's name for it (reported with each frame).
struct ListenCode {
  std::size_t id = 0;
  std::vector<Chip> chips;
};

struct ReceiverSettings {
  unsigned samples_per_chip = 1;         ///< 1..8
  std::size_t max_payload_bytes = 2048;  ///< longer frames are reported as CRC failures
  /// D/E above which a code phase is a detection (see above); ~4 gives ~1e-7
  /// false detections per sample and code.
  float detection_threshold = 4.0F;
};

/// One decode attempt, reported after a start-frame delimiter was found.
struct ReceivedFrame {
  bool header_valid = false;
  bool payload_valid = false;  ///< header valid and payload CRC-32 passed
  FrameHeader header;          ///< valid only if header_valid
  /// The payload octets as received (without CRC); valid during the callback.
  std::span<const std::uint8_t> payload;
  /// Differential products z[k] z*[k-1] of the payload, scaled so that the ideal
  /// points are the unit constellation; valid during the callback.
  std::span<const cf32> symbols;
  std::size_t code_id = 0;       ///< ListenCode::id of the code the frame arrived on
  float rssi_db = 0.0F;          ///< estimated received signal power per sample, dB
  float despread_snr_db = 0.0F;  ///< estimated SNR after despreading, dB
};

class FrameSink {
 public:
  virtual ~FrameSink() = default;
  virtual void on_frame(const ReceivedFrame& frame) = 0;
};

class DsssReceiver {
 public:
  /// Preconditions (else std::invalid_argument): 1 <= samples_per_chip <= 8;
  /// 1..kMaxListenCodes codes, all of the same nonzero length.
  DsssReceiver(const ReceiverSettings& settings, std::vector<ListenCode> codes);
  ~DsssReceiver();
  DsssReceiver(const DsssReceiver&) = delete;
  DsssReceiver& operator=(const DsssReceiver&) = delete;

  /// Replaces the listening set at the next push(), or, if a code it drops is
  /// inside a frame, after that frame (a switch never cuts a frame). Codes in
  /// both sets (same id and chips) carry on undisturbed. Same preconditions, and
  /// the codes must have the length of the current ones.
  void set_codes(std::vector<ListenCode> codes);

  /// Consumes samples; every decode attempt is reported to `sink` before return.
  void push(std::span<const cf32> in, FrameSink& sink);

  /// Drops any frame in progress and all history.
  void reset();

  /// True from a detection until the frame is decoded or abandoned.
  bool busy() const;

  /// Samples per code period, L * S.
  std::size_t period() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rfsitl::phy::dsss
