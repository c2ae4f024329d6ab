/// List settings: a list of records declared once (a channel stage's taps
/// here, as a stand-in for any owner) gives the default, the built structs,
/// refusals that name the item and field, JSON both ways and the tables.
#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <vector>

#include "rfsitl/config/fields.hpp"
#include "rfsitl/config/settings_json.hpp"
#include "rfsitl/config/settings_table.hpp"

namespace rfsitl::config {
namespace {

struct Tap {
  double delay_ns = 0;
  double gain_db = 0;
  double phase_rad = 0.5;            // may be left out: keeps 0.5
  std::optional<double> doppler_hz;  // may be left out: stays empty
};

struct Stage {
  std::vector<Tap> taps = {{0, 0, 0, std::nullopt}, {50, -3, 0.5, 10}};
  bool enabled = true;
};

const Fields<Stage>& fields() {
  static const auto taps =
      RecordFields<Tap>()
          .required("delay_ns", &Tap::delay_ns, "ns", {0, 1e6}, "delay after the first path")
          .required("gain_db", &Tap::gain_db, "dB", {-200, 0}, "power | relative to the first")
          .real("phase_rad", &Tap::phase_rad, "rad", {-7, 7}, "carrier phase")
          .real("doppler_hz", &Tap::doppler_hz, "Hz", {-1e5, 1e5, true, true}, "shift");
  static const auto f = Fields<Stage>()
                            .records("taps", &Stage::taps, taps, 1, 4, "the paths")
                            .flag("enabled", &Stage::enabled, "on")
                            .rule([](const Stage& s) {
                              for (std::size_t i = 1; i < s.taps.size(); ++i) {
                                if (s.taps[i].delay_ns <= s.taps[i - 1].delay_ns) {
                                  throw SettingError("taps[" + std::to_string(i) + "].delay_ns",
                                                     "must be later than the previous tap's");
                                }
                              }
                            });
  return f;
}

ComponentInfo info() {
  return fields().info("channel stage", "multipath", "taps");
}

std::string rejection(const Settings& s) {
  try {
    info().validate(s);
  } catch (const SettingError& e) {
    return e.key() + ": " + e.what();
  }
  return "accepted";
}

Settings with_taps(Records taps) {
  Settings s = info().defaults();
  s.set("taps", std::move(taps));
  return s;
}

TEST(ConfigRecords, TheDefaultIsTheStructsListAndBuildFillsEachItem) {
  const Settings d = info().defaults();
  EXPECT_EQ(d.get<Records>("taps"),
            (Records{{{"delay_ns", 0}, {"gain_db", 0}, {"phase_rad", 0}},
                     {{"delay_ns", 50}, {"gain_db", -3}, {"phase_rad", 0.5}, {"doppler_hz", 10}}}));
  EXPECT_EQ(rejection(d), "accepted");

  const Stage s =
      fields().build(with_taps({{{"delay_ns", 0}, {"gain_db", -1}},
                                {{"delay_ns", 20}, {"gain_db", -9}, {"doppler_hz", 4}}}));
  ASSERT_EQ(s.taps.size(), 2U);
  EXPECT_DOUBLE_EQ(s.taps[0].gain_db, -1);
  EXPECT_DOUBLE_EQ(s.taps[0].phase_rad, 0.5);  // left out: the member's initializer
  EXPECT_FALSE(s.taps[0].doppler_hz.has_value());
  EXPECT_DOUBLE_EQ(s.taps[1].delay_ns, 20);
  EXPECT_EQ(s.taps[1].doppler_hz, 4.0);
}

TEST(ConfigRecords, RefusalsNameTheItemAndTheField) {
  EXPECT_EQ(rejection(with_taps({})), "taps: must hold at least 1 item, got 0");
  const Record tap{{"delay_ns", 0}, {"gain_db", 0}};
  EXPECT_EQ(rejection(with_taps({tap, tap, tap, tap, tap})),
            "taps: must hold at most 4 items, got 5");
  EXPECT_EQ(rejection(with_taps({tap, {{"delay_ns", 5}, {"gain_db", 3}}})),
            "taps[1].gain_db: must be in [-200, 0], got 3");
  EXPECT_EQ(rejection(with_taps({tap, {{"delay_ns", 5}}})), "taps[1].gain_db: required");
  EXPECT_EQ(rejection(with_taps({tap, {{"delay_ns", 5}, {"gain_db", 0}, {"doppler_hz", 1e5}}})),
            "taps[1].doppler_hz: must be in (-1e+05, 1e+05), got 1e+05");
  EXPECT_EQ(rejection(with_taps({{{"delay_ns", 0}, {"gain_db", 0}, {"gian_db", 1}}})),
            "taps[0].gian_db: unknown key (allowed: delay_ns, gain_db, phase_rad, doppler_hz)");
  // The owner's rule sees the built items and names one.
  EXPECT_EQ(rejection(with_taps({tap, tap})),
            "taps[1].delay_ns: must be later than the previous tap's");
  Settings scalar = info().defaults();
  scalar.set("taps", 3.0);
  EXPECT_EQ(rejection(scalar), "taps: expected a list, got 3");
}

TEST(ConfigRecords, JsonRoundTripsAndRefusalsNameTheItem) {
  const Settings s = with_taps({{{"delay_ns", 0}, {"gain_db", -1}, {"phase_rad", 0.25}},
                                {{"delay_ns", 12.5}, {"gain_db", -7}}});
  const nlohmann::json j = to_json(s);
  EXPECT_EQ(
      j.at("taps").dump(),
      R"([{"delay_ns":0.0,"gain_db":-1.0,"phase_rad":0.25},{"delay_ns":12.5,"gain_db":-7.0}])");
  EXPECT_EQ(settings_from_json(info(), j), s);
  // Keys in another order and integers read back as the same records.
  nlohmann::json reordered = j;
  reordered["taps"][1] = nlohmann::json{{"gain_db", -7}, {"delay_ns", 12.5}};
  EXPECT_EQ(settings_from_json(info(), reordered), s);

  const auto refusal = [](const nlohmann::json& bad) {
    try {
      settings_from_json(info(), bad);
    } catch (const SettingError& e) {
      return e.key() + ": " + e.what();
    }
    return std::string("accepted");
  };
  const auto with = [&j](const nlohmann::json& taps) {
    nlohmann::json bad = j;
    bad["taps"] = taps;
    return bad;
  };
  const auto tap = [](nlohmann::json delay, double gain) {
    return nlohmann::json{{"delay_ns", std::move(delay)}, {"gain_db", gain}};
  };
  EXPECT_EQ(refusal(with(5)), "taps: expected a list, got 5");
  EXPECT_EQ(refusal(with(nlohmann::json::array({tap(0, 0), 7}))),
            "taps[1]: expected an object, got 7");
  EXPECT_EQ(refusal(with(nlohmann::json::array({tap("0", 0)}))),
            "taps[0].delay_ns: expected a number, got \"0\"");
  nlohmann::json extra = tap(0, 0);
  extra["x"] = 1;
  EXPECT_EQ(refusal(with(nlohmann::json::array({extra}))),
            "taps[0].x: unknown key (allowed: delay_ns, gain_db, phase_rad, doppler_hz)");
  EXPECT_EQ(refusal(with(nlohmann::json::array({tap(0, 0), tap(-1, 0)}))),
            "taps[1].delay_ns: must be in [0, 1e+06], got -1");
  EXPECT_EQ(refusal(with(nlohmann::json::array())), "taps: must hold at least 1 item, got 0");
}

TEST(ConfigRecords, TheTableListsTheItemsFields) {
  EXPECT_EQ(to_text(Value(Records{})), "[]");
  EXPECT_EQ(to_text(Value(Records{{{"t", 0}, {"x", 1.5}}, {{"t", 10}}})),
            "[{t: 0, x: 1.5}, {t: 10}]");
  const std::string t = settings_table(info());
  EXPECT_NE(t.find("| `taps` | list |  | `[{delay_ns: 0, gain_db: 0, phase_rad: 0}, {delay_ns: 50, "
                   "gain_db: -3, phase_rad: 0.5, doppler_hz: 10}]` | 1..4 items | the paths |\n"),
            std::string::npos)
      << t;
  // The items' table follows the settings' table.
  EXPECT_NE(t.find("| `enabled` | bool |  | `true` |  | on |\n\nEach item of `taps`:\n\n"
                   "| field | unit | default | allowed | meaning |\n|---|---|---|---|---|\n"
                   "| `delay_ns` | ns | required | [0, 1e+06] | delay after the first path |\n"
                   "| `gain_db` | dB | required | [-200, 0] | power \\| relative to the first |\n"
                   "| `phase_rad` | rad | `0.5` | [-7, 7] | carrier phase |\n"
                   "| `doppler_hz` | Hz |  | (-1e+05, 1e+05) | shift |\n"),
            std::string::npos)
      << t;
}

}  // namespace
}  // namespace rfsitl::config
