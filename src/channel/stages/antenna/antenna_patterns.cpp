// The analytic patterns: the half-wave dipole and TR 38.901's element.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "rfsitl/channel/stages/antenna.hpp"

namespace rfsitl::channel::antenna {
namespace {

// TR 38.901 Table 7.3-1: 3 dB beamwidths, side-lobe level and front-to-back ratio.
constexpr double kPatchBeamwidthDeg = 65.0;
constexpr double kPatchSideLobeDb = 30.0;
constexpr double kPatchFrontToBackDb = 30.0;

double square(double x) {
  return x * x;
}

}  // namespace

BodyVector axis_vector(BodyAxis axis) {
  switch (axis) {
    case BodyAxis::kForward:
      return {1.0, 0.0, 0.0};
    case BodyAxis::kBackward:
      return {-1.0, 0.0, 0.0};
    case BodyAxis::kRight:
      return {0.0, 1.0, 0.0};
    case BodyAxis::kLeft:
      return {0.0, -1.0, 0.0};
    case BodyAxis::kUp:
      return {0.0, 0.0, -1.0};
    case BodyAxis::kDown:
      break;
  }
  return {0.0, 0.0, 1.0};
}

double dipole_gain_dbi(double peak_dbi, double cos_from_axis) {
  const double c = std::clamp(cos_from_axis, -1.0, 1.0);
  const double sin_from_axis = std::sqrt(1.0 - c * c);
  // Near the axis the field ~ (pi / 4) sin t: far below the floor long before
  // sin t reaches 0, so the division below is never reached with 0.
  if (sin_from_axis < 1e-6) return peak_dbi + kDipoleNullFloorDb;
  const double field = std::cos(std::numbers::pi / 2.0 * c) / sin_from_axis;
  return peak_dbi + std::max(20.0 * std::log10(std::abs(field)), kDipoleNullFloorDb);
}

double patch_gain_dbi(double peak_dbi, double zenith_deg, double azimuth_deg) {
  const double vertical =
      -std::min(12.0 * square((zenith_deg - 90.0) / kPatchBeamwidthDeg), kPatchSideLobeDb);
  const double horizontal =
      -std::min(12.0 * square(azimuth_deg / kPatchBeamwidthDeg), kPatchFrontToBackDb);
  return peak_dbi - std::min(-(vertical + horizontal), kPatchFrontToBackDb);
}

}  // namespace rfsitl::channel::antenna
