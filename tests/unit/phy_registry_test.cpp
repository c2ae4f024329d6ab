/// The PHY registry: every PHY found by name, built from its declared defaults,
/// and refused with the name of what is wrong.
#include "rfsitl/registry/phy_registry.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

namespace rfsitl::phy {
namespace {

std::string error_of(std::string_view type, const config::Settings& s) {
  try {
    make_transceiver(type, s);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no error";
}

std::string known_list() {
  std::string out;
  for (const auto& name : known_phy_types()) out += (out.empty() ? "" : ", ") + name;
  return out;
}

TEST(PhyRegistry, ListsEveryPhySortedByName) {
  const std::vector<std::string> names = known_phy_types();
  EXPECT_TRUE(std::is_sorted(names.begin(), names.end()));
  EXPECT_EQ(std::adjacent_find(names.begin(), names.end()), names.end()) << "a name twice";
  for (const char* builtin : {"dsss", "external", "gmsk", "gmsk-liquid", "ofdm"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), builtin), names.end()) << builtin;
  }
  for (const PhyComponent& p : phy_components()) {
    EXPECT_EQ(p.info.kind, "phy");
    EXPECT_FALSE(p.info.doc.empty()) << p.info.name;
    EXPECT_EQ(find_phy(p.info.name), &p);
  }
  EXPECT_EQ(find_phy("lora"), nullptr);
}

TEST(PhyRegistry, EveryBuiltInPhyBuildsFromItsDefaultsWithTheDeclaredPayload) {
  for (const PhyComponent& p : phy_components()) {
    if (p.kind != TransceiverKind::kBuiltIn) continue;
    const config::Settings defaults = p.info.defaults();
    const auto radio = make_transceiver(p.info.name, defaults);
    ASSERT_NE(radio, nullptr) << p.info.name;
    EXPECT_EQ(radio->max_payload(), defaults.get<std::uint64_t>(kMaxPayloadSetting)) << p.info.name;
  }
}

TEST(PhyRegistry, SettingsReachTheTransceiver) {
  config::Settings s = find_phy("gmsk")->info.defaults();
  s.set("max_payload_bytes", std::uint64_t{100});
  EXPECT_EQ(make_transceiver("gmsk", s)->max_payload(), 100U);
  // k = 4 samples per symbol: the same frame takes twice the samples of k = 2.
  const auto k2 = make_transceiver("gmsk");
  s.set("samples_per_symbol", std::uint64_t{4});
  const auto k4 = make_transceiver("gmsk", s);
  EXPECT_NEAR(
      static_cast<double>(k4->frame_samples(80)) / static_cast<double>(k2->frame_samples(80)), 2.0,
      0.01);
}

TEST(PhyRegistry, RefusesUnknownTypesExternalProgramsAndBadSettingsByName) {
  EXPECT_EQ(error_of("lora", {}), "unknown phy type 'lora' (known: " + known_list() + ")");
  EXPECT_EQ(error_of("external", {}),
            "phy type 'external' is another program's transceiver; rfsitl cannot build it");
  config::Settings s = find_phy("gmsk")->info.defaults();
  s.set("samples_per_symbol", std::uint64_t{12});
  EXPECT_EQ(error_of("gmsk", s), "phy gmsk: samples_per_symbol: must be in 2..8, got 12");
  s = find_phy("gmsk")->info.defaults();
  s.set("rate_mbps", std::uint64_t{6});
  EXPECT_EQ(error_of("gmsk", s), "phy gmsk: rate_mbps: not a setting of phy gmsk");
  s = find_phy("dsss")->info.defaults();
  s.set("adaptive", true);  // barker11 has no Gold family
  EXPECT_NE(error_of("dsss", s).find("phy dsss: adaptive: needs a code with a Gold family"),
            std::string::npos);
}

}  // namespace
}  // namespace rfsitl::phy
