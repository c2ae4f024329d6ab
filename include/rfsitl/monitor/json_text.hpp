#pragma once
/// JSON as text for the wire. Strings from outside (a scenario's name, a
/// request's path or Host) may hold bytes that are not UTF-8; nlohmann::json
/// would throw on them, on a server thread with nothing to catch it. They are
/// replaced by U+FFFD instead.
#include <string>

#include <nlohmann/json.hpp>

namespace rfsitl::monitor {

inline std::string json_text(const nlohmann::json& j, int indent = -1) {
  return j.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace rfsitl::monitor
