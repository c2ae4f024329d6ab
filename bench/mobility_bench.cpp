/// Cost of evaluating the mobility models as the position pipeline would:
/// 64 nodes, each asked for its state every 10 ms of virtual time over 60 s
/// (6000 steps x 64 nodes = 384000 evaluations per model), on one thread.
///
///   rfsitl_mobility_bench
///
/// Prints one CSV row per model (with a header): model, evaluations, ns per
/// evaluation (median of 5 runs, each on freshly built models so the random
/// models pay for generating their legs), and a checksum of the positions so
/// the work cannot be optimised away.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "rfsitl/position/mobility/csv_trace.hpp"
#include "rfsitl/position/mobility/gauss_markov_model.hpp"
#include "rfsitl/position/mobility/orbit_model.hpp"
#include "rfsitl/position/mobility/random_waypoint_model.hpp"
#include "rfsitl/position/mobility/static_model.hpp"
#include "rfsitl/position/mobility/trace_replay_model.hpp"
#include "rfsitl/position/mobility/waypoint_model.hpp"

namespace {

using namespace rfsitl;
using namespace rfsitl::position::mobility;
using Clock = std::chrono::steady_clock;
using Models = std::vector<std::unique_ptr<MobilityModel>>;

constexpr int kNodes = 64;
constexpr int kSteps = 6000;  // 60 s at 10 ms
constexpr double kStepS = 0.01;
constexpr int kRepeats = 5;
const GeodeticPosition kOrigin{43.0008, -78.789, 0.0};
const Box kBox{-500, 500, -500, 500, 20, 120};

/// One model per node, node i's settings varied by i (seeds, phases, offsets).
struct Case {
  const char* name;
  std::function<std::unique_ptr<MobilityModel>(int node)> make;
};

std::string csv_trace_text() {
  // Every node sampled once a second for 61 s along a zig-zag.
  std::string text = "t,node,x,y,z\n";
  for (int t = 0; t <= 60; ++t) {
    for (int n = 0; n < kNodes; ++n) {
      text += std::to_string(t) + "," + std::to_string(n) + "," + std::to_string(n * 10 + t * 5) +
              "," + std::to_string((t % 2) * 7) + ",50\n";
    }
  }
  return text;
}

std::vector<Case> cases() {
  static const TraceParseResult trace = parse_csv_trace(csv_trace_text(), "bench.csv", {});
  return {
      {"static",
       [](int n) {
         return std::make_unique<StaticModel>(StaticSettings{LocalPosition{n * 1.0, 0, 30}},
                                              kOrigin);
       }},
      {"waypoints_loop",
       [](int n) {
         const double o = n * 3.0;
         auto p = [o](double x, double y) { return LocalPosition{o + x, y, 50}; };
         WaypointSettings s{{{p(0, 0), 0.0, std::nullopt, 1.0},
                             {p(100, 0), std::nullopt, 12.0, 0.0},
                             {p(100, 100), std::nullopt, 12.0, 0.0},
                             {p(0, 0), std::nullopt, 12.0, 0.0}},
                            true};
         return std::make_unique<WaypointModel>(s, kOrigin);
       }},
      {"orbit",
       [](int n) {
         OrbitSettings s;
         s.radius_m = 150;
         s.speed_mps = n % 2 ? 15 : -15;
         s.phase_rad = n * 0.1;
         return std::make_unique<OrbitModel>(s);
       }},
      {"random_waypoint",
       [](int n) {
         RandomWaypointSettings s;
         s.box = kBox;
         s.speed_min_mps = 5;
         s.speed_max_mps = 20;
         s.pause_s = 2;
         s.seed = static_cast<std::uint64_t>(n) + 1;
         return std::make_unique<RandomWaypointModel>(s);
       }},
      {"gauss_markov",
       [](int n) {
         GaussMarkovSettings s;
         s.box = kBox;
         s.update_interval_s = 0.1;
         s.seed = static_cast<std::uint64_t>(n) + 1;
         return std::make_unique<GaussMarkovModel>(s);
       }},
      {"csv_trace_replay",
       [](int n) {
         return std::make_unique<TraceReplayModel>(trace.tracks.at(static_cast<std::uint32_t>(n)));
       }},
  };
}

}  // namespace

int main() {
  std::printf("model,evaluations,ns_per_evaluation,checksum\n");
  for (const Case& c : cases()) {
    std::vector<double> ns;
    double checksum = 0;
    for (int r = 0; r < kRepeats; ++r) {
      Models models;
      for (int n = 0; n < kNodes; ++n) models.push_back(c.make(n));
      checksum = 0;
      const auto t0 = Clock::now();
      for (int step = 0; step < kSteps; ++step) {
        const double t = step * kStepS;
        for (auto& m : models) {
          const MotionState s = m->state_at(t);
          checksum += s.position.x_m + s.position.y_m + s.velocity.vz_mps;
        }
      }
      const double elapsed = std::chrono::duration<double, std::nano>(Clock::now() - t0).count();
      ns.push_back(elapsed / (kNodes * kSteps));
    }
    std::sort(ns.begin(), ns.end());
    std::printf("%s,%d,%.1f,%.6g\n", c.name, kNodes * kSteps, ns[ns.size() / 2], checksum);
  }
  return 0;
}
