#include "rfsitl/scenario/link_budget_of.hpp"

#include <stdexcept>
#include <utility>
#include <vector>

#include "rfsitl/channel/radio.hpp"
#include "rfsitl/channel/stages/path_loss.hpp"
#include "rfsitl/registry/channel_stage_registry.hpp"

namespace rfsitl::scenario {
namespace {

/// The chain as listed, or the paper's model from its short form.
std::vector<StageChoice> chain_of(const Scenario& s) {
  if (!s.channel.stages.empty()) return s.channel.stages;
  const auto& info = channel::path_loss_component().info;
  StageChoice paper{"path_loss", info.defaults()};
  paper.settings.set("paper_exponent", s.channel.path_loss_exponent);
  return {paper};
}

std::unique_ptr<channel::GainStage> build(const Scenario& s, const StageChoice& stage,
                                          std::size_t i) {
  const channel::ChannelStageComponent* c = channel::find_channel_stage(stage.type);
  if (c == nullptr) {
    throw std::invalid_argument("channel.stages[" + std::to_string(i) + "]: unknown stage '" +
                                stage.type + "'");
  }
  channel::StageContext context{
      s.radio.value_or(channel::RadioSettings{}).carrier_hz, s.seed, i, s.source_dir, {}};
  for (const NodeConfig& n : s.nodes) context.node_ids.push_back(n.id);
  context.sample_rate_hz = s.timing.sample_rate_hz;
  return c->make(stage.settings, context);
}

}  // namespace

std::unique_ptr<channel::GainStage> make_stage(const Scenario& s, std::size_t i) {
  return build(s, s.channel.stages.at(i), i);
}

std::shared_ptr<const channel::LinkBudget> make_link_budget(const Scenario& s) {
  // Without a radio every transmitter has 0 dBm, the paper's unit power.
  const double fixed_db = s.radio ? channel::fixed_gain_db(*s.radio) : 0.0;
  const std::vector<StageChoice> chain = chain_of(s);
  std::vector<std::unique_ptr<channel::GainStage>> stages;
  for (std::size_t i = 0; i < chain.size(); ++i) stages.push_back(build(s, chain[i], i));
  return std::make_shared<const channel::LinkBudget>(fixed_db, std::move(stages));
}

}  // namespace rfsitl::scenario
