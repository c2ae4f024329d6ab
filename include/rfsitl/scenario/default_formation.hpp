#pragma once
/// The formation used when no scenario file is given (`rfsitl run --nodes N`).
#include <cstddef>
#include <vector>

#include "rfsitl/scenario/scenario.hpp"

namespace rfsitl::scenario {

/// Nodes 1..n on a square grid of local positions at 10 m altitude, spaced so
/// that the longest link of the grid still has an SNR of at least `min_snr_db`
/// under `channel` (a 0 dBFS transmitter). Precondition: 1 <= n <= kMaxNodeId (254).
std::vector<NodeConfig> default_formation(std::size_t n, const ChannelConfig& channel,
                                          double min_snr_db = 20.0);

}  // namespace rfsitl::scenario
