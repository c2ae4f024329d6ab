#pragma once
/// Philox4x32-10 (Salmon, Moraes, Dror, Shaw, "Parallel random numbers: as easy
/// as 1, 2, 3", SC 2011): a counter-based generator. Its output is a pure
/// function of a 128-bit counter and a 64-bit key, so the noise of receiver m
/// at sample t is the same whichever thread computes it, in whatever order,
/// whether or not the samples before it were ever drawn. Ten rounds of two
/// 32x32->64-bit multiplies; passes BigCrush (per the paper). Written out here
/// so that a seed names the same numbers with any compiler.
#include <array>
#include <cstdint>

namespace rfsitl {

using PhiloxCounter = std::array<std::uint32_t, 4>;
using PhiloxKey = std::array<std::uint32_t, 2>;

/// The four 32-bit outputs for `counter` under `key`.
constexpr PhiloxCounter philox4x32(PhiloxCounter counter, PhiloxKey key) {
  // The paper's multipliers and Weyl key increments (golden ratio, sqrt(3) - 1).
  constexpr std::uint64_t kM0 = 0xD2511F53;
  constexpr std::uint64_t kM1 = 0xCD9E8D57;
  constexpr std::uint32_t kW0 = 0x9E3779B9;
  constexpr std::uint32_t kW1 = 0xBB67AE85;
  for (int round = 0; round < 10; ++round) {
    if (round > 0) {
      key[0] += kW0;
      key[1] += kW1;
    }
    const std::uint64_t p0 = kM0 * counter[0];
    const std::uint64_t p1 = kM1 * counter[2];
    counter = {
        static_cast<std::uint32_t>(p1 >> 32) ^ counter[1] ^ key[0], static_cast<std::uint32_t>(p1),
        static_cast<std::uint32_t>(p0 >> 32) ^ counter[3] ^ key[1], static_cast<std::uint32_t>(p0)};
  }
  return counter;
}

/// A 64-bit seed as a key.
constexpr PhiloxKey philox_key(std::uint64_t seed) {
  return {static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32)};
}

/// A key of its own for `stream` of a component tagged `tag` (e.g. a channel
/// stage's place in the chain): one Philox block of {stream, 0, 0, tag} under
/// the seed, so that its draws never coincide with the noise source's (keyed
/// by the seed itself) or another tag's.
constexpr PhiloxKey philox_subkey(std::uint64_t seed, std::uint32_t stream, std::uint32_t tag) {
  const PhiloxCounter k = philox4x32({stream, 0, 0, tag}, philox_key(seed));
  return {k[0], k[1]};
}

}  // namespace rfsitl
