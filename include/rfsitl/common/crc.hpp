#pragma once
/// The two checksums every rfsitl frame format uses, table-driven (a frame's
/// CRC runs once per frame but over up to 64 KiB). Header-only: the tables are
/// built at compile time.
#include <array>
#include <cstdint>
#include <span>

namespace rfsitl {
namespace crc_detail {

constexpr std::array<std::uint16_t, 256> make_crc16_table() {
  std::array<std::uint16_t, 256> t{};
  for (unsigned b = 0; b < 256; ++b) {
    auto v = static_cast<std::uint16_t>(b << 8);
    for (int i = 0; i < 8; ++i) {
      v = static_cast<std::uint16_t>((v & 0x8000U) != 0 ? (v << 1) ^ 0x1021U : v << 1);
    }
    t[b] = v;
  }
  return t;
}

constexpr std::array<std::uint32_t, 256> make_crc32_table() {
  std::array<std::uint32_t, 256> t{};
  for (std::uint32_t b = 0; b < 256; ++b) {
    std::uint32_t v = b;
    for (int i = 0; i < 8; ++i) v = (v & 1U) != 0 ? (v >> 1) ^ 0xEDB88320U : v >> 1;
    t[b] = v;
  }
  return t;
}

inline constexpr auto kCrc16Table = make_crc16_table();
inline constexpr auto kCrc32Table = make_crc32_table();

}  // namespace crc_detail

/// CRC-16/CCITT-FALSE: polynomial 0x1021, initial value 0xFFFF, no reflection,
/// no final XOR; crc16("123456789") == 0x29B1.
inline std::uint16_t crc16(std::span<const std::uint8_t> bytes) {
  std::uint16_t crc = 0xFFFF;
  for (const std::uint8_t b : bytes) {
    crc =
        static_cast<std::uint16_t>((crc << 8) ^ crc_detail::kCrc16Table[((crc >> 8) ^ b) & 0xFFU]);
  }
  return crc;
}

/// CRC-32 of IEEE 802.3 (the 802.11 FCS): reflected polynomial 0xEDB88320,
/// initial value and final XOR 0xFFFFFFFF; crc32("123456789") == 0xCBF43926.
inline std::uint32_t crc32(std::span<const std::uint8_t> bytes) {
  std::uint32_t crc = 0xFFFFFFFFU;
  for (const std::uint8_t b : bytes) crc = (crc >> 8) ^ crc_detail::kCrc32Table[(crc ^ b) & 0xFFU];
  return crc ^ 0xFFFFFFFFU;
}

}  // namespace rfsitl
