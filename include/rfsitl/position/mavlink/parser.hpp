#pragma once
/// Streaming MAVLink parser for one byte stream (a TCP connection, a serial
/// line, or the datagrams of one UDP peer fed in order).
///
/// Frames (https://mavlink.io/en/guide/serialization.html):
///   v1: FE len seq sysid compid msgid payload[len] crc_lo crc_hi
///   v2: FD len incompat compat seq sysid compid msgid(3, LE) payload[len]
///       crc_lo crc_hi [signature, 13 bytes, when incompat bit 0 is set]
///
/// What the parser accepts and what it drops (each drop is counted, see
/// ParserCounters):
///  - bytes before a magic byte (0xFE, 0xFD) are garbage;
///  - a v2 header with an incompat flag other than bit 0 (signed) is dropped;
///  - a frame whose id is not in the catalog (message_catalog.hpp) cannot be
///    checked: it is skipped whole (header, payload, checksum, signature), since
///    in a real stream it is a real frame of a message we do not know;
///  - a v1 frame whose length is not its message's base length is dropped;
///  - a frame whose checksum fails is dropped;
///  - a v2 signature is skipped unchecked (the emulator is not a security boundary).
/// After a dropped candidate (flags, length, checksum) scanning resumes at the
/// byte after its magic byte, so a real frame that starts inside the rejected
/// bytes is still found. The candidate's bytes that the rescan finds no frame
/// in (up to the end its header gave) count as rejected bytes, not garbage: a
/// corrupted frame is one bad_crc and its bytes, not also a run of garbage.
/// Accepted v2 payloads shorter than the message (trailing zeros truncated by the
/// sender) are zero-extended; longer ones (extensions newer than the catalog)
/// are accepted and the unknown tail ignored.
///
/// The result does not depend on how the stream is cut into feed() calls.
/// Memory: one frame buffer of kMaxFrameBytes, no allocation except appending
/// to the caller's vector. Not thread-safe: one parser per stream, one thread at
/// a time.
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "rfsitl/position/mavlink/mavlink_message.hpp"

namespace rfsitl::position::mavlink {

inline constexpr std::uint8_t kMagicV1 = 0xFE;
inline constexpr std::uint8_t kMagicV2 = 0xFD;
inline constexpr std::uint8_t kIncompatSigned = 0x01;
inline constexpr std::size_t kHeaderBytesV1 = 6;   ///< magic to msgid
inline constexpr std::size_t kHeaderBytesV2 = 10;  ///< magic to msgid
inline constexpr std::size_t kChecksumBytes = 2;
inline constexpr std::size_t kSignatureBytes = 13;  ///< link id, 6-byte timestamp, 6-byte hash
/// The longest frame: a signed v2 frame with a 255-byte payload.
inline constexpr std::size_t kMaxFrameBytes =
    kHeaderBytesV2 + 255 + kChecksumBytes + kSignatureBytes;

/// What the parser did with the bytes it consumed. Every byte fed is counted in
/// exactly one of frame_bytes, unknown_id_bytes, rejected_bytes and
/// garbage_bytes once it has left the buffer, so at any time
///   bytes fed == frame_bytes + unknown_id_bytes + rejected_bytes + garbage_bytes
///                + buffered().
/// Frame counts are separate from byte counts.
struct ParserCounters {
  std::uint64_t frames = 0;              ///< accepted frames (checksum good), decoded or not
  std::uint64_t frame_bytes = 0;         ///< their bytes, signatures included
  std::uint64_t garbage_bytes = 0;       ///< outside any frame or candidate, and partial
                                         ///< frames discarded by reset()
  std::uint64_t rejected_bytes = 0;      ///< of dropped candidates (checksum, length, flags)
  std::uint64_t bad_crc = 0;             ///< candidates dropped for their checksum
  std::uint64_t unknown_id = 0;          ///< frames skipped because their id is not in the catalog
  std::uint64_t unknown_id_bytes = 0;    ///< their bytes
  std::uint64_t bad_incompat_flags = 0;  ///< v2 candidates with an unknown incompat flag
  std::uint64_t bad_length = 0;          ///< v1 candidates whose length is not the message's
  std::uint64_t truncated = 0;           ///< partial frames discarded by reset()
  bool operator==(const ParserCounters&) const = default;
};

class MavlinkParser {
 public:
  /// Consumes all of `bytes` (any length, any cut); appends each accepted frame
  /// to `out` in stream order and returns how many it appended. Never throws
  /// except std::bad_alloc from `out`.
  std::size_t feed(std::span<const std::uint8_t> bytes, std::vector<MavlinkMessage>& out);

  /// Bytes of a frame not yet complete, <= kMaxFrameBytes.
  std::size_t buffered() const noexcept { return len_; }

  const ParserCounters& counters() const noexcept { return counters_; }

  /// Forgets a partial frame (for a stream that closed and reopened): its bytes
  /// count as garbage and the frame as truncated. Counters are kept.
  void reset() noexcept;

 private:
  // Drops the first n buffered bytes.
  void drop_front(std::size_t n) noexcept;
  // Copies input into the buffer until it holds `want` bytes; true when it does.
  bool fill(std::size_t want, std::span<const std::uint8_t>& in) noexcept;
  // Rejects the candidate at the buffer's start, `frame_bytes` long by its
  // header: its magic byte is dropped, the rest is scanned again.
  void reject(std::uint64_t& reason, std::size_t frame_bytes) noexcept;
  // Counts `n` bytes that leave the stream unused at stream offset consumed_:
  // rejected while inside a dropped candidate, garbage beyond it. Does not
  // move consumed_.
  void count_unused(std::size_t n) noexcept;
  // Consumes what is left of an unknown-id frame being skipped; true when done.
  bool skip(std::span<const std::uint8_t>& in) noexcept;
  // Moves the buffer's start, else the input's, to the next magic byte; true
  // when the buffer then starts with one.
  bool find_magic(std::span<const std::uint8_t>& in) noexcept;
  // Decodes the checked frame at the buffer's start into `out` and drops it.
  void accept(const FrameInfo& info, std::size_t header_bytes, std::size_t frame_bytes,
              std::vector<MavlinkMessage>& out);

  std::array<std::uint8_t, kMaxFrameBytes> buf_{};
  std::size_t len_ = 0;         // buffered bytes; buf_[0] is a magic byte when a frame is underway
  std::size_t skip_ = 0;        // bytes of an unknown-id frame still to skip
  std::uint64_t consumed_ = 0;  // stream offset of buf_[0]: bytes that left the parser
  std::uint64_t reject_end_ = 0;  // stream offset where the last dropped candidate ends
  ParserCounters counters_;
};

}  // namespace rfsitl::position::mavlink
