#pragma once
/// A circle flown at constant speed and altitude, in closed form.
#include "rfsitl/position/mobility/mobility_model.hpp"

namespace rfsitl::position::mobility {

struct OrbitSettings {
  double centre_x_m = 0.0;  ///< local east of the circle's centre
  double centre_y_m = 0.0;  ///< local north of the circle's centre
  double radius_m = 100.0;  ///< > 0
  /// Ground speed along the circle, m/s; positive flies counter-clockwise seen
  /// from above (east towards north), negative clockwise, zero hovers.
  double speed_mps = 10.0;
  double altitude_m = 0.0;  ///< local z, constant
  /// Angle of the node at t = 0, radians counter-clockwise from east of the centre.
  double phase_rad = 0.0;

  /// Throws std::invalid_argument naming the field ("orbit.radius_m must be > 0
  /// (got 0)"): a non-finite number, radius <= 0, altitude outside the limits.
  void validate() const;
};

/// With w = speed / radius and a = phase + w t:
///   position = (cx + r cos a, cy + r sin a, altitude)
///   velocity = (-r w sin a, r w cos a, 0)
class OrbitModel final : public MobilityModel {
 public:
  /// Validates `settings`.
  explicit OrbitModel(const OrbitSettings& settings);

  MotionState state_at(double t_s) override;

 private:
  OrbitSettings s_;
  double omega_rad_s_;
};

}  // namespace rfsitl::position::mobility
