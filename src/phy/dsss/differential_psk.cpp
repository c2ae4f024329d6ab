#include "differential_psk.hpp"

#include <array>
#include <cmath>

namespace rfsitl::phy::dsss {
namespace {

constexpr std::array<cf32, 4> kQuadrant = {cf32{1, 0}, cf32{0, 1}, cf32{-1, 0}, cf32{0, -1}};

// Quarter turns per dibit value (d0 | d1 << 1): 00 -> 0, 10 (d0 = 0, d1 = 1) -> 1,
// 11 -> 2, 01 (d0 = 1, d1 = 0) -> 3.
constexpr std::array<unsigned, 4> kTurnsOfDibit = {0, 3, 1, 2};
// The inverse: dibit value of each quarter-turn count.
constexpr std::array<std::uint8_t, 4> kDibitOfTurns = {0, 2, 3, 1};

void push_byte_bits(std::uint8_t byte, DifferentialEncoder& enc, std::vector<cf32>& out) {
  for (int b = 0; b < 8; ++b) enc.push_bit(static_cast<std::uint8_t>((byte >> b) & 1U), out);
}

}  // namespace

void DifferentialEncoder::rotate(unsigned quarter_turns, std::vector<cf32>& out) {
  quadrant_ = (quadrant_ + quarter_turns) & 3U;
  out.push_back(kQuadrant[quadrant_]);
}

void DifferentialEncoder::push_bit(std::uint8_t bit, std::vector<cf32>& out) {
  rotate(bit != 0 ? 2U : 0U, out);
}

void DifferentialEncoder::push_dibit(std::uint8_t d0, std::uint8_t d1, std::vector<cf32>& out) {
  rotate(kTurnsOfDibit[(d0 & 1U) | ((d1 & 1U) << 1)], out);
}

std::vector<cf32> frame_symbols(const FrameHeader& header, std::span<const std::uint8_t> payload) {
  std::vector<cf32> out;
  out.reserve(frame_symbol_count(header.modulation, payload.size()));
  DifferentialEncoder enc;
  for (std::size_t i = 0; i < kPreambleSymbols; ++i) enc.push_bit(0, out);
  for (std::size_t i = 0; i < kSfdBits; ++i) {
    enc.push_bit(static_cast<std::uint8_t>((kSfd >> i) & 1U), out);
  }
  for (const std::uint8_t b : encode_header(header)) push_byte_bits(b, enc, out);
  std::vector<std::uint8_t> body;
  body.reserve(payload.size() + kCrc32Bytes);
  append_payload_with_crc(payload, body);
  if (header.modulation == Modulation::kDbpsk) {
    for (const std::uint8_t b : body) push_byte_bits(b, enc, out);
  } else {
    for (const std::uint8_t b : body) {
      for (int k = 0; k < 8; k += 2) {
        enc.push_dibit(static_cast<std::uint8_t>((b >> k) & 1U),
                       static_cast<std::uint8_t>((b >> (k + 1)) & 1U), out);
      }
    }
  }
  return out;
}

std::uint8_t dqpsk_decide(cf32 d) {
  // Nearest of the four axes: rotate by +45 degrees so the decision regions
  // become the quadrants of the rotated point.
  const float a = d.real() - d.imag();  // sqrt(2) * Re(d e^{j pi/4})
  const float b = d.real() + d.imag();  // sqrt(2) * Im(d e^{j pi/4})
  unsigned turns = 0;
  if (a >= 0.0F && b >= 0.0F) {
    turns = 0;
  } else if (a < 0.0F && b >= 0.0F) {
    turns = 1;
  } else if (a < 0.0F) {
    turns = 2;
  } else {
    turns = 3;
  }
  return kDibitOfTurns[turns];
}

}  // namespace rfsitl::phy::dsss
