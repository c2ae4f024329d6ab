// The trace's CSV formats: the samples (t_s,tx,rx,gain_db,phase_deg) and the
// NPY companion's list of links (tx,rx).
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "rfsitl/channel/stages/trace.hpp"
#include "trace_text.hpp"

namespace rfsitl::channel::trace {
namespace {

using detail::fail_at_line;

void check_size(std::size_t bytes, const std::string& name) {
  if (bytes > kMaxFileBytes) {
    throw std::invalid_argument(name + ": " + std::to_string(bytes) +
                                " bytes, more than the 256 MiB a trace file may have");
  }
}

/// Reads a CSV table whose first non-blank, non-comment line must be the
/// header `spelled` (its fields `expected`), calling row(line, fields) for
/// every later row, each with exactly as many fields. Returns the last line's
/// number (1 for an empty text); refuses a text without header or rows.
template <class Row>
std::size_t read_table(std::string_view text, const std::string& name,
                       const std::vector<std::string_view>& expected, const std::string& spelled,
                       const std::string& what, Row row) {
  bool header = false;
  bool rows = false;
  std::size_t last_line = 0;
  detail::for_each_line(text, [&](std::size_t number, std::string_view line) {
    last_line = number;
    if (detail::is_blank_or_comment(line)) return;
    const std::vector<std::string_view> f = detail::split_fields(line);
    if (!header) {
      if (f != expected) {
        fail_at_line(
            name, number,
            "the first line must be the header '" + spelled + "', not " + detail::quote(line));
      }
      header = true;
      return;
    }
    if (f.size() != expected.size()) {
      fail_at_line(name, number,
                   "expected " + std::to_string(expected.size()) + " fields (" + spelled +
                       "), found " + std::to_string(f.size()));
    }
    rows = true;
    row(number, f);
  });
  const std::size_t end_line = last_line == 0 ? 1 : last_line;
  if (!header) fail_at_line(name, end_line, "no header line '" + spelled + "'");
  if (!rows) fail_at_line(name, end_line, "no " + what + " after the header");
  return end_line;
}

/// A directed link from two fields, both of the scenario's ids and distinct.
LinkIds read_link(std::string_view tx_field, std::string_view rx_field,
                  const detail::IdIndex& known, const std::string& name, std::size_t number) {
  std::string why;
  const auto tx = detail::parse_node(tx_field, known, why);
  if (!tx) fail_at_line(name, number, "tx: " + why);
  const auto rx = detail::parse_node(rx_field, known, why);
  if (!rx) fail_at_line(name, number, "rx: " + why);
  if (*tx == *rx) {
    fail_at_line(name, number,
                 "tx and rx are the same node (id " + std::to_string(unsigned{*tx}) +
                     "): a node's link to itself is not traced");
  }
  return {*tx, *rx};
}

std::uint64_t key_of(LinkIds link) {
  return (std::uint64_t{link.tx} << 32) | link.rx;
}

}  // namespace

Trace parse_csv(std::string_view text, const std::string& name, std::span<const NodeId> node_ids) {
  check_size(text.size(), name);
  const detail::IdIndex known = detail::index_of_ids(node_ids);
  static const std::vector<std::string_view> kHeader{"t_s", "tx", "rx", "gain_db", "phase_deg"};
  Trace trace;
  // Which entry of trace.links holds each (tx, rx), from its first row on. A
  // map, not a 256 x 256 table: a parse costs what its file holds.
  std::unordered_map<std::uint64_t, std::size_t> slot;
  const auto row = [&](std::size_t number, const std::vector<std::string_view>& f) {
    const LinkIds link = read_link(f[1], f[2], known, name, number);
    const auto t = detail::parse_number(f[0]);
    if (!t) fail_at_line(name, number, "t_s " + detail::quote(f[0]) + " is not a finite number");
    const auto g = detail::parse_number(f[3]);
    if (!g) {
      fail_at_line(name, number, "gain_db " + detail::quote(f[3]) + " is not a finite number");
    }
    const auto p = detail::parse_number(f[4]);
    if (!p) {
      fail_at_line(name, number, "phase_deg " + detail::quote(f[4]) + " is not a finite number");
    }
    const Sample s{*t, *g, *p};
    if (std::string why = detail::sample_error(s); !why.empty()) fail_at_line(name, number, why);
    const auto [at, first] = slot.try_emplace(key_of(link), trace.links.size());
    if (first) trace.links.push_back({link, {}});
    std::vector<Sample>& samples = trace.links[at->second].samples;
    if (!samples.empty() && s.t_s < samples.back().t_s) {
      fail_at_line(name, number,
                   "t_s goes backwards for link " + detail::link_name(link) + " (" +
                       detail::number_text(s.t_s) + " after " +
                       detail::number_text(samples.back().t_s) + ")");
    }
    samples.push_back(s);
  };
  read_table(text, name, kHeader, "t_s,tx,rx,gain_db,phase_deg", "samples", row);
  return trace;
}

std::vector<LinkIds> parse_links_csv(std::string_view text, const std::string& name,
                                     std::span<const NodeId> node_ids) {
  check_size(text.size(), name);
  const detail::IdIndex known = detail::index_of_ids(node_ids);
  static const std::vector<std::string_view> kHeader{"tx", "rx"};
  std::vector<LinkIds> links;
  std::unordered_map<std::uint64_t, std::size_t> listed_on;  // the line of each link
  const auto row = [&](std::size_t number, const std::vector<std::string_view>& f) {
    const LinkIds link = read_link(f[0], f[1], known, name, number);
    const auto [at, first_time] = listed_on.try_emplace(key_of(link), number);
    if (!first_time) {
      fail_at_line(name, number,
                   "link " + detail::link_name(link) + " is listed twice (first on line " +
                       std::to_string(at->second) + ")");
    }
    links.push_back(link);
  };
  read_table(text, name, kHeader, "tx,rx", "links", row);
  return links;
}

}  // namespace rfsitl::channel::trace
