// A scenario given as a JSON document (what the Python module's dicts become)
// reads as the same YAML file would: same values, same rules, errors naming
// the key's path without a line.
#include <gtest/gtest.h>

#include <string>

#include "rfsitl/scenario/scenario_loader.hpp"

namespace rfsitl::scenario {
namespace {

constexpr const char* kYaml = R"(name: twins
seed: 9
time: {mode: virtual, duration_s: 2.5, tick_samples: 500}
channel: {noise_power_db: -110}
mac: {type: csma}
nodes:
  - {id: 1, position: {x: 0, y: 0, z: 10}}
  - {id: 4, position: {x: 30, y: -2.5, z: 10}, phy: {type: gmsk, bandwidth_time: 0.3}}
)";

nlohmann::json document() {
  return nlohmann::json::parse(R"({
    "name": "twins", "seed": 9,
    "time": {"mode": "virtual", "duration_s": 2.5, "tick_samples": 500},
    "channel": {"noise_power_db": -110},
    "mac": {"type": "csma"},
    "nodes": [{"id": 1, "position": {"x": 0, "y": 0, "z": 10}},
              {"id": 4, "position": {"x": 30, "y": -2.5, "z": 10},
               "phy": {"type": "gmsk", "bandwidth_time": 0.3}}]})");
}

std::string error_of(const nlohmann::json& doc) {
  try {
    scenario_from_json(doc, "dict");
  } catch (const ScenarioError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(ScenarioFromJson, ReadsAsTheSameYamlFile) {
  const Scenario a = parse_scenario(kYaml, "twins.yaml");
  const Scenario b = scenario_from_json(document(), "dict");
  EXPECT_EQ(b.name, a.name);
  EXPECT_EQ(b.seed, a.seed);
  EXPECT_EQ(b.timing.duration_s, a.timing.duration_s);
  EXPECT_EQ(b.timing.tick_samples, a.timing.tick_samples);
  EXPECT_EQ(b.channel.noise_variance, a.channel.noise_variance);
  ASSERT_EQ(b.nodes.size(), 2U);
  EXPECT_EQ(b.nodes[1].id, 4);
  EXPECT_EQ(b.phy_of(1).settings.get<double>("bandwidth_time"), 0.3);
}

TEST(ScenarioFromJson, ErrorsNameTheKeysPathWithoutALine) {
  nlohmann::json doc = document();
  doc["nodes"][1]["phy"]["bandwidth_tme"] = 0.3;
  EXPECT_NE(error_of(doc).find("dict: nodes[1].phy.bandwidth_tme:"), std::string::npos)
      << error_of(doc);
  doc = document();
  doc["time"]["duration_s"] = "2.5";  // a string, as a quoted value in a file
  EXPECT_NE(error_of(doc).find("dict: time.duration_s: expected"), std::string::npos)
      << error_of(doc);
  doc = document();
  doc["time"]["tick_samples"] = 2.5;
  EXPECT_NE(error_of(doc).find("dict: time.tick_samples:"), std::string::npos) << error_of(doc);
  EXPECT_EQ(error_of(nlohmann::json::array()),
            "dict: a scenario is a mapping of sections, got array");
}

}  // namespace
}  // namespace rfsitl::scenario
