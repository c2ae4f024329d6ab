#pragma once
/// One MAVLink message as the parser hands it over: the frame it came in
/// (version, sequence number, sender) and its contents, decoded when this codec
/// knows the layout (messages.hpp), otherwise the checked payload bytes.
#include <array>
#include <cstdint>
#include <variant>

#include "rfsitl/position/mavlink/messages.hpp"

namespace rfsitl::position::mavlink {

enum class MavlinkVersion : std::uint8_t {
  kV1 = 1,  ///< magic 0xFE, 8-bit message ids, fixed payload lengths
  kV2 = 2,  ///< magic 0xFD, 24-bit ids, truncated payloads, optional signature
};

/// Where a message came from, as its frame header says.
struct FrameInfo {
  MavlinkVersion version = MavlinkVersion::kV2;
  std::uint8_t seq = 0;     ///< the sender's per-component counter, wraps at 255
  std::uint8_t sysid = 0;   ///< sending system (vehicle), 1..255
  std::uint8_t compid = 0;  ///< sending component (1 = autopilot)
  std::uint32_t msgid = 0;
  std::uint8_t payload_length = 0;  ///< bytes on the wire, after any v2 truncation
  std::uint8_t compat_flags = 0;    ///< v2 only; none are defined, kept for diagnostics
  bool is_signed = false;           ///< v2 signature present (never verified by this codec)
  bool operator==(const FrameInfo&) const = default;
};

/// A frame whose checksum verified but whose contents this codec does not decode
/// (for example SYS_STATUS or STATUSTEXT). `payload` holds the bytes as received
/// followed by zeros, which is the message's untruncated payload up to
/// MessageSpec::max_length.
struct UndecodedMessage {
  std::uint32_t msgid = 0;
  std::uint8_t length = 0;  ///< bytes received
  std::array<std::uint8_t, 255> payload{};
  bool operator==(const UndecodedMessage&) const = default;
};

using MessagePayload = std::variant<Heartbeat, GpsRawInt, Attitude, GlobalPositionInt,
                                    RequestDataStream, CommandLong, CommandAck, UndecodedMessage>;

struct MavlinkMessage {
  FrameInfo frame;
  MessagePayload payload;

  /// The decoded contents if they are a `T`, else nullptr.
  template <class T>
  const T* get() const {
    return std::get_if<T>(&payload);
  }

  bool operator==(const MavlinkMessage&) const = default;
};

}  // namespace rfsitl::position::mavlink
