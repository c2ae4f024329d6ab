#pragma once
/// What a channel stage knows of one link: where its two ends are and how they
/// move. (How they point joins as the stages that need it arrive.)
#include <cstddef>
#include <optional>

#include "rfsitl/common/position.hpp"

namespace rfsitl::channel {

/// A velocity in the local frame, m/s.
struct LocalVelocity {
  double east_mps = 0.0;
  double north_mps = 0.0;
  double up_mps = 0.0;
};

/// Where a node's body points: roll, pitch and yaw in radians, as MAVLink's
/// ATTITUDE (yaw clockwise from north, pitch nose up, roll right wing down).
/// The body frame is x forward, y right, z down.
struct Orientation {
  double roll_rad = 0.0;
  double pitch_rad = 0.0;
  double yaw_rad = 0.0;
};

/// One end of a link.
struct LinkEnd {
  std::size_t index = 0;  ///< the node's index, 0..N-1
  Ecef ecef;
  /// East, north, up metres around the scenario's channel.origin. Models with a
  /// ground (two-ray, TR 36.777) take up = 0, the origin's altitude, as the ground.
  LocalPosition local;
  /// How the end moves (zero when its source reports no velocity and none
  /// could be estimated). Time-varying stages see `local` extrapolated with it.
  LocalVelocity velocity;
  /// How the end's body is turned; nullopt when its source never said (an
  /// antenna stage then takes it level, facing north).
  std::optional<Orientation> attitude;
};

/// The link from `tx` to `rx`.
struct LinkGeometry {
  LinkEnd tx;
  LinkEnd rx;
  double distance_m = 0.0;    ///< straight line in ECEF, >= 0 (exactly 0 on the diagonal)
  double horizontal_m = 0.0;  ///< in the local east-north plane, >= 0
  /// The virtual time of the evaluation, seconds: when the positions were set
  /// (large-scale stages), or the grid point (time-varying stages).
  double time_s = 0.0;
  /// Which path of a dispersive link a time-varying stage is evaluated for
  /// (0 for a link of one path): stages with random draws key them by it, so
  /// that a link's paths fade independently.
  std::size_t path = 0;
};

}  // namespace rfsitl::channel
