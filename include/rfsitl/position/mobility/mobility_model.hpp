#pragma once
/// The contract every mobility model keeps: a node's motion as a function of
/// virtual time alone.
#include "rfsitl/position/mobility/motion_state.hpp"

namespace rfsitl::position::mobility {

/// A node's track. `state_at(t)` depends only on `t` and on the settings the
/// model was built with (seeded models included): the same `t` gives the same
/// answer whatever was asked before, in whatever order.
///
/// Threads: `state_at` may update a cache (the lazily generated legs of the
/// random models, a search cursor), so one instance is used by one thread at a
/// time; separate instances share nothing.
///
/// Velocity at an instant where the motion changes (a waypoint, a trace sample,
/// a random leg's end) is the velocity of the motion that starts there: tracks
/// are right-continuous in time.
class MobilityModel {
 public:
  virtual ~MobilityModel() = default;

  /// Position (local ENU metres) and velocity (m/s) at virtual time `t_s`
  /// (seconds since the run started). Precondition: `t_s` is finite.
  virtual MotionState state_at(double t_s) = 0;
};

}  // namespace rfsitl::position::mobility
