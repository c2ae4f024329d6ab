// /metrics: label values and HELP text escaped per the text exposition format,
// and every per-node number of the summary JSON exported.
#include <gtest/gtest.h>

#include <atomic>
#include <map>
#include <sstream>

#include "monitor_test_scenario.hpp"
#include "rfsitl/monitor/stats_report.hpp"

namespace rfsitl::monitor {
namespace {

using test::NullSink;

/// Two nodes; node 1 sends node 2 three frames.
scenario::Scenario metrics_scenario(std::string name) {
  scenario::Scenario s = test::two_nodes(0.05);
  s.name = std::move(name);
  s.traffic.push_back(scenario::TrafficItem{0.01, 1, 2, 80, 3, 0.01});
  return s;
}

/// series ("name{labels}") -> value, for every sample line; fails the test on a
/// line that is neither a comment nor a well-formed sample.
std::map<std::string, double> samples(const std::string& text) {
  std::map<std::string, double> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("# HELP ", 0) == 0 || line.rfind("# TYPE ", 0) == 0) continue;
    const auto brace = line.find('{');
    const auto space = line.rfind(' ');
    if (space == std::string::npos || (brace != std::string::npos && line[space - 1] != '}')) {
      ADD_FAILURE() << "not a sample: " << line;
      continue;
    }
    std::size_t used = 0;
    out[line.substr(0, space)] = std::stod(line.substr(space + 1), &used);
    EXPECT_EQ(used, line.size() - space - 1) << line;
  }
  return out;
}

TEST(StatsReportPrometheus, LabelValuesEscapeBackslashQuoteAndNewline) {
  EXPECT_EQ(prometheus_label_value(R"(swarm "alpha" \ test)"), R"(swarm \"alpha\" \\ test)");
  EXPECT_EQ(prometheus_label_value("a\nb"), R"(a\nb)");
  EXPECT_EQ(prometheus_label_value("plain-name_1"), "plain-name_1");
  EXPECT_EQ(prometheus_help_text("a \"b\" \\ c\nd"), R"(a "b" \\ c\nd)");

  const auto s = metrics_scenario("swarm \"alpha\" \\ test\nsecond line");
  NullSink sink;
  auto e = engine::make_engine(s, sink);
  const std::string text = prometheus_text(s, *e);
  EXPECT_NE(text.find(R"(rfsitl_info{scenario="swarm \"alpha\" \\ test\nsecond line",nodes="2"} 1)"
                      "\n"),
            std::string::npos)
      << text;
  const auto values = samples(text);  // the whole scrape still parses
  EXPECT_EQ(
      values.count(R"(rfsitl_info{scenario="swarm \"alpha\" \\ test\nsecond line",nodes="2"})"),
      1U);
}

TEST(StatsReportPrometheus, ExportsEveryPerNodeNumberOfTheSummaryJson) {
  const auto s = metrics_scenario("metrics");
  NullSink sink;
  auto e = engine::make_engine(s, sink);
  const std::atomic<bool> stop{false};
  e->run(stop);
  const auto values = samples(prometheus_text(s, *e));
  const auto stats = stats_json(s, *e);
  // The metric of each key of stats_json's nodes[i]; a key missing here fails.
  const std::map<std::string, std::string> metric = {
      {"handed_in", "rfsitl_frames_handed_in_total"},
      {"queue_dropped", "rfsitl_frames_queue_dropped_total"},
      {"transmitted", "rfsitl_frames_transmitted_total"},
      {"delivered", "rfsitl_frames_delivered_total"},
      {"pending", "rfsitl_frames_pending"},
      {"received", "rfsitl_frames_received_total"},
      {"rx_crc_failures", "rfsitl_rx_crc_failures_total"},
      {"framing_errors", "rfsitl_framing_errors_total"},
      {"ip_refused", "rfsitl_ip_frames_refused_total"},
      {"to_agent_dropped", "rfsitl_frames_to_agent_dropped_total"},
      {"queue_depth", "rfsitl_tx_queue_depth"},
      {"external_stalls", "rfsitl_external_stalls_total"},
      {"external_overflows", "rfsitl_external_overflows_total"},
      {"mac_retries", "rfsitl_mac_retries_total"},
      {"mac_ack_timeouts", "rfsitl_mac_ack_timeouts_total"},
      {"mac_retry_drops", "rfsitl_mac_retry_drops_total"},
      {"mac_duplicates", "rfsitl_mac_duplicates_total"},
      {"mac_control_sent", "rfsitl_mac_control_frames_total"},
      {"mac_backoff_slots", "rfsitl_mac_backoff_slots_total"},
      {"mac_busy_ticks", "rfsitl_mac_busy_ticks_total"},
      {"mac_sensed_ticks", "rfsitl_mac_sensed_ticks_total"},
  };
  for (const auto& n : stats.at("nodes")) {
    const std::string node = "node=\"" + std::to_string(n.at("id").get<unsigned>()) + "\"";
    for (const auto& [key, value] : n.items()) {
      if (key == "id") continue;
      if (key == "phy") {
        EXPECT_EQ(
            values.count("rfsitl_node_info{" + node + ",phy=\"" + value.get<std::string>() + "\"}"),
            1U);
      } else if (key == "position" || key == "velocity" || key == "attitude") {
        const std::map<std::string, std::string> family = {
            {"position", "rfsitl_node_position{" + node + ",coord=\""},
            {"velocity", "rfsitl_node_velocity_mps{" + node + ",axis=\""},
            {"attitude", "rfsitl_node_attitude_rad{" + node + ",angle=\""}};
        ASSERT_TRUE(value.is_object()) << key;  // the scenario places every node
        for (const auto& [member, v] : value.items()) {
          const std::string series = family.at(key) + member + "\"}";
          ASSERT_EQ(values.count(series), 1U) << series;
          EXPECT_EQ(values.at(series), v.get<double>()) << series;
        }
      } else if (key == "source") {
        const std::string series = "rfsitl_node_source_info{" + node + ",type=\"" +
                                   value.at("type").get<std::string>() + "\"}";
        EXPECT_EQ(values.count(series), 1U) << series;
      } else if (key == "lost") {
        for (const auto& [reason, count] : value.items()) {
          const std::string series =
              "rfsitl_frames_lost_total{" + node + ",reason=\"" + reason + "\"}";
          ASSERT_EQ(values.count(series), 1U) << series;
          EXPECT_EQ(values.at(series), count.get<double>()) << series;
        }
      } else {
        ASSERT_EQ(metric.count(key), 1U) << "stats_json key '" << key << "' has no metric";
        const std::string series = metric.at(key) + "{" + node + "}";
        ASSERT_EQ(values.count(series), 1U) << series;
        EXPECT_EQ(values.at(series), value.get<double>()) << series;
      }
    }
  }
  // And the run's numbers.
  for (const auto& [key, name] : std::map<std::string, std::string>{
           {"virtual_s", "rfsitl_virtual_seconds"},
           {"wall_s", "rfsitl_wall_seconds"},
           {"lag_s", "rfsitl_realtime_lag_seconds"},
           {"max_lag_s", "rfsitl_realtime_lag_max_seconds"},
           {"late_ticks", "rfsitl_late_ticks_total"},
           {"late_decodes", "rfsitl_late_decodes_total"},
           {"receiver_ticks_run", "rfsitl_receiver_ticks_total{state=\"run\"}"},
           {"receiver_ticks_skipped", "rfsitl_receiver_ticks_total{state=\"skipped\"}"},
           {"receiver_ticks_blanked", "rfsitl_receiver_ticks_total{state=\"blanked\"}"},
           {"mobility_wall_s", "rfsitl_mobility_seconds_total"}}) {
    ASSERT_EQ(values.count(name), 1U) << name;
    if (key == "wall_s") continue;  // the clock moves between the two reads
    EXPECT_EQ(values.at(name), stats.at(key).get<double>()) << name;
  }
  EXPECT_EQ(values.at("rfsitl_frames_delivered_total{node=\"1\"}"), 3.0);
}

}  // namespace
}  // namespace rfsitl::monitor
