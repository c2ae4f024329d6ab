/// A process the emulator refuses (wrong role, unknown node) keeps trying to
/// join: the emulator's log must stay readable while every refusal is still
/// counted, the process must back off and must say why it is refused.
#include <gtest/gtest.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include "external_test_support.hpp"
#include "log_capture.hpp"
#include "rfsitl/common/retry_backoff.hpp"
#include "rfsitl/external/client/external_client.hpp"
#include "rfsitl/external/external_hub.hpp"
#include "rfsitl/external/phy_config_json.hpp"
#include "rfsitl/external/repeat_limiter.hpp"
#include "rfsitl/external/transceiver_node.hpp"
#include "rfsitl/scenario/scenario.hpp"

namespace rfsitl::external {
namespace {

using ::rfsitl::testing::LogCapture;
using std::chrono::milliseconds;
using std::chrono::seconds;
using testing::JoiningThread;
using testing::SocketPath;
using Action = RepeatLimiter::Action;

constexpr NodeId kSamplesNode = 3;
constexpr NodeId kTransceiverNode = 4;

// --- RepeatLimiter: what to print of a repeating event -------------------------

TEST(ExternalRepeatLimiter, FirstEventsOfAKeyAreLoggedInFullThenOneSummaryPerPeriod) {
  RepeatLimiter limiter;  // 3 in full, then one summary per 10 s
  const auto t0 = RepeatLimiter::Clock::time_point{} + seconds(100);
  EXPECT_EQ(limiter.record("a", t0).action, Action::kLog);
  EXPECT_EQ(limiter.record("a", t0 + milliseconds(25)).action, Action::kLog);
  EXPECT_EQ(limiter.record("a", t0 + milliseconds(50)).action, Action::kLogLast);
  // 40 a second, as a reconnect loop without backoff: quiet until 10 s after the last line.
  std::uint64_t quiet = 0;
  auto t = t0 + milliseconds(50);
  for (int i = 0; i < 398; ++i) {
    t += milliseconds(25);
    const auto v = limiter.record("a", t);
    ASSERT_EQ(v.action, Action::kQuiet) << "event " << i << " at +" << (t - t0).count() << " ns";
    ++quiet;
  }
  ASSERT_LT(t, t0 + milliseconds(50) + seconds(10));
  const auto summary = limiter.record("a", t0 + milliseconds(50) + seconds(10));
  EXPECT_EQ(summary.action, Action::kSummarize);
  EXPECT_EQ(summary.repeats, quiet + 1) << "the summary stands for every event since the last line";
  EXPECT_DOUBLE_EQ(summary.seconds, 10.0);
  EXPECT_FALSE(summary.other_keys);
  // The next period starts at the summary.
  EXPECT_EQ(limiter.record("a", t0 + seconds(15)).action, Action::kQuiet);
  EXPECT_EQ(limiter.record("a", t0 + seconds(16)).action, Action::kQuiet);
  const auto pending = limiter.take_pending();
  ASSERT_EQ(pending.size(), 1U);
  EXPECT_EQ(pending[0].key, "a");
  EXPECT_EQ(pending[0].repeats, 2U);
  EXPECT_TRUE(limiter.take_pending().empty()) << "pending events are reported once";
}

TEST(ExternalRepeatLimiter, KeysAreLimitedIndependently) {
  RepeatLimiter limiter(RepeatLimiter::Settings{2, seconds(5), 64});
  const auto t0 = RepeatLimiter::Clock::time_point{} + seconds(1);
  EXPECT_EQ(limiter.record("node 3", t0).action, Action::kLog);
  EXPECT_EQ(limiter.record("node 3", t0).action, Action::kLogLast);
  EXPECT_EQ(limiter.record("node 3", t0).action, Action::kQuiet);
  // Another reason (another node) is news: it is logged in full.
  EXPECT_EQ(limiter.record("node 4", t0).action, Action::kLog);
  EXPECT_EQ(limiter.record("node 3", t0 + seconds(1)).action, Action::kQuiet);
  const auto pending = limiter.take_pending();
  ASSERT_EQ(pending.size(), 1U);
  EXPECT_EQ(pending[0].key, "node 3");
  EXPECT_EQ(pending[0].repeats, 2U);
}

TEST(ExternalRepeatLimiter, KeysBeyondTheLimitShareOneBucket) {
  RepeatLimiter limiter(RepeatLimiter::Settings{1, seconds(5), 2});
  const auto t0 = RepeatLimiter::Clock::time_point{} + seconds(1);
  EXPECT_FALSE(limiter.record("a", t0).other_keys);
  EXPECT_FALSE(limiter.record("b", t0).other_keys);
  const auto c = limiter.record("c", t0);
  EXPECT_TRUE(c.other_keys);
  EXPECT_EQ(c.action, Action::kLogLast);  // the shared bucket's first (and, with full = 1, last)
  const auto d = limiter.record("d", t0);
  EXPECT_TRUE(d.other_keys);
  EXPECT_EQ(d.action, Action::kQuiet);
  const auto pending = limiter.take_pending();
  ASSERT_EQ(pending.size(), 1U);
  EXPECT_EQ(pending[0].key, "");
  EXPECT_EQ(pending[0].repeats, 1U);
}

// --- RetryBackoff ---------------------------------------------------------------

TEST(ExternalRetryBackoff, DoublesFromTheFirstDelayUpToTheCapAndResets) {
  RetryBackoff b(milliseconds(50), milliseconds(2000));
  std::vector<std::int64_t> got;
  for (int i = 0; i < 9; ++i) got.push_back(b.next().count());
  EXPECT_EQ(got, (std::vector<std::int64_t>{50, 100, 200, 400, 800, 1600, 2000, 2000, 2000}));
  b.reset();
  EXPECT_EQ(b.next().count(), 50);
}

TEST(ExternalRetryBackoff, DegenerateSettingsStillGivePositiveBoundedDelays) {
  RetryBackoff zero(milliseconds(0), milliseconds(0));
  EXPECT_EQ(zero.next().count(), 1);
  EXPECT_EQ(zero.next().count(), 1);
  RetryBackoff inverted(milliseconds(300), milliseconds(100));
  EXPECT_EQ(inverted.next().count(), 300);
  EXPECT_EQ(inverted.next().count(), 300);
}

// --- the hub's log and the node process, end to end ------------------------------

HubSettings hub_settings(const std::string& path) {
  HubSettings s;
  s.socket_path = path;
  s.tick_samples = 250;
  return s;
}

/// Node 3 runs the samples role, node 4 the transceiver role (GMSK).
std::vector<ExternalNodeSpec> two_nodes() {
  scenario::PhyChoice phy;
  return {ExternalNodeSpec{0, kSamplesNode, Role::kSamples, ""},
          ExternalNodeSpec{1, kTransceiverNode, Role::kTransceiver,
                           phy_to_json(phy.type, phy.settings)}};
}

/// Tries to join as node `id` in `role`; returns the refusal reason ("" if admitted).
std::string refusal_of(const std::string& path, NodeId id, const std::string& role) {
  ExternalClient client({path, id, role, "unit-test", 3000});
  try {
    client.connect();
  } catch (const ConnectRejected& e) {
    return e.reason();
  }
  return "";
}

/// The sum of N over lines "refused N more connection(s)" (std::regex would
/// trip GCC 12's -Wmaybe-uninitialized).
std::uint64_t summarized(const std::vector<std::string>& lines) {
  const std::string prefix = "refused ";
  std::uint64_t sum = 0;
  for (const auto& l : lines) {
    const auto at = l.find(prefix);
    if (at == std::string::npos) continue;
    std::size_t used = 0;
    const std::uint64_t n = std::stoull(l.substr(at + prefix.size()), &used);
    if (l.compare(at + prefix.size() + used, 16, " more connection") == 0) sum += n;
  }
  return sum;
}

TEST(ExternalRefusals, HubLogsARepeatedRefusalAFewTimesInFullYetCountsEveryOne) {
  constexpr int kAttempts = 30;
  LogCapture log;
  SocketPath path;
  auto hub = make_external_hub(hub_settings(path.str()), two_nodes());
  for (int i = 0; i < kAttempts; ++i) {
    ASSERT_NE(refusal_of(path.str(), kSamplesNode, "transceiver"), "") << "attempt " << i;
  }
  EXPECT_EQ(hub->rejected(), std::uint64_t{kAttempts});
  const auto full = log.lines_with("refused a connection: node 3 expects role 'samples'");
  ASSERT_EQ(full.size(), RepeatLimiter::Settings{}.full)
      << "a reconnect loop must not log every refusal";
  EXPECT_NE(full.back().find("once per 10 s"), std::string::npos) << full.back();

  // A new reason is news even while the first one is quiet.
  ASSERT_NE(refusal_of(path.str(), 9, "samples"), "");
  EXPECT_EQ(log.lines_with("refused a connection: node 9 is not an external node").size(), 1U);
  EXPECT_EQ(hub->rejected(), std::uint64_t{kAttempts + 1});

  // Whatever no summary line reported yet is reported when the hub closes:
  // every refusal appears in the log, in full or in a count.
  hub.reset();
  const auto counted = log.lines_with("more connection");
  EXPECT_GE(counted.size(), 1U);
  EXPECT_EQ(full.size() + summarized(counted), std::uint64_t{kAttempts});
}

/// Runs run_transceiver_node for a node the hub refuses; returns how it ended.
struct RefusedRun {
  std::string error;      // what it threw ("" if it returned)
  bool rejected = false;  // it threw ConnectRejected
  int rc = -1;
  std::string stderr_text;
  std::chrono::steady_clock::duration took{};
};

RefusedRun run_refused(const TransceiverNodeOptions& o, const std::atomic<bool>& stop) {
  RefusedRun r;
  ::testing::internal::CaptureStderr();
  const auto t0 = std::chrono::steady_clock::now();
  try {
    r.rc = run_transceiver_node(o, stop);
  } catch (const ConnectRejected& e) {
    r.error = e.what();
    r.rejected = true;
  } catch (const std::exception& e) {
    r.error = e.what();
  }
  r.took = std::chrono::steady_clock::now() - t0;
  r.stderr_text = ::testing::internal::GetCapturedStderr();
  return r;
}

std::size_t occurrences(const std::string& text, const std::string& part) {
  std::size_t n = 0;
  for (auto at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
  return n;
}

TEST(ExternalRefusals, RefusedNodeProcessBacksOffAndPrintsTheReasonOnce) {
  SocketPath path;
  const auto hub = make_external_hub(hub_settings(path.str()), two_nodes());
  TransceiverNodeOptions o;
  o.socket_path = path.str();
  o.node_id = kSamplesNode;  // a samples-role node: `rfsitl node` is the wrong program
  o.connect_timeout_s = 1.6;
  const std::atomic<bool> stop{false};
  const RefusedRun r = run_refused(o, stop);

  EXPECT_TRUE(r.rejected) << "gave up with: " << r.error;
  EXPECT_NE(r.error.find("expects role 'samples'"), std::string::npos) << r.error;
  EXPECT_GE(r.took, milliseconds(1500));
  // 50 ms doubling: attempts at about 0, 0.05, 0.15, 0.35, 0.75, 1.55 s and
  // one at the deadline. A fixed 50 ms pause would make about 30.
  EXPECT_GE(hub->rejected(), 4U);
  EXPECT_LE(hub->rejected(), 9U) << "the process did not back off";
  // The reason reaches the user at once, and once, not with every retry.
  EXPECT_EQ(occurrences(r.stderr_text, "node 3 expects role 'samples'"), 1U) << r.stderr_text;
  EXPECT_NE(r.stderr_text.find("rfsitl node 3: the emulator at " + path.str() + " refused"),
            std::string::npos)
      << r.stderr_text;
}

TEST(ExternalRefusals, RefusedNodeProcessStopsRetryingAtOnceWhenAskedTo) {
  SocketPath path;
  const auto hub = make_external_hub(hub_settings(path.str()), two_nodes());
  TransceiverNodeOptions o;
  o.socket_path = path.str();
  o.node_id = kSamplesNode;
  o.connect_timeout_s = 60.0;
  o.retry_first_s = 5.0;  // a long pause, which SIGTERM (the stop flag) must cut short
  std::atomic<bool> stop{false};
  JoiningThread stopper([&] {
    testing::wait_until([&] { return hub->rejected() > 0; }, seconds(10));
    stop.store(true);
  });
  const RefusedRun r = run_refused(o, stop);
  EXPECT_EQ(r.error, "");
  EXPECT_EQ(r.rc, 0);
  EXPECT_LT(r.took, seconds(3)) << "the retry pause ignored the stop flag";
  EXPECT_EQ(hub->rejected(), 1U);
}

}  // namespace
}  // namespace rfsitl::external
