#pragma once
/// The PSDU an rfsitl OFDM node sends: an IEEE 802.11 data frame (so that 802.11
/// tools such as Wireshark or gr-ieee802-11 parse it) whose body is the net frame.
///
///   Frame Control 08 00 (data) | Duration 00 00 |
///   Address 1 = destination 02:00:00:00:00:<dst> (ff:ff:ff:ff:ff:ff for dst 255) |
///   Address 2 = source      02:00:00:00:00:<src> |
///   Address 3 = 02:72:<serial, 4 octets LE> (the frame's serial, for accounting) |
///   Sequence Control = (serial mod 4096) << 4 |
///   body = [src][dst][payload] | FCS (CRC-32)
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "rfsitl/phy/transceiver.hpp"

namespace rfsitl::phy::ofdm {

inline constexpr std::size_t kMacHeaderBytes = 24;
/// Octets the PSDU adds around the net payload: header, src, dst, FCS.
inline constexpr std::size_t kMacOverheadBytes = kMacHeaderBytes + 2 + 4;

std::vector<std::uint8_t> encode_mac_frame(const FrameTag& tag,
                                           std::span<const std::uint8_t> payload);

struct MacFrame {
  FrameTag tag;
  std::span<const std::uint8_t> payload;  ///< points into the PSDU passed to decode
};

/// Parses a PSDU whose FCS is already known to be valid; nullopt if it is not
/// an rfsitl data frame (wrong frame control, address 3 or body too short).
std::optional<MacFrame> decode_mac_frame(std::span<const std::uint8_t> psdu);

}  // namespace rfsitl::phy::ofdm
