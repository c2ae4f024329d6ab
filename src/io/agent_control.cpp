#include "rfsitl/io/agent_control.hpp"

#include <algorithm>
#include <charconv>

#include "rfsitl/common/types.hpp"

namespace rfsitl::io {
namespace {

constexpr std::string_view kStatusPrefix = "rfsitl status ";

/// The text after `key=` in a space-separated list of key=value words.
std::optional<std::string_view> word_value(std::string_view text, std::string_view key) {
  std::size_t at = 0;
  while (at < text.size()) {
    std::size_t end = text.find(' ', at);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view word = text.substr(at, end - at);
    if (word.size() > key.size() && word.substr(0, key.size()) == key && word[key.size()] == '=') {
      return word.substr(key.size() + 1);
    }
    at = end + 1;
  }
  return std::nullopt;
}

/// All of `v` as a decimal number, or nullopt.
std::optional<unsigned long long> number(std::string_view v) {
  unsigned long long out = 0;
  const auto [ptr, ec] = std::from_chars(v.data(), v.data() + v.size(), out);
  if (ec != std::errc{} || ptr != v.data() + v.size()) return std::nullopt;
  return out;
}

std::optional<unsigned long long> field(std::string_view text, std::string_view key) {
  const auto v = word_value(text, key);
  return v ? number(*v) : std::nullopt;
}

/// "1-4,9" -> {1, 2, 3, 4, 9}; nullopt unless every id is in 1..kMaxNodeId and
/// they ascend (which also bounds the list: a reply cannot make us build more
/// than kMaxNodeId ids).
std::optional<std::vector<unsigned>> parse_id_ranges(std::string_view v) {
  std::vector<unsigned> ids;
  if (v.empty() || v.back() == ',') return std::nullopt;
  while (!v.empty()) {
    const std::size_t comma = std::min(v.find(','), v.size());
    const std::string_view item = v.substr(0, comma);
    const std::size_t dash = item.find('-');
    const auto first = number(item.substr(0, dash));
    const auto last = dash == std::string_view::npos ? first : number(item.substr(dash + 1));
    if (!first || !last || *first < 1 || *last < *first || *last > kMaxNodeId) return std::nullopt;
    if (!ids.empty() && *first <= ids.back()) return std::nullopt;
    for (auto id = *first; id <= *last; ++id) ids.push_back(static_cast<unsigned>(id));
    v.remove_prefix(std::min(v.size(), comma + 1));
  }
  return ids;
}

}  // namespace

std::string format_status_reply(const PortStatus& s) {
  return std::string(kStatusPrefix) + "node=" + std::to_string(s.node) +
         " agent=" + (s.agent_connected ? "1" : "0") +
         " max_payload=" + std::to_string(s.max_payload) +
         (s.nodes.empty() ? "" : " nodes=" + format_id_ranges(s.nodes));
}

std::string format_id_ranges(const std::vector<unsigned>& ids) {
  std::string out;
  for (std::size_t i = 0; i < ids.size();) {
    std::size_t j = i;
    while (j + 1 < ids.size() && ids[j + 1] == ids[j] + 1) ++j;
    out += (out.empty() ? "" : ",") + std::to_string(ids[i]);
    if (j > i) out += "-" + std::to_string(ids[j]);
    i = j + 1;
  }
  return out;
}

std::string id_list_text(const std::vector<unsigned>& ids) {
  std::string out;
  for (const unsigned id : ids) out += (out.empty() ? "" : ", ") + std::to_string(id);
  return out;
}

std::optional<PortStatus> parse_status_reply(std::string_view text) {
  if (text.substr(0, kStatusPrefix.size()) != kStatusPrefix) return std::nullopt;
  text.remove_prefix(kStatusPrefix.size());
  const auto node = field(text, "node");
  const auto agent = field(text, "agent");
  const auto max_payload = field(text, "max_payload");
  if (!node || !agent || !max_payload || *agent > 1 || *node > 255) return std::nullopt;
  PortStatus st{
      static_cast<unsigned>(*node), *agent == 1, static_cast<std::size_t>(*max_payload), {}};
  if (const auto list = word_value(text, "nodes")) {
    auto ids = parse_id_ranges(*list);
    if (!ids) return std::nullopt;
    st.nodes = std::move(*ids);
  }
  return st;
}

}  // namespace rfsitl::io
