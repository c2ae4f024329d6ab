// The scenario's traffic, made lazily: the same order the engine always used
// (time, then item, then repeat), huge repeat counts cost nothing up front,
// and times beyond the sample clock never fire early.
#include "rfsitl/engine/traffic_schedule.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <vector>

namespace rfsitl::engine {
namespace {

using Item = scenario::TrafficItem;

std::vector<TrafficSchedule::Frame> drain(TrafficSchedule& s, SampleTime now) {
  std::vector<TrafficSchedule::Frame> out;
  while (const auto f = s.pop_due(now)) out.push_back(*f);
  return out;
}

TEST(TrafficSchedule, FramesComeInTimeThenItemThenRepeatOrder) {
  // Item 0: t = 0.002, 0.003, 0.004 s; item 1: t = 0.003 s twice (interval 0).
  TrafficSchedule s({Item{0.002, 1, 2, 10, 3, 0.001}, Item{0.003, 2, 1, 20, 2, 0.0}}, 1000.0);
  EXPECT_TRUE(drain(s, 1).empty());
  const auto due = drain(s, 1000);
  ASSERT_EQ(due.size(), 5U);
  const std::vector<SampleTime> expected = {2, 3, 3, 3, 4};
  for (std::size_t i = 0; i < due.size(); ++i) EXPECT_EQ(due[i].at, expected[i]) << i;
  EXPECT_EQ(due[0].src, 1);
  EXPECT_EQ(due[1].src, 1);  // item 0 before item 1 at the same time
  EXPECT_EQ(due[1].repeat_index, 1U);
  EXPECT_EQ(due[2].src, 2);
  EXPECT_EQ(due[2].repeat_index, 0U);
  EXPECT_EQ(due[3].src, 2);
  EXPECT_EQ(due[3].repeat_index, 1U);
  EXPECT_EQ(due[4].size, 10U);
}

TEST(TrafficSchedule, OnlyWhatIsDueIsPopped) {
  TrafficSchedule s({Item{0.0, 1, 2, 8, 10, 0.01}}, 1e6);  // every 10000 samples
  EXPECT_EQ(drain(s, 0).size(), 1U);
  EXPECT_EQ(drain(s, 9999).size(), 0U);
  EXPECT_EQ(drain(s, 10000).size(), 1U);
  EXPECT_EQ(drain(s, 1'000'000).size(), 8U);
  EXPECT_FALSE(s.pop_due(1'000'000'000).has_value());
}

TEST(TrafficSchedule, HugeRepeatIsMadeLazily) {
  TrafficSchedule s({Item{0.0, 1, 2, 8, 4'000'000'000U, 1.0}}, 1e6);
  EXPECT_EQ(drain(s, 2'500'000).size(), 3U);  // t = 0, 1, 2 s
}

TEST(TrafficSchedule, TimeBeyondTheSampleClockNeverFiresEarly) {
  // 1e300 s would overflow llround; it must not come out at t = 0.
  TrafficSchedule s({Item{1e300, 1, 2, 8, 1, 0.0}, Item{0.5, 2, 1, 8, 1, 0.0}}, 1e6);
  const auto due = drain(s, std::numeric_limits<SampleTime>::max() - 1);
  ASSERT_EQ(due.size(), 1U);
  EXPECT_EQ(due[0].src, 2);
}

}  // namespace
}  // namespace rfsitl::engine
