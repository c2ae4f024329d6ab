// Typed framing: with IP on, a frame's kind travels on the air as one byte
// before its payload and comes out of the receiving node's sink as it went in;
// with IP off the frame on the air is exactly the paper's.
#include <gtest/gtest.h>

#include "engine_run.hpp"
#include "spy_observer.hpp"

namespace rfsitl::testing {
namespace {

scenario::Scenario two_nodes(bool ip) {
  scenario::Scenario s =
      make_scenario({{1, LocalPosition{0, 0, 10}}, {2, LocalPosition{5, 0, 10}}}, 0.05);
  s.ip.enabled = ip;
  return s;
}

std::vector<std::uint8_t> bytes(std::size_t n, std::uint8_t first) {
  std::vector<std::uint8_t> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = static_cast<std::uint8_t>(first + i);
  return v;
}

TEST(EngineTypedFraming, EachKindArrivesAsItWasHandedIn) {
  SpyObserver spy;
  RunSetup setup;
  setup.observers = {&spy};
  setup.before = [](engine::Engine& e) {
    ASSERT_TRUE(e.submit(0, NetFrame{1, 2, bytes(80, 1), FrameKind::kEthernet}));
  };
  const auto r = run_engine(two_nodes(true), setup);
  ASSERT_EQ(r.deliveries.size(), 1U);
  EXPECT_EQ(r.deliveries[0].node, 1U);
  EXPECT_EQ(r.deliveries[0].frame, (NetFrame{1, 2, bytes(80, 1), FrameKind::kEthernet}));
  // One byte more on the air: GMSK at 2 samples per bit, 8 bits a byte.
  const auto tx = spy.events(SpyObserver::Kind::kTransmitted);
  ASSERT_EQ(tx.size(), 1U);
  EXPECT_EQ(tx[0].length_samples, 1704U + 16U);
  EXPECT_EQ(r.engine->max_payload(0), 2047U);
}

TEST(EngineTypedFraming, AgentFramesKeepTheirKindWhenIpIsOn) {
  RunSetup setup;
  setup.before = [](engine::Engine& e) { ASSERT_TRUE(e.submit(1, NetFrame{2, 1, bytes(20, 9)})); };
  const auto r = run_engine(two_nodes(true), setup);
  ASSERT_EQ(r.deliveries.size(), 1U);
  EXPECT_EQ(r.deliveries[0].frame, (NetFrame{2, 1, bytes(20, 9), FrameKind::kAgent}));
}

TEST(EngineTypedFraming, WithoutIpTheFrameOnTheAirIsThePapers) {
  SpyObserver spy;
  RunSetup setup;
  setup.observers = {&spy};
  setup.before = [](engine::Engine& e) { ASSERT_TRUE(e.submit(0, NetFrame{1, 2, bytes(80, 1)})); };
  const auto r = run_engine(two_nodes(false), setup);
  ASSERT_EQ(r.deliveries.size(), 1U);
  EXPECT_EQ(r.deliveries[0].frame, (NetFrame{1, 2, bytes(80, 1)}));
  const auto tx = spy.events(SpyObserver::Kind::kTransmitted);
  ASSERT_EQ(tx.size(), 1U);
  EXPECT_EQ(tx[0].length_samples, 1704U);
  EXPECT_EQ(r.engine->max_payload(0), 2048U);
}

}  // namespace
}  // namespace rfsitl::testing
