#pragma once
/// GMSK transceiver on liquid-dsp's gmskframegen / gmskframesync.
#include <memory>

#include "rfsitl/phy/transceiver.hpp"

namespace rfsitl::phy {

struct GmskSettings {
  unsigned samples_per_symbol = 2;    ///< k
  unsigned filter_delay_symbols = 3;  ///< m
  float bandwidth_time = 0.5F;        ///< BT
  std::size_t max_payload_bytes = 2048;
};

/// Frame layout: liquid's GMSK frame (preamble, header, payload, tail) whose
/// 8-byte header carries [src][dst][serial u32 LE][format version][reserved]
/// and whose payload is the net payload protected by CRC-32.
/// Precondition: settings valid (k >= 2, 1 <= m <= 16, 0 < BT < 1, payload <= 65535).
std::unique_ptr<Transceiver> make_gmsk_transceiver(const GmskSettings& settings);

}  // namespace rfsitl::phy
