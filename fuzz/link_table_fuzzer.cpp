/// The link table's two readers of outside input: `rfsitl links` reading a
/// server's /api/links document (monitor::link_table_text) and the dashboard
/// reading a request's query (monitor::parse_link_query).
///
/// Input: [1 byte: which][text...]; which even: a document, odd: a query.
/// Checks:
///  - a document either gives a table with one header pair and one line per
///    link, or an error text, never both or neither;
///  - a query either parses within its ranges (payload 1..65535, top and
///    worst not both) or gives an error text;
///  - the document the dashboard would write for a parsed query (with no
///    links) reads back as a table.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz_check.hpp"
#include "rfsitl/monitor/link_table.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rfsitl::monitor;
  if (size < 1) return 0;
  const std::string_view text(reinterpret_cast<const char*>(data + 1), size - 1);
  std::string error;
  if (data[0] % 2 == 0) {
    const auto table = link_table_text(text, error);
    FUZZ_CHECK(table.has_value() != !error.empty(), "table and error: '%s'", error.c_str());
    if (table) {
      const auto doc = nlohmann::json::parse(text);
      std::size_t lines = 0;
      for (const char c : *table) lines += c == '\n' ? 1 : 0;
      FUZZ_CHECK(lines == 2 + doc.at("links").size(), "%zu lines", lines);
    }
    return 0;
  }
  const auto q = parse_link_query(text, error);
  FUZZ_CHECK(q.has_value() != !error.empty(), "query and error: '%s'", error.c_str());
  if (!q) return 0;
  FUZZ_CHECK(q->payload_bytes >= 1 && q->payload_bytes <= 65535 && q->top <= 65535 &&
                 q->worst <= 65535 && !(q->top > 0 && q->worst > 0),
             "out of range");
  const std::string doc = link_table_json({}, 3, *q, 1e-9).dump();
  FUZZ_CHECK(link_table_text(doc, error).has_value(), "own document refused: %s", error.c_str());
  return 0;
}
