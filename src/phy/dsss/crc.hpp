#pragma once
/// The two checks of a DSSS frame: CRC-16 over the header and CRC-32 over the
/// payload (the project's common implementations).
#include "rfsitl/common/crc.hpp"

namespace rfsitl::phy::dsss {
using rfsitl::crc16;
using rfsitl::crc32;
}  // namespace rfsitl::phy::dsss
