#include "rfsitl/position/mavlink/encoder.hpp"

#include <stdexcept>
#include <string>

#include "rfsitl/position/mavlink/checksum.hpp"
#include "rfsitl/position/mavlink/message_catalog.hpp"
#include "rfsitl/position/mavlink/parser.hpp"
#include "wire_layout.hpp"

namespace rfsitl::position::mavlink {
namespace {

// The payload length a frame carries: v1 the base fields exactly, v2 all
// fields minus trailing zero bytes, but never less than one byte.
std::size_t wire_length(std::span<const std::uint8_t> full, const MessageSpec& spec,
                        MavlinkVersion version) {
  if (version == MavlinkVersion::kV1) return spec.base_length;
  std::size_t n = full.size();
  while (n > 1 && full[n - 1] == 0) --n;
  return n;
}

}  // namespace

template <EncodableMessage T>
std::vector<std::uint8_t> MavlinkEncoder::encode(const T& message, MavlinkVersion version) {
  const MessageSpec* spec = find_message_spec(T::kId);
  detail::PayloadWriter writer;
  detail::WireLayout<T>::fields(writer, message);
  const std::span<const std::uint8_t> full = writer.bytes();
  if (spec == nullptr || full.size() != spec->max_length) {
    // A WireLayout that disagrees with the catalog is a bug here, not bad input.
    throw std::logic_error("MAVLink encoder: layout of message " + std::to_string(T::kId) +
                           " disagrees with its catalog entry");
  }
  const std::size_t len = wire_length(full, *spec, version);

  std::vector<std::uint8_t> frame;
  frame.reserve(kHeaderBytesV2 + len + kChecksumBytes);
  if (version == MavlinkVersion::kV1) {
    frame = {kMagicV1, static_cast<std::uint8_t>(len),   seq_, sysid_,
             compid_,  static_cast<std::uint8_t>(T::kId)};
  } else {
    frame = {kMagicV2,
             static_cast<std::uint8_t>(len),
             0,  // incompat flags: not signed
             0,  // compat flags
             seq_,
             sysid_,
             compid_,
             static_cast<std::uint8_t>(T::kId & 0xFFU),
             static_cast<std::uint8_t>((T::kId >> 8) & 0xFFU),
             static_cast<std::uint8_t>((T::kId >> 16) & 0xFFU)};
  }
  frame.insert(frame.end(), full.begin(), full.begin() + static_cast<std::ptrdiff_t>(len));
  const std::uint16_t crc =
      frame_checksum(std::span<const std::uint8_t>(frame).subspan(1), spec->crc_extra);
  frame.push_back(static_cast<std::uint8_t>(crc & 0xFFU));
  frame.push_back(static_cast<std::uint8_t>(crc >> 8));
  ++seq_;  // wraps 255 -> 0 as the protocol expects
  return frame;
}

template std::vector<std::uint8_t> MavlinkEncoder::encode(const Heartbeat&, MavlinkVersion);
template std::vector<std::uint8_t> MavlinkEncoder::encode(const GpsRawInt&, MavlinkVersion);
template std::vector<std::uint8_t> MavlinkEncoder::encode(const Attitude&, MavlinkVersion);
template std::vector<std::uint8_t> MavlinkEncoder::encode(const GlobalPositionInt&, MavlinkVersion);
template std::vector<std::uint8_t> MavlinkEncoder::encode(const RequestDataStream&, MavlinkVersion);
template std::vector<std::uint8_t> MavlinkEncoder::encode(const CommandLong&, MavlinkVersion);
template std::vector<std::uint8_t> MavlinkEncoder::encode(const CommandAck&, MavlinkVersion);

}  // namespace rfsitl::position::mavlink
