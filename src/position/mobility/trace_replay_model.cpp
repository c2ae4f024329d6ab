#include "rfsitl/position/mobility/trace_replay_model.hpp"

#include <stdexcept>

namespace rfsitl::position::mobility {

TraceReplayModel::TraceReplayModel(PiecewiseLinearTrack track) : track_(std::move(track)) {
  if (track_.empty()) throw std::invalid_argument("trace replay: the node's track is empty");
}

MotionState TraceReplayModel::state_at(double t_s) {
  return track_.state_at(t_s, cursor_);
}

}  // namespace rfsitl::position::mobility
