#pragma once
/// The location port: for every node a TCP port where a program sends one
/// position per line (location_line.hpp: lat/lon/alt, JSON, local x/y/z, NMEA
/// GGA), all served by one I/O thread. It is the default source of a node, and
/// it stays open for every node as an override: a line moves any node at once,
/// whatever its own source (which takes over again at its next report).
///
/// Scenario, per node:   position: {source: location_port, port: 16000}
#include <cstdint>
#include <memory>
#include <vector>

#include "rfsitl/config/fields.hpp"
#include "rfsitl/position/source/position_source.hpp"

namespace rfsitl::position {

/// A node's settings, declared once (location_port_settings()).
struct LocationPortSettings {
  std::uint64_t port = 0;      ///< 0: the run's location base + 10 x node id
  double stale_after_s = 0.0;  ///< 0: a silent feed is never shown stale
};

const config::Fields<LocationPortSettings>& location_port_settings();

/// Longest line accepted; a longer one is refused and counted.
inline constexpr std::size_t kMaxLocationLine = 4096;

/// Node `id`'s port: its own `port` setting, else `location_base + 10 id`.
std::uint16_t location_port_number(const LocationPortSettings& s, std::uint16_t location_base,
                                   NodeId id);

/// The source for `nodes` (settings validated). Throws std::invalid_argument
/// naming both nodes when two would listen on one port, or a port passes 65535.
std::unique_ptr<PositionSource> make_location_port_source(const SourceContext& context,
                                                          const std::vector<SourceNode>& nodes);

}  // namespace rfsitl::position
