// The formation of `rfsitl run --nodes N`: ids 1..N, and every link decodable, checked
// from the positions themselves (not from the spacing the code chose).
#include "rfsitl/scenario/default_formation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>
#include <variant>

namespace rfsitl::scenario {
namespace {

double distance_m(const NodeConfig& a, const NodeConfig& b) {
  const auto& pa = std::get<LocalPosition>(*a.initial_position);
  const auto& pb = std::get<LocalPosition>(*b.initial_position);
  return std::hypot(pa.x_m - pb.x_m, pa.y_m - pb.y_m, pa.z_m - pb.z_m);
}

// Paper model, unit-power transmitter: |c|^2 = (d + 1)^(-2 * exponent).
double snr_db(double d_m, const ChannelConfig& ch) {
  return 10 * std::log10(std::pow(d_m + 1, -2 * ch.path_loss_exponent) / ch.noise_variance);
}

double longest_link_m(const std::vector<NodeConfig>& nodes) {
  double longest = 0;
  for (const auto& a : nodes) {
    for (const auto& b : nodes) longest = std::max(longest, distance_m(a, b));
  }
  return longest;
}

double shortest_link_m(const std::vector<NodeConfig>& nodes) {
  double shortest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    for (std::size_t j = i + 1; j < nodes.size(); ++j) {
      shortest = std::min(shortest, distance_m(nodes[i], nodes[j]));
    }
  }
  return shortest;
}

TEST(DefaultFormation, NodesHaveUniqueIdsOneToNAtTenMetres) {
  for (const std::size_t n : {1U, 2U, 6U, 15U, 64U, 254U}) {
    const auto nodes = default_formation(n, ChannelConfig{});
    ASSERT_EQ(nodes.size(), n);
    std::set<int> ids;
    for (std::size_t i = 0; i < n; ++i) {
      EXPECT_EQ(nodes[i].id, i + 1);
      ids.insert(nodes[i].id);
      ASSERT_TRUE(nodes[i].initial_position.has_value());
      EXPECT_DOUBLE_EQ(std::get<LocalPosition>(*nodes[i].initial_position).z_m, 10.0);
    }
    EXPECT_EQ(ids.size(), n);
  }
}

TEST(DefaultFormation, LongestLinkMeetsTheTargetSnr) {
  ChannelConfig steep;
  steep.path_loss_exponent = 4.0;
  steep.noise_variance = 1e-14;
  for (const auto& channel : {ChannelConfig{}, steep}) {
    for (const double target_db : {20.0, 40.0}) {
      for (const std::size_t n : {2U, 6U, 15U, 64U}) {
        const auto nodes = default_formation(n, channel, target_db);
        EXPECT_GE(snr_db(longest_link_m(nodes), channel), target_db)
            << "n = " << n << ", target " << target_db << " dB";
        EXPECT_GE(shortest_link_m(nodes), 1.0 - 1e-9) << "n = " << n;  // never closer than 1 m
      }
    }
  }
}

TEST(DefaultFormation, SpacingIsAsWideAsTheTargetAllows) {
  // Default channel, 64 nodes (8 x 8) at 20 dB: the diagonal may reach
  // 10^(10/6) - 1 = 45.4 m, so the spacing is 45.4 / (7 sqrt 2) = 4.58 m (to the cm).
  const auto nodes = default_formation(64, ChannelConfig{}, 20.0);
  EXPECT_NEAR(shortest_link_m(nodes), 4.58, 0.011);
  EXPECT_LT(snr_db(longest_link_m(nodes), ChannelConfig{}), 20.5);  // not needlessly tight
}

TEST(DefaultFormation, SpacingIsCappedAtTenMetres) {
  // Two nodes at 20 dB could be 45 m apart; a swarm stays within 10 m.
  const auto nodes = default_formation(2, ChannelConfig{}, 20.0);
  EXPECT_DOUBLE_EQ(longest_link_m(nodes), 10.0);
}

TEST(DefaultFormation, UnreachableTargetFallsBackToOneMetre) {
  // 120 dB - 60 log10(2) = 102 dB at 1 m: a 110 dB target cannot be met.
  const auto nodes = default_formation(6, ChannelConfig{}, 110.0);
  EXPECT_DOUBLE_EQ(shortest_link_m(nodes), 1.0);
}

TEST(DefaultFormation, NoiselessChannelUsesTenMetres) {
  ChannelConfig noiseless;
  noiseless.noise_variance = 0.0;
  EXPECT_DOUBLE_EQ(shortest_link_m(default_formation(6, noiseless, 60.0)), 10.0);
}

TEST(DefaultFormation, RejectsNodeCountsOutsideOneTo254) {
  EXPECT_THROW(default_formation(0, ChannelConfig{}), std::invalid_argument);
  EXPECT_NO_THROW(default_formation(254, ChannelConfig{}));
  EXPECT_THROW(default_formation(255, ChannelConfig{}), std::invalid_argument);
}

}  // namespace
}  // namespace rfsitl::scenario
