#pragma once
// What the CSV and ns-2 readers share: lines, fields, numbers, and the
// bookkeeping of skipped lines.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "rfsitl/common/position.hpp"
#include "rfsitl/common/text_lines.hpp"
#include "rfsitl/position/mobility/trace_parse_result.hpp"

namespace rfsitl::position::mobility::detail {

using text::for_each_line;
using text::is_blank_or_comment;
using text::parse_number;
using text::quote;
using text::trim;

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
