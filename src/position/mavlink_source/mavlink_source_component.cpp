#include "rfsitl/position/mavlink_source/mavlink_source.hpp"

namespace rfsitl::position {

PositionSourceComponent mavlink_source_component() {
  return {mavlink_source_settings().info(
              "position", "mavlink",
              "follows a vehicle's GLOBAL_POSITION_INT and ATTITUDE over MAVLink (ArduPilot, "
              "PX4); wall clock only"),
          true, [](const SourceContext&, const std::vector<SourceNode>& nodes) {
            return make_mavlink_source(nodes);
          }};
}

}  // namespace rfsitl::position
