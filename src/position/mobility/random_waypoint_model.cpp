#include "rfsitl/position/mobility/random_waypoint_model.hpp"

#include <cmath>
#include <stdexcept>

#include "settings_check.hpp"
#include "step_cache.hpp"

namespace rfsitl::position::mobility {
namespace {

/// Leg k: leaves `from` at depart_s, reaches `to` at arrive_s, leaves it at leave_s.
struct Leg {
  double depart_s = 0.0;
  double arrive_s = 0.0;
  double leave_s = 0.0;
  LocalPosition from;
  LocalPosition to;
  Velocity velocity;
};

LocalPosition draw_point(const Box& box, detail::MobilityRandom& r) {
  return box.clamp({r.uniform(box.x_min_m, box.x_max_m), r.uniform(box.y_min_m, box.y_max_m),
                    r.uniform(box.z_min_m, box.z_max_m)});
}

struct LegGenerator {
  RandomWaypointSettings s;

  Leg first(detail::MobilityRandom& r) const {
    const LocalPosition start = s.start ? *s.start : draw_point(s.box, r);
    return leg_from(start, 0.0, r);
  }
  Leg next(const Leg& prev, detail::MobilityRandom& r) const {
    return leg_from(prev.to, prev.leave_s, r);
  }

  Leg leg_from(const LocalPosition& from, double depart_s, detail::MobilityRandom& r) const {
    Leg leg;
    leg.depart_s = depart_s;
    leg.from = from;
    leg.to = draw_point(s.box, r);
    const double speed = r.uniform(s.speed_min_mps, s.speed_max_mps);
    const double dx = leg.to.x_m - from.x_m;
    const double dy = leg.to.y_m - from.y_m;
    const double dz = leg.to.z_m - from.z_m;
    const double length = std::sqrt(dx * dx + dy * dy + dz * dz);
    leg.arrive_s = depart_s + length / speed;
    leg.leave_s = leg.arrive_s + s.pause_s;
    if (length > 0.0)
      leg.velocity = {dx / length * speed, dy / length * speed, dz / length * speed};
    return leg;
  }
};

}  // namespace

void RandomWaypointSettings::validate() const {
  box.validate("random_waypoint.box");
  detail::require(speed_min_mps > 0.0 && std::isfinite(speed_min_mps),
                  "random_waypoint.speed_min_mps", "must be > 0 and finite", speed_min_mps);
  detail::require(speed_max_mps >= speed_min_mps && std::isfinite(speed_max_mps),
                  "random_waypoint.speed_max_mps", "must be >= speed_min_mps and finite",
                  speed_max_mps);
  detail::require(pause_s >= 0.0 && std::isfinite(pause_s), "random_waypoint.pause_s",
                  "must be >= 0 and finite", pause_s);
  // Legs of a one-point box take no time: without a pause time would never advance.
  if (box.is_point()) {
    detail::require(pause_s > 0.0, "random_waypoint.pause_s", "must be > 0 when the box is a point",
                    pause_s);
  }
  if (start) {
    detail::require_position("random_waypoint.start", *start);
    if (!box.contains(*start)) {
      throw std::invalid_argument("random_waypoint.start must be inside random_waypoint.box");
    }
  }
}

struct RandomWaypointModel::Impl {
  detail::StepCache<Leg, LegGenerator> legs;
  LocalPosition start = legs.at(0).from;
  std::size_t cursor = 0;  // the leg of the last answer

  // The leg whose [depart_s, leave_s) holds t_s (t_s >= 0).
  Leg find(double t_s) {
    if (t_s < legs.at(cursor).depart_s) {
      std::size_t lo = legs.begin_index();
      if (t_s >= legs.at(lo).depart_s) {
        // Back in time within the kept window: depart_s(lo) <= t_s < depart_s(hi).
        std::size_t hi = cursor;
        while (hi - lo > 1) {
          const std::size_t mid = lo + (hi - lo) / 2;
          if (t_s < legs.at(mid).depart_s) {
            hi = mid;
          } else {
            lo = mid;
          }
        }
        cursor = lo;
      } else {
        cursor = 0;  // before the window: walk again from the seed's first leg
      }
    }
    while (t_s >= legs.at(cursor).leave_s) ++cursor;
    return legs.at(cursor);
  }
};

RandomWaypointModel::RandomWaypointModel(const RandomWaypointSettings& settings) {
  settings.validate();
  impl_ = std::make_unique<Impl>(Impl{{LegGenerator{settings}, settings.seed}});
}

RandomWaypointModel::~RandomWaypointModel() = default;
RandomWaypointModel::RandomWaypointModel(RandomWaypointModel&&) noexcept = default;
RandomWaypointModel& RandomWaypointModel::operator=(RandomWaypointModel&&) noexcept = default;

MotionState RandomWaypointModel::state_at(double t_s) {
  if (t_s < 0.0) return {impl_->start, {}};
  const Leg leg = impl_->find(t_s);
  if (t_s >= leg.arrive_s) return {leg.to, {}};
  const double tau = t_s - leg.depart_s;
  const Box& box = impl_->legs.generator().s.box;
  // Clamped: rounding must not put a node a hair outside its box.
  return {
      box.clamp({leg.from.x_m + leg.velocity.vx_mps * tau, leg.from.y_m + leg.velocity.vy_mps * tau,
                 leg.from.z_m + leg.velocity.vz_mps * tau}),
      leg.velocity};
}

}  // namespace rfsitl::position::mobility
