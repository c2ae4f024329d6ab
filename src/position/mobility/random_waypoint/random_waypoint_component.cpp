// The mobility model "random_waypoint": legs to random points of a box at random speeds, with
// pauses.
#include "../component_support.hpp"
#include "rfsitl/position/mobility/random_waypoint_model.hpp"

namespace rfsitl::position::mobility {
namespace {

using namespace detail;

struct RandomWaypointFields : BoxFields {
  double speed_min_mps = 1, speed_max_mps = 10, pause_s = 0;
  RandomWaypointSettings model(const MobilityContext& c) const {
    RandomWaypointSettings s;
    s.speed_min_mps = speed_min_mps;
    s.speed_max_mps = speed_max_mps;
    s.pause_s = pause_s;
    return with_shared(s, c);
  }
};

const config::Fields<RandomWaypointFields>& random_waypoint_fields() {
  using S = RandomWaypointFields;
  static const auto f =
      with_box<S>()
          .real("speed_min_mps", &S::speed_min_mps, "m/s", {0, 1e4, true}, "least leg speed")
          .real("speed_max_mps", &S::speed_max_mps, "m/s", {0, 1e4, true}, "greatest leg speed")
          .real("pause_s", &S::pause_s, "s", {0, 1e6}, "wait at each destination")
          .rule([](const S& s) { checked(s.model(MobilityContext{})); });
  return f;
}

}  // namespace

MobilityComponent random_waypoint_component() {
  return {
      random_waypoint_fields().info("mobility", "random_waypoint",
                                    "random waypoint in a box: legs at random speeds, pauses"),
      [](const config::Settings& s, const MobilityContext& c) -> std::unique_ptr<MobilityModel> {
        return std::make_unique<RandomWaypointModel>(random_waypoint_fields().build(s).model(c));
      }};
}

}  // namespace rfsitl::position::mobility
