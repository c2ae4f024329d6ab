/// Declared settings: one declaration gives defaults, limits, the built struct,
/// JSON and the table; every refusal names the setting.
#include <gtest/gtest.h>

#include <string>

#include "rfsitl/config/fields.hpp"
#include "rfsitl/config/settings_json.hpp"
#include "rfsitl/config/settings_table.hpp"

namespace rfsitl::config {
namespace {

enum class Shape { kRound, kSquare };

struct Widget {
  unsigned count = 3;
  float gain = 0.5F;
  bool loud = false;
  std::string label = "w";
  std::string mode = "a";
  Shape shape = Shape::kSquare;
  unsigned rate = 6;
};

const Fields<Widget>& fields() {
  static const auto f =
      Fields<Widget>()
          .integer("count", &Widget::count, "items", 1, 8, "how many")
          .real("gain", &Widget::gain, "", {0, 1, true, false}, "linear gain")
          .flag("loud", &Widget::loud, "louder")
          .text("label", &Widget::label, "a name | with a bar")
          .choice("mode", &Widget::mode, {"a", "b"}, "the mode")
          .choice("shape", &Widget::shape, {{"round", Shape::kRound}, {"square", Shape::kSquare}},
                  "its shape")
          .integer_choice("rate", &Widget::rate, "Mbit/s", {6, 12}, "rate")
          .rule([](const Widget& w) {
            if (w.loud && w.count > 4) throw SettingError("loud", "needs count <= 4");
          });
  return f;
}

std::string rejection(const Settings& s) {
  try {
    fields().info("widget", "w", "doc").validate(s);
  } catch (const SettingError& e) {
    return e.key() + ": " + e.what();
  }
  return "accepted";
}

TEST(ConfigFields, DefaultsComeFromTheStructAndBuildSetsEveryField) {
  const ComponentInfo info = fields().info("widget", "w", "a test widget");
  Settings s = info.defaults();
  ASSERT_EQ(s.size(), 7U);
  EXPECT_EQ(s.get<std::uint64_t>("count"), 3U);
  EXPECT_DOUBLE_EQ(s.get<double>("gain"), 0.5);
  EXPECT_EQ(s.get<std::string>("shape"), "square");
  s.set("count", std::uint64_t{7});
  s.set("gain", 0.25);
  s.set("loud", false);
  s.set("label", std::string("x"));
  s.set("mode", std::string("b"));
  s.set("shape", std::string("round"));
  s.set("rate", std::uint64_t{12});
  const Widget w = fields().build(s);
  EXPECT_EQ(w.count, 7U);
  EXPECT_FLOAT_EQ(w.gain, 0.25F);
  EXPECT_EQ(w.label, "x");
  EXPECT_EQ(w.mode, "b");
  EXPECT_EQ(w.shape, Shape::kRound);
  EXPECT_EQ(w.rate, 12U);
  EXPECT_EQ(rejection(s), "accepted");
}

TEST(ConfigFields, EveryRefusalNamesTheSettingAndTheReason) {
  const Settings d = fields().info("widget", "w", "").defaults();
  const auto with = [&d](std::string_view key, Value v) {
    Settings s = d;
    s.set(key, std::move(v));
    return rejection(s);
  };
  EXPECT_EQ(with("count", std::uint64_t{9}), "count: must be in 1..8, got 9");
  EXPECT_EQ(with("gain", 0.0), "gain: must be in (0, 1], got 0");
  EXPECT_EQ(with("gain", std::uint64_t{1}), "gain: expected a number, got 1");
  EXPECT_EQ(with("mode", std::string("c")), "mode: unknown 'c' (known: a, b)");
  EXPECT_EQ(with("shape", std::string("oval")), "shape: unknown 'oval' (known: round, square)");
  EXPECT_EQ(with("rate", std::uint64_t{7}), "rate: unknown '7' (known: 6, 12)");
  EXPECT_EQ(with("bogus", true), "bogus: not a setting of widget w");
  Settings loud = d;
  loud.set("loud", true);
  loud.set("count", std::uint64_t{5});
  EXPECT_EQ(rejection(loud), "loud: needs count <= 4");
  Settings missing;
  EXPECT_EQ(rejection(missing), "count: missing");
}

TEST(ConfigJson, RoundTripsInDeclarationOrderAndRefusesWhatTheDeclarationsDoNot) {
  const ComponentInfo info = fields().info("widget", "w", "");
  Settings s = info.defaults();
  s.set("gain", 0.75);
  s.set("label", std::string("quote\" and \xff"));
  const nlohmann::json j = to_json(s);
  EXPECT_EQ(settings_from_json(info, j), s);
  nlohmann::json integral = j;
  integral["gain"] = 1;  // an integer is a fine real
  EXPECT_DOUBLE_EQ(settings_from_json(info, integral).get<double>("gain"), 1.0);
  const auto refusal = [&info](const nlohmann::json& bad) {
    try {
      settings_from_json(info, bad);
    } catch (const SettingError& e) {
      return e.key() + ": " + e.what();
    }
    return std::string("accepted");
  };
  nlohmann::json bad = j;
  bad["count"] = -1;
  EXPECT_EQ(refusal(bad), "count: expected an integer, got -1");
  bad = j;
  bad["extra"] = 1;
  EXPECT_EQ(refusal(bad), "extra: not a setting of widget w");
  bad = j;
  bad.erase("mode");
  EXPECT_EQ(refusal(bad), "mode: missing");
  EXPECT_EQ(refusal(nlohmann::json::array()), ": expected a JSON object, got []");
}

TEST(ConfigTable, OneRowPerSettingWithUnitDefaultAndLimits) {
  const std::string t = settings_table(fields().info("widget", "w", ""));
  EXPECT_EQ(t.substr(0, t.find('\n')), "| setting | type | unit | default | allowed | meaning |");
  EXPECT_NE(t.find("| `count` | integer | items | `3` | 1..8 | how many |\n"), std::string::npos)
      << t;
  EXPECT_NE(t.find("| `gain` | real |  | `0.5` | (0, 1] | linear gain |\n"), std::string::npos);
  EXPECT_NE(t.find("a name \\| with a bar"), std::string::npos) << "a '|' must not end the cell";
  EXPECT_EQ(settings_table(ComponentInfo{"phy", "none", "", {}, {}}), "(no settings)\n");
}

}  // namespace
}  // namespace rfsitl::config
