#include "rfsitl/position/mobility/box.hpp"

#include <algorithm>
#include <string>

#include "settings_check.hpp"

namespace rfsitl::position::mobility {

bool Box::contains(const LocalPosition& p) const {
  return p.x_m >= x_min_m && p.x_m <= x_max_m && p.y_m >= y_min_m && p.y_m <= y_max_m &&
         p.z_m >= z_min_m && p.z_m <= z_max_m;
}

bool Box::is_point() const {
  return x_min_m == x_max_m && y_min_m == y_max_m && z_min_m == z_max_m;
}

LocalPosition Box::clamp(const LocalPosition& p) const {
  return {std::clamp(p.x_m, x_min_m, x_max_m), std::clamp(p.y_m, y_min_m, y_max_m),
          std::clamp(p.z_m, z_min_m, z_max_m)};
}

void Box::validate(std::string_view field) const {
  const std::string f(field);
  // The corners must be positions a trace could hold, so every point inside is.
  detail::require_position(f + ".min", LocalPosition{x_min_m, y_min_m, z_min_m});
  detail::require_position(f + ".max", LocalPosition{x_max_m, y_max_m, z_max_m});
  detail::require(x_min_m <= x_max_m, f + ".x_max_m", "must be >= x_min_m", x_max_m);
  detail::require(y_min_m <= y_max_m, f + ".y_max_m", "must be >= y_min_m", y_max_m);
  detail::require(z_min_m <= z_max_m, f + ".z_max_m", "must be >= z_min_m", z_max_m);
}

}  // namespace rfsitl::position::mobility
