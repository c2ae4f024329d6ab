#pragma once
/// The bit-level stages of the 802.11 OFDM PHY (IEEE 802.11-2016 17.3.5). Bits
/// are std::uint8_t values 0 or 1, one per element, in transmission order. All
/// functions are pure.
#include <cstdint>
#include <span>
#include <vector>

#include "rates.hpp"
#include "rfsitl/common/types.hpp"

namespace rfsitl::phy::ofdm {

/// The PSDU's octets as bits, LSB of each octet first (17.3.5.2 / Table I-13 order).
std::vector<std::uint8_t> bytes_to_bits(std::span<const std::uint8_t> bytes);
/// Inverse of bytes_to_bits. Precondition: bits.size() is a multiple of 8.
std::vector<std::uint8_t> bits_to_bytes(std::span<const std::uint8_t> bits);

/// XORs `bits` in place with the scrambler sequence of generator x^7 + x^4 + 1
/// (17.3.5.5, Figure 17-7) started from `seed`. Seed bit order: bit i of `seed`
/// is register stage x(i+1), i.e. x1 in bit 0 ... x7 in bit 6 (bit 7 ignored).
/// Each step outputs x7 ^ x4, XORs it onto the next bit and shifts it in as
/// the new x1. So seed 0x01 (x1 = 1) gives the sequence 0 0 0 1 0 0 1 1 ...,
/// and Annex I's state 1011101 (a palindrome, so x1-first and x7-first read the
/// same) is 0x5D and gives Table I-14: 0 1 1 0 1 1 0 0 ... Scrambling and
/// descrambling are the same operation. Precondition: (seed & 0x7F) != 0.
void scramble(std::span<std::uint8_t> bits, std::uint8_t seed);

/// Recovers the scrambler seed (same bit order as scramble()) from the first 7
/// received (scrambled) SERVICE bits, whose unscrambled value is 0.
/// Precondition: first7.size() == 7.
std::uint8_t seed_from_service(std::span<const std::uint8_t> first7);

/// Rate-1/2 convolutional encoder, K = 7, generators g0 = 133, g1 = 171 (octal),
/// starting in the all-zero state. Output: A0 B0 A1 B1 ... (2 bits per input bit).
std::vector<std::uint8_t> convolutional_encode(std::span<const std::uint8_t> bits);

/// Removes coded bits by the 17.3.5.6 puncturing patterns (kHalf: unchanged).
std::vector<std::uint8_t> puncture(std::span<const std::uint8_t> coded, CodeRate rate);

/// Interleaver permutation for one OFDM symbol: out[j(i(k))] = in[k] (17.3.5.7).
/// Returns the destination index of each input index k.
std::vector<unsigned> interleaver_permutation(unsigned n_cbps, unsigned n_bpsc);

/// Interleaves one symbol's n_cbps coded bits. Precondition: in.size() == n_cbps.
std::vector<std::uint8_t> interleave(std::span<const std::uint8_t> in, unsigned n_bpsc);

/// Maps n_bpsc bits to one constellation point (17.3.5.8, Gray coded, with the
/// normalization K_MOD: 1, 1/sqrt2, 1/sqrt10, 1/sqrt42). Precondition:
/// bits.size() == n_bpsc in {1, 2, 4, 6}.
cf32 map_point(std::span<const std::uint8_t> bits, unsigned n_bpsc);

}  // namespace rfsitl::phy::ofdm
