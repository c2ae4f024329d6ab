#pragma once
/// The delay stage: propagation delay, the distance over the speed of light
/// (plus a fixed excess), as a fractional number of samples (a short
/// interpolating filter, fractional_delay.hpp). At 1 Msps a sample is 300 m of
/// path, at 20 Msps 15 m. The stage moves when a node moves, like the other
/// large-scale stages; its phase is left to the time-varying stages (fading
/// turns the carrier's phase as the ends move).
#include "rfsitl/channel/channel_stage.hpp"
#include "rfsitl/config/fields.hpp"

namespace rfsitl::channel {

struct DelaySettings {
  double excess_ns = 0.0;      ///< added to every link's d / c (cables, a repeater)
  bool whole_samples = false;  ///< round to the nearest sample (one tap, cheaper)
};

const config::Fields<DelaySettings>& delay_fields();
ChannelStageComponent delay_component();

namespace delay {

/// The link's delay in seconds: distance_m / c + excess, rounded to a whole
/// number of samples at sample_rate_hz when the settings say so. Pure.
double seconds(const DelaySettings& settings, double distance_m, double sample_rate_hz);

}  // namespace delay
}  // namespace rfsitl::channel
