#pragma once
/// The radio every node shares: carrier, transmit power, antenna gain and the
/// receiver's noise figure, in physical units (the scenario's `radio:`). From it
/// come the fixed part of every link's budget and the thermal noise power.
#include "rfsitl/config/fields.hpp"

namespace rfsitl::channel {

struct RadioSettings {
  double carrier_hz = 2.4e9;
  double tx_power_dbm = 20.0;
  double antenna_gain_dbi = 0.0;  ///< each end's, so a link gets twice this
  double noise_figure_db = 7.0;
  double temperature_k = 290.0;  ///< the noise reference temperature T0
};

const config::Fields<RadioSettings>& radio_fields();

/// The radio's self-description (kind and name "radio"), as `rfsitl describe`
/// lists it and the scenario reader checks it.
const config::ComponentInfo& radio_info();

/// Boltzmann's constant, J/K (exact since the 2019 SI).
inline constexpr double kBoltzmann = 1.380649e-23;

/// The speed of light in vacuum, m/s (exact).
inline constexpr double kSpeedOfLight = 299792458.0;

/// Thermal noise power in mW over `bandwidth_hz`: k T B times the noise figure.
/// The simulated noise is white across the sample rate, so B = fs.
double noise_power_mw(const RadioSettings& r, double bandwidth_hz);

/// Transmit power plus both antennas' gains, dBm: what every link shares.
double fixed_gain_db(const RadioSettings& r);

}  // namespace rfsitl::channel
