// The trace readers' shared pieces (trace_text.hpp).
#include "trace_text.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace rfsitl::channel::trace::detail {

IdIndex index_of_ids(std::span<const NodeId> node_ids) {
  IdIndex index;
  index.fill(-1);
  for (std::size_t i = 0; i < node_ids.size(); ++i) {
    index[node_ids[i]] = static_cast<std::int32_t>(i);
  }
  return index;
}

std::optional<NodeId> parse_node(std::string_view token, const IdIndex& known, std::string& why) {
  unsigned v = 0;
  const char* end = token.data() + token.size();
  const auto [ptr, ec] = std::from_chars(token.data(), end, v);
  if (token.empty() || ec != std::errc() || ptr != end) {
    why = quote(token) + " is not a node id";
    return std::nullopt;
  }
  if (v > 255 || known[v] < 0) {
    why = "unknown node id " + std::to_string(v) + " (not in the scenario's nodes)";
    return std::nullopt;
  }
  return static_cast<NodeId>(v);
}

std::string link_name(LinkIds link) {
  return std::to_string(unsigned{link.tx}) + "->" + std::to_string(unsigned{link.rx});
}

std::string sample_error(const Sample& s) {
  if (!(s.t_s >= 0.0 && s.t_s <= kMaxTimeS)) {
    return "t_s " + number_text(s.t_s) + " is outside [0, 1e9]";
  }
  if (!(s.gain_db >= kMinGainDb && s.gain_db <= kMaxGainDb)) {
    return "gain_db " + number_text(s.gain_db) + " is outside [-300, 100]";
  }
  if (!(std::abs(s.phase_deg) <= kMaxPhaseDeg)) {
    return "phase_deg " + number_text(s.phase_deg) + " is outside [-1e9, 1e9]";
  }
  return "";
}

std::string extension(const std::string& file) {
  std::string ext = std::filesystem::path(file).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

void fail_at_line(const std::string& name, std::size_t line, const std::string& why) {
  throw std::invalid_argument(name + ":" + std::to_string(line) + ": " + why);
}

}  // namespace rfsitl::channel::trace::detail
