#include "rfsitl/position/location_port/location_port_source.hpp"

namespace rfsitl::position {

PositionSourceComponent location_port_component() {
  // Not wall-clock bound: a line moves its node at whatever tick the engine
  // has reached, in virtual time too (the engine's pending-position inbox).
  return {location_port_settings().info(
              "position", "location_port",
              "one position per line on a TCP port per node (lat lon alt, JSON, local x/y/z, "
              "NMEA GGA); the default source, and an override for every node"),
          false,
          make_location_port_source,
          {}};
}

}  // namespace rfsitl::position
