#pragma once
/// IEEE 802.11a/g OFDM transceiver (clause 17) at one of the eight rates; the
/// 20 MHz numerology scales with the emulator's sample rate.
#include <memory>

#include "rfsitl/phy/transceiver.hpp"

namespace rfsitl::phy {

struct OfdmSettings {
  unsigned rate_mbps = 6;  ///< 6, 9, 12, 18, 24, 36, 48 or 54 (at 20 MHz)
  std::size_t max_payload_bytes = 2048;
};

/// PSDU = 802.11 data frame carrying the net frame plus FCS (see
/// ofdm/mac_frame.hpp). Output is scaled to unit mean power, like the GMSK PHY.
/// Throws std::invalid_argument for an unknown rate or a payload limit above
/// 4095 - 30 octets.
std::unique_ptr<Transceiver> make_ofdm_transceiver(const OfdmSettings& settings);

}  // namespace rfsitl::phy
