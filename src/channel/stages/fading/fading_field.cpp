// The fading field: M plane waves per link, drawn from Philox.
#include <cmath>
#include <numbers>

#include "rfsitl/channel/radio.hpp"
#include "rfsitl/channel/stages/fading.hpp"
#include "rfsitl/common/philox.hpp"

namespace rfsitl::channel::fading {
namespace {

constexpr std::uint32_t kTag = 0x46414445;  // "FADE": apart from other stages' counters
constexpr double kTwoPi = 2.0 * std::numbers::pi;

/// Uniform in [0, 1) with 32 bits.
double unit(std::uint32_t w) {
  return static_cast<double>(w) * 0x1.0p-32;
}

}  // namespace

Waves draw_waves(const FadingSettings& settings, std::uint64_t seed, std::size_t stage_position,
                 std::size_t tx_index, std::size_t rx_index, std::size_t path) {
  // Keyed by (seed, stage position): apart from the noise source and other stages.
  const PhiloxKey key = philox_subkey(seed, static_cast<std::uint32_t>(stage_position), kTag);
  const auto a = static_cast<std::uint32_t>(tx_index);
  const auto b = static_cast<std::uint32_t>(rx_index);
  const std::uint32_t m = settings.sinusoids;
  // Paths above 0 (the taps of a dispersive link) draw their own sinusoids:
  // sinusoid counts stay below 2^16, so path 0's counters are those of a link
  // of one path.
  const auto offset = static_cast<std::uint32_t>(path) << 16;
  Waves w;
  w.departure.reserve(m);
  w.arrival.reserve(m);
  w.phase.reserve(m);
  for (std::uint32_t i = 0; i < m; ++i) {
    const PhiloxCounter u = philox4x32({a, b, offset + i, kTag}, key);
    const double departure = kTwoPi * unit(u[0]);
    const double arrival = kTwoPi * unit(u[1]);
    w.departure.push_back({std::cos(departure), std::sin(departure)});
    w.arrival.push_back({std::cos(arrival), std::sin(arrival)});
    w.phase.push_back(kTwoPi * unit(u[2]));
  }
  // The line-of-sight wave arrives first: on path 0 only; its own draw is the
  // counter one past the sinusoids.
  if (settings.model == FadingModel::kRician && path == 0) {
    w.los_phase = kTwoPi * unit(philox4x32({a, b, m, kTag}, key)[0]);
  }
  return w;
}

std::complex<double> gain(const FadingSettings& settings, double carrier_hz, const Waves& w,
                          const LinkEnd& tx, const LinkEnd& rx) {
  const double k = kTwoPi * carrier_hz / kSpeedOfLight;  // wavenumber, rad/m
  std::complex<double> scatter = 0.0;
  for (std::size_t i = 0; i < w.phase.size(); ++i) {
    const double phase =
        w.phase[i] +
        k * (w.departure[i].real() * tx.local.x_m + w.departure[i].imag() * tx.local.y_m) +
        k * (w.arrival[i].real() * rx.local.x_m + w.arrival[i].imag() * rx.local.y_m);
    scatter += std::polar(1.0, phase);
  }
  scatter *= std::sqrt(1.0 / static_cast<double>(w.phase.size()));
  if (!w.los_phase) return scatter;
  const double kk = std::pow(10.0, settings.k_db / 10.0);
  const double d = std::hypot(rx.local.x_m - tx.local.x_m, rx.local.y_m - tx.local.y_m,
                              rx.local.z_m - tx.local.z_m);
  const std::complex<double> los = std::polar(1.0, *w.los_phase - k * d);
  return std::sqrt(kk / (kk + 1.0)) * los + std::sqrt(1.0 / (kk + 1.0)) * scatter;
}

std::complex<double> gain(const FadingSettings& settings, double carrier_hz, std::uint64_t seed,
                          std::size_t stage_position, const LinkEnd& tx, const LinkEnd& rx,
                          std::size_t path) {
  return gain(settings, carrier_hz,
              draw_waves(settings, seed, stage_position, tx.index, rx.index, path), tx, rx);
}

}  // namespace rfsitl::channel::fading
