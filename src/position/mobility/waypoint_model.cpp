#include "rfsitl/position/mobility/waypoint_model.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "rfsitl/common/position_limits.hpp"
#include "rfsitl/position/mobility/local_frame.hpp"
#include "settings_check.hpp"

namespace rfsitl::position::mobility {
namespace {

constexpr std::string_view kPoints = "waypoints.points";
// Closing a loop compares two conversions of what may be the same WGS84 point.
constexpr double kSamePointM = 1e-3;

double distance(const LocalPosition& a, const LocalPosition& b) {
  return std::sqrt((b.x_m - a.x_m) * (b.x_m - a.x_m) + (b.y_m - a.y_m) * (b.y_m - a.y_m) +
                   (b.z_m - a.z_m) * (b.z_m - a.z_m));
}

std::string field(std::size_t i, std::string_view member) {
  return detail::indexed(kPoints, i, member);
}

}  // namespace

void WaypointSettings::validate() const {
  if (points.empty()) throw std::invalid_argument("waypoints.points must hold at least one point");
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Waypoint& w = points[i];
    detail::require_position(field(i, "point"), w.point);
    if (w.time_s) {
      detail::require(std::isfinite(*w.time_s), field(i, "time_s"), "must be finite", *w.time_s);
    }
    if (w.speed_mps) {
      if (i == 0) {
        throw std::invalid_argument(field(0, "speed_mps") +
                                    " is not allowed: no leg arrives at the first point");
      }
      detail::require(*w.speed_mps > 0.0 && std::isfinite(*w.speed_mps), field(i, "speed_mps"),
                      "must be > 0 and finite", *w.speed_mps);
    }
    if (i > 0 && w.time_s.has_value() == w.speed_mps.has_value()) {
      throw std::invalid_argument(field(i, "") + "time_s/speed_mps: exactly one must be set");
    }
    detail::require(w.dwell_s >= 0.0 && std::isfinite(w.dwell_s), field(i, "dwell_s"),
                    "must be >= 0 and finite", w.dwell_s);
  }
}

WaypointModel::WaypointModel(const WaypointSettings& settings, const GeodeticPosition& origin) {
  settings.validate();
  std::vector<TrackKnot> knots;
  knots.reserve(2 * settings.points.size());
  double departure = 0.0;
  LocalPosition at;
  for (std::size_t i = 0; i < settings.points.size(); ++i) {
    const Waypoint& w = settings.points[i];
    const LocalPosition p = to_local(w.point, origin);
    double arrival = w.time_s.value_or(0.0);
    if (i > 0) {
      const double length = distance(at, p);
      if (w.speed_mps) arrival = departure + length / *w.speed_mps;
      if (arrival < departure) {
        detail::reject(field(i, "time_s"),
                       "must not be before the departure from the previous point at " +
                           format_coordinate(departure) + " s",
                       arrival);
      }
      if (arrival == departure && length > kSamePointM) {
        detail::reject(field(i, "time_s"), "leaves no time for the leg from the previous point",
                       arrival);
      }
    }
    knots.push_back({arrival, p});
    departure = arrival + w.dwell_s;
    if (w.dwell_s > 0.0) knots.push_back({departure, p});
    at = p;
  }
  if (settings.loop) {
    if (distance(knots.front().position, knots.back().position) > kSamePointM) {
      throw std::invalid_argument(
          "waypoints.loop: the last point must be the first one (a closed path), " +
          format_coordinate(distance(knots.front().position, knots.back().position)) + " m away");
    }
    period_s_ = knots.back().time_s - knots.front().time_s;
    detail::require(period_s_ > 0.0, "waypoints.loop", "needs a path that takes time: period",
                    period_s_);
  }
  track_ = PiecewiseLinearTrack(std::move(knots));
}

MotionState WaypointModel::state_at(double t_s) {
  const double start = track_.start_s();
  if (period_s_ > 0.0 && t_s > start) {
    t_s = start + std::fmod(t_s - start, period_s_);
  }
  return track_.state_at(t_s, cursor_);
}

}  // namespace rfsitl::position::mobility
