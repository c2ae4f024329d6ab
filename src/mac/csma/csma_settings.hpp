#pragma once
// Internal to the MAC "csma": its settings, declared once in csma_mac.cpp.
#include <cstdint>

namespace rfsitl::mac {

struct CsmaSettings {
  double slot_us = 250.0;  // one tick at 1 Msps and 250-sample ticks
  double sifs_us = 250.0;
  std::uint32_t cw_min = 15;
  std::uint32_t cw_max = 1023;
  std::uint32_t retry_limit = 7;
  double cca_threshold_db = 3.0;
};

}  // namespace rfsitl::mac
