/// Net ports: the status reply `rfsitl ping` reads from a port
/// (io::parse_status_reply), on arbitrary text.
///
/// Checks, for every reply that parses:
///  - its node list ascends strictly within 1..kMaxNodeId (so its size is
///    bounded by kMaxNodeId whatever the peer sent);
///  - formatting it and parsing that again gives the same status.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz_check.hpp"
#include "rfsitl/common/types.hpp"
#include "rfsitl/io/agent_control.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rfsitl::io;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const auto st = parse_status_reply(text);
  if (!st) return 0;
  FUZZ_CHECK(st->nodes.size() <= rfsitl::kMaxNodeId, "%zu ids", st->nodes.size());
  for (std::size_t i = 0; i < st->nodes.size(); ++i) {
    FUZZ_CHECK(st->nodes[i] >= 1 && st->nodes[i] <= rfsitl::kMaxNodeId, "id %u", st->nodes[i]);
    FUZZ_CHECK(i == 0 || st->nodes[i] > st->nodes[i - 1], "ids not ascending at %zu", i);
  }
  const std::string again = format_status_reply(*st);
  const auto back = parse_status_reply(again);
  FUZZ_CHECK(back.has_value(), "its own format does not parse: %s", again.c_str());
  FUZZ_CHECK(back->node == st->node && back->agent_connected == st->agent_connected &&
                 back->max_payload == st->max_payload && back->nodes == st->nodes,
             "round trip differs: %s", again.c_str());
  return 0;
}
