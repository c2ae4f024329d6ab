// Mobility models move nodes on the virtual clock, and link outcomes follow:
// a node on an orbit is heard while it passes close to its peer and lost while
// it is far (real GMSK receiver, paper channel).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <set>

#include "engine_run.hpp"
#include "rfsitl/common/geodesy.hpp"
#include "rfsitl/position/mobility/mobility_component.hpp"
#include "rfsitl/registry/mobility_registry.hpp"

namespace rfsitl::testing {
namespace {

constexpr double kCentreX = 60, kRadius = 60, kSpeed = 2 * std::numbers::pi * kRadius / 20.0;
constexpr double kNoiseDb = -90, kExponent = 3, kSensitivityDb = 5.3;

// SNR of the link at distance d (the README's closed form for the paper model).
double snr_db(double d) {
  return -20 * kExponent * std::log10(d + 1) - kNoiseDb;
}

double distance_at(double t) {  // node 1 sits at the origin; node 2 orbits (kCentreX, 0)
  const double a = kSpeed / kRadius * t;
  return std::hypot(kCentreX + kRadius * std::cos(a), kRadius * std::sin(a));
}

scenario::Scenario orbiting_pair(double mobility_update_s) {
  scenario::Scenario s = make_scenario({{1, LocalPosition{0, 0, 0}}, {2, std::nullopt}}, 20.0);
  s.channel.noise_variance = std::pow(10.0, kNoiseDb / 10);
  s.channel.path_loss_exponent = kExponent;
  s.engine.mobility_update_s = mobility_update_s;
  const auto* orbit = position::mobility::find_mobility("orbit");
  scenario::MobilityChoice m{"orbit", orbit->info.defaults()};
  m.settings.set("centre_x_m", kCentreX);
  m.settings.set("radius_m", kRadius);
  m.settings.set("speed_mps", kSpeed);
  s.nodes[1].mobility = m;
  // 80 frames of 40 bytes, one every 0.25 s from 0.05 s: a payload's first
  // byte is its repeat index.
  s.traffic.push_back(scenario::TrafficItem{0.05, 1, 2, 40, 80, 0.25});
  return s;
}

TEST(EngineMobility, LinkOutcomesFollowAnOrbitingNode) {
  const scenario::Scenario s = orbiting_pair(0.01);
  const RunResult r = run_engine(s);
  std::set<unsigned> heard;
  for (const Delivery& d : r.deliveries) heard.insert(d.frame.payload.at(0));
  unsigned sure_in = 0, sure_out = 0;
  for (unsigned k = 0; k < 80; ++k) {
    const double margin = snr_db(distance_at(0.05 + 0.25 * k)) - kSensitivityDb;
    if (margin > 3) {  // well inside range: delivered
      ++sure_in;
      EXPECT_TRUE(heard.count(k)) << "frame " << k << " at margin " << margin << " dB";
    } else if (margin < -3) {  // well outside: lost
      ++sure_out;
      EXPECT_FALSE(heard.count(k)) << "frame " << k << " at margin " << margin << " dB";
    }
  }
  // The orbit passes through both regimes many times over.
  EXPECT_GE(sure_in, 5U);
  EXPECT_GE(sure_out, 40U);
  EXPECT_EQ(r.counters[0].delivered + r.counters[0].lost_total(), 80U);
  EXPECT_EQ(r.counters[0].delivered, heard.size());
}

TEST(EngineMobility, TheModelsPositionIsWhereTheEngineHasTheNode) {
  // After the run the engine's published copy of node 2's position is the
  // orbit's, within the distance flown in one update interval (0.01 s) plus
  // the copy's own period (0.02 s of virtual time) and a tick.
  const scenario::Scenario s = orbiting_pair(0.01);
  const RunResult r = run_engine(s);
  const auto positions = r.engine->positions();
  ASSERT_TRUE(positions.at(1).has_value());
  const double t_end = 20.0;
  const double a = kSpeed / kRadius * t_end;
  const Ecef want = local_to_ecef(
      LocalPosition{kCentreX + kRadius * std::cos(a), kRadius * std::sin(a), 0}, s.channel.origin);
  const Ecef& got = *positions[1];
  EXPECT_LT(std::hypot(got.x - want.x, got.y - want.y, got.z - want.z), kSpeed * 0.035);
}

}  // namespace
}  // namespace rfsitl::testing
