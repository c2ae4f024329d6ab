#pragma once
/// What a mobility model answers for one instant: where a node is and how it
/// moves, both in the scenario's local east/north/up frame.
#include "rfsitl/common/position.hpp"

namespace rfsitl::position::mobility {

/// Velocity in metres per second along local east (x), north (y) and up (z).
struct Velocity {
  double vx_mps = 0.0;
  double vy_mps = 0.0;
  double vz_mps = 0.0;
};

/// Position (local ENU metres) and velocity (m/s) at one virtual time.
struct MotionState {
  LocalPosition position;
  Velocity velocity;
};

}  // namespace rfsitl::position::mobility
