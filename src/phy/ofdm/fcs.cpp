#include "fcs.hpp"

#include "rfsitl/common/crc.hpp"

namespace rfsitl::phy::ofdm {

std::uint32_t crc32(std::span<const std::uint8_t> bytes) {
  return rfsitl::crc32(bytes);
}

std::vector<std::uint8_t> append_fcs(std::span<const std::uint8_t> frame) {
  std::vector<std::uint8_t> out(frame.begin(), frame.end());
  const std::uint32_t fcs = crc32(frame);
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(fcs >> (8 * i)));
  return out;
}

bool fcs_valid(std::span<const std::uint8_t> frame_with_fcs) {
  if (frame_with_fcs.size() < 4) return false;
  const auto body = frame_with_fcs.first(frame_with_fcs.size() - 4);
  const std::uint32_t fcs = crc32(body);
  for (int i = 0; i < 4; ++i) {
    if (frame_with_fcs[body.size() + i] != static_cast<std::uint8_t>(fcs >> (8 * i))) return false;
  }
  return true;
}

}  // namespace rfsitl::phy::ofdm
