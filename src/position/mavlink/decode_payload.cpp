#include "decode_payload.hpp"

#include <algorithm>
#include <cstddef>
#include <variant>

#include "wire_layout.hpp"

namespace rfsitl::position::mavlink::detail {
namespace {

constexpr std::size_t kAlternatives = std::variant_size_v<MessagePayload>;
static_assert(
    std::is_same_v<std::variant_alternative_t<kAlternatives - 1, MessagePayload>, UndecodedMessage>,
    "UndecodedMessage is the fallback, so it must come last");

// Tries each decoded type of MessagePayload in turn, so adding a type to the
// variant (with its WireLayout) is all it takes to decode it.
template <std::size_t I>
MessagePayload decode_as(std::uint32_t msgid, std::span<const std::uint8_t> payload) {
  if constexpr (I + 1 == kAlternatives) {
    UndecodedMessage raw;
    raw.msgid = msgid;
    raw.length = static_cast<std::uint8_t>(std::min(payload.size(), raw.payload.size()));
    std::copy_n(payload.begin(), raw.length, raw.payload.begin());
    return raw;
  } else {
    using M = std::variant_alternative_t<I, MessagePayload>;
    if (msgid != M::kId) return decode_as<I + 1>(msgid, payload);
    M message;
    PayloadReader reader(payload);
    WireLayout<M>::fields(reader, message);
    return message;
  }
}

}  // namespace

MessagePayload decode_payload(std::uint32_t msgid, std::span<const std::uint8_t> payload) {
  return decode_as<0>(msgid, payload);
}

}  // namespace rfsitl::position::mavlink::detail
