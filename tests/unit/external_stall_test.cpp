/// A process that stops answering stalls the whole engine: the engine waits
/// for its reply for external.reply_timeout_s before dropping it. Each stall
/// is counted in its node's counters (so the summary JSON, /api/stats,
/// /metrics and the dashboard show it) and logged with the node.
#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <string>

#include "engine_run.hpp"
#include "external_test_support.hpp"
#include "log_capture.hpp"
#include "rfsitl/external/client/external_client.hpp"
#include "rfsitl/external/external_runtime.hpp"
#include "rfsitl/monitor/node_counter_report.hpp"
#include "rfsitl/scenario/scenario_loader.hpp"

namespace rfsitl::external {
namespace {

using Clock = std::chrono::steady_clock;
using ::rfsitl::testing::LogCapture;
using ::rfsitl::testing::run_engine;
using testing::SocketPath;

TEST(ExternalStall, AHungProcessIsCountedAsAStallOfItsNodeAndLoggedWithIt) {
  SocketPath path;
  constexpr int kReplyTimeoutMs = 200;
  // Node 3's program joins, then never answers a tick; node 1 is built in.
  const scenario::Scenario s = scenario::parse_scenario(
      "nodes:\n"
      "  - {id: 1, position: {x: 0, y: 0, z: 10}}\n"
      "  - {id: 3, position: {x: 10, y: 0, z: 10}, phy: {type: external}}\n"
      "time: {mode: virtual, tick_samples: 250, duration_s: 0.005}\n"
      "external: {socket: " +
          path.str() + ", reply_timeout_s: " + std::to_string(kReplyTimeoutMs / 1e3) + "}\n",
      "t.yaml");
  LogCapture log;
  const auto runtime = ExternalRuntime::create(s);
  ASSERT_NE(runtime, nullptr);
  ExternalClient hung({path.str(), 3, "samples", "hung-program", 5000});
  hung.connect();
  ASSERT_TRUE(testing::wait_until([&] { return runtime->hub().never_joined().empty(); }));

  const auto t0 = Clock::now();
  const auto r = run_engine(s, {.factory = runtime->transceiver_factory()});
  const auto took = Clock::now() - t0;

  EXPECT_GE(took, std::chrono::milliseconds(kReplyTimeoutMs)) << "the engine did not wait";
  EXPECT_EQ(r.counters[1].external_stalls, 1U) << "dropped after its first stall";
  EXPECT_EQ(r.counters[0].external_stalls, 0U);
  EXPECT_EQ(monitor::node_counters_json(r.counters[1]).at("external_stalls"), 1);
  EXPECT_EQ(runtime->summary().at("nodes")[0].at("timeouts"), 1);
  const auto stalls = log.lines_with("stalled");
  ASSERT_EQ(stalls.size(), 1U);
  EXPECT_EQ(stalls[0].rfind("node 3: external transceiver 'hung-program' dropped: no reply within "
                            "200 ms (tick ",
                            0),
            0U)
      << stalls[0];
  EXPECT_NE(stalls[0].find("the engine stalled that long waiting for it (stall 1 of this node)"),
            std::string::npos)
      << stalls[0];
}

}  // namespace
}  // namespace rfsitl::external
