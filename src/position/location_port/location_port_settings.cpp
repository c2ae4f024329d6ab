#include "rfsitl/position/location_port/location_port_source.hpp"

namespace rfsitl::position {

const config::Fields<LocationPortSettings>& location_port_settings() {
  using S = LocationPortSettings;
  static const auto f =
      config::Fields<S>()
          .integer("port", &S::port, "", 0, 65535,
                   "TCP port of this node's feed; 0: the run's location base + 10 x node id "
                   "(ports.loc_base, --loc-base)")
          .real("stale_after_s", &S::stale_after_s, "s", {0.0, 3600.0},
                "without a line this long the node is shown stale (it keeps its last "
                "position); 0: never");
  return f;
}

std::uint16_t location_port_number(const LocationPortSettings& s, std::uint16_t location_base,
                                   NodeId id) {
  if (s.port != 0) return static_cast<std::uint16_t>(s.port);
  const std::uint64_t p = location_base + 10ULL * id;
  if (p > 65535) {
    throw std::invalid_argument("node " + std::to_string(id) + ": location port " +
                                std::to_string(location_base) + " + 10 x " + std::to_string(id) +
                                " passes 65535 (lower ports.loc_base or give the node a port)");
  }
  return static_cast<std::uint16_t>(p);
}

}  // namespace rfsitl::position
