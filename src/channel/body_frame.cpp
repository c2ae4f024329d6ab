// The local-to-body rotation (body_frame.hpp writes out the matrix).
#include "rfsitl/channel/body_frame.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace rfsitl::channel {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

}  // namespace

BodyVector to_body(const EnuVector& v, const std::optional<Orientation>& attitude) {
  const Orientation a = attitude.value_or(Orientation{});
  const double cph = std::cos(a.roll_rad), sph = std::sin(a.roll_rad);
  const double cth = std::cos(a.pitch_rad), sth = std::sin(a.pitch_rad);
  const double cps = std::cos(a.yaw_rad), sps = std::sin(a.yaw_rad);
  const double n = v.north, e = v.east, d = -v.up;
  return {cth * cps * n + cth * sps * e - sth * d,
          (sph * sth * cps - cph * sps) * n + (sph * sth * sps + cph * cps) * e + sph * cth * d,
          (cph * sth * cps + sph * sps) * n + (cph * sth * sps - sph * cps) * e + cph * cth * d};
}

std::optional<BodyVector> direction_in_body(const LinkEnd& from, const LinkEnd& to) {
  const EnuVector v{to.local.x_m - from.local.x_m, to.local.y_m - from.local.y_m,
                    to.local.z_m - from.local.z_m};
  const double length = std::hypot(v.east, v.north, v.up);
  if (!(length > 0.0)) return std::nullopt;
  const BodyVector b = to_body(v, from.attitude);
  return BodyVector{b.forward / length, b.right / length, b.down / length};
}

BodyVector body_vector_at(double azimuth_deg, double elevation_deg) {
  const double az = azimuth_deg / kDegPerRad;
  const double el = elevation_deg / kDegPerRad;
  return {std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), -std::sin(el)};
}

double azimuth_deg(const BodyVector& u) {
  double az = std::atan2(u.right, u.forward) * kDegPerRad;
  if (az < 0.0) az += 360.0;
  // A tiny negative angle plus 360 rounds to 360, which is 0.
  return az >= 360.0 ? 0.0 : az;
}

double elevation_deg(const BodyVector& u) {
  // Clamped: rounding may leave a unit vector's component just beyond 1.
  return std::asin(std::clamp(-u.down, -1.0, 1.0)) * kDegPerRad;
}

}  // namespace rfsitl::channel
