// The fading field: M plane waves per link, drawn from Philox.
#include <cmath>
#include <numbers>

#include "rfsitl/channel/radio.hpp"
#include "rfsitl/channel/stages/fading.hpp"
#include "rfsitl/common/philox.hpp"

namespace rfsitl::channel::fading {
namespace {

constexpr std::uint32_t kTag = 0x46414445;  // "FADE": apart from other stages' counters

/// Uniform in [0, 1) with 32 bits.
double unit(std::uint32_t w) {
  return static_cast<double>(w) * 0x1.0p-32;
}

}  // namespace

std::complex<double> gain(const FadingSettings& settings, double carrier_hz, std::uint64_t seed,
                          std::size_t stage_position, const LinkEnd& tx, const LinkEnd& rx,
                          std::size_t path) {
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  const double k = kTwoPi * carrier_hz / kSpeedOfLight;  // wavenumber, rad/m
  // Keyed by (seed, stage position): apart from the noise source and other stages.
  const PhiloxKey key = philox_subkey(seed, static_cast<std::uint32_t>(stage_position), kTag);
  const auto a = static_cast<std::uint32_t>(tx.index);
  const auto b = static_cast<std::uint32_t>(rx.index);
  const std::uint32_t m = settings.sinusoids;
  // Paths above 0 (the taps of a dispersive link) draw their own sinusoids:
  // sinusoid counts stay below 2^16, so path 0's counters are those of a link
  // of one path.
  const auto offset = static_cast<std::uint32_t>(path) << 16;
  std::complex<double> scatter = 0.0;
  for (std::uint32_t i = 0; i < m; ++i) {
    const PhiloxCounter u = philox4x32({a, b, offset + i, kTag}, key);
    const double departure = kTwoPi * unit(u[0]);
    const double arrival = kTwoPi * unit(u[1]);
    const double phase =
        kTwoPi * unit(u[2]) +
        k * (std::cos(departure) * tx.local.x_m + std::sin(departure) * tx.local.y_m) +
        k * (std::cos(arrival) * rx.local.x_m + std::sin(arrival) * rx.local.y_m);
    scatter += std::polar(1.0, phase);
  }
  scatter *= std::sqrt(1.0 / m);
  // The line-of-sight wave arrives first: on path 0 only.
  if (settings.model == FadingModel::kRayleigh || path != 0) return scatter;
  const double kk = std::pow(10.0, settings.k_db / 10.0);
  // The line-of-sight wave's own draw: the counter one past the sinusoids.
  const PhiloxCounter u = philox4x32({a, b, m, kTag}, key);
  const double d = std::hypot(rx.local.x_m - tx.local.x_m, rx.local.y_m - tx.local.y_m,
                              rx.local.z_m - tx.local.z_m);
  const std::complex<double> los = std::polar(1.0, kTwoPi * unit(u[0]) - k * d);
  return std::sqrt(kk / (kk + 1.0)) * los + std::sqrt(1.0 / (kk + 1.0)) * scatter;
}

}  // namespace rfsitl::channel::fading
