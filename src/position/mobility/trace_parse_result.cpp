#include "rfsitl/position/mobility/trace_parse_result.hpp"

namespace rfsitl::position::mobility {

std::string TraceParseResult::message(const TraceLineError& e) const {
  return source + ":" + std::to_string(e.line) + ": " + e.reason;
}

}  // namespace rfsitl::position::mobility
