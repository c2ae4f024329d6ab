// The shadowing field S(p_a, p_b): a sum of sinusoids whose wave vectors and
// phases are Philox draws named by (link, sinusoid), so no state is kept.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "rfsitl/channel/stages/shadowing.hpp"
#include "rfsitl/common/philox.hpp"

namespace rfsitl::channel::shadowing {
namespace {

// "shad": tags the key derivation so that this stage's streams are not the
// noise source's, which keys Philox with the scenario's seed itself.
constexpr std::uint32_t kDomainTag = 0x73686164;

/// One Philox key per (seed, stage position): a Philox block of the position
/// under the seed, so two stages of the same scenario draw independently.
PhiloxKey stream_key(std::uint64_t seed, std::size_t stage_position) {
  const auto position = static_cast<std::uint64_t>(stage_position);
  const PhiloxCounter mixed =
      philox4x32({static_cast<std::uint32_t>(position), static_cast<std::uint32_t>(position >> 32),
                  kDomainTag, 0},
                 {static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32)});
  return {mixed[0], mixed[1]};
}

/// A 32-bit word as a uniform in the open interval (0, 1): never 0 or 1, so
/// the logarithm below is finite and nonzero.
double open_uniform(std::uint32_t word) {
  return (static_cast<double>(word) + 0.5) * 0x1.0p-32;
}

struct NormalPair {
  double first;
  double second;
};

/// Box-Muller: two independent N(0, 1) from two uniforms. With the open
/// uniforms the radius is in [1.5e-5, 6.8] and the angle never a multiple of
/// pi / 2, so neither output is ever exactly 0 (|w| > 0 keeps k finite).
NormalPair box_muller(std::uint32_t a, std::uint32_t b) {
  const double radius = std::sqrt(-2.0 * std::log(open_uniform(a)));
  const double angle = 2.0 * std::numbers::pi * open_uniform(b);
  return {radius * std::cos(angle), radius * std::sin(angle)};
}

/// k . p for k = z / (d |w|), z ~ N(0, I_3), w ~ N(0, 1), from one Philox block.
double wave_phase(const PhiloxCounter& block, double decorrelation_m, const LocalPosition& p) {
  const NormalPair z01 = box_muller(block[0], block[1]);
  const NormalPair z2w = box_muller(block[2], block[3]);
  const double z_dot_p = z01.first * p.x_m + z01.second * p.y_m + z2w.first * p.z_m;
  return z_dot_p / (decorrelation_m * std::abs(z2w.second));
}

}  // namespace

double field_db(const ShadowingSettings& settings, std::uint64_t seed, std::size_t stage_position,
                const LinkEnd& u, const LinkEnd& v) {
  if (u.index == v.index) return 0.0;
  // The unordered pair: the lower index is a, whichever end transmits.
  const LinkEnd& a = u.index < v.index ? u : v;
  const LinkEnd& b = u.index < v.index ? v : u;
  const PhiloxKey key = stream_key(seed, stage_position);
  const auto a_word = static_cast<std::uint32_t>(a.index);
  const auto b_word = static_cast<std::uint32_t>(b.index);
  double sum = 0.0;
  for (std::uint32_t i = 0; i < settings.sinusoids; ++i) {
    // Block 0 draws k (a's end), block 1 draws q (b's end), block 2 the phase.
    const double k_dot_pa =
        wave_phase(philox4x32({a_word, b_word, i, 0}, key), settings.decorrelation_m, a.local);
    const double q_dot_pb =
        wave_phase(philox4x32({a_word, b_word, i, 1}, key), settings.decorrelation_m, b.local);
    const double phase = 2.0 * std::numbers::pi *
                         static_cast<double>(philox4x32({a_word, b_word, i, 2}, key)[0]) *
                         0x1.0p-32;
    sum += std::cos(k_dot_pa + q_dot_pb + phase);
  }
  return settings.sigma_db * std::sqrt(2.0 / static_cast<double>(settings.sinusoids)) * sum;
}

}  // namespace rfsitl::channel::shadowing
