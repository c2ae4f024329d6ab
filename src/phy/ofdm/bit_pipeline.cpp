#include "bit_pipeline.hpp"

#include <array>
#include <cmath>
#include <stdexcept>

namespace rfsitl::phy::ofdm {
namespace {

/// Generator polynomials of the 17.3.5.6 encoder as tap masks over the register
/// (bit d set = the input delayed by d samples is summed): g0 = 133 (octal) =
/// 1 011 011 taps delays 0, 2, 3, 5, 6; g1 = 171 = 1 111 001 taps 0, 1, 2, 3, 6.
constexpr unsigned kTapsA = 0b1101101;  // bit d = delay d
constexpr unsigned kTapsB = 0b1001111;

unsigned parity(unsigned v) {
  unsigned p = 0;
  while (v != 0) {
    p ^= v & 1U;
    v >>= 1U;
  }
  return p;
}

/// 17.3.5.6 / Figure 17-9: which rate-1/2 outputs (A0 B0 A1 B1 ...) survive.
/// R = 2/3 sends A0 B0 A1 of every A0 B0 A1 B1 (B1 stolen); R = 3/4 sends
/// A0 B0 A1 B2 of every A0 B0 A1 B1 A2 B2 (B1 and A2 stolen).
constexpr std::array<bool, 4> kKeepTwoThirds = {true, true, true, false};
constexpr std::array<bool, 6> kKeepThreeQuarters = {true, true, true, false, false, true};

template <std::size_t N>
std::vector<std::uint8_t> apply_pattern(std::span<const std::uint8_t> coded,
                                        const std::array<bool, N>& keep) {
  std::vector<std::uint8_t> out;
  out.reserve(coded.size());
  for (std::size_t i = 0; i < coded.size(); ++i) {
    if (keep[i % N]) out.push_back(coded[i]);
  }
  return out;
}

/// Gray-coded amplitude levels of one I or Q axis, Tables 17-9 and 17-10 (16-QAM:
/// b0 b1; 64-QAM: b0 b1 b2), indexed with the first bit as the most significant.
constexpr std::array<float, 4> kLevels16 = {-3.0F, -1.0F, 3.0F, 1.0F};
constexpr std::array<float, 8> kLevels64 = {-7.0F, -5.0F, -1.0F, -3.0F, 7.0F, 5.0F, 1.0F, 3.0F};

unsigned bits_msb_first(std::span<const std::uint8_t> bits) {
  unsigned v = 0;
  for (std::uint8_t b : bits) v = (v << 1U) | (b & 1U);
  return v;
}

}  // namespace

std::vector<std::uint8_t> bytes_to_bits(std::span<const std::uint8_t> bytes) {
  std::vector<std::uint8_t> bits;
  bits.reserve(bytes.size() * 8);
  for (std::uint8_t byte : bytes) {
    for (unsigned i = 0; i < 8; ++i) bits.push_back(static_cast<std::uint8_t>((byte >> i) & 1U));
  }
  return bits;
}

std::vector<std::uint8_t> bits_to_bytes(std::span<const std::uint8_t> bits) {
  if (bits.size() % 8 != 0) throw std::invalid_argument("bits_to_bytes: size not a multiple of 8");
  std::vector<std::uint8_t> bytes(bits.size() / 8, 0);
  for (std::size_t i = 0; i < bits.size(); ++i) {
    bytes[i / 8] = static_cast<std::uint8_t>(bytes[i / 8] | ((bits[i] & 1U) << (i % 8)));
  }
  return bytes;
}

void scramble(std::span<std::uint8_t> bits, std::uint8_t seed) {
  if ((seed & 0x7FU) == 0) throw std::invalid_argument("scramble: seed must be nonzero");
  // Figure 17-7: the output x7 ^ x4 is both the scrambling bit and the new x1;
  // the register shifts x1 -> x2 -> ... -> x7. Bit i of `state` holds x(i+1).
  unsigned state = seed & 0x7FU;
  for (std::uint8_t& b : bits) {
    const unsigned out = ((state >> 6U) ^ (state >> 3U)) & 1U;
    state = ((state << 1U) | out) & 0x7FU;
    b = static_cast<std::uint8_t>((b ^ out) & 1U);
  }
}

std::uint8_t seed_from_service(std::span<const std::uint8_t> first7) {
  if (first7.size() != 7) throw std::invalid_argument("seed_from_service: need 7 bits");
  // With the SERVICE bits zero, the scrambled bits are the scrambler outputs
  // z0..z6, and z(n) = z(n-4) ^ z(n-7) with x_i = z(-i) at the start. Running the
  // recurrence backwards, z(m) = z(m+7) ^ z(m+3), yields z(-1)..z(-7) = x1..x7.
  std::array<unsigned, 14> z{};  // z[m + 7] holds z(m), m = -7..6
  for (std::size_t n = 0; n < 7; ++n) z[n + 7] = first7[n] & 1U;
  for (int m = -1; m >= -7; --m) {
    z[static_cast<std::size_t>(m + 7)] =
        z[static_cast<std::size_t>(m + 14)] ^ z[static_cast<std::size_t>(m + 10)];
  }
  unsigned seed = 0;
  for (unsigned i = 1; i <= 7; ++i) seed |= z[7 - i] << (i - 1);
  return static_cast<std::uint8_t>(seed);
}

std::vector<std::uint8_t> convolutional_encode(std::span<const std::uint8_t> bits) {
  std::vector<std::uint8_t> out;
  out.reserve(bits.size() * 2);
  unsigned reg = 0;  // bit d = input delayed by d; starts all zero (17.3.5.6)
  for (std::uint8_t b : bits) {
    reg = ((reg << 1U) | (b & 1U)) & 0x7FU;
    out.push_back(static_cast<std::uint8_t>(parity(reg & kTapsA)));
    out.push_back(static_cast<std::uint8_t>(parity(reg & kTapsB)));
  }
  return out;
}

std::vector<std::uint8_t> puncture(std::span<const std::uint8_t> coded, CodeRate rate) {
  switch (rate) {
    case CodeRate::kHalf:
      return {coded.begin(), coded.end()};
    case CodeRate::kTwoThirds:
      return apply_pattern(coded, kKeepTwoThirds);
    case CodeRate::kThreeQuarters:
      return apply_pattern(coded, kKeepThreeQuarters);
  }
  throw std::invalid_argument("puncture: unknown code rate");
}

std::vector<unsigned> interleaver_permutation(unsigned n_cbps, unsigned n_bpsc) {
  if (n_cbps == 0 || n_cbps % 16 != 0 || n_bpsc == 0) {
    throw std::invalid_argument(
        "interleaver_permutation: n_cbps must be a positive multiple of 16");
  }
  // 17.3.5.7, first and second permutation: the first spreads adjacent coded
  // bits over non-adjacent subcarriers; the second alternates them between more
  // and less significant constellation bits, within groups of s = max(N_BPSC/2, 1).
  const unsigned s = n_bpsc / 2 > 1 ? n_bpsc / 2 : 1;
  std::vector<unsigned> perm(n_cbps);
  for (unsigned k = 0; k < n_cbps; ++k) {
    const unsigned i = (n_cbps / 16) * (k % 16) + k / 16;
    const unsigned j = s * (i / s) + (i + n_cbps - (16 * i) / n_cbps) % s;
    perm[k] = j;
  }
  return perm;
}

std::vector<std::uint8_t> interleave(std::span<const std::uint8_t> in, unsigned n_bpsc) {
  const auto n_cbps = static_cast<unsigned>(in.size());
  const std::vector<unsigned> perm = interleaver_permutation(n_cbps, n_bpsc);
  std::vector<std::uint8_t> out(n_cbps);
  for (unsigned k = 0; k < n_cbps; ++k) out[perm[k]] = in[k];
  return out;
}

cf32 map_point(std::span<const std::uint8_t> bits, unsigned n_bpsc) {
  if (bits.size() != n_bpsc) throw std::invalid_argument("map_point: need n_bpsc bits");
  // 17.3.5.8: the first half of the bits selects I, the second half Q, each
  // Gray coded; K_MOD scales every constellation to unit average power.
  const auto level = [](unsigned b) { return b != 0 ? 1.0F : -1.0F; };
  switch (n_bpsc) {
    case 1:
      return {level(bits[0] & 1U), 0.0F};
    case 2: {
      const float k_mod = 1.0F / std::sqrt(2.0F);
      return {level(bits[0] & 1U) * k_mod, level(bits[1] & 1U) * k_mod};
    }
    case 4: {
      const float k_mod = 1.0F / std::sqrt(10.0F);
      return {kLevels16[bits_msb_first(bits.subspan(0, 2))] * k_mod,
              kLevels16[bits_msb_first(bits.subspan(2, 2))] * k_mod};
    }
    case 6: {
      const float k_mod = 1.0F / std::sqrt(42.0F);
      return {kLevels64[bits_msb_first(bits.subspan(0, 3))] * k_mod,
              kLevels64[bits_msb_first(bits.subspan(3, 3))] * k_mod};
    }
    default:
      throw std::invalid_argument("map_point: n_bpsc must be 1, 2, 4 or 6");
  }
}

}  // namespace rfsitl::phy::ofdm
