#pragma once
// What the trace readers share: lines and fields of CSV text, numbers, node
// ids, the sample limits, and the wording of errors.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "rfsitl/channel/stages/trace.hpp"
#include "rfsitl/common/text_lines.hpp"
#include "rfsitl/config/range.hpp"

namespace rfsitl::channel::trace::detail {

using config::number_text;  // the shortest form that reads back exactly
using text::for_each_line;
using text::is_blank_or_comment;
using text::parse_number;
using text::quote;
using text::split_fields;

/// Index of every id (1..255) among the scenario's nodes; -1 for the others.
using IdIndex = std::array<std::int32_t, 256>;
IdIndex index_of_ids(std::span<const NodeId> node_ids);

/// The node id `token` spells when it is one of the scenario's, else nullopt
/// and `why` says what is wrong.
std::optional<NodeId> parse_node(std::string_view token, const IdIndex& known, std::string& why);

/// "2->3".
std::string link_name(LinkIds link);

/// "" when the sample is within the limits of trace.hpp, else why not.
std::string sample_error(const Sample& s);

/// The file name's extension in lower case (".csv"), or "".
std::string extension(const std::string& file);

/// std::invalid_argument("name:line: reason").
[[noreturn]] void fail_at_line(const std::string& name, std::size_t line, const std::string& why);

}  // namespace rfsitl::channel::trace::detail
