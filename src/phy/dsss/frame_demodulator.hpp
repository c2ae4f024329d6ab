#pragma once
// Internal to the DSSS receiver: the symbol-rate half. Takes one despread
// symbol per code period from the moment of acquisition, finds the SFD, reads
// and checks the header, collects the payload and checks its CRC-32.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "frame_format.hpp"
#include "receiver.hpp"
#include "rfsitl/common/types.hpp"

namespace rfsitl::phy::dsss::detail {

class FrameDemodulator {
 public:
  /// period: L * S, to turn despread amplitudes into per-sample power.
  void configure(std::size_t max_payload_bytes, std::size_t period);

  /// Starts on a new frame whose first despread symbol (the phase reference) is z.
  void start(cf32 z, std::size_t code_id);

  /// Takes the next despread symbol. Returns true when the frame is over: it
  /// was reported to `sink` (SFD found) or abandoned (no SFD in time).
  bool push(cf32 z, FrameSink& sink);

  /// True once the SFD was found: from then on the frame runs to its end.
  bool committed() const { return stage_ != Stage::kSfd; }

 private:
  enum class Stage { kSfd, kHeader, kPayload };

  void take_bit(std::uint8_t bit, std::uint8_t* bytes);
  void measure(cf32 z);
  void report(bool header_valid, bool payload_valid, std::span<const std::uint8_t> payload,
              FrameSink& sink);

  std::size_t max_payload_ = 0;
  std::size_t period_ = 1;
  Stage stage_ = Stage::kSfd;
  std::size_t code_id_ = 0;
  cf32 previous_{};
  std::size_t symbols_seen_ = 0;
  std::uint16_t sfd_register_ = 0;
  std::size_t ones_before_sfd_ = 0;
  std::size_t bit_count_ = 0;
  std::size_t bits_wanted_ = 0;
  HeaderBytes header_bytes_{};
  FrameHeader header_;
  std::vector<std::uint8_t> body_;  // payload + CRC-32
  std::vector<cf32> products_;      // payload differential products, unscaled
  double amplitude_sum_ = 0.0;      // of |z| over header and payload
  double power_sum_ = 0.0;          // of |z|^2
  std::size_t measured_ = 0;
};

}  // namespace rfsitl::phy::dsss::detail
