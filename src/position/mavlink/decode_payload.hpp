#pragma once
/// Private: checked payload bytes -> message contents.
#include <cstdint>
#include <span>

#include "rfsitl/position/mavlink/mavlink_message.hpp"

namespace rfsitl::position::mavlink::detail {

/// The contents of a message `msgid` whose payload (as received, possibly
/// truncated, at most 255 bytes) passed its checksum: the decoded struct when
/// the id is one of MessagePayload's types, else an UndecodedMessage.
MessagePayload decode_payload(std::uint32_t msgid, std::span<const std::uint8_t> payload);

}  // namespace rfsitl::position::mavlink::detail
