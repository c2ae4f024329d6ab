#pragma once
/// A node's body frame, for the stages whose gain depends on where the body
/// points (antenna, occlusion): the direction of a link's other end as seen
/// from one end's airframe.
///
/// Frames. The local frame is ENU (x east, y north, z up; LinkEnd::local). The
/// body frame is MAVLink's FRD: x forward, y right, z down. An attitude is
/// MAVLink's ATTITUDE: yaw psi clockwise from north, pitch theta nose up, roll
/// phi right wing down, applied in that order (Z-Y-X Tait-Bryan angles). A node
/// whose source never reported an attitude counts as level and facing north
/// (roll = pitch = yaw = 0), so its body x is north, y east, z down.
///
/// Rotation. With the local vector as NED (n = north, e = east, d = -up), the
/// body vector is R^T (n, e, d), R = Rz(psi) Ry(theta) Rx(phi) the body-to-NED
/// rotation; written out (c = cos, s = sin):
///   forward = c(th)c(ps) n + c(th)s(ps) e - s(th) d
///   right = (s(ph)s(th)c(ps) - c(ph)s(ps)) n + (s(ph)s(th)s(ps) + c(ph)c(ps)) e + s(ph)c(th) d
///   down  = (c(ph)s(th)c(ps) + s(ph)s(ps)) n + (c(ph)s(th)s(ps) - s(ph)c(ps)) e + c(ph)c(th) d
/// e.g. yaw 90 deg (facing east): east is forward and north is left; roll
/// 90 deg: down is right (the right wing points at the ground).
///
/// Angles of a body direction u: azimuth = atan2(u.right, u.forward) in
/// [0, 360) degrees, clockwise from the nose seen from above the body (90 =
/// right wing); elevation = asin(-u.down) in [-90, 90] degrees, above the
/// body's x-y plane (-90 = straight down through the belly).
///
/// Positions are taken from LinkEnd::local: the frame is the one at the
/// scenario's origin, whose tilt against a node's own horizon (about 0.01 deg
/// per km from the origin) is far below any pattern's resolution.
#include <optional>

#include "rfsitl/channel/link_geometry.hpp"

namespace rfsitl::channel {

/// A vector in the local frame: metres or unitless.
struct EnuVector {
  double east = 0.0;
  double north = 0.0;
  double up = 0.0;
};

/// A vector in a node's body frame (FRD).
struct BodyVector {
  double forward = 0.0;
  double right = 0.0;
  double down = 0.0;
};

inline double dot(const BodyVector& a, const BodyVector& b) {
  return a.forward * b.forward + a.right * b.right + a.down * b.down;
}

/// `v` in the body frame of a node turned by `attitude` (the formula above;
/// nullopt: level, facing north). Preserves length. Pure, thread-safe.
BodyVector to_body(const EnuVector& v, const std::optional<Orientation>& attitude);

/// The unit vector from `from` towards `to`, in `from`'s body frame; nullopt
/// when the two ends are at the same place (no direction).
std::optional<BodyVector> direction_in_body(const LinkEnd& from, const LinkEnd& to);

/// The unit body vector at `azimuth_deg`, `elevation_deg` (the angles above).
BodyVector body_vector_at(double azimuth_deg, double elevation_deg);

/// The azimuth of `u` in degrees, [0, 360) (0 for a vector along the body z axis).
double azimuth_deg(const BodyVector& u);

/// The elevation of the unit vector `u` in degrees, [-90, 90].
double elevation_deg(const BodyVector& u);

}  // namespace rfsitl::channel
