#include "rfsitl/position/mobility/static_model.hpp"

#include "rfsitl/position/mobility/local_frame.hpp"
#include "settings_check.hpp"

namespace rfsitl::position::mobility {

void StaticSettings::validate() const {
  detail::require_position("static.position", position);
}

StaticModel::StaticModel(const StaticSettings& settings, const GeodeticPosition& origin) {
  settings.validate();
  position_ = to_local(settings.position, origin);
}

MotionState StaticModel::state_at(double /*t_s*/) {
  return {position_, {}};
}

}  // namespace rfsitl::position::mobility
