#include "rfsitl/phy/ofdm/fcs.hpp"

#include <array>

namespace rfsitl::phy::ofdm {
namespace {

constexpr std::array<std::uint32_t, 256> make_table() {
  std::array<std::uint32_t, 256> t{};
  for (std::uint32_t i = 0; i < 256; ++i) {
    std::uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1U) != 0 ? 0xEDB88320U ^ (c >> 1) : c >> 1;
    t[i] = c;
  }
  return t;
}

constexpr std::array<std::uint32_t, 256> kTable = make_table();

}  // namespace

std::uint32_t crc32(std::span<const std::uint8_t> bytes) {
  std::uint32_t c = 0xFFFFFFFFU;
  for (const std::uint8_t b : bytes) c = kTable[(c ^ b) & 0xFFU] ^ (c >> 8);
  return c ^ 0xFFFFFFFFU;
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
