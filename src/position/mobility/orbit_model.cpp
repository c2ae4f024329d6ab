#include "rfsitl/position/mobility/orbit_model.hpp"

#include <cmath>

#include "rfsitl/position/mobility/local_frame.hpp"
#include "settings_check.hpp"

namespace rfsitl::position::mobility {

void OrbitSettings::validate() const {
  detail::require_position("orbit.centre", LocalPosition{centre_x_m, centre_y_m, altitude_m});
  detail::require(radius_m > 0.0 && radius_m <= kMaxLocalCoordinateM, "orbit.radius_m",
                  "must be > 0 and <= 1e8", radius_m);
  detail::require(std::isfinite(speed_mps), "orbit.speed_mps", "must be finite", speed_mps);
  detail::require(std::isfinite(phase_rad), "orbit.phase_rad", "must be finite", phase_rad);
}

namespace {
const OrbitSettings& validated(const OrbitSettings& s) {
  s.validate();
  return s;
}
}  // namespace

OrbitModel::OrbitModel(const OrbitSettings& settings)
    : s_(validated(settings)), omega_rad_s_(s_.speed_mps / s_.radius_m) {}

MotionState OrbitModel::state_at(double t_s) {
  const double a = s_.phase_rad + omega_rad_s_ * t_s;
  const double c = std::cos(a);
  const double s = std::sin(a);
  return {{s_.centre_x_m + s_.radius_m * c, s_.centre_y_m + s_.radius_m * s, s_.altitude_m},
          {-s_.speed_mps * s, s_.speed_mps * c, 0.0}};
}

}  // namespace rfsitl::position::mobility
