// The scenario's channel: `channel.stages` and `radio:` read into the link
// budget the engine uses, and every mistake refused at load with its line.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <complex>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include "rfsitl/channel/stages/path_loss.hpp"
#include "rfsitl/scenario/link_budget_of.hpp"
#include "rfsitl/scenario/scenario_loader.hpp"
#include "scenario_errors.hpp"

namespace rfsitl::scenario {
namespace {

const std::string kNodes = "nodes:\n  - id: 1\n  - id: 2\n";

/// Two nodes `d` metres apart at 10 m height.
channel::LinkGeometry link(double d) {
  channel::LinkGeometry g;
  g.tx.local = {0.0, 0.0, 10.0};
  g.rx.index = 1;
  g.rx.local = {d, 0.0, 10.0};
  g.distance_m = g.horizontal_m = d;
  return g;
}

double power_dbm(const channel::LinkBudget& b, double d) {
  return 10.0 * std::log10(std::norm(b.coefficient(link(d))));
}

TEST(ChannelStages, WithoutStagesTheBudgetIsThePapersModel) {
  const Scenario s = parse_scenario(kNodes + "channel: {path_loss_exponent: 2.5}\n", "t.yaml");
  EXPECT_TRUE(s.channel.stages.empty());
  const auto budget = make_link_budget(s);
  const auto paper = channel::make_paper_budget(2.5);
  for (const double d : {0.0, 3.0, 80.0}) {
    EXPECT_EQ(budget->coefficient(link(d)), paper->coefficient(link(d))) << d;
  }
}

TEST(ChannelStages, StagesAreReadInOrderWithTheirSettings) {
  const Scenario s =
      parse_scenario(kNodes +
                         "channel:\n"
                         "  stages:\n"
                         "    - {type: path_loss, model: log_distance, exponent: 3.5}\n"
                         "    - type: path_loss\n"
                         "      model: free_space\n",
                     "t.yaml");
  ASSERT_EQ(s.channel.stages.size(), 2U);
  EXPECT_EQ(s.channel.stages[0].settings.get<std::string>("model"), "log_distance");
  EXPECT_EQ(s.channel.stages[0].settings.get<double>("exponent"), 3.5);
  EXPECT_EQ(s.channel.stages[1].settings.get<std::string>("model"), "free_space");
  // Unset settings take the stage's defaults.
  EXPECT_EQ(s.channel.stages[1].settings.get<double>("min_distance_m"), 1.0);
  // Two stages in a chain multiply: their losses in dB add (0 dBm, no radio).
  const auto budget = make_link_budget(s);
  const double want = -channel::path_loss::log_distance_db(500.0, 2.4e9, 3.5, 1.0) -
                      channel::path_loss::free_space_db(500.0, 2.4e9);
  EXPECT_NEAR(power_dbm(*budget, 500.0), want, 1e-4);
}

TEST(ChannelRadio, TheNoiseIsKT0TimesTheSampleRateTimesTheNoiseFigure) {
  const Scenario s = parse_scenario(
      kNodes + "time: {sample_rate_hz: 1e6}\nradio: {noise_figure_db: 7, tx_power_dbm: 20}\n",
      "t.yaml");
  ASSERT_TRUE(s.radio);
  // k T0 = 1.380649e-23 J/K x 290 K = -173.98 dBm/Hz; + 60 dB (1 MHz) + 7 dB.
  const double kt0_dbm_per_hz = 10.0 * std::log10(1.380649e-23 * 290.0 * 1e3);
  EXPECT_NEAR(kt0_dbm_per_hz, -173.98, 0.005);
  EXPECT_NEAR(10.0 * std::log10(s.channel.noise_variance), kt0_dbm_per_hz + 60.0 + 7.0, 1e-9);
}

TEST(ChannelRadio, TheNoiseFollowsASampleRateChangedLater) {
  Scenario s = parse_scenario(kNodes + "radio: {noise_figure_db: 5}\n", "t.yaml");
  const double before = s.channel.noise_variance;
  apply_setting(s, "time.sample_rate_hz", "4e6", "--sample-rate");
  EXPECT_NEAR(10.0 * std::log10(s.channel.noise_variance / before), 10.0 * std::log10(4.0), 1e-9);
  // A radio setting from the command line keeps the file's other radio settings.
  apply_setting(s, "radio.tx_power_dbm", "10", "--set");
  EXPECT_EQ(s.radio->tx_power_dbm, 10.0);
  EXPECT_EQ(s.radio->noise_figure_db, 5.0);
}

TEST(ChannelRadio, TheBudgetAddsTransmitPowerAndBothAntennas) {
  const Scenario s =
      parse_scenario(kNodes +
                         "radio: {tx_power_dbm: 20, antenna_gain_dbi: 2, "
                         "carrier_hz: 2.4e9}\n"
                         "channel:\n  stages: [{type: path_loss, model: free_space}]\n",
                     "t.yaml");
  // 100 m at 2.4 GHz: Friis loses 20 log10(4 pi 100 / lambda) = 80.05 dB.
  const double lambda = 299792458.0 / 2.4e9;
  const double fspl = 20.0 * std::log10(4.0 * std::numbers::pi * 100.0 / lambda);
  EXPECT_NEAR(power_dbm(*make_link_budget(s), 100.0), 20.0 + 2.0 + 2.0 - fspl, 1e-4);
}

// ---- mistakes ----------------------------------------------------------------------------

TEST(ChannelErrors, AnUnknownStageNamesItsLineAndTheKnownOnes) {
  const std::string e = parse_error_of(
      kNodes + "channel:\n  stages:\n    - {type: path_loss}\n    - {type: fadin}\n");
  EXPECT_NE(e.find("t.yaml:7: channel.stages[1].type: unknown 'fadin' (known: "), std::string::npos)
      << e;
  EXPECT_NE(e.find("path_loss"), std::string::npos) << e;
}

TEST(ChannelErrors, AnUnknownModelOrAnOutOfRangeParameterNamesItsKey) {
  std::string e =
      parse_error_of(kNodes + "channel:\n  stages:\n    - type: path_loss\n      model: hata\n");
  EXPECT_NE(e.find("t.yaml:7: channel.stages[0].model: "), std::string::npos) << e;
  EXPECT_NE(e.find("hata"), std::string::npos) << e;
  e = parse_error_of(kNodes +
                     "channel:\n  stages:\n    - type: path_loss\n      model: log_distance\n"
                     "      exponent: 20\n");
  EXPECT_NE(e.find("t.yaml:8: channel.stages[0].exponent: must be in [1, 10], got 20"),
            std::string::npos)
      << e;
  e = parse_error_of(kNodes + "channel:\n  stages:\n    - {type: path_loss, sigma: 3}\n");
  EXPECT_NE(e.find("t.yaml:6: channel.stages[0].sigma: unknown key"), std::string::npos) << e;
}

TEST(ChannelErrors, TheStagesMustBeANonEmptyListOfMappings) {
  std::string e = parse_error_of(kNodes + "channel:\n  stages: path_loss\n");
  EXPECT_NE(e.find("t.yaml:5: channel.stages: expected a list"), std::string::npos) << e;
  e = parse_error_of(kNodes + "channel:\n  stages: []\n");
  EXPECT_NE(e.find("t.yaml:5: channel.stages: needs at least one stage"), std::string::npos) << e;
  e = parse_error_of(kNodes + "channel:\n  stages:\n    - {model: free_space}\n");
  EXPECT_NE(e.find("t.yaml:6: channel.stages[0].type: required"), std::string::npos) << e;
}

TEST(ChannelErrors, ThePapersShortFormConflictsWithStages) {
  const std::string e =
      parse_error_of(kNodes + "channel:\n  stages: [{type: path_loss}]\n  path_loss_exponent: 2\n");
  EXPECT_NE(e.find("t.yaml:6: channel.path_loss_exponent: conflicts with channel.stages (line 5)"),
            std::string::npos)
      << e;
}

TEST(ChannelErrors, ARadioAndAnExplicitNoiseConflict) {
  std::string e =
      parse_error_of(kNodes + "radio: {noise_figure_db: 6}\nchannel: {noise_power_db: -100}\n");
  EXPECT_NE(e.find("t.yaml:5: channel.noise_power_db: conflicts with radio (line 4)"),
            std::string::npos)
      << e;
  // The same from the command line over a file with a radio.
  Scenario s = parse_scenario(kNodes + "radio: {noise_figure_db: 6}\n", "t.yaml");
  try {
    apply_setting(s, "channel.noise_power_db", "-100", "--noise-db");
    ADD_FAILURE() << "accepted";
  } catch (const ScenarioError& err) {
    EXPECT_NE(std::string(err.what())
                  .find("--noise-db: channel.noise_power_db: the scenario has a radio"),
              std::string::npos)
        << err.what();
  }
}

TEST(ChannelErrors, ARadioSettingOutOfRangeNamesItsLine) {
  const std::string e =
      parse_error_of(kNodes + "radio:\n  carrier_hz: 2.4e9\n  tx_power_dbm: 100\n");
  EXPECT_NE(e.find("t.yaml:6: radio.tx_power_dbm: must be in [-100, 60], got 100"),
            std::string::npos)
      << e;
}

TEST(ChannelErrors, ABrokenDataFileIsRefusedAtLoadWithItsOwnLine) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("rfsitl-broken-pattern-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  {
    std::ofstream(dir / "bad.csv") << "el\\az,0,180\n-90,0,0\n90,0,x\n";
    std::ofstream(dir / "s.yaml") << kNodes
                                  << "channel:\n  stages:\n    - {type: path_loss}\n"
                                     "    - {type: antenna, pattern: file, file: bad.csv}\n";
  }
  std::string e;
  try {
    load_scenario_file((dir / "s.yaml").string());
  } catch (const ScenarioError& err) {
    e = err.what();
  }
  std::filesystem::remove_all(dir);
  // The scenario's line and key, then the data file's own line.
  EXPECT_NE(e.find("s.yaml:7: channel.stages[1]: "), std::string::npos) << e;
  EXPECT_NE(e.find("bad.csv:3"), std::string::npos) << e;
}

TEST(ChannelErrors, ValidationChecksStagesOfAScenarioBuiltInCode) {
  Scenario s = parse_scenario(kNodes, "t.yaml");
  s.channel.stages.push_back({"nonesuch", {}});
  try {
    validate_scenario(s);
    ADD_FAILURE() << "accepted";
  } catch (const ScenarioError& err) {
    EXPECT_NE(std::string(err.what()).find("channel.stages[0].type: unknown 'nonesuch'"),
              std::string::npos)
        << err.what();
  }
}

}  // namespace
}  // namespace rfsitl::scenario
