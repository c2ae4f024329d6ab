#include "rfsitl/position/mobility/local_frame.hpp"

#include <cmath>
#include <variant>

#include "rfsitl/common/geodesy.hpp"
#include "rfsitl/common/position_limits.hpp"

namespace rfsitl::position::mobility {

LocalPosition to_local(const Position& p, const GeodeticPosition& origin) {
  if (const auto* l = std::get_if<LocalPosition>(&p)) return *l;
  return ecef_to_local(geodetic_to_ecef(std::get<GeodeticPosition>(p)), origin);
}

std::string local_coordinate_error(const LocalPosition& p) {
  constexpr CoordinateLimit kLimit{-kMaxLocalCoordinateM, kMaxLocalCoordinateM};
  for (const auto& [axis, v] : {std::pair{"x", p.x_m}, {"y", p.y_m}, {"z", p.z_m}}) {
    if (std::string e = coordinate_error(axis, v, kLimit); !e.empty()) return e;
  }
  return "";
}

}  // namespace rfsitl::position::mobility
