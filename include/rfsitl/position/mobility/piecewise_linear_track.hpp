#pragma once
/// Straight-line motion through timed points: the kernel under waypoint paths
/// and trace replay (CSV samples and ns-2 setdest files compile to it).
#include <cstddef>
#include <vector>

#include "rfsitl/position/mobility/motion_state.hpp"

namespace rfsitl::position::mobility {

/// At `time_s` (virtual seconds) the node is at `position` (local ENU metres).
struct TrackKnot {
  double time_s = 0.0;
  LocalPosition position;
};

/// Linear motion from each knot to the next, at the constant velocity that
/// joins them. Before the first knot the node is at the first knot's position,
/// after the last at the last one's, with velocity zero. Two knots at the same
/// time are a jump: from that time on the later one holds. Knots less than
/// kSameInstantS apart are taken as the same time (a jump), so no segment is
/// short enough to give an infinite speed.
///
/// Immutable after construction: any number of threads may evaluate it, each
/// with its own cursor.
class PiecewiseLinearTrack {
 public:
  static constexpr double kSameInstantS = 1e-9;

  /// An empty track (no knots); state_at must not be called on it.
  PiecewiseLinearTrack() = default;
  /// Throws std::invalid_argument when `knots` is empty, a time is not finite,
  /// times decrease, or a position fails local_coordinate_error.
  explicit PiecewiseLinearTrack(std::vector<TrackKnot> knots);

  bool empty() const { return knots_.empty(); }
  const std::vector<TrackKnot>& knots() const { return knots_; }
  /// Time of the first and the last knot. Precondition: !empty().
  double start_s() const { return knots_.front().time_s; }
  double end_s() const { return knots_.back().time_s; }

  /// Position and velocity at `t_s`. `cursor` is a search hint owned by the
  /// caller (start it at 0; any value is safe): evaluating at non-decreasing
  /// times costs amortised O(1), an arbitrary time O(log knots).
  /// Precondition: !empty(), `t_s` finite.
  MotionState state_at(double t_s, std::size_t& cursor) const;

 private:
  std::size_t segment_of(double t_s, std::size_t cursor) const;

  std::vector<TrackKnot> knots_;
};

}  // namespace rfsitl::position::mobility
