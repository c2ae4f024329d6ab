#pragma once
/// Differential PSK over code periods, as in IEEE 802.11b (DBPSK at 1 Mbit/s,
/// DQPSK at 2 Mbit/s): each symbol is the previous one rotated by the data.
///   DBPSK: bit 0 -> 0, bit 1 -> pi.
///   DQPSK (Gray): dibit (d0, d1), d0 first in time: 00 -> 0, 01 -> +pi/2,
///                 11 -> pi, 10 -> -pi/2.
/// Symbols are unit-magnitude and lie on {1, j, -1, -j}: rotations by quarter
/// turns are exact in floating point, so a long frame accumulates no error.
#include <cstdint>
#include <span>
#include <vector>

#include "frame_format.hpp"
#include "rfsitl/common/types.hpp"

namespace rfsitl::phy::dsss {

/// Encoder state: the phase of the last symbol, in quarter turns.
class DifferentialEncoder {
 public:
  /// Appends one DBPSK symbol. Precondition: bit is 0 or 1.
  void push_bit(std::uint8_t bit, std::vector<cf32>& out);
  /// Appends one DQPSK symbol carrying d0 (first in time) and d1.
  void push_dibit(std::uint8_t d0, std::uint8_t d1, std::vector<cf32>& out);

 private:
  void rotate(unsigned quarter_turns, std::vector<cf32>& out);
  unsigned quadrant_ = 0;
};

/// The symbols (one per code period) of a whole frame: preamble, SFD, header in
/// DBPSK, then payload + CRC-32 in header.modulation.
/// Precondition: header.length == payload.size().
std::vector<cf32> frame_symbols(const FrameHeader& header, std::span<const std::uint8_t> payload);

/// DBPSK decision on d = z[k] * conj(z[k-1]) (z: despread symbols).
inline std::uint8_t dbpsk_decide(cf32 d) {
  return d.real() < 0.0F ? 1 : 0;
}

/// DQPSK decision on d = z[k] * conj(z[k-1]): returns d0 in bit 0 and d1 in bit 1.
std::uint8_t dqpsk_decide(cf32 d);

}  // namespace rfsitl::phy::dsss
