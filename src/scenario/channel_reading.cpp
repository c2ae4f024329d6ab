#include "channel_reading.hpp"

#include <cmath>
#include <string>
#include <vector>

#include "rfsitl/registry/channel_stage_registry.hpp"

namespace rfsitl::scenario::detail {
namespace {

// `{type: path_loss, model: free_space}`: a registered stage and its settings.
StageChoice read_stage(Context& c, const Entry& at) {
  Section sec(c, at);
  const Entry type = sec.require("type");
  StageChoice stage{text(c, type), {}};
  std::vector<std::string> names;
  std::vector<const config::ComponentInfo*> stages;
  for (const channel::ChannelStageComponent& component : channel::channel_stage_components()) {
    names.push_back(component.info.name);
    stages.push_back(&component.info);
  }
  c.check_name(stage.type, type.key, names);
  const config::ComponentInfo& info = channel::find_channel_stage(stage.type)->info;
  stage.settings = info.defaults();
  read_declared(c, sec, at, info, stages, stage.settings);
  return stage;
}

// `{cfo_hz: 200, ...}` under channel.impairments.tx or .rx.
channel::FrontEndSettings read_front_end(Context& c, const Entry& at) {
  Section sec(c, at);
  const config::ComponentInfo& info = channel::front_end_info();
  config::Settings settings = info.defaults();
  read_declared(c, sec, at, info, {}, settings);
  return channel::front_end_fields().build(settings);
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
  if (const Entry impairments = sec.take("impairments")) {
    Section isec(c, impairments);
    const Entry tx = isec.take("tx");
    const Entry rx = isec.take("rx");
    isec.finish();
    if (tx) ch.tx_impairments = read_front_end(c, tx);
    if (rx) ch.rx_impairments = read_front_end(c, rx);
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
    ch.stages.clear();
    for_each_item(c, stages, [&](const Entry& e) { ch.stages.push_back(read_stage(c, e)); });
    if (ch.stages.empty()) c.fail(stages.key, "needs at least one stage (or leave it out)");
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
