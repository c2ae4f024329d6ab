#pragma once
// Shared by the models' validate(): one wording for every rejected setting,
// "<field> <rule> (got <value>)", so a scenario error reads the same whatever
// model it names.
#include <string>
#include <string_view>

#include "rfsitl/common/position.hpp"

namespace rfsitl::position::mobility::detail {

/// Throws std::invalid_argument("<field> <rule> (got <value>)").
[[noreturn]] void reject(std::string_view field, std::string_view rule, double got);

/// reject() unless `ok`. A NaN fails every comparison, so `ok` built from
/// comparisons already refuses it.
inline void require(bool ok, std::string_view field, std::string_view rule, double got) {
  if (!ok) reject(field, rule, got);
}

/// "<base>[<i>].<member>", e.g. "waypoints.points[2].speed_mps".
std::string indexed(std::string_view base, std::size_t i, std::string_view member);

/// Throws std::invalid_argument("<field>: <why>") when `p` fails the common
/// position limits or, once local, kMaxLocalCoordinateM.
void require_position(std::string_view field, const Position& p);

}  // namespace rfsitl::position::mobility::detail
