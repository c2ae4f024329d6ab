#include <algorithm>
#include <cmath>
#include <numbers>

#include "rfsitl/channel/stages/path_loss.hpp"

namespace rfsitl::channel::path_loss {

std::complex<double> paper_gain(double d_m, double exponent) {
  const double g = std::pow(d_m + 1.0, -exponent) * (1.0 / std::numbers::sqrt2);
  return {g, g};
}

double free_space_db(double d_m, double carrier_hz) {
  return 20.0 * std::log10(4.0 * std::numbers::pi * d_m * carrier_hz / kSpeedOfLight);
}

double log_distance_db(double d_m, double carrier_hz, double exponent, double d0_m) {
  return free_space_db(d0_m, carrier_hz) + 10.0 * exponent * std::log10(d_m / d0_m);
}

std::complex<double> two_ray_gain(double horizontal_m, double h_tx_m, double h_rx_m,
                                  double carrier_hz, double reflection) {
  const double ht = std::max(h_tx_m, 0.0);
  const double hr = std::max(h_rx_m, 0.0);
  const double lambda = kSpeedOfLight / carrier_hz;
  const double k = 2.0 * std::numbers::pi / lambda;
  const double r1 = std::hypot(horizontal_m, ht - hr);
  const double r2 = std::hypot(horizontal_m, ht + hr);
  // Only the path difference matters for |g|, so the common phase k r1 is
  // taken out; r2 - r1 is written as (r2^2 - r1^2) / (r1 + r2) = 4 ht hr /
  // (r1 + r2), which does not cancel at long range.
  const double path_difference = 4.0 * ht * hr / (r1 + r2);
  const std::complex<double> direct = 1.0 / r1;
  const std::complex<double> reflected = reflection * std::polar(1.0 / r2, -k * path_difference);
  return lambda / (4.0 * std::numbers::pi) * (direct + reflected);
}

double two_ray_crossover_m(double h_tx_m, double h_rx_m, double carrier_hz) {
  return 4.0 * h_tx_m * h_rx_m * carrier_hz / kSpeedOfLight;
}

}  // namespace rfsitl::channel::path_loss
