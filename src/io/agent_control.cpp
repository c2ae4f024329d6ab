#include "rfsitl/io/agent_control.hpp"

#include <charconv>

namespace rfsitl::io {
namespace {

constexpr std::string_view kStatusPrefix = "rfsitl status ";

/// Reads the value of `key=` from a space-separated list of key=value words.
std::optional<unsigned long long> field(std::string_view text, std::string_view key) {
  std::size_t at = 0;
  while (at < text.size()) {
    std::size_t end = text.find(' ', at);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view word = text.substr(at, end - at);
    if (word.size() > key.size() && word.substr(0, key.size()) == key && word[key.size()] == '=') {
      const std::string_view v = word.substr(key.size() + 1);
      unsigned long long out = 0;
      const auto [ptr, ec] = std::from_chars(v.data(), v.data() + v.size(), out);
      if (ec != std::errc{} || ptr != v.data() + v.size()) return std::nullopt;
      return out;
    }
    at = end + 1;
  }
  return std::nullopt;
}

}  // namespace

std::string format_status_reply(const PortStatus& s) {
  return std::string(kStatusPrefix) + "node=" + std::to_string(s.node) +
         " agent=" + (s.agent_connected ? "1" : "0") +
         " max_payload=" + std::to_string(s.max_payload);
}

std::optional<PortStatus> parse_status_reply(std::string_view text) {
  if (text.substr(0, kStatusPrefix.size()) != kStatusPrefix) return std::nullopt;
  text.remove_prefix(kStatusPrefix.size());
  const auto node = field(text, "node");
  const auto agent = field(text, "agent");
  const auto max_payload = field(text, "max_payload");
  if (!node || !agent || !max_payload || *agent > 1 || *node > 255) return std::nullopt;
  return PortStatus{static_cast<unsigned>(*node), *agent == 1,
                    static_cast<std::size_t>(*max_payload)};
}

}  // namespace rfsitl::io
