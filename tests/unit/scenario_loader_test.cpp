// Scenario files: every value read, every default kept, and every mistake reported as
// "<source>:<line>: <key>: <reason>" with the exact line.
#include "rfsitl/scenario/scenario_loader.hpp"

#include "rfsitl/scenario/default_formation.hpp"
#include "scenario_errors.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <variant>

#include "rfsitl/registry/phy_registry.hpp"
#include "rfsitl/scenario/default_formation.hpp"

namespace rfsitl::scenario {
namespace {

std::string error_of(const std::string& yaml) {
  return parse_error_of(yaml);
}

std::string validation_error_of(const Scenario& s) {
  try {
    validate_scenario(s);
  } catch (const ScenarioError& e) {
    return e.what();
  }
  ADD_FAILURE() << "validate_scenario accepted the scenario";
  return {};
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

constexpr const char* kFull = R"(name: full-test
seed: 18446744073709551615
time:
  mode: virtual
  speed: 2.5
  sample_rate_hz: 2000000
  tick_samples: 500
  duration_s: 12.5
ports:
  bind: "::1"
  net_base: 20000
  loc_base: 20005
phy:
  type: gmsk
  samples_per_symbol: 4
  bandwidth_time: 0.3
  filter_delay_symbols: 4
  max_payload_bytes: 1000
  tx_queue_frames: 8
channel:
  model: paper
  path_loss_exponent: 2.5
  noise_variance: 1e-10
  shared_noise: yes
  origin: {lat: 40.5, lon: -75.25, alt: 100}
engine:
  threads: 4
  skip_idle_receivers: false
  stats_interval_s: 0
nodes:
  - id: 3
    position: {lat: 40.5001, lon: -75.2501, alt: 20}
  - id: 7
    position: {x: 1.5, y: -2, z: 30}
  - id: 9
    position: "40.5002, -75.2502, 40"
  - id: 12
traffic:
  - {at_s: 0.01, src: 3, dst: 7, size_bytes: 100, repeat: 5, interval_s: 0.2}
  - {src: 7, dst: 255}
)";

TEST(ParseScenario, FullScenarioReadsEveryValue) {
  const Scenario s = parse_scenario(kFull, "full.yaml");
  EXPECT_EQ(s.name, "full-test");
  EXPECT_EQ(s.seed, 18446744073709551615ULL);
  EXPECT_EQ(s.timing.mode, TimeMode::kVirtual);
  EXPECT_DOUBLE_EQ(s.timing.speed, 2.5);
  EXPECT_DOUBLE_EQ(s.timing.sample_rate_hz, 2e6);
  EXPECT_EQ(s.timing.tick_samples, 500U);
  EXPECT_DOUBLE_EQ(s.timing.duration_s, 12.5);
  EXPECT_EQ(s.ports.bind_address, "::1");
  EXPECT_EQ(s.ports.net_base, 20000);
  EXPECT_EQ(s.ports.loc_base, 20005);
  EXPECT_EQ(s.phy.type, "gmsk");
  EXPECT_EQ(s.phy.settings.get<std::uint64_t>("samples_per_symbol"), 4U);
  EXPECT_DOUBLE_EQ(s.phy.settings.get<double>("bandwidth_time"), 0.3);
  EXPECT_EQ(s.phy.settings.get<std::uint64_t>("filter_delay_symbols"), 4U);
  EXPECT_EQ(s.phy.max_payload_bytes(), 1000U);
  EXPECT_EQ(s.phy.tx_queue_frames, 8U);
  EXPECT_EQ(s.channel.model, "paper");
  EXPECT_DOUBLE_EQ(s.channel.path_loss_exponent, 2.5);
  EXPECT_DOUBLE_EQ(s.channel.noise_variance, 1e-10);
  EXPECT_TRUE(s.channel.shared_noise);
  EXPECT_DOUBLE_EQ(s.channel.origin.lat_deg, 40.5);
  EXPECT_DOUBLE_EQ(s.channel.origin.lon_deg, -75.25);
  EXPECT_DOUBLE_EQ(s.channel.origin.alt_m, 100);
  EXPECT_EQ(s.engine.threads, 4U);
  EXPECT_FALSE(s.engine.skip_idle_receivers);
  EXPECT_DOUBLE_EQ(s.engine.stats_interval_s, 0);

  ASSERT_EQ(s.nodes.size(), 4U);
  EXPECT_EQ(s.nodes[0].id, 3);
  const auto& g = std::get<GeodeticPosition>(*s.nodes[0].initial_position);
  EXPECT_DOUBLE_EQ(g.lat_deg, 40.5001);
  EXPECT_DOUBLE_EQ(g.lon_deg, -75.2501);
  EXPECT_DOUBLE_EQ(g.alt_m, 20);
  EXPECT_EQ(s.nodes[1].id, 7);
  const auto& l = std::get<LocalPosition>(*s.nodes[1].initial_position);
  EXPECT_DOUBLE_EQ(l.x_m, 1.5);
  EXPECT_DOUBLE_EQ(l.y_m, -2);
  EXPECT_DOUBLE_EQ(l.z_m, 30);
  EXPECT_EQ(s.nodes[2].id, 9);
  const auto& str = std::get<GeodeticPosition>(*s.nodes[2].initial_position);
  EXPECT_DOUBLE_EQ(str.lat_deg, 40.5002);
  EXPECT_DOUBLE_EQ(str.lon_deg, -75.2502);
  EXPECT_DOUBLE_EQ(str.alt_m, 40);
  EXPECT_EQ(s.nodes[3].id, 12);
  EXPECT_FALSE(s.nodes[3].initial_position.has_value());

  ASSERT_EQ(s.traffic.size(), 2U);
  EXPECT_DOUBLE_EQ(s.traffic[0].at_s, 0.01);
  EXPECT_EQ(s.traffic[0].src, 3);
  EXPECT_EQ(s.traffic[0].dst, 7);
  EXPECT_EQ(s.traffic[0].size_bytes, 100U);
  EXPECT_EQ(s.traffic[0].repeat, 5U);
  EXPECT_DOUBLE_EQ(s.traffic[0].interval_s, 0.2);
  EXPECT_EQ(s.traffic[1].dst, kBroadcastId);
  EXPECT_EQ(s.traffic[1].size_bytes, TrafficItem{}.size_bytes);  // per-item defaults
}

TEST(ParseScenario, AbsentSectionsKeepTheStructDefaults) {
  const Scenario s = parse_scenario("nodes:\n  - id: 1\n", "t.yaml");
  const Scenario d;
  EXPECT_EQ(s.name, d.name);
  EXPECT_EQ(s.seed, d.seed);
  EXPECT_EQ(s.timing.mode, d.timing.mode);
  EXPECT_EQ(s.timing.speed, d.timing.speed);
  EXPECT_EQ(s.timing.sample_rate_hz, d.timing.sample_rate_hz);
  EXPECT_EQ(s.timing.tick_samples, d.timing.tick_samples);
  EXPECT_EQ(s.timing.duration_s, d.timing.duration_s);
  EXPECT_EQ(s.ports.bind_address, d.ports.bind_address);
  EXPECT_EQ(s.ports.net_base, d.ports.net_base);
  EXPECT_EQ(s.ports.loc_base, d.ports.loc_base);
  EXPECT_EQ(s.phy, d.phy);
  EXPECT_EQ(s.channel.model, d.channel.model);
  EXPECT_EQ(s.channel.path_loss_exponent, d.channel.path_loss_exponent);
  EXPECT_EQ(s.channel.noise_variance, d.channel.noise_variance);
  EXPECT_EQ(s.channel.shared_noise, d.channel.shared_noise);
  EXPECT_EQ(s.channel.origin.lat_deg, d.channel.origin.lat_deg);
  EXPECT_EQ(s.channel.origin.lon_deg, d.channel.origin.lon_deg);
  EXPECT_EQ(s.channel.origin.alt_m, d.channel.origin.alt_m);
  EXPECT_EQ(s.engine.threads, d.engine.threads);
  EXPECT_EQ(s.engine.skip_idle_receivers, d.engine.skip_idle_receivers);
  EXPECT_EQ(s.engine.stats_interval_s, d.engine.stats_interval_s);
  ASSERT_EQ(s.nodes.size(), 1U);
  EXPECT_FALSE(s.nodes[0].initial_position.has_value());
  EXPECT_TRUE(s.traffic.empty());
}

TEST(ParseScenario, EmptySectionsKeepTheStructDefaults) {
  const Scenario s = parse_scenario("time:\nphy:\ntraffic:\nnodes: [{id: 1}]\n", "t.yaml");
  EXPECT_EQ(s.timing.tick_samples, TimingConfig{}.tick_samples);
  EXPECT_EQ(s.phy.type, "gmsk");
  EXPECT_TRUE(s.traffic.empty());
}

TEST(ParseScenario, NumbersInEitherNotation) {
  const char* yaml = "time: {sample_rate_hz: %s, tick_samples: %s}\nnodes: [{id: 1}]\n";
  for (const auto& [rate, tick] :
       {std::pair{"1e6", "1e3"}, {"1000000", "1000"}, {"+1.0e+6", "+1000"}}) {
    std::string text(yaml);
    text.replace(text.find("%s"), 2, rate);
    text.replace(text.find("%s"), 2, tick);
    const Scenario s = parse_scenario(text, "t.yaml");
    EXPECT_EQ(s.timing.sample_rate_hz, 1e6) << text;
    EXPECT_EQ(s.timing.tick_samples, 1000U) << text;
  }
}

TEST(ParseScenario, NoisePowerDbSetsTheVariance) {
  const Scenario s = parse_scenario("channel: {noise_power_db: -90}\nnodes: [{id: 1}]\n", "t.yaml");
  EXPECT_NEAR(s.channel.noise_variance, 1e-9, 1e-21);
}

TEST(ParseScenario, ErrorsNameKeyAndExactLine) {
  // Each case: a scenario with one mistake, and the whole message it must produce.
  const std::pair<const char*, const char*> cases[] = {
      {"nodes: [{id: 1}]\nphy:\n  type: gmsk\n  bandwidth_time: 1.5\n",
       "t.yaml:4: phy.bandwidth_time: must be in [0.2, 1], got 1.5"},
      {"nodes: [{id: 1}]\nphy:\n  type: gmsk\n  samples_per_symbol: 12\n",
       "t.yaml:4: phy.samples_per_symbol: must be in 2..8, got 12"},
      {"nodes: [{id: 1}]\nphy:\n  type: gmsk-liquid\n  bandwidth_time: 1\n",
       "t.yaml:4: phy.bandwidth_time: must be in (0, 1), got 1"},
      {"nodes: [{id: 1}]\nphy:\n  rate_mbps: 24\n",
       "t.yaml:3: phy.rate_mbps: is a setting of phy type ofdm, not of gmsk (whose settings "
       "are: samples_per_symbol, bandwidth_time, filter_delay_symbols, max_payload_bytes)"},
      {"nodes: [{id: 1}]\nphy:\n  type: gmsk\n  bogus: 1\n",
       "t.yaml:4: phy.bogus: unknown key (allowed in phy: type, process, tx_queue_frames, "
       "samples_per_symbol, bandwidth_time, filter_delay_symbols, max_payload_bytes)"},
      {"nodes: [{id: 1}]\ntime:\n  tick_samples: 0\n",
       "t.yaml:3: time.tick_samples: must be in 1..1048576, got 0"},
      {"nodes: [{id: 1}]\ntime:\n  tick_samples: 2.5\n",
       "t.yaml:3: time.tick_samples: must be an integer, got 2.5"},
      {"nodes: [{id: 1}]\ntime:\n  speed:\n  mode: virtual\n",
       "t.yaml:3: time.speed: expected a number, got nothing"},  // the key's line, not the next
      {"nodes: [{id: 1}]\ntime:\n  speed: -1\n", "t.yaml:3: time.speed: must be > 0, got -1"},
      {"nodes: [{id: 1}]\ntime:\n  mode: fast\n",
       "t.yaml:3: time.mode: unknown 'fast' (known: realtime, virtual)"},
      {"nodes:\n  - id: 1\n  - id: 255\n", "t.yaml:3: nodes[1].id: must be in 1..254, got 255"},
      {"nodes:\n  - position: {x: 0, y: 0}\n", "t.yaml:2: nodes[0].id: required"},
      {"nodes:\n  - id: 1\n    position:\n      lat: 91\n      lon: 0\n",
       "t.yaml:4: nodes[0].position.lat: must be in [-90, 90], got 91"},
      {"nodes:\n  - id: 1\n    position: \"43 -78\"\n",
       "t.yaml:3: nodes[0].position: expected 'lat lon alt' (three numbers), got '43 -78'"},
      {"nodes:\n  - id: 1\n    position: {lat: 43, lon: -78, x: 1}\n",
       "t.yaml:3: nodes[0].position: mixes lat/lon/alt with x/y/z; use one form"},
      {"nodes: []\n", "t.yaml:1: nodes: must list 1..254 nodes, got 0"},
      {"name: x\n", "t.yaml:1: nodes: required"},
      {"nodes: [{id: 1}]\nchannel:\n  model: free_space\n",
       "t.yaml:3: channel.model: unknown 'free_space' (known: paper)"},
      {"nodes: [{id: 1}]\nchannel:\n  origin: {x: 1, y: 2}\n",
       "t.yaml:3: channel.origin: must be a geodetic position {lat, lon, alt}"},
      {"nodes: [{id: 1}]\nports:\n  bind: 300.1.2.3\n",
       "t.yaml:3: ports.bind: expected an IPv4/IPv6 address or a host name such as localhost, "
       "got '300.1.2.3'"},
      {"nodes:\n  - id: 250\nports:\n  net_base: 64000\n",
       "t.yaml:4: ports.net_base: port of node 250 would be 66500 (> 65535); must be <= 63035"},
      {"nodes:\n  - id: 1\n  - id: 2\nports:\n  net_base: 15763\n  loc_base: 15753\n",
       "t.yaml:6: ports.loc_base: location port of node 2 and net port of node 1 are both 15773"},
      {"nodes: [{id: 1}, {id: 2}]\ntraffic:\n  - {src: 1, dst: 2}\n  - src: 3\n    dst: 1\n",
       "t.yaml:4: traffic[1].src: node 3 is not in nodes"},
      {"nodes: [{id: 1}, {id: 2}]\ntraffic:\n  - src: 1\n    dst: 9\n",
       "t.yaml:4: traffic[0].dst: node 9 is not in nodes (255 = broadcast)"},
      {"nodes: [{id: 1}, {id: 2}]\ntraffic:\n  - src: 1\n    dst: 1\n",
       "t.yaml:4: traffic[0].dst: equals src (a half-duplex node cannot hear itself)"},
      {"nodes: [{id: 1}, {id: 2}]\nphy: {max_payload_bytes: 64}\ntraffic:\n"
       "  - src: 1\n    dst: 2\n    size_bytes: 65\n",
       "t.yaml:6: traffic[0].size_bytes: must be in 1..64, got 65"},
      {"nodes: [{id: 1}, {id: 2}]\ntraffic:\n  - src: 1\n", "t.yaml:3: traffic[0].dst: required"},
      {"nodes: [{id: 1}]\nphy:\n  process: fork\n",
       "t.yaml:3: phy.process: unknown 'fork' (known: inline, child)"},
      {"nodes: [{id: 1, phy: {type: external}}]\ntime:\n  tick_samples: 20000\n",
       "t.yaml:3: time.tick_samples: must be in 1..16384, got 20000"},
      {"nodes: [{id: 1, phy: {type: external}}, {id: 2}]\ntraffic:\n  - src: 1\n    dst: 2\n",
       "t.yaml:3: traffic[0].src: node 1 is external: its own program serves its net port and "
       "sends its traffic"},
      {"nodes: [{id: 1}]\nexternal:\n  reply_timeout_s: 0\n",
       "t.yaml:3: external.reply_timeout_s: must be in (0, 3600], got 0"},
  };
  for (const auto& [yaml, expected] : cases) EXPECT_EQ(error_of(yaml), expected) << yaml;
}

TEST(ParseScenario, ExternalSectionAndProcessesAreRead) {
  const Scenario s = parse_scenario(
      "nodes:\n  - {id: 1, phy: {process: child}}\n  - {id: 2, phy: {type: external}}\n"
      "  - {id: 3}\nexternal: {socket: /tmp/x.sock, reply_timeout_s: 0.5, start_timeout_s: 3, "
      "restart_children: false}\n",
      "t.yaml");
  EXPECT_EQ(s.external.socket_path, "/tmp/x.sock");
  EXPECT_EQ(s.external.reply_timeout_s, 0.5);
  EXPECT_EQ(s.external.start_timeout_s, 3.0);
  EXPECT_FALSE(s.external.restart_children);
  EXPECT_TRUE(s.runs_externally(0));
  EXPECT_TRUE(s.runs_externally(1));
  EXPECT_FALSE(s.runs_externally(2));
  EXPECT_EQ(s.phy_of(0).process, Process::kChild);
  EXPECT_EQ(s.phy_of(2).process, Process::kInline);
}

TEST(ParseScenario, ANodeCountPlacesTheDefaultFormation) {
  const Scenario s = parse_scenario(
      "radio: {carrier_hz: 2.4e9}\nchannel:\n  stages:\n    - {type: path_loss, model: "
      "free_space}\nnodes: 9\ntraffic:\n  - {at_s: 0, src: 9, dst: 1}\n",
      "t.yaml");
  const auto want = default_formation(9, s.channel);
  ASSERT_EQ(s.nodes.size(), 9u);
  for (std::size_t i = 0; i < 9; ++i) {
    EXPECT_EQ(s.nodes[i].id, i + 1);
    ASSERT_TRUE(s.nodes[i].initial_position.has_value());
    const auto& got = std::get<LocalPosition>(*s.nodes[i].initial_position);
    const auto& placed = std::get<LocalPosition>(*want[i].initial_position);
    EXPECT_EQ(got.x_m, placed.x_m);
    EXPECT_EQ(got.y_m, placed.y_m);
    EXPECT_EQ(got.z_m, placed.z_m);
  }
  EXPECT_EQ(parse_error_of("nodes: 0\n"), "t.yaml:1: nodes: must be in 1..254, got 0");
  EXPECT_EQ(parse_error_of("nodes: 255\n"), "t.yaml:1: nodes: must be in 1..254, got 255");
  EXPECT_NE(parse_error_of("nodes: six\n").find("t.yaml:1: nodes:"), std::string::npos);
  // Traffic is checked against the formation's ids like against listed nodes.
  EXPECT_NE(parse_error_of("nodes: 2\ntraffic:\n  - {at_s: 0, src: 3, dst: 1}\n")
                .find("t.yaml:3: traffic[0].src"),
            std::string::npos);
}

TEST(ParseScenario, IpSectionAndANodesNamespaceAreReadAndChecked) {
  const Scenario s = parse_scenario(
      "ip: {enabled: true, subnet: 10.9.8.0/24, ipv6_prefix: 'fd00:9::/64', interface: wl0}\n"
      "nodes:\n  - {id: 1, netns: drone1}\n  - {id: 2, netns: 'pid:4242'}\n  - {id: 3}\n",
      "t.yaml");
  EXPECT_TRUE(s.ip.enabled);
  EXPECT_EQ(s.ip.subnet, "10.9.8.0/24");
  EXPECT_EQ(s.ip.ipv6_prefix, "fd00:9::/64");
  EXPECT_EQ(s.ip.interface, "wl0");
  EXPECT_EQ(s.nodes[0].netns, "drone1");
  EXPECT_EQ(s.nodes[1].netns, "pid:4242");
  EXPECT_FALSE(s.nodes[2].netns.has_value());
  EXPECT_TRUE(s.typed_framing());
  EXPECT_EQ(parse_error_of("ip: {subnet: 10.9.8.0/25}\nnodes: 2\n"),
            "t.yaml:1: ip.subnet: expected an IPv4 network a.b.c.d/8 to /24 (the host part is the "
            "node id), got '10.9.8.0/25'");
  EXPECT_NE(parse_error_of("ip: {ipv6_prefix: 'fd00::/96'}\nnodes: 2\n").find("ip.ipv6_prefix"),
            std::string::npos);
  EXPECT_NE(parse_error_of("ip: {interface: way-too-long-name}\nnodes: 2\n").find("ip.interface"),
            std::string::npos);
  for (const char* bad : {"a/b", "pid:", "pid:x1", "pid:0", ".."}) {
    const std::string e =
        parse_error_of(std::string("nodes:\n  - {id: 1, netns: '") + bad + "'}\n");
    EXPECT_NE(e.find("t.yaml:2: nodes[0].netns: expected the name of a network namespace"),
              std::string::npos)
        << bad << ": " << e;
  }
}

TEST(ParseScenario, UnknownKeyIsNamedWithTheAllowedOnes) {
  EXPECT_EQ(error_of("nodes: [{id: 1}]\ntime:\n  mode: virtual\n  tick_sample: 500\n"),
            "t.yaml:4: time.tick_sample: unknown key (allowed in time: mode, speed, "
            "sample_rate_hz, tick_samples, tick_us, duration_s)");
  EXPECT_TRUE(contains(error_of("nodes: [{id: 1}]\nnode: []\n"),
                       "t.yaml:2: node: unknown key (allowed at top level: name, seed,"));
  EXPECT_TRUE(contains(error_of("nodes:\n  - id: 1\n    pos: {x: 0, y: 0}\n"),
                       "t.yaml:3: nodes[0].pos: unknown key (allowed in nodes[0]: id, position, "
                       "mobility, phy, netns, channel, tx_hz, rx_hz, bandwidth_hz, duplex)"));
  EXPECT_TRUE(contains(error_of("nodes:\n  - id: 1\n    position: {lat: 1, lon: 2, altitude: 3}\n"),
                       "t.yaml:3: nodes[0].position.altitude: unknown key"));
}

TEST(ParseScenario, DuplicateNodeIdNamesBothLines) {
  EXPECT_EQ(error_of("nodes:\n  - id: 4\n  - id: 5\n  - id: 4\n"),
            "t.yaml:4: nodes[2].id: duplicate id 4 (also nodes[0].id, line 2)");
}

TEST(ParseScenario, DuplicateYamlKeyIsAnError) {
  EXPECT_EQ(error_of("nodes: [{id: 1}]\nphy:\n  bandwidth_time: 0.3\n  bandwidth_time: 0.5\n"),
            "t.yaml:4: phy.bandwidth_time: duplicate key (first at line 3)");
}

TEST(ParseScenario, BothNoiseKeysAreAnError) {
  EXPECT_EQ(
      error_of("nodes: [{id: 1}]\nchannel:\n  noise_variance: 1e-12\n  noise_power_db: -120\n"),
      "t.yaml:4: channel.noise_power_db: conflicts with channel.noise_variance (line 3); "
      "give only one");
}

TEST(ParseScenario, WrongTypeNamesTheKey) {
  EXPECT_EQ(error_of("nodes: [{id: 1}]\ntime:\n  tick_samples: lots\n"),
            "t.yaml:3: time.tick_samples: expected an integer, got 'lots'");
  EXPECT_EQ(error_of("nodes: [{id: 1}]\ntime:\n  speed: \"2\"\n"),
            "t.yaml:3: time.speed: expected a number, got the string \"2\"");
  EXPECT_EQ(error_of("nodes: [{id: 1}]\nchannel:\n  shared_noise: maybe\n"),
            "t.yaml:3: channel.shared_noise: expected true or false, got 'maybe'");
  EXPECT_EQ(error_of("nodes: [{id: 1}]\nphy: [gmsk]\n"),
            "t.yaml:2: phy: expected a mapping (key: value), got a list");
  EXPECT_EQ(error_of("nodes: {id: 1}\n"), "t.yaml:1: nodes: expected a list, got a mapping");
  EXPECT_EQ(error_of("nodes: [{id: 1}]\nname: [a, b]\n"),
            "t.yaml:2: name: expected a string, got a list");
  EXPECT_EQ(error_of("- id: 1\n"), "t.yaml:1: (top level): expected a mapping, got a list");
}

TEST(ParseScenario, YamlSyntaxErrorReportsTheLine) {
  EXPECT_EQ(error_of("nodes:\n  - id: 1\nphy: {type: gmsk\nchannel: {}\n")
                .rfind("t.yaml:4: YAML syntax: ", 0),
            0U);
  EXPECT_EQ(error_of("nodes: [{id: 1}]\ntime:\n  speed: 1\n   mode: virtual\n")
                .rfind("t.yaml:4: YAML syntax: ", 0),
            0U);
}

TEST(ValidateScenario, AcceptsAStructBuiltScenario) {
  Scenario s;
  s.nodes = {NodeConfig::at(1), NodeConfig::at(2, LocalPosition{5, 0, 10})};
  s.traffic = {TrafficItem{}};
  EXPECT_NO_THROW(validate_scenario(s));
}

TEST(ParseScenario, UnknownPhyTypeListsTheRegisteredOnes) {
  std::string known;
  for (const auto& name : phy::known_phy_types()) known += (known.empty() ? "" : ", ") + name;
  EXPECT_EQ(error_of("nodes: [{id: 1}]\nphy:\n  type: lora\n"),
            "t.yaml:3: phy.type: unknown 'lora' (known: " + known + ")");
}

TEST(ValidateScenario, ReportsWithSourceScenarioAndNoLine) {
  Scenario s;
  EXPECT_EQ(validation_error_of(s), "scenario: nodes: must list 1..254 nodes, got 0");
  s.nodes = {NodeConfig::at(4), NodeConfig::at(4)};
  EXPECT_EQ(validation_error_of(s), "scenario: nodes[1].id: duplicate id 4 (also nodes[0].id)");
  s.nodes = {NodeConfig::at(0)};
  EXPECT_EQ(validation_error_of(s), "scenario: nodes[0].id: must be in 1..254, got 0");
  s.nodes = {NodeConfig::at(1)};
  s.phy.settings.set("bandwidth_time", 0.1);
  EXPECT_EQ(validation_error_of(s), "scenario: phy.bandwidth_time: must be in [0.2, 1], got 0.1");
  s.phy.settings.set("bandwidth_time", std::uint64_t{1});
  EXPECT_EQ(validation_error_of(s), "scenario: phy.bandwidth_time: expected a number, got 1");
  s.phy = PhyChoice{};
  s.phy.settings.set("rate_mbps", std::uint64_t{6});
  EXPECT_EQ(validation_error_of(s), "scenario: phy.rate_mbps: not a setting of phy gmsk");
  s.phy = PhyChoice{};
  s.ports.loc_base = s.ports.net_base;  // node 1's two ports would be one
  EXPECT_EQ(
      validation_error_of(s),
      "scenario: ports.loc_base: location port of node 1 and net port of node 1 are both 15773");
  s.ports = PortConfig{};
  s.timing.sample_rate_hz = std::nan("");
  EXPECT_EQ(validation_error_of(s), "scenario: time.sample_rate_hz: must be > 0, got nan");
  s.timing = TimingConfig{};
  s.engine.threads = 257;
  EXPECT_EQ(validation_error_of(s), "scenario: engine.threads: must be in 0..256, got 257");
}

TEST(LoadScenarioFile, UnreadableFileNamesPathAndReason) {
  const std::string path = "/nonexistent/rfsitl/none.yaml";
  try {
    load_scenario_file(path);
    FAIL() << "no error";
  } catch (const ScenarioError& e) {
    EXPECT_STREQ(e.what(),
                 (path + ": cannot read scenario file: No such file or directory").c_str());
  }
}

TEST(LoadScenarioFile, ErrorsNameThePath) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("rfsitl_scenario_loader_test_" + std::to_string(getpid()) + ".yaml");
  std::ofstream(path) << "nodes:\n  - id: 1\nengine:\n  threads: 999\n";
  try {
    load_scenario_file(path.string());
    FAIL() << "no error";
  } catch (const ScenarioError& e) {
    EXPECT_EQ(std::string(e.what()),
              path.string() + ":4: engine.threads: must be in 0..256, got 999");
  }
  std::filesystem::remove(path);
}

// ---- the shipped scenarios --------------------------------------------------------------

const std::filesystem::path kScenarioDir = std::filesystem::path(RFSITL_SOURCE_DIR) / "scenarios";

// WGS84 geodetic -> ECEF, written out here so the test does not lean on the channel module.
std::array<double, 3> ecef(const GeodeticPosition& g) {
  constexpr double kA = 6378137.0;
  constexpr double kF = 1 / 298.257223563;
  constexpr double kE2 = kF * (2 - kF);
  const double lat = g.lat_deg * std::numbers::pi / 180;
  const double lon = g.lon_deg * std::numbers::pi / 180;
  const double n = kA / std::sqrt(1 - kE2 * std::sin(lat) * std::sin(lat));
  return {(n + g.alt_m) * std::cos(lat) * std::cos(lon),
          (n + g.alt_m) * std::cos(lat) * std::sin(lon), (n * (1 - kE2) + g.alt_m) * std::sin(lat)};
}

TEST(ShippedScenarios, EveryFileLoads) {
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(kScenarioDir)) {
    if (entry.path().extension() != ".yaml") continue;
    ++files;
    EXPECT_NO_THROW(load_scenario_file(entry.path().string())) << entry.path();
  }
  EXPECT_GE(files, 2);
}

TEST(ShippedScenarios, ReadmeExampleParses) {
  std::ifstream in(kScenarioDir / "README.md");
  std::stringstream readme;
  readme << in.rdbuf();
  const std::string text = readme.str();
  const auto begin = text.find("```yaml\n");
  ASSERT_NE(begin, std::string::npos);
  const auto end = text.find("```", begin + 8);
  const Scenario s = parse_scenario(text.substr(begin + 8, end - begin - 8), "README.md");
  EXPECT_EQ(s.nodes.size(), 3U);
  EXPECT_EQ(s.traffic.size(), 1U);
}

TEST(ShippedScenarios, DemosAreRealTimeOneMspsWithConsecutiveIds) {
  for (const auto& [file, n] : {std::pair{"six_uav.yaml", 6U}, {"fifteen_uav.yaml", 15U}}) {
    const Scenario s = load_scenario_file((kScenarioDir / file).string());
    ASSERT_EQ(s.nodes.size(), n) << file;
    for (unsigned i = 0; i < n; ++i) {
      EXPECT_EQ(s.nodes[i].id, i + 1) << file;
      ASSERT_TRUE(s.nodes[i].initial_position.has_value()) << file;
      EXPECT_TRUE(std::holds_alternative<GeodeticPosition>(*s.nodes[i].initial_position)) << file;
    }
    EXPECT_EQ(s.timing.mode, TimeMode::kRealTime) << file;
    EXPECT_EQ(s.timing.sample_rate_hz, 1e6) << file;
    EXPECT_EQ(s.timing.tick_samples, 250U) << file;
  }
}

TEST(ShippedScenarios, EveryLinkIsWellAbove20dB) {
  for (const char* file : {"six_uav.yaml", "fifteen_uav.yaml"}) {
    const Scenario s = load_scenario_file((kScenarioDir / file).string());
    double worst_db = std::numeric_limits<double>::infinity();
    for (const auto& a : s.nodes) {
      for (const auto& b : s.nodes) {
        const auto pa = ecef(std::get<GeodeticPosition>(*a.initial_position));
        const auto pb = ecef(std::get<GeodeticPosition>(*b.initial_position));
        const double d = std::hypot(pa[0] - pb[0], pa[1] - pb[1], pa[2] - pb[2]);
        EXPECT_TRUE(a.id == b.id || d >= 2.0) << file << ": nodes " << +a.id << ", " << +b.id;
        const double snr_db = -20 * s.channel.path_loss_exponent * std::log10(d + 1) -
                              10 * std::log10(s.channel.noise_variance);
        worst_db = std::min(worst_db, snr_db);
      }
    }
    EXPECT_GE(worst_db, 35.0) << file;
  }
}

}  // namespace
}  // namespace rfsitl::scenario

namespace rfsitl::scenario {
namespace {

TEST(ParseScenario, NodePhyInheritsTheScenarioPhysSettingsOnlyForTheSameType) {
  const Scenario s = parse_scenario(
      "phy: {type: gmsk, max_payload_bytes: 500, samples_per_symbol: 4, tx_queue_frames: 8}\n"
      "nodes:\n  - id: 1\n  - id: 2\n    phy: {type: ofdm, rate_mbps: 24}\n"
      "  - id: 3\n    phy: {type: gmsk, max_payload_bytes: 100}\n",
      "t.yaml");
  ASSERT_EQ(s.nodes.size(), 3U);
  EXPECT_FALSE(s.nodes[0].phy.has_value());
  ASSERT_TRUE(s.nodes[1].phy.has_value());
  EXPECT_EQ(s.nodes[1].phy->type, "ofdm");
  EXPECT_EQ(s.nodes[1].phy->settings.get<std::uint64_t>("rate_mbps"), 24U);
  EXPECT_EQ(s.nodes[1].phy->max_payload_bytes(), 2048U);  // ofdm's default, not gmsk's 500
  EXPECT_EQ(s.nodes[1].phy->tx_queue_frames, 8U);         // every PHY's: inherited
  ASSERT_TRUE(s.nodes[2].phy.has_value());
  EXPECT_EQ(s.nodes[2].phy->settings.get<std::uint64_t>("samples_per_symbol"), 4U);  // inherited
  EXPECT_EQ(s.nodes[2].phy->max_payload_bytes(), 100U);
}

TEST(ParseScenario, NodePhyErrorsNameTheNodeKeyAndLine) {
  EXPECT_EQ(error_of("nodes:\n  - id: 1\n    phy: {type: ofdm, rate_mbps: 7}\n"),
            "t.yaml:3: nodes[0].phy.rate_mbps: unknown '7' (known: 6, 9, 12, 18, 24, 36, 48, "
            "54)");
  EXPECT_EQ(error_of("nodes:\n  - id: 1\n    phy: {type: ofdm, max_payload_bytes: 5000}\n"),
            "t.yaml:3: nodes[0].phy.max_payload_bytes: must be in 1..4065, got 5000");
}

}  // namespace
}  // namespace rfsitl::scenario

namespace rfsitl::scenario {
namespace {

TEST(ParseScenario, DsssNodeSettingsAreReadAndChecked) {
  const Scenario s = parse_scenario(
      "nodes:\n  - id: 1\n    phy: {type: dsss, code: mseq127, modulation: dqpsk, "
      "samples_per_chip: 2, adaptive: true}\n",
      "t.yaml");
  ASSERT_TRUE(s.nodes[0].phy.has_value());
  const config::Settings& p = s.nodes[0].phy->settings;
  EXPECT_EQ(p.get<std::string>("code"), "mseq127");
  EXPECT_EQ(p.get<std::string>("modulation"), "dqpsk");
  EXPECT_EQ(p.get<std::uint64_t>("samples_per_chip"), 2U);
  EXPECT_TRUE(p.get<bool>("adaptive"));
  EXPECT_TRUE(error_of("nodes:\n  - id: 1\n    phy: {type: dsss, code: gold255}\n")
                  .starts_with("t.yaml:3: nodes[0].phy.code: "));
  EXPECT_EQ(error_of("nodes:\n  - id: 1\n    phy: {type: dsss, modulation: d8psk}\n"),
            "t.yaml:3: nodes[0].phy.modulation: unknown 'd8psk' (known: dbpsk, dqpsk)");
}

}  // namespace
}  // namespace rfsitl::scenario

namespace rfsitl::scenario {
namespace {

TEST(ParseScenario, NodeMobilityIsReadWithItsModelsSettings) {
  const Scenario s = parse_scenario(
      "nodes:\n  - id: 1\n    mobility: {type: orbit, radius_m: 50, speed_mps: -5}\n"
      "  - id: 2\n",
      "t.yaml");
  ASSERT_TRUE(s.nodes[0].mobility.has_value());
  EXPECT_EQ(s.nodes[0].mobility->type, "orbit");
  EXPECT_DOUBLE_EQ(s.nodes[0].mobility->settings.get<double>("radius_m"), 50.0);
  EXPECT_DOUBLE_EQ(s.nodes[0].mobility->settings.get<double>("speed_mps"), -5.0);
  EXPECT_DOUBLE_EQ(s.nodes[0].mobility->settings.get<double>("phase_rad"), 0.0);  // default
  EXPECT_FALSE(s.nodes[1].mobility.has_value());
}

TEST(ParseScenario, MobilityErrorsNameTheNodeKeyAndLine) {
  EXPECT_EQ(error_of("nodes:\n  - id: 1\n    mobility:\n      type: orbit\n      radius_m: 0\n"),
            "t.yaml:5: nodes[0].mobility.radius_m: must be in (0, 1e+07], got 0");
  EXPECT_EQ(error_of("nodes:\n  - id: 1\n    mobility: {type: levy_walk}\n"),
            "t.yaml:3: nodes[0].mobility.type: unknown 'levy_walk' (known: gauss_markov, orbit, "
            "random_waypoint, trace, waypoints)");
  EXPECT_EQ(error_of("nodes:\n  - id: 1\n    mobility: {radius_m: 5}\n"),
            "t.yaml:3: nodes[0].mobility.type: required");
  EXPECT_EQ(error_of("nodes:\n  - id: 1\n    mobility:\n      type: orbit\n      pause_s: 1\n"),
            "t.yaml:5: nodes[0].mobility.pause_s: is a setting of mobility type "
            "random_waypoint, not of orbit (whose settings are: centre_x_m, centre_y_m, radius_m, "
            "speed_mps, altitude_m, phase_rad)");
  // A rule across settings, checked by the model itself.
  EXPECT_EQ(error_of("nodes:\n  - id: 1\n    mobility: {type: random_waypoint, speed_min_mps: 5, "
                     "speed_max_mps: 2}\n")
                .rfind("t.yaml:3: nodes[0].mobility.speed_max_mps: ", 0),
            0U);
  EXPECT_EQ(error_of("nodes:\n  - id: 1\n    mobility: {type: trace}\n"),
            "t.yaml:3: nodes[0].mobility.file: required");
}

}  // namespace
}  // namespace rfsitl::scenario
