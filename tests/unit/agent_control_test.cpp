// Control frames on a net port: recognised only with src = dst = 0, and the
// status reply reads back exactly what was written.
#include "rfsitl/io/agent_control.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace rfsitl::io {
namespace {

TEST(AgentControl, OnlySrcAndDstZeroIsControl) {
  EXPECT_TRUE(is_control_frame(make_control_frame(kStatusRequest)));
  EXPECT_FALSE(is_control_frame(NetFrame{0, 2, {}}));
  EXPECT_FALSE(is_control_frame(NetFrame{1, 0, {}}));
  EXPECT_EQ(control_text(make_control_frame(kTakeRequest)), kTakeRequest);
}

TEST(AgentControl, StatusReplyRoundTrips) {
  for (const PortStatus& s : {PortStatus{2, true, 2048, {}}, PortStatus{250, false, 65535, {}}}) {
    const auto back = parse_status_reply(format_status_reply(s));
    ASSERT_TRUE(back.has_value()) << format_status_reply(s);
    EXPECT_EQ(back->node, s.node);
    EXPECT_EQ(back->agent_connected, s.agent_connected);
    EXPECT_EQ(back->max_payload, s.max_payload);
  }
}

TEST(AgentControl, StatusReplyCarriesTheRunsNodesAsRanges) {
  const std::vector<unsigned> ids = {1, 2, 3, 4, 9, 11, 12, 254};
  const std::string text = format_status_reply(PortStatus{3, false, 80, ids});
  EXPECT_NE(text.find(" nodes=1-4,9,11-12,254"), std::string::npos) << text;
  const auto back = parse_status_reply(text);
  ASSERT_TRUE(back.has_value()) << text;
  EXPECT_EQ(back->nodes, ids);
  EXPECT_EQ(id_list_text(back->nodes), "1, 2, 3, 4, 9, 11, 12, 254");
  // An emulator that does not say (older ones) still parses, with no list.
  const auto old = parse_status_reply("rfsitl status node=2 agent=0 max_payload=10");
  ASSERT_TRUE(old.has_value());
  EXPECT_TRUE(old->nodes.empty());
}

TEST(AgentControl, MalformedNodeListsAreRefused) {
  for (const char* list : {"", "0", "1-", "-3", "3-1", "2,1", "1,1", "1-3,3", "1,,2", "1,", "1-255",
                           "x", "1-2-3", "99999999999999999999"}) {
    const std::string text =
        std::string("rfsitl status node=2 agent=0 max_payload=10 nodes=") + list;
    EXPECT_FALSE(parse_status_reply(text).has_value()) << text;
  }
}

TEST(AgentControl, MalformedStatusRepliesAreRefused) {
  for (const char* text : {"", "rfsitl taken", "rfsitl status node=2 agent=1",
                           "rfsitl status node=2 agent=2 "
                           "max_payload=10",
                           "rfsitl status node=x agent=1 max_payload=10",
                           "rfsitl status node=300 agent=0 max_payload=10",
                           "rfsitl status node=2 agent=0 "
                           "max_payload=-1"}) {
    EXPECT_FALSE(parse_status_reply(text).has_value()) << text;
  }
}

}  // namespace
}  // namespace rfsitl::io
