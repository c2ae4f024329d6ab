#include "rfsitl/scenario/link_budget_of.hpp"

#include <stdexcept>
#include <utility>
#include <vector>

#include "rfsitl/channel/radio.hpp"
#include "rfsitl/channel/stages/path_loss.hpp"
#include "rfsitl/registry/channel_stage_registry.hpp"

namespace rfsitl::scenario {

std::shared_ptr<const channel::LinkBudget> make_link_budget(const Scenario& s) {
  const channel::RadioSettings radio = s.radio.value_or(channel::RadioSettings{});
  // Without a radio every transmitter has 0 dBm, the paper's unit power.
  const double fixed_db = s.radio ? channel::fixed_gain_db(radio) : 0.0;
  std::vector<std::unique_ptr<channel::GainStage>> stages;
  std::vector<StageChoice> chain = s.channel.stages;
  if (chain.empty()) {  // the paper's model, from its short form
    const auto& info = channel::path_loss_component().info;
    StageChoice paper{"path_loss", info.defaults()};
    paper.settings.set("paper_exponent", s.channel.path_loss_exponent);
    chain.push_back(std::move(paper));
  }
  for (std::size_t i = 0; i < chain.size(); ++i) {
    const channel::ChannelStageComponent* c = channel::find_channel_stage(chain[i].type);
    if (c == nullptr) {
      throw std::invalid_argument("channel.stages[" + std::to_string(i) + "]: unknown stage '" +
                                  chain[i].type + "'");
    }
    const channel::StageContext context{radio.carrier_hz, s.seed, i, s.source_dir};
    stages.push_back(c->make(chain[i].settings, context));
  }
  return std::make_shared<const channel::LinkBudget>(fixed_db, std::move(stages));
}

}  // namespace rfsitl::scenario
