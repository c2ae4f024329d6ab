#pragma once
/// The scenario's sample stages as the channel uses them: channel.tx_stages or
/// channel.rx_stages built in order (channel/sample_stage.hpp).
#include "rfsitl/channel/sample_stage.hpp"
#include "rfsitl/scenario/scenario.hpp"

namespace rfsitl::scenario {

/// One side's chain for every node of `s`. Precondition: `s` is validated
/// (every stage registered, its settings checked). Throws
/// std::invalid_argument naming the stage when one cannot be built.
channel::SampleChain make_sample_chain(const Scenario& s, channel::SampleSide side);

}  // namespace rfsitl::scenario
