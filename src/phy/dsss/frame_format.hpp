#pragma once
/// The DSSS frame, in code periods (one symbol per period):
///
///   preamble  kPreambleSymbols DBPSK symbols of bit 0: the same symbol every period
///   SFD       16 DBPSK bits, kSfd sent LSB first (802.11b's long-preamble SFD)
///   header    kHeaderBytes DBPSK bytes, LSB first:
///               [0]     format: bits 0-3 version (1), bit 4 payload modulation
///                       (0 DBPSK, 1 DQPSK), bits 5-7 zero
///               [1..2]  payload length, octets, little endian
///               [3]     src   [4] dst   [5..8] serial, little endian
///               [9..10] control field (see ControlField), little endian
///               [11..12] CRC-16 of bytes 0..10, little endian
///   payload   payload octets then their CRC-32 (little endian), LSB first, in the
///             header's modulation (DBPSK: 1 bit per period; DQPSK: 2, Gray coded)
///
/// Why a constant preamble: over it the received signal is periodic, so what a
/// receiver listening on another code of the same family sees is the periodic
/// cross-correlation, which Gold's bound keeps at |R| <= t(n). At one sample per
/// chip its despread power over noise (see receiver.hpp) then stays below
/// 1 + t(n)^2 / L however strong the frame: under the receiver's verification
/// threshold of 4 for gold31 (3.6), gold127 (3.3) and gold511 (3.1); not for
/// gold63 (5.6) and gold1023 (5.1), whose families are less isolated. With phase
/// flips the odd cross-correlation would count, which no such bound limits.
/// The unit tests check that no 16-bit window overlapping the preamble equals the SFD.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "rfsitl/common/types.hpp"

namespace rfsitl::phy::dsss {

enum class Modulation : std::uint8_t { kDbpsk = 0, kDqpsk = 1 };

/// "dbpsk" or "dqpsk"; nullopt for anything else.
std::optional<Modulation> modulation_from_name(std::string_view name);

/// Payload bits per code period: 1 (DBPSK) or 2 (DQPSK).
unsigned bits_per_symbol(Modulation m);

inline constexpr std::size_t kPreambleSymbols = 32;
inline constexpr std::uint16_t kSfd = 0xF3A0;
inline constexpr std::size_t kSfdBits = 16;
inline constexpr std::size_t kHeaderBytes = 13;
inline constexpr std::size_t kHeaderBits = 8 * kHeaderBytes;
inline constexpr std::size_t kCrc32Bytes = 4;
inline constexpr std::uint8_t kFormatVersion = 1;
/// Largest payload the 16-bit length field can announce.
inline constexpr std::size_t kMaxPayloadBytes = 65535;

/// Symbols before the header's first bit: preamble and SFD.
inline constexpr std::size_t kSyncSymbols = kPreambleSymbols + kSfdBits;

struct FrameHeader {
  Modulation modulation = Modulation::kDbpsk;
  std::uint16_t length = 0;  ///< payload octets, without the CRC-32
  NodeId src = 0;
  NodeId dst = 0;
  std::uint32_t serial = 0;
  std::uint16_t control = 0;  ///< opaque to the PHY: see ControlField
};

using HeaderBytes = std::array<std::uint8_t, kHeaderBytes>;

/// The header's octets with its CRC-16 in place.
HeaderBytes encode_header(const FrameHeader& header);

/// The header, or nullopt if its CRC-16 fails or its format octet is not one
/// this version writes.
std::optional<FrameHeader> decode_header(const HeaderBytes& bytes);

/// The meaning the code adaptation gives to the header's 16-bit control field:
/// a request "send to me on code `code_index`" (an index into the code set both
/// ends agree on) tagged with a 4-bit `epoch` so that a peer can tell a new
/// request from a repeat. Every frame repeats the sender's current request, so
/// a lost frame delays a switch but never desynchronizes the link.
///   bit 15: request present; bits 10-13: epoch; bits 0-9: code index; bit 14: zero.
struct ControlField {
  bool code_request = false;
  std::uint16_t code_index = 0;  ///< 0..1023
  std::uint8_t epoch = 0;        ///< 0..15

  bool operator==(const ControlField&) const = default;
};

inline constexpr std::uint16_t kMaxControlCodeIndex = 1023;
inline constexpr std::uint8_t kMaxControlEpoch = 15;

/// Precondition: code_index <= 1023 and epoch <= 15, else std::invalid_argument.
std::uint16_t encode_control(const ControlField& field);

/// Inverse of encode_control; nullopt if reserved bit 14 is set, or if the request
/// bit is clear but other bits are not (a value encode_control never writes).
std::optional<ControlField> decode_control(std::uint16_t value);

/// Code periods of a frame carrying `payload_bytes` octets.
std::size_t frame_symbol_count(Modulation payload_modulation, std::size_t payload_bytes);

/// The payload followed by its CRC-32.
void append_payload_with_crc(std::span<const std::uint8_t> payload, std::vector<std::uint8_t>& out);

/// True if the last four octets are the CRC-32 of the rest (and there are four).
bool payload_crc_valid(std::span<const std::uint8_t> payload_with_crc);

}  // namespace rfsitl::phy::dsss
