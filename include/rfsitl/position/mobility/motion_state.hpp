#pragma once
/// What a mobility model answers for one instant: where a node is and how it
/// moves, both in the scenario's local east/north/up frame.
#include "rfsitl/common/position.hpp"
#include "rfsitl/position/source/node_state.hpp"

namespace rfsitl::position::mobility {

using Velocity = position::Velocity;  ///< east, north, up in m/s

/// Position (local ENU metres) and velocity (m/s) at one virtual time.
struct MotionState {
  LocalPosition position;
  Velocity velocity;
};

}  // namespace rfsitl::position::mobility
