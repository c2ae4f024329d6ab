#pragma once
// Internal to the scenario module: reading `channel:` (its stages, the paper
// model's short form, the noise) and `radio:` (the link budget).
#include "yaml_reading.hpp"

namespace rfsitl::scenario::detail {

/// Reads both sections into `s`; either may be absent. Then, with a radio
/// (given now or before: the command line adds to a file), sets the noise to
/// the radio's k T0 fs NF for the current sample rate.
void read_channel_and_radio(Context& c, const Entry& channel, const Entry& radio, Scenario& s);

}  // namespace rfsitl::scenario::detail
