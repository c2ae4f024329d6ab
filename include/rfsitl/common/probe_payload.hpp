#pragma once
/// Payloads of measurement traffic (rfsitl ping, the benchmark's swarm load):
/// a 4-byte magic naming the kind (ping, ack, ...), a 32-bit sequence number
/// (LE), then filler up to the requested size. Header-only.
#include <algorithm>
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

namespace rfsitl {

using ProbeMagic = std::array<std::uint8_t, 4>;

/// A payload of max(size, 8) bytes carrying `magic` and `seq`.
inline std::vector<std::uint8_t> make_probe(const ProbeMagic& magic, std::uint32_t seq,
                                            std::size_t size) {
  std::vector<std::uint8_t> p(std::max<std::size_t>(size, 8), 0);
  std::copy(magic.begin(), magic.end(), p.begin());
  for (std::size_t i = 0; i < 4; ++i) p[4 + i] = static_cast<std::uint8_t>(seq >> (8 * i));
  // Filler that changes with the sequence number, so no two probes are alike.
  for (std::size_t i = 8; i < p.size(); ++i) p[i] = static_cast<std::uint8_t>(i * 7 + seq);
  return p;
}

/// The sequence number of a probe of kind `magic`, or nullopt for anything else.
inline std::optional<std::uint32_t> read_probe(const std::vector<std::uint8_t>& p,
                                               const ProbeMagic& magic) {
  if (p.size() < 8 || !std::equal(magic.begin(), magic.end(), p.begin())) return std::nullopt;
  std::uint32_t seq = 0;
  for (std::size_t i = 0; i < 4; ++i) seq |= static_cast<std::uint32_t>(p[4 + i]) << (8 * i);
  return seq;
}

}  // namespace rfsitl
