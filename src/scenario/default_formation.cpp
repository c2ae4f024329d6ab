// The formation of `rfsitl run --nodes N`: a square grid close enough that every link
// decodes, so a user who just wants N connected nodes gets them without a scenario file.
#include "rfsitl/scenario/default_formation.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rfsitl::scenario {
namespace {

constexpr double kAltitudeM = 10.0;
constexpr double kMaxSpacingM = 10.0;  // a swarm, not a country: links beyond need no test
constexpr double kMinSpacingM = 1.0;   // closer than this the airframes would collide

// SNR of a d-metre link under the paper model with a unit-power transmitter:
// |c|^2 = (d + 1)^(-2 * exponent), noise power = noise_variance.
double snr_db(double d_m, const ChannelConfig& ch) {
  return -20.0 * ch.path_loss_exponent * std::log10(d_m + 1.0) -
         10.0 * std::log10(ch.noise_variance);
}

// The largest spacing in [1, 10] m at which a link of `diagonal_cells` grid cells still
// meets the target. When even 1 m misses it, 1 m anyway: nothing closer is sensible, and
// the links are then as good as this channel allows.
double choose_spacing(double diagonal_cells, const ChannelConfig& ch, double min_snr_db) {
  if (diagonal_cells == 0.0 || ch.noise_variance <= 0.0) return kMaxSpacingM;  // no link / no noise
  if (snr_db(diagonal_cells * kMinSpacingM, ch) < min_snr_db) return kMinSpacingM;
  if (ch.path_loss_exponent <= 0.0 || snr_db(diagonal_cells * kMaxSpacingM, ch) >= min_snr_db) {
    return kMaxSpacingM;
  }
  // (d + 1)^(2e) * sigma^2 <= 10^(-snr/10)  <=>  d <= 10^((-snr/10 - log10 sigma^2) / 2e) - 1
  const double exponent =
      (-min_snr_db / 10.0 - std::log10(ch.noise_variance)) / (2.0 * ch.path_loss_exponent);
  const double max_diagonal_m = std::pow(10.0, exponent) - 1.0;
  // Round down to whole centimetres: tidy coordinates, and a margin against rounding.
  const double spacing = std::floor(max_diagonal_m / diagonal_cells * 100.0) / 100.0;
  return std::clamp(spacing, kMinSpacingM, kMaxSpacingM);
}

}  // namespace

std::vector<NodeConfig> default_formation(std::size_t n, const ChannelConfig& channel,
                                          double min_snr_db) {
  if (n < kMinNodeId || n > kMaxNodeId) {
    throw std::invalid_argument("default_formation: node count must be in 1.." +
                                std::to_string(kMaxNodeId) + ", got " + std::to_string(n));
  }
  if (std::isnan(min_snr_db)) throw std::invalid_argument("default_formation: min_snr_db is NaN");
  const auto cols = static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(n))));
  const std::size_t rows = (n + cols - 1) / cols;
  // The bounding box's diagonal is the longest link any pair of grid points can have.
  const double diagonal_cells =
      std::hypot(static_cast<double>(cols - 1), static_cast<double>(rows - 1));
  const double spacing = choose_spacing(diagonal_cells, channel, min_snr_db);

  std::vector<NodeConfig> nodes(n);
  for (std::size_t i = 0; i < n; ++i) {
    nodes[i].id = static_cast<NodeId>(i + 1);
    nodes[i].initial_position = LocalPosition{static_cast<double>(i % cols) * spacing,
                                              static_cast<double>(i / cols) * spacing, kAltitudeM};
  }
  return nodes;
}

}  // namespace rfsitl::scenario
