#include "rfsitl/scenario/sample_chain_of.hpp"

#include <stdexcept>
#include <string>

#include "rfsitl/registry/sample_stage_registry.hpp"

namespace rfsitl::scenario {

channel::SampleChain make_sample_chain(const Scenario& s, channel::SampleSide side) {
  const bool tx = side == channel::SampleSide::kTransmit;
  const std::vector<StageChoice>& list = tx ? s.channel.tx_stages : s.channel.rx_stages;
  const std::string key = tx ? "channel.tx_stages" : "channel.rx_stages";
  channel::SampleChain chain;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string at = key + "[" + std::to_string(i) + "]";
    const channel::SampleStageComponent* c = channel::find_sample_stage(list[i].type);
    if (c == nullptr) throw std::invalid_argument(at + ": unknown stage '" + list[i].type + "'");
    const channel::SampleStageContext context{
        side, s.nodes.size(), s.timing.sample_rate_hz, s.timing.tick_samples, s.seed, i};
    try {
      chain.push_back(c->make(list[i].settings, context));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(at + " (" + list[i].type + "): " + e.what());
    }
  }
  return chain;
}

}  // namespace rfsitl::scenario
