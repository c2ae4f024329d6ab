#pragma once
/// What a position source says about a node besides where it is: how it moves
/// and how it is turned. The channel may use both (Doppler, antenna patterns);
/// the dashboard and the summary show them.
#include <optional>

namespace rfsitl::position {

/// Velocity in metres per second along local east (x), north (y) and up (z).
struct Velocity {
  double vx_mps = 0.0;
  double vy_mps = 0.0;
  double vz_mps = 0.0;
  bool operator==(const Velocity&) const = default;
};

/// Euler angles of the body frame (x forward, y right, z down) in radians, as
/// aviation and MAVLink define them: yaw 0 = north, positive clockwise seen
/// from above; roll positive right wing down; pitch positive nose up.
struct Attitude {
  double roll_rad = 0.0;
  double pitch_rad = 0.0;
  double yaw_rad = 0.0;
  bool operator==(const Attitude&) const = default;
};

/// A node's motion as last reported: absent parts were never reported.
struct NodeMotion {
  std::optional<Velocity> velocity;
  std::optional<Attitude> attitude;
  bool operator==(const NodeMotion&) const = default;
};

}  // namespace rfsitl::position
