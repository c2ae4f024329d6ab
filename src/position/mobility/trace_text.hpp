#pragma once
// What the CSV and ns-2 readers share: lines, fields, numbers, and the
// bookkeeping of skipped lines.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "rfsitl/common/position.hpp"
#include "rfsitl/position/mobility/trace_parse_result.hpp"

namespace rfsitl::position::mobility::detail {

/// Calls fn(line_number, line) for every line of `text` (1-based, split at
/// '\n', a trailing '\r' removed).
template <class Fn>
void for_each_line(std::string_view text, Fn&& fn) {
  std::size_t number = 0;
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t nl = text.find('\n', start);
    const std::size_t end = nl == std::string_view::npos ? text.size() : nl;
    std::string_view line = text.substr(start, end - start);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    fn(++number, line);
    start = end + 1;
  }
}

/// `s` without leading and trailing spaces and tabs.
std::string_view trim(std::string_view s);

/// True for lines that carry nothing: empty, white space, or a '#' comment.
bool is_blank_or_comment(std::string_view line);

/// `token` quoted for a message: at most 32 characters, anything but
/// printable ASCII shown as '?', so a binary file cannot garble the log.
std::string quote(std::string_view token);

/// The finite number `token` spells in full (no sign '+', no spaces), or nullopt.
std::optional<double> parse_number(std::string_view token);

/// The node number `token` spells (decimal, 0..TraceParseResult::kMaxNode), or nullopt.
std::optional<std::uint32_t> parse_node(std::string_view token);

/// "" when a sample at `p` is acceptable, else why not: the common position
/// limits (rfsitl/common/position_limits.hpp), then kMaxLocalCoordinateM.
std::string sample_position_error(const Position& p);

/// "" when `t_s` is in [0, TraceParseResult::kMaxTraceTimeS], else why not.
std::string time_error(double t_s);

/// Counts a skipped line and keeps its reason while there is room.
void skip_line(TraceParseResult& result, std::size_t line, std::string reason);

/// The whole file at `path`; throws std::runtime_error("path: cannot read: why").
std::string read_text_file(const std::string& path);

}  // namespace rfsitl::position::mobility::detail
