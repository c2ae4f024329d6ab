#include "rfsitl/channel/channel_matrix.hpp"
#include "rfsitl/channel/stages/path_loss.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>

namespace rfsitl::channel {
namespace {

constexpr float kInvSqrt2 = 0.70710678118654752f;

// Points on a straight line in ECEF: distance is the difference in x.
Ecef at_x(double x_m) {
  return Ecef{6378137.0 + x_m, 0.0, 0.0};
}

std::shared_ptr<const LinkBudget> paper3() {
  return make_paper_budget(3.0);
}

void expect_coeff(const ChannelMatrix& m, std::size_t tx, std::size_t rx, float path_loss) {
  const cf32 c = m.coefficient(tx, rx);
  EXPECT_FLOAT_EQ(c.real(), kInvSqrt2 * path_loss) << "tx " << tx << " rx " << rx;
  EXPECT_FLOAT_EQ(c.imag(), kInvSqrt2 * path_loss) << "tx " << tx << " rx " << rx;
}

void expect_zero(const ChannelMatrix& m, std::size_t tx, std::size_t rx) {
  EXPECT_EQ(m.coefficient(tx, rx), cf32(0.0f, 0.0f)) << "tx " << tx << " rx " << rx;
}

TEST(ChannelMatrix, NodesWithoutPositionsHaveNoLinksNotEvenToThemselves) {
  const ChannelMatrix m(3, paper3());
  EXPECT_EQ(m.size(), 3u);
  for (std::size_t tx = 0; tx < 3; ++tx) {
    for (std::size_t rx = 0; rx < 3; ++rx) {
      expect_zero(m, tx, rx);
    }
  }
}

TEST(ChannelMatrix, PositionedNodeHearsItselfButNotUnpositionedNodes) {
  ChannelMatrix m(3, paper3());
  m.set_position(1, at_x(0.0));
  expect_coeff(m, 1, 1, 1.0f);  // the model at d = 0: half duplex
  for (std::size_t other : {0u, 2u}) {
    expect_zero(m, 1, other);
    expect_zero(m, other, 1);
    expect_zero(m, other, other);
  }
}

TEST(ChannelMatrix, CoefficientsFollowDistanceBothWays) {
  ChannelMatrix m(3, paper3());
  m.set_position(0, at_x(0.0));
  m.set_position(1, at_x(1.0));
  m.set_position(2, at_x(9.0));
  expect_coeff(m, 0, 1, 1.0f / 8.0f);  // d = 1
  expect_coeff(m, 1, 0, 1.0f / 8.0f);
  expect_coeff(m, 0, 2, 1e-3f);  // d = 9
  expect_coeff(m, 2, 0, 1e-3f);
  expect_coeff(m, 1, 2, 1.0f / 729.0f);  // d = 8
  expect_coeff(m, 2, 1, 1.0f / 729.0f);
  for (std::size_t i = 0; i < 3; ++i) {
    expect_coeff(m, i, i, 1.0f);
  }
}

TEST(ChannelMatrix, MovingNodeUpdatesItsRowAndColumnOnly) {
  ChannelMatrix m(3, paper3());
  m.set_position(0, at_x(0.0));
  m.set_position(1, at_x(1.0));
  m.set_position(2, at_x(3.0));
  const cf32 link02 = m.coefficient(0, 2);
  const cf32 link20 = m.coefficient(2, 0);

  m.set_position(1, at_x(9.0));  // node 1 now 9 m from node 0 and 6 m from node 2
  expect_coeff(m, 0, 1, 1e-3f);
  expect_coeff(m, 1, 0, 1e-3f);
  expect_coeff(m, 1, 2, 1.0f / 343.0f);
  expect_coeff(m, 2, 1, 1.0f / 343.0f);
  expect_coeff(m, 1, 1, 1.0f);
  EXPECT_EQ(m.coefficient(0, 2), link02);
  EXPECT_EQ(m.coefficient(2, 0), link20);
  expect_coeff(m, 0, 2, 1.0f / 64.0f);  // d = 3, untouched
}

TEST(ChannelMatrix, ClearingPositionRemovesEveryLinkOfThatNode) {
  ChannelMatrix m(3, paper3());
  m.set_position(0, at_x(0.0));
  m.set_position(1, at_x(1.0));
  m.set_position(2, at_x(3.0));
  m.set_position(1, std::nullopt);
  for (std::size_t other = 0; other < 3; ++other) {
    expect_zero(m, 1, other);
    expect_zero(m, other, 1);
  }
  expect_coeff(m, 0, 2, 1.0f / 64.0f);
  EXPECT_FALSE(m.position(1).has_value());
}

TEST(ChannelMatrix, ReceiverRowIsIndexedByTransmitter) {
  ChannelMatrix m(3, paper3());
  m.set_position(0, at_x(0.0));
  m.set_position(1, at_x(1.0));
  m.set_position(2, at_x(3.0));
  for (std::size_t rx = 0; rx < 3; ++rx) {
    const auto row = m.receiver_row(rx);
    ASSERT_EQ(row.size(), 3u);
    for (std::size_t tx = 0; tx < 3; ++tx) {
      EXPECT_EQ(row[tx], m.coefficient(tx, rx));
    }
  }
  EXPECT_FLOAT_EQ(m.power_gain(0, 2), 1.0f / 4096.0f);  // |c|^2 = 4^-6
}

TEST(ChannelMatrix, DistanceIsNulloptUntilBothPositionsAreKnown) {
  ChannelMatrix m(2, paper3());
  EXPECT_FALSE(m.distance(0, 1).has_value());
  m.set_position(0, at_x(0.0));
  EXPECT_FALSE(m.distance(0, 1).has_value());
  EXPECT_FALSE(m.distance(1, 1).has_value());
  ASSERT_TRUE(m.distance(0, 0).has_value());
  EXPECT_DOUBLE_EQ(*m.distance(0, 0), 0.0);
  m.set_position(1, at_x(42.5));
  ASSERT_TRUE(m.distance(0, 1).has_value());
  EXPECT_NEAR(*m.distance(0, 1), 42.5, 1e-9);
  EXPECT_NEAR(*m.distance(1, 0), 42.5, 1e-9);
}

TEST(ChannelMatrix, RejectsNullModelAndOutOfRangeNode) {
  EXPECT_THROW(ChannelMatrix(2, nullptr), std::invalid_argument);
  ChannelMatrix m(2, paper3());
  EXPECT_THROW(m.set_position(2, at_x(0.0)), std::out_of_range);
}

}  // namespace
}  // namespace rfsitl::channel
