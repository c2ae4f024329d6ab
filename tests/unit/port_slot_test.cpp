// Who holds a node's port: probes never displace the agent, a connection that
// speaks (or asks) takes over, and a waiting connection inherits a closed port.
#include "rfsitl/io/port_slot.hpp"

#include <gtest/gtest.h>

#include <memory>

namespace rfsitl::io {
namespace {

/// A connection that only records whether it was closed.
class FakeConnection final : public SlotMember {
 public:
  void close() override { open_ = false; }
  bool open() const override { return open_; }

 private:
  bool open_ = true;
};

std::shared_ptr<FakeConnection> connection() {
  return std::make_shared<FakeConnection>();
}

TEST(PortSlot, FirstConnectionIsTheAgentAtOnce) {
  PortSlot slot("node 1 net port 15773");
  const auto a = connection();
  slot.admit(a);
  EXPECT_TRUE(slot.is_agent(a.get()));
}

TEST(PortSlot, ProbeThatClosesWithoutSpeakingLeavesTheAgentAlone) {
  PortSlot slot("p");
  const auto agent = connection();
  slot.admit(agent);
  for (int i = 0; i < 20; ++i) {  // more than kMaxCandidates probes
    const auto probe = connection();
    slot.admit(probe);
    probe->close();
    slot.closed(probe.get());
  }
  EXPECT_TRUE(slot.is_agent(agent.get()));
  EXPECT_TRUE(agent->open());
}

TEST(PortSlot, ConnectionThatSpeaksReplacesTheAgentAndClosesIt) {
  PortSlot slot("p");
  const auto old_agent = connection();
  const auto next = connection();
  slot.admit(old_agent);
  slot.admit(next);
  EXPECT_TRUE(slot.is_agent(old_agent.get())) << "a silent newcomer waits";
  EXPECT_TRUE(slot.held_by_other(next.get()));
  slot.claim(next.get(), "sent a frame");
  EXPECT_TRUE(slot.is_agent(next.get()));
  EXPECT_FALSE(old_agent->open());
  EXPECT_FALSE(slot.held_by_other(next.get()));
  slot.closed(old_agent.get());  // its read handler reports the close: no effect
  EXPECT_TRUE(slot.is_agent(next.get()));
}

TEST(PortSlot, NewestWaitingConnectionInheritsTheClosedAgentsPort) {
  PortSlot slot("p");
  const auto agent = connection();
  const auto older = connection();
  const auto newer = connection();
  slot.admit(agent);
  slot.admit(older);
  slot.admit(newer);
  agent->close();
  slot.closed(agent.get());
  EXPECT_TRUE(slot.is_agent(newer.get()));
  EXPECT_TRUE(older->open()) << "still waiting; it may speak and take over";
  slot.claim(older.get(), "sent a frame");
  EXPECT_TRUE(slot.is_agent(older.get()));
  EXPECT_FALSE(newer->open());
}

TEST(PortSlot, ClosedWaitingConnectionsAreSkippedWhenTheAgentLeaves) {
  PortSlot slot("p");
  const auto agent = connection();
  const auto gone = connection();
  slot.admit(agent);
  slot.admit(gone);
  gone->close();  // closed, but its handler has not reported yet
  agent->close();
  slot.closed(agent.get());
  EXPECT_EQ(slot.agent(), nullptr);
}

TEST(PortSlot, CandidatesBeyondTheLimitCloseTheOldest) {
  PortSlot slot("p");
  const auto agent = connection();
  slot.admit(agent);
  std::vector<std::shared_ptr<FakeConnection>> waiting;
  for (std::size_t i = 0; i <= PortSlot::kMaxCandidates; ++i) {
    waiting.push_back(connection());
    slot.admit(waiting.back());
  }
  EXPECT_FALSE(waiting.front()->open());
  EXPECT_TRUE(waiting.back()->open());
  slot.claim(waiting.front().get(), "sent a frame");  // too late: it was closed
  EXPECT_TRUE(slot.is_agent(agent.get()));
}

TEST(PortSlot, ConnectionAfterTheAgentLeftIsTheAgentAtOnce) {
  PortSlot slot("p");
  const auto first = connection();
  slot.admit(first);
  first->close();  // the agent's peer went away; its handler has not run yet
  const auto second = connection();
  slot.admit(second);
  EXPECT_TRUE(slot.is_agent(second.get()));
  slot.closed(first.get());
  EXPECT_TRUE(slot.is_agent(second.get()));
}

TEST(PortSlot, CloseAllClosesAgentAndCandidates) {
  PortSlot slot("p");
  const auto agent = connection();
  const auto waiting = connection();
  slot.admit(agent);
  slot.admit(waiting);
  slot.close_all();
  EXPECT_FALSE(agent->open());
  EXPECT_FALSE(waiting->open());
}

}  // namespace
}  // namespace rfsitl::io
