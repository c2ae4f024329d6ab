#pragma once
/// The multipath stage: a tapped delay line. Each link becomes the paths of a
/// power delay profile: 3GPP TR 38.901's TDL-A, TDL-B or TDL-C (Tables
/// 7.7.2-1 to 7.7.2-3, NLOS: normalized delays scaled by the wanted RMS delay
/// spread, section 7.7.3) or taps given in the scenario. Fractional delays are
/// kept (fractional_delay.hpp): at 1 Msps a 100 ns delay spread puts every tap
/// within one sample, and the link is a gentle filter; at 20 Msps it spreads
/// over a few samples, as OFDM's cyclic prefix expects.
///
/// Powers are normalised to a total of 1, so the stage adds no mean gain: path
/// loss and shadowing set the link's power, multipath how it spreads in time.
/// Each tap gets a phase, uniform, drawn once per unordered node pair and tap
/// (Philox under the stage's seed and position), so the link is reciprocal and
/// fixed for the run; a fading stage after this one makes every tap fade
/// independently (a TDL fading channel), its Doppler from the nodes' motion.
#include <cstdint>
#include <span>
#include <vector>

#include "rfsitl/channel/channel_stage.hpp"
#include "rfsitl/config/fields.hpp"

namespace rfsitl::channel {

enum class MultipathProfile { kTdlA, kTdlB, kTdlC, kTaps };

/// A tap given in the scenario.
struct MultipathTap {
  double delay_ns = 0.0;  ///< after the link's first arrival
  double gain_db = 0.0;   ///< power, relative (the profile is normalised)
};

struct MultipathSettings {
  MultipathProfile profile = MultipathProfile::kTdlC;
  double delay_spread_ns = 100.0;  ///< tdl_*: the RMS delay spread the profile is scaled to
  std::vector<MultipathTap> taps;  ///< profile taps
  std::uint64_t seed = 0;          ///< 0: the scenario's seed; otherwise this stage's own
};

const config::Fields<MultipathSettings>& multipath_fields();
ChannelStageComponent multipath_component();

namespace multipath {

/// A profile's taps before normalisation: delays in ns (the TDL tables' scaled
/// by delay_spread_ns), powers in dB.
std::vector<MultipathTap> profile_taps(const MultipathSettings& settings);

/// The taps as paths (delay, amplitude), powers normalised to sum 1, phases 0.
std::vector<Path> normalised_paths(std::span<const MultipathTap> taps);

/// The RMS delay spread, seconds, of a set of paths (power-weighted).
double rms_delay_spread_s(std::span<const Path> paths);

}  // namespace multipath
}  // namespace rfsitl::channel
