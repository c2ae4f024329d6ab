// The composition root (session/session.hpp): a run assembled in named steps
// in virtual time without a single port, as the benchmarks and the Python
// module use it; its counters and summary; steps out of order refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <mutex>
#include <string>
#include <vector>

#include "rfsitl/scenario/default_formation.hpp"
#include "rfsitl/session/session.hpp"

namespace rfsitl::session {
namespace {

/// Counts the frames the engine delivers, per node (engine thread).
struct CountingSink final : engine::FrameSink {
  std::mutex mutex;
  std::vector<std::size_t> frames = std::vector<std::size_t>(3);
  void deliver(std::size_t node, NetFrame&&) override {
    std::lock_guard lock(mutex);
    ++frames.at(node);
  }
};

/// Three nodes of the default formation (every link decodes), node 1 sending
/// 5 frames to node 2 and node 2 one to node 3 between them, in 0.5 s of
/// virtual time.
scenario::Scenario trio() {
  scenario::Scenario s;
  s.name = "session-trio";
  s.timing.mode = scenario::TimeMode::kVirtual;
  s.timing.duration_s = 0.5;
  s.engine.stats_interval_s = 0.0;
  s.nodes = scenario::default_formation(3, s.channel);
  s.traffic.push_back({0.05, 1, 2, 40, 5, 0.05});
  s.traffic.push_back({0.225, 2, 3, 40, 1, 0.0});
  return s;
}

SessionOptions portless(CountingSink* sink) {
  SessionOptions o;
  o.scenario = trio();
  o.ports = false;
  o.frames = sink;
  // As a flag would give it: through the scenario file's rules.
  o.settings.push_back({"engine.threads", "2", "--threads"});
  return o;
}

TEST(Session, VirtualRunWithoutPortsDeliversTheScenariosTraffic) {
  CountingSink sink;
  Session run(portless(&sink));
  EXPECT_EQ(run.next_step(), Step::kScenario);
  run.assemble();
  EXPECT_EQ(run.next_step(), Step::kServe);
  EXPECT_EQ(run.scenario().engine.threads, 2U);
  EXPECT_EQ(run.sources(), nullptr);
  EXPECT_EQ(run.external(), nullptr);
  EXPECT_EQ(run.dashboard(), nullptr);
  EXPECT_FALSE(run.ranks().distributed());

  const ServeResult served = run.serve();
  ASSERT_EQ(served.end, ServeEnd::kCompleted) << served.error;
  EXPECT_EQ(run.next_step(), Step::kFinish);
  const SessionSummary& r = run.finish();
  EXPECT_EQ(run.next_step(), Step::kDone);

  EXPECT_NEAR(r.status.virtual_s, 0.5, 0.01);
  ASSERT_EQ(r.node_ids, (std::vector<NodeId>{1, 2, 3}));
  ASSERT_EQ(r.counters.size(), 3U);
  EXPECT_EQ(r.counters[0].handed_in, 5U);
  EXPECT_EQ(r.counters[0].delivered, 5U);
  EXPECT_EQ(r.counters[0].pending(), 0U);
  EXPECT_EQ(r.counters[1].handed_in, 1U);
  EXPECT_EQ(r.counters[1].delivered, 1U);
  EXPECT_EQ(r.counters[1].received, 5U);
  EXPECT_EQ(r.counters[2].received, 1U);
  // Without ports the decoded frames went to the options' sink.
  EXPECT_EQ(sink.frames, (std::vector<std::size_t>{0, 5, 1}));
  // The summary document holds what --summary-json writes.
  EXPECT_TRUE(r.external.is_null());
  EXPECT_TRUE(r.pcap.is_null());
  ASSERT_TRUE(r.document.contains("nodes"));
  ASSERT_EQ(r.document["nodes"].size(), 3U);
  EXPECT_EQ(r.document["mac"]["type"], "none");
  EXPECT_FALSE(r.document.contains("distributed"));
}

TEST(Session, ObserversStepWritesThePcapTrace) {
  CountingSink sink;
  SessionOptions o = portless(&sink);
  o.pcap.path = ::testing::TempDir() + "session_test.pcapng";
  Session run(std::move(o));
  run.assemble();
  ASSERT_EQ(run.serve().end, ServeEnd::kCompleted);
  const SessionSummary& r = run.finish();
  ASSERT_FALSE(r.pcap.is_null());
  // Each of the 6 frames is at least handed in, transmitted and delivered.
  EXPECT_GE(r.pcap["events_written"].get<std::uint64_t>(), 18U);
  EXPECT_EQ(r.document["pcap"], r.pcap);
  std::remove(run.pcap_path().c_str());
}

TEST(Session, StepsOutOfOrderAreRefused) {
  Session run(portless(nullptr));
  try {
    run.make_engine();
    FAIL() << "make_engine before build_scenario was accepted";
  } catch (const SessionStepError& e) {
    EXPECT_EQ(std::string(e.what()),
              "session: step 'engine' called out of order: the step due is 'scenario'");
  }
  EXPECT_THROW(run.engine(), SessionStepError);  // nothing built yet
  run.build_scenario();
  EXPECT_THROW(run.build_scenario(), SessionStepError);  // twice
  EXPECT_THROW(run.serve(), SessionStepError);
  EXPECT_THROW(run.finish(), SessionStepError);
  EXPECT_EQ(run.next_step(), Step::kPlacement);
  // The refusals changed nothing: the run still assembles and runs.
  run.place_ranks();
  run.make_ports();
  run.make_ip();
  run.make_external();
  run.make_engine();
  run.add_observers();
  EXPECT_EQ(run.serve().end, ServeEnd::kCompleted);
  EXPECT_EQ(run.finish().counters[0].delivered, 5U);
}

TEST(Session, AFailedStepNamesItsCauseAndRefusesTheRest) {
  SessionOptions o = portless(nullptr);
  o.settings.push_back({"time.duration_s", "-1", "--duration"});
  Session run(std::move(o));
  try {
    run.build_scenario();
    FAIL() << "a negative duration was accepted";
  } catch (const SessionError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("--duration: ", 0), 0U) << e.what();
  }
  try {
    run.place_ranks();
    FAIL() << "a step after a failed one was accepted";
  } catch (const SessionStepError& e) {
    EXPECT_NE(std::string(e.what()).find("step 'scenario' failed"), std::string::npos) << e.what();
  }
}

TEST(Session, BothTicksAreRefusedNamingTheirOrigins) {
  SessionOptions o = portless(nullptr);
  o.settings.push_back({"time.tick_samples", "400", "--tick"});
  o.settings.push_back({"time.tick_us", "100", "--tick-us"});
  Session run(std::move(o));
  try {
    run.build_scenario();
    FAIL() << "both ticks were accepted";
  } catch (const SessionError& e) {
    EXPECT_STREQ(e.what(), "--tick-us: give the tick as --tick or as --tick-us, not both");
  }
}

TEST(Session, HooksCancelOrStopTheRun) {
  {
    Session run(portless(nullptr));
    run.assemble();
    ServeHooks hooks;
    hooks.ready = [] { return false; };
    EXPECT_EQ(run.serve(hooks).end, ServeEnd::kCancelled);
    EXPECT_EQ(run.engine().status().virtual_s, 0.0);
    EXPECT_THROW(run.finish(), SessionStepError);
  }
  {
    SessionOptions o = portless(nullptr);
    o.settings.push_back({"time.duration_s", "1000", "--duration"});
    Session run(std::move(o));
    run.assemble();
    ServeHooks hooks;
    hooks.poll = [] { return false; };  // stop at once
    EXPECT_EQ(run.serve(hooks).end, ServeEnd::kCompleted);
    const SessionSummary& r = run.finish();
    EXPECT_LT(r.status.virtual_s, 1000.0);
  }
}

}  // namespace
}  // namespace rfsitl::session

namespace rfsitl::session {
namespace {

// A run in parts (open, advance, advance, finish) ends with the counters of
// one serve() of the same scenario, whatever the parts' lengths; frames
// handed in between two parts go out from the next tick.
TEST(Session, ARunInPartsEndsAsOneServe) {
  CountingSink whole_sink;
  Session whole(portless(&whole_sink));
  whole.assemble();
  ASSERT_EQ(whole.serve().end, ServeEnd::kCompleted);
  const SessionSummary& once = whole.finish();

  CountingSink parts_sink;
  Session parts(portless(&parts_sink));
  parts.assemble();
  EXPECT_THROW(parts.advance(0.1), SessionStepError);  // not opened yet
  parts.open();
  const double tick = static_cast<double>(parts.scenario().timing.tick_samples) /
                      parts.scenario().timing.sample_rate_hz;
  EXPECT_NEAR(parts.advance(0.0), 0.0, 1e-12);  // nothing to do
  EXPECT_NEAR(parts.advance(0.1003), 0.1003 + tick - std::fmod(0.1003, tick), 1e-9);
  EXPECT_NEAR(parts.advance(0.2), 0.2, 1e-9);
  EXPECT_NEAR(parts.advance(7.0), 0.5, 1e-9);  // the scenario's duration ends it
  EXPECT_NEAR(parts.advance(8.0), 0.5, 1e-9);  // and stays ended
  const SessionSummary& r = parts.finish();
  EXPECT_EQ(parts.next_step(), Step::kDone);
  ASSERT_EQ(r.counters.size(), once.counters.size());
  for (std::size_t i = 0; i < r.counters.size(); ++i) {
    EXPECT_EQ(r.counters[i].handed_in, once.counters[i].handed_in) << i;
    EXPECT_EQ(r.counters[i].delivered, once.counters[i].delivered) << i;
    EXPECT_EQ(r.counters[i].received, once.counters[i].received) << i;
    EXPECT_EQ(r.counters[i].lost, once.counters[i].lost) << i;
  }
  EXPECT_EQ(parts_sink.frames, whole_sink.frames);
  EXPECT_EQ(r.document["nodes"], once.document["nodes"]);
}

TEST(Session, FramesHandedInBetweenPartsAreSent) {
  CountingSink sink;
  SessionOptions o = portless(&sink);
  o.scenario->traffic.clear();
  Session run(std::move(o));
  run.assemble();
  run.open();
  run.advance(0.1);
  ASSERT_TRUE(run.engine().submit(2, NetFrame{3, 1, std::vector<std::uint8_t>(30, 7)}));
  run.advance(0.2);
  EXPECT_EQ(run.engine().counters(2).delivered.load(), 1U);
  EXPECT_EQ(sink.frames, (std::vector<std::size_t>{1, 0, 0}));
  // A run in parts cannot also be served.
  EXPECT_THROW(run.serve(), SessionStepError);
  run.finish();
}

}  // namespace
}  // namespace rfsitl::session
