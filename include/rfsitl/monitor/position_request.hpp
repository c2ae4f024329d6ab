#pragma once
/// A position a viewer asks for (POST /api/nodes/ID/position, the WebSocket
/// "move" message), read with the location port's limits
/// (rfsitl/common/position_limits.hpp) and refused in our own words.
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "rfsitl/common/position.hpp"

namespace rfsitl::monitor {

struct PositionRequest {
  std::optional<Position> position;  ///< set when accepted
  std::string error;                 ///< else why not, naming the field ("x: expected a number")
};

/// Reads {"x","y"[,"z"]} (local metres) or {"lat","lon"[,"alt"]} from `body`;
/// other keys ("type", "node") are ignored. A missing z or alt is
/// `default_z_m` or `default_alt_m` (the node's current height). Mixing the two
/// forms, a missing or non-number coordinate, or a value out of the limits is
/// an error.
PositionRequest read_position_request(const nlohmann::json& body, double default_z_m,
                                      double default_alt_m);

}  // namespace rfsitl::monitor
