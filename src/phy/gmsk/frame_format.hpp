#pragma once
/// The fast GMSK frame, in symbols.
///
///   preamble   64  8 repetitions of an 8-symbol pattern: the receiver detects the
///                  repetition (delay-and-correlate), which needs no timing,
///                  phase or knowledge of the data, and costs a few operations
///                  per sample (see preamble_detector.hpp)
///   sync       32  a fixed word chosen (by search over random words) for low
///                  correlation sidelobes against the preamble before it; its
///                  matched-filter correlation peak gives symbol timing and
///                  carrier phase
///   header     80  src, dst, serial (u32 LE), payload length (u16 LE), CRC-16
///   payload  8 n   the n payload octets, then their CRC-32 (32 symbols)
///   tail        2  so that the last CRC bit's pulse is fully on the air
///
/// Header and payload (with CRCs) are whitened with a PN9 sequence so that long
/// runs in the data neither leave a tone nor look like the preamble. Bits go
/// least significant first, bit 0 as pseudo-symbol +1 and bit 1 as -1.
///
/// Pseudo-symbols c_n are what the coherent receiver decides: with the GMSK
/// frequency symbols a_n = c_n c_{n-1} (c_{-1} = +1), Laurent's principal
/// pseudo-symbols are A_n = exp(j pi/2 sum a_i) = j^n c_n up to a constant, so
/// each bit is one matched-filter sample on alternately the real and imaginary
/// axis and a symbol error costs one bit (no differential decoding).
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

#include "rfsitl/phy/transceiver.hpp"

namespace rfsitl::phy::gmsk {

inline constexpr std::size_t kPreamblePeriodSymbols = 8;
inline constexpr std::size_t kPreambleRepeats = 8;
inline constexpr std::size_t kPreambleSymbols = kPreamblePeriodSymbols * kPreambleRepeats;
inline constexpr std::size_t kSyncSymbols = 32;
inline constexpr std::size_t kHeaderBytes = 10;  ///< including the CRC-16
inline constexpr std::size_t kHeaderSymbols = 8 * kHeaderBytes;
inline constexpr std::size_t kPayloadCrcBytes = 4;
inline constexpr std::size_t kTailSymbols = 2;
inline constexpr std::size_t kMaxPayloadBytes = 65535;
/// Symbols from the frame start to the first header symbol.
inline constexpr std::size_t kHeaderStartSymbol = kPreambleSymbols + kSyncSymbols;

/// Pseudo-symbol (+1 or -1) i of the preamble period. Precondition: i < 8.
std::int8_t preamble_symbol(std::size_t i);

/// Pseudo-symbol (+1 or -1) i of the sync word. Precondition: i < 32.
std::int8_t sync_symbol(std::size_t i);

/// Symbols of a frame carrying `payload_bytes` payload octets.
constexpr std::size_t frame_symbol_count(std::size_t payload_bytes) {
  return kHeaderStartSymbol + kHeaderSymbols + 8 * (payload_bytes + kPayloadCrcBytes) +
         kTailSymbols;
}

struct FrameHeader {
  FrameTag tag;
  std::size_t payload_bytes = 0;
};

/// The header octets, CRC-16 included, before whitening.
/// Precondition: h.payload_bytes <= kMaxPayloadBytes.
std::array<std::uint8_t, kHeaderBytes> encode_header(const FrameHeader& h);

/// The header, or nothing if the CRC-16 fails.
std::optional<FrameHeader> decode_header(std::span<const std::uint8_t, kHeaderBytes> bytes);

/// The whitening sequence, one octet (8 bits of PN9, x^9 + x^5 + 1, seeded
/// with ones) at a time; XOR it in to whiten and again to de-whiten.
class Whitener {
 public:
  std::uint8_t next();

 private:
  std::uint16_t state_ = 0x1FF;
};

/// Writes the GMSK frequency symbols a_n (+1 or -1) of a whole frame to the front
/// of `out` and returns their number, frame_symbol_count(payload.size()).
/// Preconditions: payload.size() <= kMaxPayloadBytes; out is at least that long.
std::size_t build_frame_symbols(const FrameTag& tag, std::span<const std::uint8_t> payload,
                                std::span<std::int8_t> out);

}  // namespace rfsitl::phy::gmsk
