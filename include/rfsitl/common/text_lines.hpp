#pragma once
/// Reading line-oriented text files from outside (traces, tables): lines,
/// comma-separated fields, numbers, and tokens quoted safely for messages.
/// Header-only; shared by the mobility traces and the channel's data files.
#include <charconv>
#include <cmath>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace rfsitl::text {

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
inline std::string_view trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  return s.substr(first, s.find_last_not_of(" \t") - first + 1);
}

/// True for lines that carry nothing: empty, white space, or a '#' comment.
inline bool is_blank_or_comment(std::string_view line) {
  const std::string_view t = trim(line);
  return t.empty() || t.front() == '#';
}

/// The comma-separated fields of `line`, each without surrounding spaces/tabs.
inline std::vector<std::string_view> split_fields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    if (comma == std::string_view::npos) {
      fields.push_back(trim(line.substr(start)));
      return fields;
    }
    fields.push_back(trim(line.substr(start, comma - start)));
    start = comma + 1;
  }
}

/// `token` quoted for a message: at most 32 characters, anything but
/// printable ASCII shown as '?', so a binary file cannot garble the log.
inline std::string quote(std::string_view token) {
  constexpr std::size_t kMax = 32;
  std::string out = "'";
  for (std::size_t i = 0; i < token.size() && i < kMax; ++i) {
    const char c = token[i];
    out += (c >= 0x20 && c < 0x7f) ? c : '?';
  }
  if (token.size() > kMax) out += "...";
  return out + "'";
}

/// The finite number `token` spells in full (no sign '+', no spaces), or nullopt.
inline std::optional<double> parse_number(std::string_view token) {
  double v = 0.0;
  const char* end = token.data() + token.size();
  const auto [ptr, ec] = std::from_chars(token.data(), end, v);
  if (token.empty() || ec != std::errc() || ptr != end || !std::isfinite(v)) return std::nullopt;
  return v;
}

}  // namespace rfsitl::text
