#pragma once
/// A transmitter's power spectral density relative to its peak, as a PHY
/// declares it (phy_component.hpp) and the channel integrates it into the
/// power that leaks into another radio's band (channel/radio_tuning.hpp).
/// Data only: the shared vocabulary of the PHYs and the channel.
#include <vector>

namespace rfsitl {

/// One corner of a mask: at `offset` from the centre (either side: masks are
/// symmetric), the density is `dbr` dB below the peak. Offsets are in units of
/// the emulator's sample rate, which every built-in PHY makes its samples at
/// (so its spectrum scales with it); an offset beyond 1/2 is the regrowth of
/// a real transmitter's analog chain, which sampled signals cannot show.
struct MaskPoint {
  double offset = 0.0;  ///< >= 0, in units of the sample rate
  double dbr = 0.0;     ///< <= 0
  bool operator==(const MaskPoint&) const = default;
};

/// Points in ascending offset, the first at offset 0; the density is linear in
/// dB between them and zero beyond the last (a mask says nothing of what lies
/// further out, and a transmitter's regrowth does not reach there in any
/// measurable amount). Empty: flat over the node's channel bandwidth and zero
/// beyond, a brick wall, for a PHY that declares nothing.
struct SpectralMask {
  std::vector<MaskPoint> points;
  bool operator==(const SpectralMask&) const = default;
};

}  // namespace rfsitl
