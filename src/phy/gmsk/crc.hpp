#pragma once
/// The two checksums of the fast GMSK frame: CRC-16 over the header, CRC-32 over
/// the payload (the project's common implementations).
#include "rfsitl/common/crc.hpp"

namespace rfsitl::phy::gmsk {
using rfsitl::crc16;
using rfsitl::crc32;
}  // namespace rfsitl::phy::gmsk
