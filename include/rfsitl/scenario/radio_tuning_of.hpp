#pragma once
/// A node's radio on the spectrum as the channel takes it: the scenario's
/// band for the node (spectrum.hpp) with its PHY's spectral mask.
#include "rfsitl/channel/radio_tuning.hpp"
#include "rfsitl/scenario/scenario.hpp"

namespace rfsitl::scenario {

/// Precondition: `s` is validated and `node` < s.nodes.size().
channel::RadioTuning radio_tuning_of(const Scenario& s, std::size_t node);

}  // namespace rfsitl::scenario
