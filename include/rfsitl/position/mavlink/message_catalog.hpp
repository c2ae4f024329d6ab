#pragma once
/// The MAVLink messages this codec can check: every message of the ArduPilot
/// dialect (ardupilotmega.xml with common, standard, minimal and the dialects it
/// includes), which also covers what PX4 sends in practice. A frame's checksum
/// can only be verified when its message's CRC_EXTRA is known, so a frame of an
/// id outside this catalog cannot be told apart from noise that happens to start
/// with a magic byte; the parser skips and counts such frames.
///
/// The table is generated from the XML definitions by
/// src/position/mavlink/generate_message_catalog.py; the unit tests re-derive the
/// entries of the decoded messages by hand. Immutable: safe from any thread.
#include <cstdint>
#include <span>

namespace rfsitl::position::mavlink {

/// One message definition, as far as framing needs it.
struct MessageSpec {
  std::uint32_t id;
  /// The 8-bit seed folded into every frame's checksum: a hash of the message's
  /// name and its base fields' types and names in wire order.
  std::uint8_t crc_extra;
  /// Payload bytes of the fields before <extensions>: the exact payload length
  /// of a MAVLink 1 frame (v1 neither truncates nor carries extensions).
  std::uint8_t base_length;
  /// Payload bytes with the extension fields: the longest MAVLink 2 payload of
  /// this definition (v2 senders drop trailing zero bytes, so frames may be shorter).
  std::uint8_t max_length;
  const char* name;  ///< e.g. "GLOBAL_POSITION_INT"; static storage
};

/// The definition of message `id`, or nullptr if this catalog does not know it.
/// O(log n), no allocation.
const MessageSpec* find_message_spec(std::uint32_t id) noexcept;

/// Every known definition, sorted by id.
std::span<const MessageSpec> message_catalog() noexcept;

}  // namespace rfsitl::position::mavlink
