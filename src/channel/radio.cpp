#include "rfsitl/channel/radio.hpp"

#include <cmath>

namespace rfsitl::channel {

const config::Fields<RadioSettings>& radio_fields() {
  using S = RadioSettings;
  static const auto f =
      config::Fields<S>()
          .real("carrier_hz", &S::carrier_hz, "Hz", {1e6, 1e11},
                "carrier frequency: the wavelength of path loss models and Doppler")
          .real("tx_power_dbm", &S::tx_power_dbm, "dBm", {-100.0, 60.0},
                "every transmitter's power (its samples have unit mean power)")
          .real("antenna_gain_dbi", &S::antenna_gain_dbi, "dBi", {-50.0, 50.0},
                "each antenna's gain towards the other end, before antenna stages")
          .real("noise_figure_db", &S::noise_figure_db, "dB", {0.0, 50.0},
                "the receiver's noise figure: noise = k T0 fs NF")
          .real("temperature_k", &S::temperature_k, "K", {1.0, 1e4},
                "the noise reference temperature T0");
  return f;
}

const config::ComponentInfo& radio_info() {
  static const config::ComponentInfo info = radio_fields().info(
      "radio", "radio",
      "the link budget every node shares (the scenario's radio: section): transmit power, "
      "antenna gain, noise figure and carrier");
  return info;
}

double noise_power_mw(const RadioSettings& r, double bandwidth_hz) {
  // W -> mW: 1e3.
  return kBoltzmann * r.temperature_k * bandwidth_hz * std::pow(10.0, r.noise_figure_db / 10.0) *
         1e3;
}

double fixed_gain_db(const RadioSettings& r) {
  return r.tx_power_dbm + 2.0 * r.antenna_gain_dbi;
}

}  // namespace rfsitl::channel
