#include "frame_format.hpp"

#include <stdexcept>
#include <string>
#include <vector>

#include "crc.hpp"

namespace rfsitl::phy::dsss {
namespace {

constexpr std::uint8_t kModulationBit = 0x10;
constexpr std::uint16_t kRequestBit = 0x8000;
constexpr std::uint16_t kReservedControlBit = 0x4000;

void put_le(std::uint8_t* p, std::uint32_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}

std::uint32_t get_le(const std::uint8_t* p, int bytes) {
  std::uint32_t v = 0;
  for (int i = 0; i < bytes; ++i) v |= static_cast<std::uint32_t>(p[i]) << (8 * i);
  return v;
}

}  // namespace

std::optional<Modulation> modulation_from_name(std::string_view name) {
  if (name == "dbpsk") return Modulation::kDbpsk;
  if (name == "dqpsk") return Modulation::kDqpsk;
  return std::nullopt;
}

unsigned bits_per_symbol(Modulation m) {
  return m == Modulation::kDqpsk ? 2 : 1;
}

HeaderBytes encode_header(const FrameHeader& h) {
  HeaderBytes b{};
  b[0] = static_cast<std::uint8_t>(kFormatVersion |
                                   (h.modulation == Modulation::kDqpsk ? kModulationBit : 0));
  put_le(&b[1], h.length, 2);
  b[3] = h.src;
  b[4] = h.dst;
  put_le(&b[5], h.serial, 4);
  put_le(&b[9], h.control, 2);
  put_le(&b[11], crc16(std::span(b).first(11)), 2);
  return b;
}

std::optional<FrameHeader> decode_header(const HeaderBytes& b) {
  if (get_le(&b[11], 2) != crc16(std::span(b).first(11))) return std::nullopt;
  if ((b[0] & ~kModulationBit) != kFormatVersion) return std::nullopt;
  FrameHeader h;
  h.modulation = (b[0] & kModulationBit) != 0 ? Modulation::kDqpsk : Modulation::kDbpsk;
  h.length = static_cast<std::uint16_t>(get_le(&b[1], 2));
  h.src = b[3];
  h.dst = b[4];
  h.serial = get_le(&b[5], 4);
  h.control = static_cast<std::uint16_t>(get_le(&b[9], 2));
  return h;
}

std::uint16_t encode_control(const ControlField& f) {
  if (f.code_index > kMaxControlCodeIndex) {
    throw std::invalid_argument("control field: code index " + std::to_string(f.code_index) +
                                " exceeds " + std::to_string(kMaxControlCodeIndex));
  }
  if (f.epoch > kMaxControlEpoch) {
    throw std::invalid_argument("control field: epoch " + std::to_string(f.epoch) + " exceeds " +
                                std::to_string(kMaxControlEpoch));
  }
  if (!f.code_request) {
    if (f.code_index != 0 || f.epoch != 0) {
      throw std::invalid_argument("control field: code index and epoch need a code request");
    }
    return 0;
  }
  return static_cast<std::uint16_t>(kRequestBit | (f.epoch << 10) | f.code_index);
}

std::optional<ControlField> decode_control(std::uint16_t v) {
  if ((v & kReservedControlBit) != 0) return std::nullopt;
  if ((v & kRequestBit) == 0) {
    if (v != 0) return std::nullopt;
    return ControlField{};
  }
  return ControlField{true, static_cast<std::uint16_t>(v & 0x3FFU),
                      static_cast<std::uint8_t>((v >> 10) & 0xFU)};
}

std::size_t frame_symbol_count(Modulation m, std::size_t payload_bytes) {
  const std::size_t payload_bits = 8 * (payload_bytes + kCrc32Bytes);
  const unsigned k = bits_per_symbol(m);
  return kSyncSymbols + kHeaderBits + (payload_bits + k - 1) / k;
}

void append_payload_with_crc(std::span<const std::uint8_t> payload,
                             std::vector<std::uint8_t>& out) {
  out.insert(out.end(), payload.begin(), payload.end());
  std::uint8_t c[kCrc32Bytes];
  put_le(c, crc32(payload), 4);
  out.insert(out.end(), c, c + kCrc32Bytes);
}

bool payload_crc_valid(std::span<const std::uint8_t> p) {
  if (p.size() < kCrc32Bytes) return false;
  const std::size_t n = p.size() - kCrc32Bytes;
  return get_le(&p[n], 4) == crc32(p.first(n));
}

}  // namespace rfsitl::phy::dsss
