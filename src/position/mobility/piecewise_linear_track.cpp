#include "rfsitl/position/mobility/piecewise_linear_track.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "rfsitl/common/position_limits.hpp"
#include "rfsitl/position/mobility/local_frame.hpp"

namespace rfsitl::position::mobility {
namespace {

// Beyond this many knots a cursor walks forward before it falls back to a
// binary search: stepping every 10 ms through a track sampled every 1 s or
// faster crosses at most a few knots per call.
constexpr std::size_t kCursorWalk = 8;

}  // namespace

PiecewiseLinearTrack::PiecewiseLinearTrack(std::vector<TrackKnot> knots)
    : knots_(std::move(knots)) {
  if (knots_.empty()) throw std::invalid_argument("a track needs at least one knot");
  for (std::size_t i = 0; i < knots_.size(); ++i) {
    TrackKnot& k = knots_[i];
    const std::string where = "track knot " + std::to_string(i) + ": ";
    if (!std::isfinite(k.time_s)) {
      throw std::invalid_argument(where + "time " + format_coordinate(k.time_s) + " is not finite");
    }
    if (const std::string e = local_coordinate_error(k.position); !e.empty()) {
      throw std::invalid_argument(where + e);
    }
    if (i == 0) continue;
    const double prev = knots_[i - 1].time_s;
    if (k.time_s < prev) {
      throw std::invalid_argument(where + "time " + format_coordinate(k.time_s) +
                                  " is before the previous knot's " + format_coordinate(prev));
    }
    // A segment this short is a jump: snapping it keeps every speed finite.
    if (k.time_s - prev < kSameInstantS) k.time_s = prev;
  }
}

std::size_t PiecewiseLinearTrack::segment_of(double t_s, std::size_t cursor) const {
  // Returns the last knot with time <= t_s (0 when t_s precedes them all).
  const std::size_t n = knots_.size();
  if (cursor >= n || knots_[cursor].time_s > t_s) cursor = 0;
  for (std::size_t step = 0; step < kCursorWalk; ++step) {
    if (cursor + 1 >= n || knots_[cursor + 1].time_s > t_s) return cursor;
    ++cursor;
  }
  const auto after =
      std::upper_bound(knots_.begin() + static_cast<std::ptrdiff_t>(cursor), knots_.end(), t_s,
                       [](double t, const TrackKnot& k) { return t < k.time_s; });
  return static_cast<std::size_t>(after - knots_.begin()) - 1;
}

MotionState PiecewiseLinearTrack::state_at(double t_s, std::size_t& cursor) const {
  cursor = segment_of(t_s, cursor);
  const TrackKnot& a = knots_[cursor];
  if (t_s < a.time_s || cursor + 1 == knots_.size()) return {a.position, {}};
  // Here a.time_s <= t_s < b.time_s, so the segment has a positive duration.
  const TrackKnot& b = knots_[cursor + 1];
  const double dt = b.time_s - a.time_s;
  const Velocity v{(b.position.x_m - a.position.x_m) / dt, (b.position.y_m - a.position.y_m) / dt,
                   (b.position.z_m - a.position.z_m) / dt};
  const double tau = t_s - a.time_s;
  return {{a.position.x_m + v.vx_mps * tau, a.position.y_m + v.vy_mps * tau,
           a.position.z_m + v.vz_mps * tau},
          v};
}

}  // namespace rfsitl::position::mobility
