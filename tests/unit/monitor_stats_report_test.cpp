#include "rfsitl/monitor/stats_report.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "monitor_test_scenario.hpp"
#include "rfsitl/common/build_version.hpp"

namespace rfsitl::monitor {
namespace {

using test::NullSink;

scenario::Scenario three_nodes() {
  scenario::Scenario s;
  s.name = "stats-test";
  const double xs[] = {0, 10, 40};
  for (NodeId id = 1; id <= 3; ++id) {
    scenario::NodeConfig n;
    n.id = id;
    n.initial_position = LocalPosition{xs[id - 1], 0, 10};
    s.nodes.push_back(n);
  }
  scenario::NodeConfig lost;  // no position: no links
  lost.id = 9;
  s.nodes.push_back(lost);
  s.timing.mode = scenario::TimeMode::kVirtual;
  s.timing.duration_s = 0.1;
  s.traffic.push_back(scenario::TrafficItem{0.01, 1, 2, 80, 5, 0.01});
  s.traffic.push_back(scenario::TrafficItem{0.015, 3, 9, 40, 2, 0.01});
  return s;
}

TEST(StatsReport, PrometheusTextDeclaresEveryFamilyAndMatchesTheCounters) {
  const auto s = three_nodes();
  NullSink sink;
  auto e = engine::make_engine(s, sink);
  const std::atomic<bool> stop{false};
  e->run(stop);
  const std::string text = prometheus_text(s, *e);
  std::istringstream in(text);
  std::set<std::string> declared;
  std::map<std::string, double> values;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("# TYPE ", 0) == 0) declared.insert(line.substr(7, line.find(' ', 7) - 7));
    if (line.empty() || line[0] == '#') continue;
    // name{labels} value, or name value (std::regex trips GCC 12's -Wmaybe-uninitialized).
    const auto space = line.rfind(' ');
    ASSERT_NE(space, std::string::npos) << line;
    const std::string series = line.substr(0, space);
    const std::string name = series.substr(0, series.find('{'));
    ASSERT_FALSE(name.empty()) << line;
    EXPECT_TRUE(name.find_first_not_of("abcdefghijklmnopqrstuvwxyz_") == std::string::npos) << line;
    EXPECT_TRUE(declared.count(name)) << "no TYPE before " << line;
    std::size_t used = 0;
    values[series] = std::stod(line.substr(space + 1), &used);
    EXPECT_EQ(used, line.size() - space - 1) << line;
  }
  for (std::size_t i = 0; i < e->num_nodes(); ++i) {
    const auto c = e->counters(i).snapshot();
    const std::string node = "{node=\"" + std::to_string(e->node_ids()[i]) + "\"}";
    EXPECT_EQ(values["rfsitl_frames_delivered_total" + node], static_cast<double>(c.delivered));
    EXPECT_EQ(values["rfsitl_frames_transmitted_total" + node], static_cast<double>(c.transmitted));
  }
  EXPECT_EQ(values["rfsitl_frames_delivered_total{node=\"1\"}"], 5.0);
  EXPECT_EQ(values["rfsitl_frames_lost_total{node=\"3\",reason=\"below_sensitivity\"}"], 2.0);
  EXPECT_NEAR(values["rfsitl_virtual_seconds"], 0.1, 1e-9);
  // The one version, as `rfsitl --version` and the summary JSON say it.
  EXPECT_EQ(values["rfsitl_build_info{version=\"" + std::string(build_version()) + "\"}"], 1.0);
}

TEST(StatsReport, SnapshotLinksAreSnrInDbWithNullForNoLinkAndTheDiagonal) {
  const auto s = three_nodes();
  NullSink sink;
  auto e = engine::make_engine(s, sink);
  LiveView view(e->node_ids());
  e->add_observer(view);
  const std::atomic<bool> stop{false};
  e->run(stop);
  const auto j = snapshot_json(s, *e, view, {5.0, 5.0, 5.0, 5.0}, false);
  const auto& snr = j.at("links").at("snr_db");
  ASSERT_EQ(snr.size(), 16U);
  for (std::size_t k = 0; k < 4; ++k) EXPECT_TRUE(snr[k * 4 + k].is_null());
  for (std::size_t k = 0; k < 4; ++k) EXPECT_TRUE(snr[3 * 4 + k].is_null());  // node 9: unknown
  // Paper model, exponent 3, 10 m: |c|^2 = 11^-6; noise 1e-12.
  const double expected = 10.0 * std::log10(std::pow(11.0, -6.0) / 1e-12);
  EXPECT_NEAR(snr[0 * 4 + 1].get<double>(), expected, 0.06);
  EXPECT_EQ(j.at("links").at("received")[0 * 4 + 1], 5);  // node 2 received node 1's five
  EXPECT_TRUE(j.at("nodes")[3].at("position").is_null());
  EXPECT_NEAR(j.at("nodes")[1].at("position").at("x").get<double>(), 10.0, 0.01);
  EXPECT_EQ(j.at("control"), false);
}

}  // namespace
}  // namespace rfsitl::monitor
