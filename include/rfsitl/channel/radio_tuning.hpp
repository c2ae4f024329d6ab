#pragma once
/// Where each radio is on the spectrum, and what that makes of a link: a
/// transmitter n tuned to tx_hz(n) with channel bandwidth B(n), heard by a
/// receiver m tuned to rx_hz(m) with filter bandwidth W(m), offset
/// df = tx_hz(n) - rx_hz(m):
///   in band       |df| + B/2 <= W/2: the whole signal passes m's filter and
///                 arrives shifted by df (a carrier offset to m's PHY);
///   leaking       otherwise, when a fraction kappa >= kLeakageFloor of n's
///                 power (its spectral mask integrated over m's band) falls in
///                 m's band: that power arrives as noise (spectral regrowth and
///                 a pulse's skirt, which no receiver decodes);
///   out of band   below that: m does not hear n at all.
/// Worked out when a node tunes, never per tick.
#include <vector>

#include "rfsitl/common/spectral_mask.hpp"

namespace rfsitl::channel {

/// One node's radio as the channel sees it.
struct RadioTuning {
  double tx_hz = 0.0;
  double rx_hz = 0.0;
  /// The channel's width: the transmitter's occupied band (what must fit in a
  /// receiver's band for it to be in band) and the receiver's filter.
  double bandwidth_hz = 1e6;
  SpectralMask mask;         ///< of the node's transmitter
  bool full_duplex = false;  ///< its receiver runs while it transmits
  /// A full-duplex node's own signal at its receiver, in the budget's unit
  /// (mW) per unit of sample power, arriving as noise (0: it never hears itself).
  double self_gain = 0.0;
  bool operator==(const RadioTuning&) const = default;
};

enum class BandRelation { kInBand, kLeaking, kOutOfBand };

/// What reaches a receiver of a transmitter.
struct LinkBand {
  BandRelation relation = BandRelation::kInBand;
  double offset_hz = 0.0;  ///< df = tx_hz - rx_hz
  /// kappa: the fraction of the transmitter's power inside the receiver's
  /// band (1 in band, 0 out of band). What the link table and the ledger
  /// multiply the link's power gain by.
  float kappa = 1.0F;
};

/// A leaked fraction below this (-70 dB) is out of band: no mask's skirt
/// matters there next to the receiver's own noise, and the link then costs
/// nothing.
inline constexpr double kLeakageFloor = 1e-7;

/// The fraction of the power of a mask of `points` (not empty) between
/// offsets lo < hi from its centre (either side, in the points' unit): the
/// integral of its density, exact for a density linear in dB between points.
double mask_power_fraction(const std::vector<MaskPoint>& points, double lo, double hi);

/// What the receiver `rx` makes of the transmitter `tx` on a grid of
/// `sample_rate_hz` (the unit of the transmitter's mask).
LinkBand link_band(const RadioTuning& tx, const RadioTuning& rx, double sample_rate_hz);

}  // namespace rfsitl::channel
