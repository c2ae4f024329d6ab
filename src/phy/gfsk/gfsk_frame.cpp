#include "gfsk_frame.hpp"

#include "rfsitl/common/crc.hpp"

namespace rfsitl::phy::gfsk {
namespace {

/// Appends octets to a symbol buffer, most significant bit first, optionally
/// whitened.
class SymbolWriter {
 public:
  explicit SymbolWriter(std::span<std::int8_t> out) : out_(out) {}

  void put(std::uint8_t octet) {
    for (int bit = 7; bit >= 0; --bit) {
      out_[n_++] = ((octet >> bit) & 1U) != 0 ? std::int8_t{1} : std::int8_t{-1};
    }
  }
  void put_whitened(std::uint8_t octet, gmsk::Whitener* w) {
    put(w != nullptr ? static_cast<std::uint8_t>(octet ^ w->next()) : octet);
  }
  std::size_t size() const { return n_; }

 private:
  std::span<std::int8_t> out_;
  std::size_t n_ = 0;
};

}  // namespace

std::size_t build_frame_symbols(std::size_t preamble_bytes, bool whitening, const FrameTag& tag,
                                std::span<const std::uint8_t> payload, std::span<std::int8_t> out) {
  SymbolWriter w(out);
  for (std::size_t i = 0; i < preamble_bytes; ++i) w.put(kPreambleOctet);
  for (int shift = 24; shift >= 0; shift -= 8) w.put(static_cast<std::uint8_t>(kSyncWord >> shift));

  gmsk::Whitener pn9;
  gmsk::Whitener* white = whitening ? &pn9 : nullptr;
  for (const std::uint8_t b : gmsk::encode_header(gmsk::FrameHeader{tag, payload.size()})) {
    w.put_whitened(b, white);
  }
  for (const std::uint8_t b : payload) w.put_whitened(b, white);
  const std::uint16_t crc = crc16(payload);
  w.put_whitened(static_cast<std::uint8_t>(crc >> 8), white);
  w.put_whitened(static_cast<std::uint8_t>(crc), white);
  return w.size();
}

}  // namespace rfsitl::phy::gfsk
