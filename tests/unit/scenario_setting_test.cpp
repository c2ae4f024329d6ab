// One set of rules for the scenario file and the command line: apply_setting()
// reads a flag's value with the file's reader, so both accept and refuse the
// same values, and the error names the flag.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "rfsitl/common/position_limits.hpp"
#include "rfsitl/scenario/scenario_loader.hpp"
#include "scenario_errors.hpp"

namespace rfsitl::scenario {
namespace {

Scenario two_nodes() {
  return parse_scenario("nodes: [{id: 1}, {id: 2}]\n", "t.yaml");
}

std::string setting_error(const std::string& key, const std::string& value,
                          const std::string& flag) {
  Scenario s = two_nodes();
  try {
    apply_setting(s, key, value, flag);
  } catch (const ScenarioError& e) {
    return e.what();
  }
  ADD_FAILURE() << key << " = " << value << " accepted";
  return {};
}

std::string file_error(const std::string& yaml) {
  return parse_error_of(yaml);
}

TEST(ScenarioSetting, ValuesSetWhatTheFileWouldSet) {
  Scenario s = two_nodes();
  apply_setting(s, "channel.noise_power_db", "-90", "--noise-db");
  apply_setting(s, "time.mode", "virtual", "--mode");
  apply_setting(s, "time.tick_samples", "1e3", "--tick");
  apply_setting(s, "ports.bind", "localhost", "--bind");
  apply_setting(s, "engine.skip_idle_receivers", "false", "--no-skip");
  EXPECT_DOUBLE_EQ(10 * std::log10(s.channel.noise_variance), -90);
  EXPECT_EQ(s.timing.mode, TimeMode::kVirtual);
  EXPECT_EQ(s.timing.tick_samples, 1000U);
  EXPECT_EQ(s.ports.bind_address, "localhost");
  EXPECT_FALSE(s.engine.skip_idle_receivers);
  EXPECT_EQ(s.nodes.size(), 2U) << "nodes are untouched";
}

TEST(ScenarioSetting, NoisePowerHasTheFilesLimitOnBothPaths) {
  EXPECT_EQ(setting_error("channel.noise_power_db", "400", "--noise-db"),
            "--noise-db: channel.noise_power_db: must be in [-300, 300], got 400");
  EXPECT_EQ(file_error("nodes: [{id: 1}]\nchannel: {noise_power_db: 400}\n"),
            "t.yaml:2: channel.noise_power_db: must be in [-300, 300], got 400");
  // The same range holds when the variance is given directly (or set in code).
  EXPECT_EQ(file_error("nodes: [{id: 1}]\nchannel: {noise_variance: 1e40}\n"),
            "t.yaml:2: channel.noise_variance: the noise power must be in [-300, 300] dB, got "
            "400 dB");
  // Both ends of the range stay usable although 10^(dB/10) does not round-trip exactly.
  Scenario s = two_nodes();
  apply_setting(s, "channel.noise_power_db", "300", "--noise-db");
  apply_setting(s, "channel.noise_power_db", "-300", "--noise-db");
}

TEST(ScenarioSetting, ErrorsAreShortAndNameTheFlag) {
  EXPECT_EQ(setting_error("time.speed", "0", "--speed"), "--speed: time.speed: must be > 0, got 0");
  EXPECT_EQ(setting_error("time.mode", "fast", "--mode"),
            "--mode: time.mode: unknown 'fast' (known: realtime, virtual)");
  EXPECT_EQ(setting_error("time.tick_samples", "abc", "--tick"),
            "--tick: time.tick_samples: expected an integer, got 'abc'");
  EXPECT_EQ(setting_error("ports.bind", "not an address!", "--bind"),
            "--bind: ports.bind: expected an IPv4/IPv6 address or a host name such as localhost, "
            "got 'not an address!'");
}

TEST(ScenarioSetting, CrossFieldRulesSeeTheNewValue) {
  // Port of node 2 would be 65000 + 20 > 65535.
  const std::string e = setting_error("ports.net_base", "65530", "--net-base");
  EXPECT_EQ(e.rfind("--net-base: ports.net_base: port of node 2 would be 65550", 0), 0U) << e;
}

TEST(ScenarioRules, AdaptationNeedsACodeWithAGoldFamily) {
  EXPECT_EQ(file_error("nodes: [{id: 1}]\nphy: {type: dsss, code: barker11, adaptive: true}\n"),
            "t.yaml:2: phy.adaptive: needs a code with a Gold family (mseq<N> or gold<N> with N "
            "in 31, 63, 127, 511, 1023), but code is 'barker11'");
  EXPECT_NO_THROW(
      parse_scenario("nodes: [{id: 1}]\nphy: {type: dsss, code: gold31, adaptive: true}\n", "t"));
  // A GMSK node has no such setting: it is refused, naming whose it is.
  EXPECT_EQ(file_error("nodes: [{id: 1}]\nphy: {type: gmsk, adaptive: true}\n"),
            "t.yaml:2: phy.adaptive: is a setting of phy type dsss, not of gmsk (whose settings "
            "are: samples_per_symbol, bandwidth_time, filter_delay_symbols, max_payload_bytes)");
}

TEST(ScenarioRules, MisspeltTopLevelKeyIsNamedBeforeMissingNodes) {
  const std::string e = file_error("name: x\nnodez:\n  - id: 1\n");
  EXPECT_EQ(e.rfind("t.yaml:2: nodez: unknown key (allowed at top level: ", 0), 0U) << e;
  EXPECT_EQ(file_error("name: x\n"), "t.yaml:1: nodes: required");
}

TEST(ScenarioRules, HostNamesAreAcceptedForBind) {
  EXPECT_NO_THROW(parse_scenario("nodes: [{id: 1}]\nports: {bind: localhost}\n", "t"));
  EXPECT_NO_THROW(parse_scenario("nodes: [{id: 1}]\nports: {bind: '::1'}\n", "t"));
}

TEST(ScenarioRules, TrafficBeyondTheSampleClockIsRefused) {
  EXPECT_EQ(file_error("nodes: [{id: 1}, {id: 2}]\ntraffic:\n  - {at_s: 1e300, src: 1, dst: 2}\n"),
            "t.yaml:3: traffic[0].at_s: its last frame would be at 1e+300 s, beyond the sample "
            "clock (2^62 samples at time.sample_rate_hz)");
  EXPECT_NO_THROW(parse_scenario(
      "nodes: [{id: 1}, {id: 2}]\ntraffic:\n  - {src: 1, dst: 2, repeat: 2e7, interval_s: 1}\n",
      "t"));
}

TEST(ScenarioRules, PositionsHaveTheLimitsEveryOtherInputHas) {
  // Accepted exactly when the shared limits (common/position_limits.hpp) accept:
  // the scenario keeps no copy of them that could drift.
  const double values[] = {-1.7e308, -1e7 - 0.5, -1e7,      -100001, -1000.5, -1000,
                           -180.5,   -90,        0,         90.5,    180,     100000,
                           100000.5, 1e7,        1e7 + 0.5, 1.7e308};
  const auto accepted = [](const std::string& position) {
    try {
      parse_scenario("nodes:\n  - id: 1\n    position: " + position + "\n", "t.yaml");
      return true;
    } catch (const ScenarioError&) {
      return false;
    }
  };
  for (const double v : values) {
    const std::string n = format_coordinate(v);
    for (const auto& [text, p] :
         {std::pair{"{x: " + n + ", y: 0}", Position{LocalPosition{v, 0, 0}}},
          {"{x: 0, y: " + n + "}", Position{LocalPosition{0, v, 0}}},
          {"{x: 0, y: 0, z: " + n + "}", Position{LocalPosition{0, 0, v}}},
          {"{lat: " + n + ", lon: 0}", Position{GeodeticPosition{v, 0, 0}}},
          {"{lat: 0, lon: " + n + "}", Position{GeodeticPosition{0, v, 0}}},
          {"{lat: 0, lon: 0, alt: " + n + "}", Position{GeodeticPosition{0, 0, v}}}}) {
      EXPECT_EQ(accepted(text), position_error(p).empty()) << text;
    }
  }
  EXPECT_EQ(file_error("nodes:\n  - id: 1\n    position: {x: 1.7e308, y: 0}\n"),
            "t.yaml:3: nodes[0].position.x: must be in [-1e+07, 1e+07], got 1.7e+308");
}

TEST(ScenarioRules, SocketPathTooLongForASocketNamesFileLineAndKey) {
  const std::string fits = "/tmp/" + std::string(97, 's') + ".sock";  // 107 bytes
  const std::string path = "/tmp/" + std::string(98, 's') + ".sock";  // 108 bytes
  EXPECT_NO_THROW(parse_scenario("nodes: [{id: 1}]\nexternal:\n  socket: " + fits + "\n", "t"));
  EXPECT_EQ(file_error("nodes: [{id: 1}]\nexternal:\n  socket: " + path + "\n"),
            "t.yaml:3: external.socket: '" + path +
                "' is 108 bytes long; a Unix socket path holds at most 107");
  EXPECT_EQ(setting_error("external.socket", path, "--external-socket"),
            "--external-socket: external.socket: '" + path +
                "' is 108 bytes long; a Unix socket path holds at most 107");
}

TEST(ScenarioRules, ReplyTimeoutFitsTheHubsMilliseconds) {
  EXPECT_EQ(file_error("nodes: [{id: 1}]\nexternal: {reply_timeout_s: 1e30}\n"),
            "t.yaml:2: external.reply_timeout_s: must be in (0, 3600], got 1e+30");
  EXPECT_NO_THROW(parse_scenario("nodes: [{id: 1}]\nexternal: {reply_timeout_s: 3600}\n", "t"));
}

TEST(ScenarioFile, EndlessFileIsRefusedWithoutReadingItAll) {
  try {
    load_scenario_file("/dev/zero");
    ADD_FAILURE() << "/dev/zero accepted";
  } catch (const ScenarioError& e) {
    EXPECT_EQ(std::string(e.what()), "/dev/zero: cannot read scenario file: larger than 16 MiB");
  }
}

}  // namespace
}  // namespace rfsitl::scenario
