#pragma once
/// Helpers of the MAVLink codec tests, written from the specification and kept
/// independent of the library's own checksum and layout code, so that the
/// tests check the library against a second reading of the spec.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <span>
#include <vector>

#include "rfsitl/position/mavlink/parser.hpp"

namespace rfsitl::position::mavlink::test {

using Bytes = std::vector<std::uint8_t>;

/// CRC-16/MCRF4XX bit by bit, straight from its catalogue definition: reflected
/// polynomial 0x8408, initial 0xFFFF, no final XOR.
inline std::uint16_t reference_crc(std::span<const std::uint8_t> bytes) {
  std::uint16_t crc = 0xFFFF;
  for (const std::uint8_t b : bytes) {
    crc = static_cast<std::uint16_t>(crc ^ b);
    for (int i = 0; i < 8; ++i) {
      crc = static_cast<std::uint16_t>((crc & 1U) != 0 ? (crc >> 1) ^ 0x8408U : crc >> 1);
    }
  }
  return crc;
}

/// Appends the checksum over frame[1..] + crc_extra, low byte first.
inline void append_crc(Bytes& frame, std::uint8_t crc_extra) {
  Bytes covered(frame.begin() + 1, frame.end());
  covered.push_back(crc_extra);
  const std::uint16_t crc = reference_crc(covered);
  frame.push_back(static_cast<std::uint8_t>(crc & 0xFF));
  frame.push_back(static_cast<std::uint8_t>(crc >> 8));
}

/// A v1 frame: FE len seq sysid compid msgid payload crc.
inline Bytes v1_frame(std::uint8_t msgid, std::uint8_t crc_extra, const Bytes& payload,
                      std::uint8_t seq = 0, std::uint8_t sysid = 1, std::uint8_t compid = 1) {
  Bytes f = {0xFE, static_cast<std::uint8_t>(payload.size()), seq, sysid, compid, msgid};
  f.insert(f.end(), payload.begin(), payload.end());
  append_crc(f, crc_extra);
  return f;
}

/// A v2 frame with the payload as given (no truncation here: tests choose).
/// With `signature`, sets incompat bit 0 and appends the 13 signature bytes
/// (link id, timestamp, hash; any contents, as the parser does not verify them).
inline Bytes v2_frame(std::uint32_t msgid, std::uint8_t crc_extra, const Bytes& payload,
                      std::uint8_t seq = 0, std::uint8_t sysid = 1, std::uint8_t compid = 1,
                      std::uint8_t incompat = 0, const Bytes& signature = {}) {
  Bytes f = {0xFD,
             static_cast<std::uint8_t>(payload.size()),
             incompat,
             0,
             seq,
             sysid,
             compid,
             static_cast<std::uint8_t>(msgid & 0xFF),
             static_cast<std::uint8_t>((msgid >> 8) & 0xFF),
             static_cast<std::uint8_t>((msgid >> 16) & 0xFF)};
  f.insert(f.end(), payload.begin(), payload.end());
  append_crc(f, crc_extra);
  f.insert(f.end(), signature.begin(), signature.end());
  return f;
}

inline Bytes concat(std::initializer_list<Bytes> parts) {
  Bytes out;
  for (const Bytes& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

/// Little-endian field writers for hand-built payloads.
inline void put_u8(Bytes& b, std::uint8_t v) {
  b.push_back(v);
}
inline void put_u16(Bytes& b, std::uint16_t v) {
  for (int i = 0; i < 2; ++i) b.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}
inline void put_u32(Bytes& b, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

struct Parsed {
  std::vector<MavlinkMessage> messages;
  ParserCounters counters;
  std::size_t buffered = 0;
};

/// Feeds `stream` in reads of `chunk` bytes (all at once for 0), checking after
/// every read that the buffer stays bounded and every byte is accounted for.
inline Parsed parse(const Bytes& stream, std::size_t chunk = 0) {
  MavlinkParser parser;
  Parsed out;
  std::size_t pos = 0;
  while (pos < stream.size()) {
    const std::size_t n = chunk == 0 ? stream.size() : std::min(chunk, stream.size() - pos);
    // A fresh copy per read, so ASan catches any read past the caller's bytes.
    const Bytes read(stream.begin() + static_cast<std::ptrdiff_t>(pos),
                     stream.begin() + static_cast<std::ptrdiff_t>(pos + n));
    parser.feed(read, out.messages);
    pos += n;
    EXPECT_LE(parser.buffered(), kMaxFrameBytes);
    const ParserCounters& c = parser.counters();
    EXPECT_EQ(pos, c.frame_bytes + c.unknown_id_bytes + c.rejected_bytes + c.garbage_bytes +
                       parser.buffered())
        << "every byte fed is in a frame, an unknown-id frame, garbage or the buffer";
  }
  out.counters = parser.counters();
  out.buffered = parser.buffered();
  return out;
}

}  // namespace rfsitl::position::mavlink::test
