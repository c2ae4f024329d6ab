#pragma once
/// A path through given points, flown in straight legs.
#include <optional>
#include <vector>

#include "rfsitl/common/position.hpp"
#include "rfsitl/position/mobility/mobility_model.hpp"
#include "rfsitl/position/mobility/piecewise_linear_track.hpp"

namespace rfsitl::position::mobility {

/// One point of a path and when the node gets there: by time, or by the speed
/// of the leg that arrives here.
struct Waypoint {
  Position point;  ///< local metres or WGS84 (converted once, see local_frame.hpp)
  /// Arrival time, virtual seconds. The first point's defaults to 0.
  std::optional<double> time_s;
  /// Or: the speed of the straight leg from the previous point, m/s (> 0); the
  /// arrival time is the previous departure + leg length / speed. Every point
  /// after the first sets exactly one of time_s and speed_mps; the first sets
  /// no speed.
  std::optional<double> speed_mps;
  /// Time spent at this point before leaving it, s (>= 0).
  double dwell_s = 0.0;
};

struct WaypointSettings {
  std::vector<Waypoint> points;  ///< at least one
  /// Repeat the path forever. The path must be closed: its last point is its
  /// first (within 1 mm), so the return leg is written out like any other leg,
  /// with its own time or speed. The period is from the first point's arrival
  /// to the last point's departure (arrival + dwell_s).
  bool loop = false;

  /// Checks that need no origin; throws std::invalid_argument naming the field
  /// ("waypoints.points[2].speed_mps must be > 0 (got 0)").
  void validate() const;
};

/// Before the first point's time: at the first point. Between points: straight
/// at constant velocity (in local ENU). After the last: at the last point, or
/// with `loop` the path again from its start, with period as above.
class WaypointModel final : public MobilityModel {
 public:
  /// Validates `settings`, converts every point to local ENU around `origin`
  /// and derives the times. Also throws std::invalid_argument when a leg
  /// arrives before the previous departure, a non-zero leg takes no time (a
  /// jump), or a loop is not closed or lasts no time.
  WaypointModel(const WaypointSettings& settings, const GeodeticPosition& origin);

  MotionState state_at(double t_s) override;

  /// The timed path (one knot per arrival and per departure after a dwell).
  const PiecewiseLinearTrack& track() const { return track_; }
  /// The loop's period in seconds, or 0 without loop.
  double period_s() const { return period_s_; }

 private:
  PiecewiseLinearTrack track_;
  double period_s_ = 0.0;
  std::size_t cursor_ = 0;
};

}  // namespace rfsitl::position::mobility
