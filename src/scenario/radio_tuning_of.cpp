#include "rfsitl/scenario/radio_tuning_of.hpp"

#include <cmath>

namespace rfsitl::scenario {

channel::RadioTuning radio_tuning_of(const Scenario& s, std::size_t node) {
  const NodeBand band = s.band_of(node);
  channel::RadioTuning t;
  t.tx_hz = band.tx_hz;
  t.rx_hz = band.rx_hz;
  t.bandwidth_hz = band.bandwidth_hz;
  t.full_duplex = band.duplex == Duplex::kFull;
  const PhyChoice& phy = s.phy_of(node);
  if (const auto& mask = phy.component().spectral_mask) t.mask = mask(phy.settings);
  if (t.full_duplex) {
    // Its transmit power (0 dBm without a radio: unit power, as every
    // link's) below the duplexer's isolation, times the part of its own
    // spectrum that falls in its receive band.
    const double tx_dbm = s.radio ? s.radio->tx_power_dbm : 0.0;
    t.self_gain = std::pow(10.0, (tx_dbm - s.spectrum.duplexer_isolation_db) / 10.0) *
                  channel::link_band(t, t, s.timing.sample_rate_hz).kappa;
  }
  return t;
}

}  // namespace rfsitl::scenario
