// The scenario's spectrum: channel plans, each node's tuning, and the errors
// for a tuning that cannot be (each naming its file, line and key).
#include <gtest/gtest.h>

#include <string>

#include "rfsitl/scenario/scenario_loader.hpp"
#include "rfsitl/scenario/spectrum.hpp"
#include "scenario_errors.hpp"

namespace rfsitl::scenario {
namespace {

const std::string kHead = R"(time: {sample_rate_hz: 20e6}
radio: {carrier_hz: 2.437e9}
spectrum:
  plans:
    wifi24: {first_hz: 2.412e9, spacing_hz: 5e6, channels: 13, bandwidth_hz: 20e6}
    ism915: {first_hz: 902.2e6, spacing_hz: 400e3, channels: 64, bandwidth_hz: 200e3}
nodes:
)";

TEST(ScenarioSpectrum, PlansAndTuningsResolveToBands) {
  const Scenario s = parse_scenario(kHead + R"(  - {id: 1, channel: wifi24/1}
  - {id: 2, channel: ism915/3, duplex: full}
  - {id: 3, tx_hz: 1.7325e9, rx_hz: 2.1325e9, bandwidth_hz: 1.4e6, duplex: full}
  - {id: 4, tx_hz: 2.45e9}
  - {id: 5}
)",
                                    "t.yaml");
  ASSERT_EQ(s.spectrum.plans.size(), 2U);
  EXPECT_EQ(s.spectrum.plans.at("ism915").channels, 64U);
  EXPECT_TRUE(s.tuned());
  EXPECT_EQ(s.band_of(0), (NodeBand{2.412e9, 2.412e9, 20e6, Duplex::kHalf}));
  EXPECT_EQ(s.band_of(1),
            (NodeBand{902.2e6 + 2 * 400e3, 902.2e6 + 2 * 400e3, 200e3, Duplex::kFull}));
  EXPECT_EQ(s.band_of(2), (NodeBand{1.7325e9, 2.1325e9, 1.4e6, Duplex::kFull}));
  // rx_hz defaults to tx_hz, the bandwidth to the sample rate.
  EXPECT_EQ(s.band_of(3), (NodeBand{2.45e9, 2.45e9, 20e6, Duplex::kHalf}));
  // No tuning: the radio's carrier over the whole sample rate, as before plans.
  EXPECT_FALSE(s.nodes[4].tuning.has_value());
  EXPECT_EQ(s.band_of(4), (NodeBand{2.437e9, 2.437e9, 20e6, Duplex::kHalf}));
}

TEST(ScenarioSpectrum, NoTuningAnywhereIsTheSharedBand) {
  const Scenario s = parse_scenario("nodes: [{id: 1}, {id: 2, duplex: half}]\n", "t.yaml");
  EXPECT_FALSE(s.tuned());
  EXPECT_EQ(s.band_of(1).tx_hz, channel::RadioSettings{}.carrier_hz);
}

TEST(ScenarioSpectrum, ACommandLineSettingChangesOneKeyOfAPlan) {
  Scenario s = parse_scenario(kHead + "  - {id: 1, channel: wifi24/2}\n", "t.yaml");
  apply_setting(s, "spectrum.plans.wifi24.spacing_hz", "10e6", "--set");
  EXPECT_EQ(s.spectrum.plans.at("wifi24").first_hz, 2.412e9);
  EXPECT_EQ(s.band_of(0).tx_hz, 2.422e9);
}

TEST(ScenarioSpectrum, MistakesNameFileLineAndKey) {
  struct Case {
    const char* node;  // the node's entry (line 8 of the file)
    const char* error;
  };
  const Case cases[] = {
      {"{id: 1, channel: wifi24/14}",
       "t.yaml:8: nodes[0].channel: plan 'wifi24' has channels 1..13, not 14"},
      {"{id: 1, channel: wifi5/1}",
       "t.yaml:8: nodes[0].channel: no plan 'wifi5' in spectrum.plans (known: ism915, wifi24)"},
      {"{id: 1, channel: wifi24}",
       "t.yaml:8: nodes[0].channel: expected PLAN/N (e.g. wifi24/6), got 'wifi24'"},
      {"{id: 1, channel: wifi24/0}",
       "t.yaml:8: nodes[0].channel: expected PLAN/N (e.g. wifi24/6), got 'wifi24/0'"},
      {"{id: 1, channel: wifi24/1, tx_hz: 2.4e9}",
       "t.yaml:8: nodes[0].tx_hz: give a node's frequencies as channel or as tx_hz/rx_hz, not "
       "both"},
      {"{id: 1, tx_hz: 2.4e9,\n     bandwidth_hz: 40e6}",
       "t.yaml:9: nodes[0].bandwidth_hz: a band of 4e+07 Hz is wider than the emulator's "
       "sample rate (2e+07 Hz, time.sample_rate_hz)"},
      {"{id: 1, duplex: both}", "t.yaml:8: nodes[0].duplex: unknown 'both' (known: half, full)"},
  };
  for (const Case& c : cases) {
    EXPECT_EQ(parse_error_of(kHead + "  - " + c.node + "\n"), c.error) << c.node;
  }
  EXPECT_NE(parse_error_of(kHead + "  - {id: 1, tx_hz: -5}\n").find("t.yaml:8: nodes[0].tx_hz"),
            std::string::npos);
  EXPECT_NE(parse_error_of("spectrum: {plans: {p: {channels: 0}}}\nnodes: [{id: 1}]\n")
                .find("t.yaml:1: spectrum.plans.p.channels"),
            std::string::npos);
  EXPECT_EQ(parse_error_of("time: {sample_rate_hz: 1e6}\nspectrum:\n  plans:\n"
                           "    wifi24: {bandwidth_hz: 20e6}\nnodes: [{id: 1}]\n"),
            "t.yaml:4: spectrum.plans.wifi24.bandwidth_hz: a channel of 2e+07 Hz is wider "
            "than the emulator's sample rate (1e+06 Hz, time.sample_rate_hz)");
  EXPECT_NE(parse_error_of("spectrum: {plans: [1, 2]}\nnodes: [{id: 1}]\n")
                .find("t.yaml:1: spectrum.plans: expected a mapping"),
            std::string::npos);
  EXPECT_NE(
      parse_error_of("spectrum: {plan: {}}\nnodes: [{id: 1}]\n").find("spectrum.plan: unknown key"),
      std::string::npos);
}

TEST(ScenarioSpectrum, ChannelReferences) {
  EXPECT_EQ(parse_channel_ref("wifi24/11")->plan, "wifi24");
  EXPECT_EQ(parse_channel_ref("a/b/7")->plan, "a/b");
  EXPECT_EQ(parse_channel_ref("wifi24/11")->number, 11U);
  EXPECT_FALSE(parse_channel_ref("/3"));
  EXPECT_FALSE(parse_channel_ref("x/"));
  EXPECT_FALSE(parse_channel_ref("x/3a"));
  EXPECT_FALSE(parse_channel_ref("x/-3"));
}

}  // namespace
}  // namespace rfsitl::scenario
