// The mobility model "orbit": a circle at constant speed and altitude.
#include "../component_support.hpp"
#include "rfsitl/position/mobility/orbit_model.hpp"

namespace rfsitl::position::mobility {
namespace {

using namespace detail;

const config::Fields<OrbitSettings>& orbit_fields() {
  using S = OrbitSettings;
  static const auto f =
      config::Fields<S>()
          .real("centre_x_m", &S::centre_x_m, "m", kEastNorth, "centre, east")
          .real("centre_y_m", &S::centre_y_m, "m", kEastNorth, "centre, north")
          .real("radius_m", &S::radius_m, "m", {0, kHorizontalLimit.hi, true}, "radius")
          .real("speed_mps", &S::speed_mps, "m/s", {-1e4, 1e4},
                "ground speed; positive counter-clockwise seen from above")
          .real("altitude_m", &S::altitude_m, "m", kHeight, "local z")
          .real("phase_rad", &S::phase_rad, "rad", {-1e3, 1e3},
                "angle at t = 0, counter-clockwise from east of the centre")
          .rule(checked<S>);
  return f;
}

}  // namespace

MobilityComponent orbit_component() {
  return {orbit_fields().info("mobility", "orbit", "a circle at constant speed and altitude"),
          [](const config::Settings& s, const MobilityContext&) -> std::unique_ptr<MobilityModel> {
            return std::make_unique<OrbitModel>(orbit_fields().build(s));
          }};
}

}  // namespace rfsitl::position::mobility
