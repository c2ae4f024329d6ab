#include "rfsitl/position/mavlink_source/mavlink_source.hpp"

namespace rfsitl::position {

PositionSourceComponent mavlink_source_component() {
  return {mavlink_source_settings().info(
              "position", "mavlink",
              "follows a vehicle's GLOBAL_POSITION_INT and ATTITUDE over MAVLink (ArduPilot, "
              "PX4); wall clock only"),
          true,
          [](const SourceContext&, const std::vector<SourceNode>& nodes) {
            return make_mavlink_source(nodes);
          },
          {"--mavlink", "endpoint", "ENDPOINT",
           "Follow MAVLink vehicles: tcp:HOST:PORT (connect) or udp:HOST:PORT (listen), +STEP: "
           "node n uses PORT + STEP (n - 1); e.g. tcp:127.0.0.1:5762+10 follows ArduPilot SITL "
           "instances 0, 1, 2 ... (rfsitl mavlink-send plays vehicles)"}};
}

}  // namespace rfsitl::position
