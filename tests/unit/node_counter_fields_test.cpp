// engine::kNodeCounterFields is the one list of per-node counters: the summary
// JSON, /metrics, the end-of-run table and the dashboard's hello all follow it,
// in its order, under the names users depend on.
#include "rfsitl/engine/node_counter_fields.hpp"

#include <gtest/gtest.h>
#include <algorithm>

#include <map>
#include <set>
#include <sstream>
#include <vector>

#include "dashboard_test_support.hpp"
#include "rfsitl/monitor/node_counter_report.hpp"
#include "rfsitl/monitor/stats_report.hpp"

namespace rfsitl::monitor {
namespace {

using engine::kLossReasons;
using engine::kNodeCounterFields;
using engine::NodeCounterField;

/// A different number in every field (pending = 1000 - 2 - 4 - 35).
engine::NodeCountersSnapshot distinct_values() {
  engine::NodeCountersSnapshot c;
  c.handed_in = 1000;
  c.queue_dropped = 2;
  c.transmitted = 3;
  c.delivered = 4;
  c.lost = {5, 6, 7, 8, 9, 10};
  c.received = 10;
  c.rx_crc_failures = 11;
  c.framing_errors = 12;
  c.to_agent_dropped = 13;
  c.ip_refused = 18;
  c.queue_depth = 16;
  c.external_stalls = 17;
  c.external_overflows = 27;
  c.mac = {19, 20, 21, 22, 23, 24, 25, 26};
  return c;
}

/// The published names (JSON key -> metric) and distinct_values()' numbers,
/// written out here so that a renamed key or metric fails the test.
struct Expected {
  const char* metric;
  std::uint64_t value;
};
const std::map<std::string, Expected>& expected_scalars() {
  static const std::map<std::string, Expected> m = {
      {"handed_in", {"rfsitl_frames_handed_in_total", 1000}},
      {"queue_dropped", {"rfsitl_frames_queue_dropped_total", 2}},
      {"transmitted", {"rfsitl_frames_transmitted_total", 3}},
      {"delivered", {"rfsitl_frames_delivered_total", 4}},
      {"pending", {"rfsitl_frames_pending", 949}},
      {"received", {"rfsitl_frames_received_total", 10}},
      {"rx_crc_failures", {"rfsitl_rx_crc_failures_total", 11}},
      {"framing_errors", {"rfsitl_framing_errors_total", 12}},
      {"ip_refused", {"rfsitl_ip_frames_refused_total", 18}},
      {"to_agent_dropped", {"rfsitl_frames_to_agent_dropped_total", 13}},
      {"queue_depth", {"rfsitl_tx_queue_depth", 16}},
      {"external_stalls", {"rfsitl_external_stalls_total", 17}},
      {"external_overflows", {"rfsitl_external_overflows_total", 27}},
      {"mac_retries", {"rfsitl_mac_retries_total", 19}},
      {"mac_ack_timeouts", {"rfsitl_mac_ack_timeouts_total", 20}},
      {"mac_retry_drops", {"rfsitl_mac_retry_drops_total", 21}},
      {"mac_duplicates", {"rfsitl_mac_duplicates_total", 22}},
      {"mac_control_sent", {"rfsitl_mac_control_frames_total", 23}},
      {"mac_backoff_slots", {"rfsitl_mac_backoff_slots_total", 24}},
      {"mac_busy_ticks", {"rfsitl_mac_busy_ticks_total", 25}},
      {"mac_sensed_ticks", {"rfsitl_mac_sensed_ticks_total", 26}},
  };
  return m;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

TEST(NodeCounterFields, KeysAndMetricsAreUniqueAndEveryFieldIsDescribed) {
  std::set<std::string_view> keys, metrics, columns;
  for (const auto& f : kNodeCounterFields) {
    EXPECT_TRUE(keys.insert(f.key).second) << f.key;
    EXPECT_TRUE(metrics.insert(f.metric).second) << f.metric;
    EXPECT_TRUE(columns.insert(f.column).second) << f.column;
    EXPECT_FALSE(f.help.empty()) << f.key;
    EXPECT_EQ(f.help.find('\n'), std::string_view::npos) << f.key;  // one line
    EXPECT_FALSE(f.label.empty()) << f.key;
    EXPECT_EQ(f.kind == engine::CounterKind::kCounter, f.metric.ends_with("_total")) << f.metric;
  }
  for (std::size_t r = 0; r < kLossReasons.size(); ++r) {
    EXPECT_EQ(engine::loss_reason_name(static_cast<engine::LossReason>(r)), kLossReasons[r].key);
  }
}

TEST(NodeCounterFields, DistinctValuesLandUnderTheirJsonKeys) {
  nlohmann::json want = nlohmann::json::object();
  for (const auto& [key, e] : expected_scalars()) want[key] = e.value;
  want["lost"] = {{"below_sensitivity", 5}, {"collision", 6},           {"half_duplex", 7},
                  {"decode_failure", 8},    {"unknown_destination", 9}, {"retry_limit", 10}};
  EXPECT_EQ(node_counters_json(distinct_values()), want);
}

TEST(NodeCounterFields, MetricsFollowTheListInOrderWithHelpTypeAndValues) {
  const std::vector<NodeId> ids = {7, 9};
  const std::vector<engine::NodeCountersSnapshot> c = {distinct_values(), {}};
  std::ostringstream o;
  write_node_counter_metrics(o, ids, c);
  const auto lines = lines_of(o.str());
  std::size_t at = 0;
  for (const auto& f : kNodeCounterFields) {
    const std::string name(f.metric);
    ASSERT_LT(at + 1, lines.size()) << name;
    EXPECT_EQ(lines[at++], "# HELP " + name + " " + std::string(f.help));
    EXPECT_EQ(lines[at++], "# TYPE " + name + " " + std::string(counter_kind_name(f.kind)));
    for (const NodeId id : ids) {
      const std::string node = "{node=\"" + std::to_string(id) + "\"";
      const bool seven = id == 7;
      if (f.by_reason == nullptr) {
        const auto& e = expected_scalars().at(std::string(f.key));
        EXPECT_EQ(e.metric, name);
        ASSERT_LT(at, lines.size());
        EXPECT_EQ(lines[at++], name + node + "} " + std::to_string(seven ? e.value : 0));
        continue;
      }
      for (std::size_t r = 0; r < kLossReasons.size(); ++r) {
        ASSERT_LT(at, lines.size());
        EXPECT_EQ(lines[at++], name + node + ",reason=\"" + std::string(kLossReasons[r].key) +
                                   "\"} " + std::to_string(seven ? 5 + r : 0));
      }
    }
  }
  EXPECT_EQ(at, lines.size()) << "lines after the last declared family";
}

TEST(NodeCounterFields, EveryStoredCounterRoundTripsThroughAssignAndSnapshot) {
  // snapshot() and assign() are driven by the table: a counter the table
  // forgot would come back 0 here (and fail its static_assert before that).
  engine::NodeCountersSnapshot want = distinct_values();
  want.queue_depth = 0;  // the engine's, not a stored counter: snapshot() leaves it 0
  engine::NodeCounters c;
  c.assign(want);
  const engine::NodeCountersSnapshot got = c.snapshot();
  for (const NodeCounterField& f : kNodeCounterFields) {
    if (f.by_reason != nullptr) {
      EXPECT_EQ(got.*f.by_reason, want.*f.by_reason) << f.key;
    } else {
      EXPECT_EQ(f.read(got), f.read(want)) << f.key;
    }
  }
  EXPECT_EQ(c.mac.sensed_ticks.load(), 26U);  // the nested MAC counters too
  EXPECT_EQ(c.lost[5].load(), 10U);
}

TEST(NodeCounterFields, SummaryTableHasAColumnPerFieldInOrder) {
  const std::vector<NodeId> ids = {7};
  const std::vector<engine::NodeCountersSnapshot> c = {distinct_values()};
  const auto lines = lines_of(node_counters_table(ids, c));
  ASSERT_EQ(lines.size(), 2U);
  std::istringstream head(lines[0]), row(lines[1]);
  std::vector<std::string> titles;
  std::vector<std::uint64_t> values;
  for (std::string t; head >> t;) titles.push_back(t);
  for (std::uint64_t v; row >> v;) values.push_back(v);
  // The columns the table has always had, then the ones added since.
  const std::vector<std::string> want_titles = {
      "node",          "in",        "tx",         "delivered", "lost:sen", "lost:col", "lost:hd",
      "lost:dec",      "lost:dst",  "lost:retry", "q-drop",    "pending",  "received", "crc-fail",
      "to-agent-drop", "frame-err", "ip-ref",     "q-depth",   "stalls",   "ovfl",     "retry",
      "ack-to",        "rl-drop",   "dup",        "ctl",       "backoff",  "busy",     "sensed"};
  EXPECT_EQ(titles, want_titles);
  const std::vector<std::uint64_t> want_values = {7,  1000, 3,  4,  5,  6,  7,  8,  9,  10,
                                                  2,  949,  10, 11, 13, 12, 18, 16, 17, 27,
                                                  19, 20,   21, 22, 23, 24, 25, 26};
  EXPECT_EQ(values, want_values);
  // Right-aligned under its title.
  EXPECT_EQ(lines[0].size(), lines[1].size());
}

TEST(NodeCounterFields, TheTableLeavesOutMacColumnsThatAreZeroEverywhere) {
  const std::vector<NodeId> ids = {7, 8};
  engine::NodeCountersSnapshot one_retry;
  one_retry.mac.retries = 1;
  const auto titles_of = [&](const std::vector<engine::NodeCountersSnapshot>& c) {
    std::istringstream head(lines_of(node_counters_table(ids, c))[0]);
    std::vector<std::string> titles;
    for (std::string t; head >> t;) titles.push_back(t);
    return titles;
  };
  const auto without = titles_of({{}, {}});
  EXPECT_EQ(std::count(without.begin(), without.end(), "retry"), 0);
  EXPECT_EQ(without.back(), "stalls");
  const auto with = titles_of({{}, one_retry});
  EXPECT_EQ(with.back(), "retry");  // the one MAC counter that is not zero
  EXPECT_EQ(with.size(), without.size() + 1);
}

TEST(NodeCounterFields, TheLegendExplainsEveryColumnTheTableShows) {
  const std::vector<NodeId> ids = {7, 8};
  engine::NodeCountersSnapshot one_retry;
  one_retry.mac.retries = 1;
  const std::vector<engine::NodeCountersSnapshot> c = {{}, one_retry};
  std::istringstream head(lines_of(node_counters_table(ids, c))[0]);
  std::vector<std::string> titles;
  for (std::string t; head >> t;) titles.push_back(t);
  const auto legend = lines_of(node_counters_legend(c));
  ASSERT_FALSE(legend.empty());
  EXPECT_EQ(legend[0], "columns:");
  // Each line: its title (by-reason fields once, as "lost:R"), then the help.
  std::vector<std::string> explained;
  for (std::size_t i = 1; i < legend.size(); ++i) {
    std::istringstream line(legend[i]);
    std::string title;
    line >> title;
    explained.push_back(title);
    EXPECT_GT(legend[i].size(), title.size() + 10) << legend[i];  // some words of help
  }
  for (std::size_t i = 1; i < titles.size(); ++i) {  // titles[0] is "node"
    const std::string& t = titles[i];
    const std::string field = t.substr(0, t.find(':'));
    const std::string named = t.find(':') == std::string::npos ? t : field + ":R";
    EXPECT_EQ(std::count(explained.begin(), explained.end(), named), 1) << t;
  }
  // The reasons' short names are spelled out.
  const std::string all = node_counters_legend(c);
  for (const auto& r : kLossReasons) {
    EXPECT_NE(all.find(std::string(r.column) + " " + std::string(r.label)), std::string::npos)
        << r.column;
  }
  // Hidden columns are not explained: the MAC's other counters are all zero.
  EXPECT_EQ(std::count(explained.begin(), explained.end(), "ack-to"), 0);
}

TEST(NodeCounterFields, StatsJsonAndMetricsOfARunCarryEveryField) {
  const auto s = test::two_nodes();
  test::NullSink sink;
  auto e = engine::make_engine(s, sink);
  e->counters(1).framing_errors.store(3);
  const auto stats = stats_json(s, *e);
  const std::string metrics = prometheus_text(s, *e);
  for (const auto& n : stats.at("nodes")) {
    // Besides the counters: identity, and where the node is and what places it.
    std::set<std::string> keys = {"id", "phy", "position", "source"};
    for (const auto& f : kNodeCounterFields) keys.insert(std::string(f.key));
    std::set<std::string> have;
    for (const auto& [key, value] : n.items()) have.insert(key);
    EXPECT_EQ(have, keys);
  }
  EXPECT_EQ(stats.at("nodes")[1].at("framing_errors"), 3);
  for (const auto& f : kNodeCounterFields) {
    EXPECT_NE(metrics.find("# HELP " + std::string(f.metric) + " " + std::string(f.help) + "\n"),
              std::string::npos)
        << f.metric;
  }
  EXPECT_NE(metrics.find("rfsitl_framing_errors_total{node=\"2\"} 3\n"), std::string::npos);
}

TEST(NodeCounterFields, DashboardHelloListsTheFieldsInOrder) {
  test::LiveDashboard d;
  test::Viewer v;
  const auto ec = v.connect(d.port());
  ASSERT_FALSE(ec) << ec.message();
  const auto hello = nlohmann::json::parse(v.read());
  ASSERT_EQ(hello.at("type"), "hello");
  const auto& fields = hello.at("counters");
  EXPECT_EQ(fields, node_counter_fields_json());
  ASSERT_EQ(fields.size(), kNodeCounterFields.size());
  for (std::size_t i = 0; i < fields.size(); ++i) {
    const auto& f = kNodeCounterFields[i];
    EXPECT_EQ(fields[i].at("key"), f.key);
    EXPECT_EQ(fields[i].at("label"), f.label);
    EXPECT_EQ(fields[i].at("help"), f.help);
    EXPECT_EQ(fields[i].at("kind"), counter_kind_name(f.kind));
    EXPECT_EQ(fields[i].contains("reasons"), f.by_reason != nullptr);
  }
  const auto& lost = fields[3];
  ASSERT_EQ(lost.at("key"), "lost");
  ASSERT_EQ(lost.at("reasons").size(), kLossReasons.size());
  for (std::size_t r = 0; r < kLossReasons.size(); ++r) {
    EXPECT_EQ(lost.at("reasons")[r].at("key"), kLossReasons[r].key);
    EXPECT_EQ(lost.at("reasons")[r].at("label"), kLossReasons[r].label);
  }
}

}  // namespace
}  // namespace rfsitl::monitor
