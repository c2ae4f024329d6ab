// Control frames on a net port: recognised only with src = dst = 0, and the
// status reply reads back exactly what was written.
#include "rfsitl/io/agent_control.hpp"

#include <gtest/gtest.h>

namespace rfsitl::io {
namespace {

TEST(AgentControl, OnlySrcAndDstZeroIsControl) {
  EXPECT_TRUE(is_control_frame(make_control_frame(kStatusRequest)));
  EXPECT_FALSE(is_control_frame(NetFrame{0, 2, {}}));
  EXPECT_FALSE(is_control_frame(NetFrame{1, 0, {}}));
  EXPECT_EQ(control_text(make_control_frame(kTakeRequest)), kTakeRequest);
}

TEST(AgentControl, StatusReplyRoundTrips) {
  for (const PortStatus s : {PortStatus{2, true, 2048}, PortStatus{250, false, 65535}}) {
    const auto back = parse_status_reply(format_status_reply(s));
    ASSERT_TRUE(back.has_value()) << format_status_reply(s);
    EXPECT_EQ(back->node, s.node);
    EXPECT_EQ(back->agent_connected, s.agent_connected);
    EXPECT_EQ(back->max_payload, s.max_payload);
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
