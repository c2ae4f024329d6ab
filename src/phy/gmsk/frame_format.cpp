#include "frame_format.hpp"

#include "crc.hpp"

namespace rfsitl::phy::gmsk {
namespace {

// Bit i set means pseudo-symbol i is -1. The sync word was picked among 20000
// random balanced words as the one with the lowest noise-free normalised
// correlation sidelobe (0.07, against 0.82 at the peak, k = 2, BT = 0.5) over
// every timing offset at which the preamble or part of it fills the correlator.
constexpr std::uint8_t kPreambleBits = 0b11101000;  // +1 +1 +1 -1 +1 -1 -1 -1
constexpr std::uint32_t kSyncBits = 0xB0155FB0U;

std::int8_t bit_to_symbol(unsigned bit) {
  return bit != 0 ? std::int8_t{-1} : std::int8_t{1};
}

/// Appends pseudo-symbols, converting each to the frequency symbol a_n = c_n c_{n-1}.
class Precoder {
 public:
  explicit Precoder(std::span<std::int8_t> out) : out_(out) {}
  void push(std::int8_t c) {
    out_[n_++] = static_cast<std::int8_t>(c * prev_);
    prev_ = c;
  }
  void push_byte(std::uint8_t b) {
    for (unsigned i = 0; i < 8; ++i) push(bit_to_symbol((b >> i) & 1U));
  }
  std::size_t size() const { return n_; }

 private:
  std::span<std::int8_t> out_;
  std::size_t n_ = 0;
  std::int8_t prev_ = 1;
};

}  // namespace

std::int8_t preamble_symbol(std::size_t i) {
  return bit_to_symbol((kPreambleBits >> i) & 1U);
}

std::int8_t sync_symbol(std::size_t i) {
  return bit_to_symbol((kSyncBits >> i) & 1U);
}

std::array<std::uint8_t, kHeaderBytes> encode_header(const FrameHeader& h) {
  std::array<std::uint8_t, kHeaderBytes> b{};
  b[0] = h.tag.src;
  b[1] = h.tag.dst;
  for (unsigned i = 0; i < 4; ++i) b[2 + i] = static_cast<std::uint8_t>(h.tag.serial >> (8 * i));
  b[6] = static_cast<std::uint8_t>(h.payload_bytes);
  b[7] = static_cast<std::uint8_t>(h.payload_bytes >> 8);
  const std::uint16_t crc = crc16(std::span(b).first(8));
  b[8] = static_cast<std::uint8_t>(crc);
  b[9] = static_cast<std::uint8_t>(crc >> 8);
  return b;
}

std::optional<FrameHeader> decode_header(std::span<const std::uint8_t, kHeaderBytes> b) {
  const auto crc = static_cast<std::uint16_t>(b[8] | (b[9] << 8));
  if (crc16(b.first(8)) != crc) return std::nullopt;
  FrameHeader h;
  h.tag.src = b[0];
  h.tag.dst = b[1];
  h.tag.serial = 0;
  for (unsigned i = 0; i < 4; ++i) h.tag.serial |= static_cast<std::uint32_t>(b[2 + i]) << (8 * i);
  h.payload_bytes = static_cast<std::size_t>(b[6] | (b[7] << 8));
  return h;
}

std::uint8_t Whitener::next() {
  std::uint8_t out = 0;
  for (unsigned i = 0; i < 8; ++i) {
    const unsigned bit = state_ & 1U;  // output the oldest stage
    const unsigned feedback = (state_ ^ (state_ >> 5)) & 1U;
    state_ = static_cast<std::uint16_t>((state_ >> 1) | (feedback << 8));
    out = static_cast<std::uint8_t>(out | (bit << i));
  }
  return out;
}

std::size_t build_frame_symbols(const FrameTag& tag, std::span<const std::uint8_t> payload,
                                std::span<std::int8_t> out) {
  Precoder p(out);
  for (std::size_t r = 0; r < kPreambleRepeats; ++r) {
    for (std::size_t i = 0; i < kPreamblePeriodSymbols; ++i) p.push(preamble_symbol(i));
  }
  for (std::size_t i = 0; i < kSyncSymbols; ++i) p.push(sync_symbol(i));
  Whitener w;
  for (const std::uint8_t b : encode_header(FrameHeader{tag, payload.size()})) {
    p.push_byte(b ^ w.next());
  }
  for (const std::uint8_t b : payload) p.push_byte(b ^ w.next());
  const std::uint32_t crc = crc32(payload);
  for (unsigned i = 0; i < kPayloadCrcBytes; ++i) {
    p.push_byte(static_cast<std::uint8_t>(crc >> (8 * i)) ^ w.next());
  }
  for (std::size_t i = 0; i < kTailSymbols; ++i) p.push(1);
  return p.size();
}

}  // namespace rfsitl::phy::gmsk
