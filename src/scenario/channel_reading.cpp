#include "channel_reading.hpp"

#include <cmath>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "rfsitl/registry/channel_stage_registry.hpp"
#include "rfsitl/registry/sample_stage_registry.hpp"

namespace rfsitl::scenario::detail {
namespace {

// `{type: path_loss, model: free_space}`: a registered stage of either kind
// (`all`: the kind's registry, sorted) and its settings.
template <class Component>
StageChoice read_stage(Context& c, const Entry& at,
                       const typename registry::Registry<Component>::List& all) {
  Section sec(c, at);
  const Entry type = sec.require("type");
  StageChoice stage{text(c, type), {}};
  std::vector<std::string> names;
  std::vector<const config::ComponentInfo*> stages;
  const config::ComponentInfo* chosen = nullptr;
  for (const Component& component : all) {
    names.push_back(component.info.name);
    stages.push_back(&component.info);
    if (component.info.name == stage.type) chosen = &component.info;
  }
  c.check_name(stage.type, type.key, names);
  stage.settings = chosen->defaults();
  read_declared(c, sec, at, *chosen, stages, stage.settings);
  return stage;
}

// A list of stages under `key` (channel.stages, .tx_stages, .rx_stages).
template <class Component>
std::vector<StageChoice> read_stages(Context& c, const Entry& list,
                                     const typename registry::Registry<Component>::List& all) {
  if (!list.value.IsNull() && !list.value.IsSequence()) {
    c.fail(list.key, "expected a list of stages ({type: ..., ...}), got " + kind_of(list.value));
  }
  std::vector<StageChoice> out;
  for_each_item(c, list, [&](const Entry& e) { out.push_back(read_stage<Component>(c, e, all)); });
  return out;
}

// `{cfo_hz: 200, ...}` under channel.impairments.tx or .rx: the settings of a
// leading `impairments` sample stage, or nothing when they change nothing.
std::optional<StageChoice> read_impairments(Context& c, const Entry& at) {
  Section sec(c, at);
  const channel::SampleStageComponent* component = channel::find_sample_stage("impairments");
  if (component == nullptr) c.fail(at.key, "this build has no impairments stage");
  StageChoice stage{component->info.name, component->info.defaults()};
  read_declared(c, sec, at, component->info, {}, stage.settings);
  if (stage.settings == component->info.defaults()) return std::nullopt;
  return stage;
}

// Two keys that say one thing two ways: accepting both would silently prefer one.
[[noreturn]] void conflict(const Context& c, const Entry& second, const std::string& first,
                           const std::string& why) {
  c.fail(second.key,
         "conflicts with " + first + " (line " + std::to_string(c.line(first)) + "); " + why);
}

}  // namespace

void read_channel_and_radio(Context& c, const Entry& channel, const Entry& radio, Scenario& s) {
  ChannelConfig& ch = s.channel;
  Section sec(c, channel);
  const Entry model = sec.take("model");
  const Entry exponent = sec.take("path_loss_exponent");
  const Entry stages = sec.take("stages");
  const Entry variance = sec.take("noise_variance");
  const Entry power_db = sec.take("noise_power_db");
  sec.get("shared_noise", ch.shared_noise);
  const Entry tx_stages = sec.take("tx_stages");
  const Entry rx_stages = sec.take("rx_stages");
  std::optional<Entry> tx_impairments;
  std::optional<Entry> rx_impairments;
  if (const Entry impairments = sec.take("impairments")) {
    Section isec(c, impairments);
    if (Entry tx = isec.take("tx")) tx_impairments = tx;
    if (Entry rx = isec.take("rx")) rx_impairments = rx;
    isec.finish();
  }
  if (const Entry origin = sec.take("origin")) {
    const auto p = read_position(c, origin);
    if (!p || !std::holds_alternative<GeodeticPosition>(*p)) {
      c.fail(origin.key, "must be a geodetic position {lat, lon, alt}");
    }
    ch.origin = std::get<GeodeticPosition>(*p);
  }
  sec.finish();

  if (stages && (model || exponent)) {
    const Entry& shorthand = model ? model : exponent;
    conflict(c, shorthand, stages.key,
             "with stages, give the paper model as {type: path_loss, model: paper, "
             "paper_exponent: ...}");
  }
  if (model) ch.model = text(c, model);
  if (exponent) ch.path_loss_exponent = real(c, exponent);
  if (stages) {
    if (!stages.value.IsNull() && !stages.value.IsSequence()) {
      c.fail(stages.key,
             "expected a list of stages ({type: ..., ...}), got " + kind_of(stages.value));
    }
    ch.stages =
        read_stages<channel::ChannelStageComponent>(c, stages, channel::channel_stage_components());
    if (ch.stages.empty()) c.fail(stages.key, "needs at least one stage (or leave it out)");
  }
  const auto& samples = channel::sample_stage_components();
  for (const auto& [impairments, list, chain] :
       {std::tuple{&tx_impairments, &tx_stages, &ch.tx_stages},
        std::tuple{&rx_impairments, &rx_stages, &ch.rx_stages}}) {
    if (!*impairments && !*list) continue;
    chain->clear();
    if (*impairments) {
      if (auto stage = read_impairments(c, **impairments)) chain->push_back(std::move(*stage));
    }
    if (*list) {
      for (StageChoice& stage : read_stages<channel::SampleStageComponent>(c, *list, samples))
        chain->push_back(std::move(stage));
    }
  }

  if (variance && power_db) {
    conflict(c, power_db, variance.key, "give only one");
  }
  if (radio && (variance || power_db)) {
    conflict(c, variance ? variance : power_db, radio.key,
             "with a radio the noise is k T0 fs NF (radio.noise_figure_db)");
  }
  if (s.radio && !radio && (variance || power_db)) {
    c.fail((variance ? variance : power_db).key,
           "the scenario has a radio: its noise is k T0 fs NF (set radio.noise_figure_db)");
  }
  if (variance) ch.noise_variance = real(c, variance);
  if (power_db) {
    const double db = real(c, power_db);
    c.check(db, power_db.key, kNoisePowerDb);
    ch.noise_variance = std::pow(10.0, db / 10.0);
  }

  if (radio) {
    Section rsec(c, radio);
    const config::ComponentInfo& info = channel::radio_info();
    config::Settings settings =
        s.radio ? channel::radio_fields().settings_of(*s.radio) : info.defaults();
    read_declared(c, rsec, radio, info, {}, settings);
    s.radio = channel::radio_fields().build(settings);
  }
  if (s.radio) ch.noise_variance = channel::noise_power_mw(*s.radio, s.timing.sample_rate_hz);
}

}  // namespace rfsitl::scenario::detail
