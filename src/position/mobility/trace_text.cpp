#include "trace_text.hpp"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <variant>

#include "rfsitl/common/position_limits.hpp"
#include "rfsitl/position/mobility/local_frame.hpp"

namespace rfsitl::position::mobility::detail {

std::optional<std::uint32_t> parse_node(std::string_view token) {
  std::uint32_t v = 0;
  const char* end = token.data() + token.size();
  const auto [ptr, ec] = std::from_chars(token.data(), end, v);
  if (ec != std::errc() || ptr != end || v > TraceParseResult::kMaxNode) return std::nullopt;
  return v;
}

std::string sample_position_error(const Position& p) {
  if (std::string e = position_error(p); !e.empty()) return e;
  if (const auto* l = std::get_if<LocalPosition>(&p)) return local_coordinate_error(*l);
  return "";
}

std::string time_error(double t_s) {
  return coordinate_error("t", t_s, CoordinateLimit{0.0, TraceParseResult::kMaxTraceTimeS});
}

void skip_line(TraceParseResult& result, std::size_t line, std::string reason) {
  ++result.bad_lines;
  if (result.errors.size() < TraceParseResult::kMaxReportedErrors) {
    result.errors.push_back({line, std::move(reason)});
  }
}

std::string read_text_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot read: " + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw std::runtime_error(path + ": cannot read: I/O error");
  return std::move(text).str();
}

}  // namespace rfsitl::position::mobility::detail
