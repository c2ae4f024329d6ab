#pragma once
/// Serializes messages into MAVLink frames for one sending component.
///
/// v2 frames drop the payload's trailing zero bytes (keeping at least one), as
/// the specification requires of senders; v1 frames carry exactly the fields
/// before <extensions>. Frames are never signed. Each frame takes the next
/// value of the encoder's sequence counter (wrapping 255 -> 0), whatever the
/// version or message.
///
/// Not thread-safe (the counter): one encoder per sending component per thread,
/// or guard it. No exceptions for the messages declared here.
#include <cstdint>
#include <type_traits>
#include <vector>

#include "rfsitl/position/mavlink/mavlink_message.hpp"

namespace rfsitl::position::mavlink {

/// The message types the encoder serializes: every decoded type (messages.hpp).
template <class T>
concept EncodableMessage =
    std::is_same_v<T, Heartbeat> || std::is_same_v<T, GpsRawInt> || std::is_same_v<T, Attitude> ||
    std::is_same_v<T, GlobalPositionInt> || std::is_same_v<T, RequestDataStream> ||
    std::is_same_v<T, CommandLong> || std::is_same_v<T, CommandAck>;

class MavlinkEncoder {
 public:
  /// `sysid`, `compid`: the sender's identity written into every frame (the
  /// emulator talks to a vehicle as an onboard component of its own system id,
  /// or as a GCS with 255). `first_seq`: the first frame's sequence number.
  MavlinkEncoder(std::uint8_t sysid, std::uint8_t compid, std::uint8_t first_seq = 0) noexcept
      : sysid_(sysid), compid_(compid), seq_(first_seq) {}

  /// One complete frame holding `message`.
  template <EncodableMessage T>
  std::vector<std::uint8_t> encode(const T& message, MavlinkVersion version = MavlinkVersion::kV2);

  /// The sequence number the next frame will carry.
  std::uint8_t next_seq() const noexcept { return seq_; }
  std::uint8_t sysid() const noexcept { return sysid_; }
  std::uint8_t compid() const noexcept { return compid_; }

 private:
  std::uint8_t sysid_;
  std::uint8_t compid_;
  std::uint8_t seq_;
};

}  // namespace rfsitl::position::mavlink
