// validate(): every range and cross-field rule of a Scenario, whether it came
// from a file or from defaults plus command-line overrides.
#include <arpa/inet.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "rfsitl/common/ip_prefix.hpp"
#include "rfsitl/common/unix_socket_path.hpp"
#include "rfsitl/position/mobility/mobility_component.hpp"
#include "rfsitl/registry/channel_stage_registry.hpp"
#include "rfsitl/registry/mobility_registry.hpp"
#include "rfsitl/registry/phy_registry.hpp"
#include "rfsitl/registry/position_source_registry.hpp"
#include "rfsitl/registry/sample_stage_registry.hpp"
#include "scenario_rules.hpp"

namespace rfsitl::scenario::detail {
namespace {

void check_position(const Context& c, const Position& p, const std::string& key) {
  if (const auto* g = std::get_if<GeodeticPosition>(&p)) {
    c.check(g->lat_deg, key + ".lat", kLatitudeLimit);
    c.check(g->lon_deg, key + ".lon", kLongitudeLimit);
    c.check(g->alt_m, key + ".alt", kAltitudeLimit);
  } else {
    const auto& l = std::get<LocalPosition>(p);
    c.check(l.x_m, key + ".x", kHorizontalLimit);
    c.check(l.y_m, key + ".y", kHorizontalLimit);
    c.check(l.z_m, key + ".z", kAltitudeLimit);
  }
}

// An address literal, or a host name (resolved when the run starts, e.g. localhost).
bool valid_bind_address(const std::string& a) {
  in6_addr buf{};  // large enough for either family
  if (inet_pton(AF_INET, a.c_str(), &buf) == 1 || inet_pton(AF_INET6, a.c_str(), &buf) == 1) {
    return true;
  }
  const auto name_char = [](char ch) {
    return std::isalnum(static_cast<unsigned char>(ch)) || ch == '-' || ch == '.';
  };
  // A name needs a letter: 300.1.2.3 is a mistyped address, not a host.
  const auto letter = [](char ch) { return std::isalpha(static_cast<unsigned char>(ch)) != 0; };
  return a.size() <= 253 && std::all_of(a.begin(), a.end(), name_char) &&
         std::any_of(a.begin(), a.end(), letter);
}

using Listed = std::array<bool, 256>;  // indexed by NodeId

void check_ports(const PortConfig& p, const Context& c, const Listed& listed, unsigned max_id) {
  if (!valid_bind_address(p.bind_address)) {
    c.fail("ports.bind", "expected an IPv4/IPv6 address or a host name such as localhost, got '" +
                             p.bind_address + "'");
  }
  for (const auto& [key, base] :
       {std::pair{"ports.net_base", p.net_base}, {"ports.loc_base", p.loc_base}}) {
    if (const unsigned top = base + 10U * max_id; top > 65535) {
      c.fail(key, "port of node " + std::to_string(max_id) + " would be " + std::to_string(top) +
                      " (> 65535); must be <= " + std::to_string(65535 - 10 * max_id));
    }
  }
  // Node a's net port is node b's location port when net_base + 10a == loc_base + 10b.
  for (unsigned a = 0; a < listed.size(); ++a) {
    const unsigned port = p.net_base + 10 * a;
    if (!listed[a] || port < p.loc_base || (port - p.loc_base) % 10 != 0) continue;
    if (const unsigned b = (port - p.loc_base) / 10; b < listed.size() && listed[b]) {
      c.fail("ports.loc_base", "location port of node " + std::to_string(b) +
                                   " and net port of node " + std::to_string(a) + " are both " +
                                   std::to_string(port));
    }
  }
}

void check_traffic(const Scenario& s, const Context& c, const Listed& listed) {
  for (std::size_t i = 0; i < s.traffic.size(); ++i) {
    const TrafficItem& t = s.traffic[i];
    const std::string key = "traffic[" + std::to_string(i) + "]";
    c.check(t.at_s, key + ".at_s", kNonNegative);
    if (!listed[t.src]) c.fail(key + ".src", "node " + std::to_string(t.src) + " is not in nodes");
    if (t.dst != kBroadcastId && !listed[t.dst]) {
      c.fail(key + ".dst", "node " + std::to_string(t.dst) + " is not in nodes (255 = broadcast)");
    }
    if (t.dst == t.src) c.fail(key + ".dst", "equals src (a half-duplex node cannot hear itself)");
    const auto src = std::find_if(s.nodes.begin(), s.nodes.end(),
                                  [&](const NodeConfig& n) { return n.id == t.src; });
    const PhyChoice& src_phy = src->phy ? *src->phy : s.phy;
    if (src_phy.external_program()) {
      c.fail(key + ".src", "node " + std::to_string(t.src) +
                               " is external: its own program serves its net port and sends "
                               "its traffic");
    }
    c.check(t.size_bytes, key + ".size_bytes", IntLimit{1, src_phy.max_payload_bytes()});
    c.check(t.repeat, key + ".repeat", kRepeat);
    c.check(t.interval_s, key + ".interval_s", kNonNegative);
    // The sample clock counts to 2^62; a later frame could never be sent.
    const double last_s = t.at_s + (t.repeat - 1.0) * t.interval_s;
    if (!(last_s * s.timing.sample_rate_hz < 0x1p62)) {
      c.fail(key + ".at_s",
             "its last frame would be at " + fmt(last_s) +
                 " s, beyond the sample clock (2^62 samples at time.sample_rate_hz)");
    }
  }
}

// The PHY's declared settings (limits and rules) are the PHY's; the rest is ours.
void check_phy(const Context& c, const PhyChoice& p, const std::string& key) {
  c.check_name(p.type, key + ".type", phy::known_phy_types());
  c.check(p.tx_queue_frames, key + ".tx_queue_frames", kTxQueue);
  try {
    p.component().info.validate(p.settings);
  } catch (const config::SettingError& e) {
    c.fail(key + "." + e.key(), e.what());
  }
}

// A position source must be registered, its settings valid, and (for one that
// follows the wall clock) the run in real time.
void check_source(const Context& c, const Scenario& s, const PositionSourceChoice& p,
                  const std::string& key) {
  const auto* component = position::find_position_source(p.type);
  if (component == nullptr) c.fail(key + ".source", "unknown '" + p.type + "'");
  // Settings a choice leaves out take the component's defaults (the default
  // choice, the location port, names none).
  config::Settings full = component->info.defaults();
  for (const auto& [name, value] : p.settings) full.set(name, value);
  try {
    component->info.validate(full);
  } catch (const config::SettingError& e) {
    c.fail(e.key().empty() ? key : key + "." + e.key(), e.what());
  }
  if (component->wall_clock && s.timing.mode == TimeMode::kVirtual) {
    c.fail(key + ".source", p.type + " " + scenario::wall_clock_conflict(s.timing));
  }
}

// Every stage of a list registered (`find` by name) and its settings valid.
template <class Find>
void check_stages(const Context& c, const std::vector<StageChoice>& stages, const std::string& list,
                  const Find& find) {
  for (std::size_t i = 0; i < stages.size(); ++i) {
    const StageChoice& stage = stages[i];
    const std::string key = list + "[" + std::to_string(i) + "]";
    const auto* component = find(stage.type);
    if (component == nullptr) c.fail(key + ".type", "unknown '" + stage.type + "'");
    try {
      component->info.validate(stage.settings);
    } catch (const config::SettingError& e) {
      c.fail(e.key().empty() ? key : key + "." + e.key(), e.what());
    }
  }
}

// Every stage registered and its settings valid; the radio within its limits.
void check_channel(const Context& c, const Scenario& s) {
  check_stages(c, s.channel.stages, "channel.stages", channel::find_channel_stage);
  check_stages(c, s.channel.tx_stages, "channel.tx_stages", channel::find_sample_stage);
  check_stages(c, s.channel.rx_stages, "channel.rx_stages", channel::find_sample_stage);
  if (s.radio) {
    try {
      channel::radio_info().validate(channel::radio_fields().settings_of(*s.radio));
    } catch (const config::SettingError& e) {
      c.fail("radio." + e.key(), e.what());
    }
  }
}

}  // namespace

namespace {

// Linux interface names: 1..15 characters, no '/', ':' or whitespace (IFNAMSIZ).
bool valid_interface_name(const std::string& name) {
  if (name.empty() || name.size() > 15 || name == "." || name == "..") return false;
  return std::all_of(name.begin(), name.end(), [](char ch) {
    return std::isalnum(static_cast<unsigned char>(ch)) || ch == '-' || ch == '_' || ch == '.';
  });
}

void check_ip(const Scenario& s, const Context& c) {
  const IpConfig& ip = s.ip;
  if (const auto v4 = parse_ipv4_prefix(ip.subnet); !v4 || v4->length < 8 || v4->length > 24) {
    c.fail("ip.subnet",
           "expected an IPv4 network a.b.c.d/8 to /24 (the host part is the node id), "
           "got '" +
               ip.subnet + "'");
  }
  if (const auto v6 = parse_ipv6_prefix(ip.ipv6_prefix); !v6 || v6->length > 64) {
    c.fail("ip.ipv6_prefix", "expected an IPv6 network of /64 or shorter, e.g. fd00:1::/64, got '" +
                                 ip.ipv6_prefix + "'");
  }
  if (!valid_interface_name(ip.interface)) {
    c.fail("ip.interface", "expected 1..15 of A-Z a-z 0-9 - _ . (a Linux interface name), got '" +
                               ip.interface + "'");
  }
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    const std::string key = "nodes[" + std::to_string(i) + "]";
    if (const auto& ns = s.nodes[i].netns) {
      const bool pid = ns->starts_with("pid:");
      const std::string digits = pid ? ns->substr(4) : "";
      const bool pid_ok = pid && !digits.empty() && digits.size() <= 9 &&
                          std::all_of(digits.begin(), digits.end(),
                                      [](char ch) { return ch >= '0' && ch <= '9'; }) &&
                          std::stoul(digits) > 0;
      const bool name_ok = !pid && !ns->empty() && ns->size() <= 255 &&
                           ns->find('/') == std::string::npos && *ns != "." && *ns != "..";
      if (!pid_ok && !name_ok) {
        c.fail(key + ".netns",
               "expected the name of a network namespace (as `ip netns list` "
               "shows it) or pid:PID (a process's namespace), got '" +
                   *ns + "'");
      }
    }
    // An external transceiver serves its node's net port itself and has no
    // frame kinds: IP cannot reach it through the radio.
    if (ip.enabled && s.phy_of(i).external_program()) {
      c.fail(key + ".phy",
             "an external transceiver owns its node's net port and cannot carry "
             "IP; turn ip off or give this node a built-in phy");
    }
  }
}

// A band wider than the grid every band is mixed on.
void check_fits(const Context& c, const std::string& key, const char* what, double hz, double fs) {
  if (hz > fs) {
    c.fail(key, std::string(what) + " of " + fmt(hz) +
                    " Hz is wider than the emulator's sample rate (" + fmt(fs) +
                    " Hz, time.sample_rate_hz)");
  }
}

// Every node's tuning names a plan and channel that exist, gives its
// frequencies one way, and fits in the emulator's sample rate (the channel
// mixes every band on one grid of that rate); each plan's channels too.
void check_spectrum(const Scenario& s, const Context& c) {
  const double fs = s.timing.sample_rate_hz;
  try {
    spectrum_info().validate(spectrum_fields().settings_of(s.spectrum));
  } catch (const config::SettingError& e) {
    c.fail("spectrum." + e.key(), e.what());
  }
  for (const auto& [name, plan] : s.spectrum.plans) {
    const std::string key = "spectrum.plans." + name;
    try {
      channel_plan_info().validate(channel_plan_fields().settings_of(plan));
    } catch (const config::SettingError& e) {
      c.fail(key + "." + e.key(), e.what());
    }
    check_fits(c, key + ".bandwidth_hz", "a channel", plan.bandwidth_hz, fs);
  }
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    const auto& t = s.nodes[i].tuning;
    if (!t) continue;
    const std::string key = "nodes[" + std::to_string(i) + "]";
    try {
      node_tuning_info().validate(node_tuning_fields().settings_of(*t));
    } catch (const config::SettingError& e) {
      c.fail(key + "." + e.key(), e.what());
    }
    if (!t->channel.empty()) {
      if (t->tx_hz > 0.0 || t->rx_hz > 0.0) {
        c.fail(key + (t->tx_hz > 0.0 ? ".tx_hz" : ".rx_hz"),
               "give a node's frequencies as channel or as tx_hz/rx_hz, not both");
      }
      const auto ref = parse_channel_ref(t->channel);
      if (!ref)
        c.fail(key + ".channel", "expected PLAN/N (e.g. wifi24/6), got '" + t->channel + "'");
      std::vector<std::string> names;
      for (const auto& plan : s.spectrum.plans) names.push_back(plan.first);
      const auto plan = s.spectrum.plans.find(ref->plan);
      if (plan == s.spectrum.plans.end()) {
        c.fail(key + ".channel", "no plan '" + ref->plan + "' in spectrum.plans (known: " +
                                     (names.empty() ? std::string("none") : join(names)) + ")");
      }
      if (ref->number > plan->second.channels) {
        c.fail(key + ".channel", "plan '" + ref->plan + "' has channels 1.." +
                                     std::to_string(plan->second.channels) + ", not " +
                                     std::to_string(ref->number));
      }
    }
    check_fits(c, key + ".bandwidth_hz", "a band", t->bandwidth_hz, fs);
  }
}

}  // namespace

void validate(const Scenario& s, const Context& c) {
  if (s.nodes.empty() || s.nodes.size() > kMaxNodeId) {
    c.fail("nodes", "must list 1.." + std::to_string(kMaxNodeId) + " nodes, got " +
                        std::to_string(s.nodes.size()));
  }
  Listed listed{};
  std::array<std::size_t, 256> first{};  // index of the first node with each id
  unsigned max_id = 0;
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    const std::string key = "nodes[" + std::to_string(i) + "]";
    const NodeId id = s.nodes[i].id;
    c.check(id, key + ".id", kNodeIdLimit);
    if (listed[id]) {
      const std::string other = "nodes[" + std::to_string(first[id]) + "].id";
      const int other_line = c.line(other);
      c.fail(key + ".id", "duplicate id " + std::to_string(id) + " (also " + other +
                              (other_line > 0 ? ", line " + std::to_string(other_line) : "") + ")");
    }
    listed[id] = true;
    first[id] = i;
    max_id = std::max<unsigned>(max_id, id);
    if (const auto& p = s.nodes[i].initial_position) check_position(c, *p, key + ".position");
  }
  check_phy(c, s.phy, "phy");
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    const auto& m = s.nodes[i].mobility;
    if (!m) continue;
    const std::string key = "nodes[" + std::to_string(i) + "].mobility";
    const auto* model = position::mobility::find_mobility(m->type);
    if (model == nullptr) c.fail(key + ".type", "unknown '" + m->type + "'");
    try {
      model->info.validate(m->settings);
    } catch (const config::SettingError& e) {
      c.fail(e.key().empty() ? key : key + "." + e.key(), e.what());
    }
  }
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    if (const auto& p = s.nodes[i].phy) check_phy(c, *p, "nodes[" + std::to_string(i) + "].phy");
  }
  check_source(c, s, s.position_source, "position");
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    const auto& own = s.nodes[i].source;
    if (!own) continue;
    const std::string key = "nodes[" + std::to_string(i) + "].position";
    check_source(c, s, *own, key);
    if (!own->is_location_port() && s.nodes[i].mobility) {
      c.fail(key + ".source", "node " + std::to_string(s.nodes[i].id) +
                                  " also has a mobility model; a node has one position source");
    }
  }
  check_channel(c, s);
  check_spectrum(s, c);
  c.check_name(s.channel.model, "channel.model", kChannelModels);
  c.check(s.channel.path_loss_exponent, "channel.path_loss_exponent", kNonNegative);
  c.check(s.channel.noise_variance, "channel.noise_variance", kNonNegative);
  if (s.channel.noise_variance > 0) {  // noise_power_db's range, however it was given
    const double db = 10.0 * std::log10(s.channel.noise_variance);
    constexpr double kRoundTrip = 1e-9;  // 10^(300/10) reads back as 300.00000000000006
    if (!(db >= kNoisePowerDb.lo - kRoundTrip && db <= kNoisePowerDb.hi + kRoundTrip)) {
      c.fail("channel.noise_variance",
             "the noise power " + kNoisePowerDb.describe() + " dB, got " + fmt(db) + " dB");
    }
  }
  check_position(c, s.channel.origin, "channel.origin");
  c.check(s.timing.speed, "time.speed", kPositive);
  c.check(s.timing.sample_rate_hz, "time.sample_rate_hz", kPositive);
  c.check(s.timing.tick_samples, "time.tick_samples", kTickSamples);
  c.check(s.timing.duration_s, "time.duration_s", kNonNegative);
  c.check(s.engine.threads, "engine.threads", kThreads);
  c.check(s.engine.stats_interval_s, "engine.stats_interval_s", kNonNegative);
  c.check(s.engine.mobility_update_s, "engine.mobility_update_s", RealLimit{1e-6, 3600});
  c.check(s.external.reply_timeout_s, "external.reply_timeout_s", kReplyTimeout);
  c.check(s.external.start_timeout_s, "external.start_timeout_s", kNonNegative);
  // Here rather than at bind(): a path too long for a socket address would fail
  // only once the run starts, and without the file and line that set it.
  if (const std::string& path = s.external.socket_path; !path.empty()) {
    if (const std::string why = unix_socket_path_error(path); !why.empty()) {
      c.fail("external.socket", "'" + path + "' " + why);
    }
  }
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    if (s.runs_externally(i)) {
      c.check(s.timing.tick_samples, "time.tick_samples", kExternalTickSamples);
      break;
    }
  }
  check_ports(s.ports, c, listed, max_id);
  check_traffic(s, c, listed);
  check_ip(s, c);
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    // The MAC runs in the engine around the node's transceiver; an external
    // transceiver's program sends when it likes.
    if (s.mac.type != "none" && s.phy_of(i).external_program()) {
      c.fail("nodes[" + std::to_string(i) + "].phy",
             "an external transceiver sends on its own schedule and cannot run under mac '" +
                 s.mac.type + "'; use mac: {type: none} or give this node a built-in phy");
    }
  }
}

}  // namespace rfsitl::scenario::detail

namespace rfsitl::scenario {

std::string wall_clock_conflict(const TimingConfig& t) {
  const std::string at = t.mode_given_at.empty() ? "" : " at " + t.mode_given_at;
  return "follows live vehicles on the wall clock, which virtual time cannot (time.mode "
         "virtual" +
         at +
         "; use time.mode realtime or --mode realtime, and time.speed to match "
         "the simulator's speed-up)";
}

}  // namespace rfsitl::scenario
