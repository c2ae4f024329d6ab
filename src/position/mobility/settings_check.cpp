#include "settings_check.hpp"

#include <stdexcept>

#include "rfsitl/common/position_limits.hpp"
#include "rfsitl/position/mobility/local_frame.hpp"

namespace rfsitl::position::mobility::detail {

void reject(std::string_view field, std::string_view rule, double got) {
  throw std::invalid_argument(std::string(field) + " " + std::string(rule) + " (got " +
                              format_coordinate(got) + ")");
}

std::string indexed(std::string_view base, std::size_t i, std::string_view member) {
  return std::string(base) + "[" + std::to_string(i) + "]." + std::string(member);
}

void require_position(std::string_view field, const Position& p) {
  std::string why = position_error(p);
  if (why.empty()) {
    if (const auto* l = std::get_if<LocalPosition>(&p)) why = local_coordinate_error(*l);
  }
  if (!why.empty()) throw std::invalid_argument(std::string(field) + ": " + why);
}

}  // namespace rfsitl::position::mobility::detail
