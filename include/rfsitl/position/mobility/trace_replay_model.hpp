#pragma once
/// A node that replays a recorded track (from csv_trace.hpp or ns2_trace.hpp).
#include <cstddef>

#include "rfsitl/position/mobility/mobility_model.hpp"
#include "rfsitl/position/mobility/piecewise_linear_track.hpp"

namespace rfsitl::position::mobility {

class TraceReplayModel final : public MobilityModel {
 public:
  /// Throws std::invalid_argument when `track` is empty.
  explicit TraceReplayModel(PiecewiseLinearTrack track);

  /// The track at `t_s` (see PiecewiseLinearTrack: holds its ends).
  MotionState state_at(double t_s) override;

 private:
  PiecewiseLinearTrack track_;
  std::size_t cursor_ = 0;
};

}  // namespace rfsitl::position::mobility
