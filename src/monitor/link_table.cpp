#include "rfsitl/monitor/link_table.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>

#include "rfsitl/monitor/stats_report.hpp"
#include "rfsitl/registry/phy_registry.hpp"

namespace rfsitl::monitor {
namespace {

std::optional<double> db(double ratio) {
  if (!(ratio > 0.0) || !std::isfinite(ratio)) return std::nullopt;
  return 10.0 * std::log10(ratio);
}

nlohmann::json or_null(const std::optional<double>& v, int decimals) {
  return v ? nlohmann::json(round_to(*v, decimals)) : nlohmann::json(nullptr);
}

/// Best SNR first; links without one after every link with one.
bool better(const LinkRow& a, const LinkRow& b) {
  if (a.snr_db.has_value() != b.snr_db.has_value()) return a.snr_db.has_value();
  return a.snr_db && *a.snr_db > *b.snr_db;
}

}  // namespace

std::vector<LinkRow> link_rows(const LinkInputs& in) {
  const std::size_t n = in.ids.size();
  std::vector<LinkRow> rows;
  rows.reserve(n * (n > 0 ? n - 1 : 0));
  const auto position = [&](std::size_t i) -> std::optional<Ecef> {
    return i < in.positions.size() ? in.positions[i] : std::nullopt;
  };
  for (std::size_t t = 0; t < n; ++t) {
    for (std::size_t r = 0; r < n; ++r) {
      if (t == r) continue;
      const std::size_t k = t * n + r;
      LinkRow row{in.ids[t], in.ids[r], std::nullopt, std::nullopt, std::nullopt, std::nullopt,
                  0,         0};
      if (const auto a = position(t), b = position(r); a && b) {
        row.distance_m = std::hypot(a->x - b->x, a->y - b->y, a->z - b->z);
      }
      if (k < in.gains.size()) {
        row.gain_db = db(in.gains[k]);
        if (in.noise_variance > 0.0) row.snr_db = db(in.gains[k] / in.noise_variance);
      }
      if (row.snr_db && r < in.curves.size() && in.curves[r]) {
        row.per = in.curves[r](*row.snr_db, in.payload_bytes);
      }
      if (in.outcomes != nullptr && k < in.outcomes->received.size() &&
          k < in.outcomes->lost.size()) {
        row.received = in.outcomes->received[k];
        row.lost = in.outcomes->lost[k];
      }
      rows.push_back(row);
    }
  }
  return rows;
}

std::vector<phy::PerCurve> declared_per_curves(const scenario::Scenario& s) {
  std::vector<phy::PerCurve> curves;
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    const scenario::PhyChoice& phy = s.phy_of(i);
    curves.push_back(phy::declared_per_curve(phy.type, phy.settings));
  }
  return curves;
}

std::optional<LinkQuery> parse_link_query(std::string_view query, std::string& error) {
  LinkQuery q;
  bool seen[4] = {false, false, false, false};
  static constexpr std::string_view kKeys[4] = {"payload", "top", "worst", "min_snr_db"};
  while (!query.empty()) {
    const std::size_t amp = std::min(query.find('&'), query.size());
    const std::string_view item = query.substr(0, amp);
    query.remove_prefix(std::min(query.size(), amp + 1));
    if (item.empty()) continue;
    const std::size_t eq = item.find('=');
    const std::string_view key = item.substr(0, eq);
    const std::string_view value = eq == std::string_view::npos ? "" : item.substr(eq + 1);
    const auto which = std::find(std::begin(kKeys), std::end(kKeys), key) - std::begin(kKeys);
    if (which == 4) {
      error =
          "unknown parameter '" + std::string(key) + "' (known: payload, top, worst, min_snr_db)";
      return std::nullopt;
    }
    if (seen[which]) {
      error = "parameter '" + std::string(key) + "' given twice";
      return std::nullopt;
    }
    seen[which] = true;
    const char* const end = value.data() + value.size();
    if (which == 3) {
      double v = 0;
      const auto [ptr, ec] = std::from_chars(value.data(), end, v);
      if (value.empty() || ec != std::errc{} || ptr != end || !std::isfinite(v)) {
        error = "min_snr_db must be a number of dB";
        return std::nullopt;
      }
      q.min_snr_db = v;
      continue;
    }
    std::size_t v = 0;
    const auto [ptr, ec] = std::from_chars(value.data(), end, v);
    const std::size_t low = which == 0 ? 1 : 0;
    if (value.empty() || ec != std::errc{} || ptr != end || v < low || v > 65535) {
      error = std::string(key) + " must be a whole number in " + std::to_string(low) + "..65535";
      return std::nullopt;
    }
    (which == 0 ? q.payload_bytes : which == 1 ? q.top : q.worst) = v;
  }
  if (q.top > 0 && q.worst > 0) {
    error = "top and worst exclude each other";
    return std::nullopt;
  }
  return q;
}

std::vector<LinkRow> select_links(std::vector<LinkRow> rows, const LinkQuery& q) {
  if (q.min_snr_db) {
    std::erase_if(rows, [&](const LinkRow& r) { return !r.snr_db || *r.snr_db < *q.min_snr_db; });
  }
  if (q.top > 0) {
    const std::size_t k = std::min(q.top, rows.size());
    std::partial_sort(rows.begin(), rows.begin() + static_cast<std::ptrdiff_t>(k), rows.end(),
                      better);
    rows.resize(k);
  } else if (q.worst > 0) {
    std::erase_if(rows, [](const LinkRow& r) { return !r.snr_db.has_value(); });
    const std::size_t k = std::min(q.worst, rows.size());
    std::partial_sort(rows.begin(), rows.begin() + static_cast<std::ptrdiff_t>(k), rows.end(),
                      [](const LinkRow& a, const LinkRow& b) { return *a.snr_db < *b.snr_db; });
    rows.resize(k);
  }
  return rows;
}

nlohmann::json link_table_json(std::span<const LinkRow> rows, std::size_t nodes, const LinkQuery& q,
                               double noise_variance) {
  nlohmann::json links = nlohmann::json::array();
  for (const LinkRow& r : rows) {
    links.push_back({{"tx", r.tx},
                     {"rx", r.rx},
                     {"distance_m", or_null(r.distance_m, 1)},
                     {"gain_db", or_null(r.gain_db, 1)},
                     {"snr_db", or_null(r.snr_db, 1)},
                     {"per", or_null(r.per, 4)},
                     {"received", r.received},
                     {"lost", r.lost}});
  }
  return {{"nodes", nodes},
          {"payload_bytes", q.payload_bytes},
          {"noise_db", or_null(db(noise_variance), 1)},
          {"links_total", nodes * (nodes > 0 ? nodes - 1 : 0)},
          {"links", std::move(links)}};
}

namespace {

/// A document's number field: a finite number, null (nullopt), or wrong
/// (sets `ok` false).
std::optional<double> optional_number(const nlohmann::json& o, const char* key, bool& ok) {
  const auto it = o.find(key);
  if (it == o.end() || it->is_null()) return std::nullopt;
  if (!it->is_number() || !std::isfinite(it->get<double>())) {
    ok = false;
    return std::nullopt;
  }
  return it->get<double>();
}

/// A document's unsigned field no larger than `max`; nullopt when it is not.
std::optional<std::uint64_t> count(const nlohmann::json& o, const char* key, std::uint64_t max) {
  const auto it = o.find(key);
  if (it == o.end() || !it->is_number_unsigned() || it->get<std::uint64_t>() > max) {
    return std::nullopt;
  }
  return it->get<std::uint64_t>();
}

std::string cell(const std::optional<double>& v, const char* format, int width) {
  char buf[48];
  if (v) {
    std::snprintf(buf, sizeof buf, format, width, *v);
  } else {
    std::snprintf(buf, sizeof buf, "%*s", width, "-");
  }
  return buf;
}

}  // namespace

std::optional<std::string> link_table_text(std::string_view doc, std::string& error) {
  const nlohmann::json j = nlohmann::json::parse(doc, nullptr, false);
  const auto fail = [&](std::string why) {
    error = "not a link table: " + std::move(why);
    return std::nullopt;
  };
  if (j.is_discarded() || !j.is_object()) return fail("not a JSON object");
  const auto nodes = count(j, "nodes", kMaxNodeId + 1);
  const auto payload = count(j, "payload_bytes", 65535);
  const auto total = count(j, "links_total", std::uint64_t{65536} * 65536);
  if (!nodes || !payload || !total) return fail("nodes, payload_bytes or links_total missing");
  const auto links = j.find("links");
  if (links == j.end() || !links->is_array()) return fail("no links array");
  char head[160];
  std::snprintf(head, sizeof head,
                "links: %zu of %llu (%llu nodes), PER estimated for %llu-byte frames\n"
                "  tx ->  rx  distance_m   gain_db    snr_db      per  received      lost\n",
                links->size(), static_cast<unsigned long long>(*total),
                static_cast<unsigned long long>(*nodes), static_cast<unsigned long long>(*payload));
  std::string out = head;
  for (const nlohmann::json& l : *links) {
    if (!l.is_object()) return fail("a link is not an object");
    bool ok = true;
    const auto tx = count(l, "tx", 255);
    const auto rx = count(l, "rx", 255);
    const auto received = count(l, "received", UINT32_MAX);
    const auto lost = count(l, "lost", UINT32_MAX);
    const auto distance = optional_number(l, "distance_m", ok);
    const auto gain = optional_number(l, "gain_db", ok);
    const auto snr = optional_number(l, "snr_db", ok);
    const auto per = optional_number(l, "per", ok);
    if (!tx || !rx || !received || !lost || !ok) return fail("a link with a bad field");
    char line[64];
    std::snprintf(line, sizeof line, "%4llu -> %3llu", static_cast<unsigned long long>(*tx),
                  static_cast<unsigned long long>(*rx));
    out += line + cell(distance, "%*.1f", 12) + cell(gain, "%*.1f", 10) + cell(snr, "%*.1f", 10) +
           cell(per, "%*.4f", 9);
    std::snprintf(line, sizeof line, "%10llu%10llu\n", static_cast<unsigned long long>(*received),
                  static_cast<unsigned long long>(*lost));
    out += line;
  }
  return out;
}

void write_link_metrics(std::ostream& o, std::vector<LinkRow> rows, std::size_t nodes) {
  if (nodes > kMetricsAllLinksUpToNodes) {
    LinkQuery best;
    best.top = kMetricsTopLinks;
    rows = select_links(std::move(rows), best);
    // Node order within the chosen links: a scrape reads like a smaller run's.
    std::sort(rows.begin(), rows.end(), [](const LinkRow& a, const LinkRow& b) {
      return std::pair(a.tx, a.rx) < std::pair(b.tx, b.rx);
    });
  }
  const std::string scope = nodes > kMetricsAllLinksUpToNodes
                                ? " Above " + std::to_string(kMetricsAllLinksUpToNodes) +
                                      " nodes only the " + std::to_string(kMetricsTopLinks) +
                                      " links of highest SNR."
                                : std::string();
  const auto labels = [](const LinkRow& r) {
    return "{tx=\"" + std::to_string(r.tx) + "\",rx=\"" + std::to_string(r.rx) + "\"";
  };
  struct Gauge {
    const char* name;
    const char* help;
    std::optional<double> LinkRow::*field;
  };
  static constexpr Gauge kGauges[] = {
      {"rfsitl_link_snr_db", "Each link's SNR (dB, per sample, fading included).",
       &LinkRow::snr_db},
      {"rfsitl_link_gain_db", "Each link's power gain |c|^2 (dB).", &LinkRow::gain_db},
      {"rfsitl_link_per_estimate",
       "The receiver's declared PER at the link's SNR for 80-byte frames (an estimate).",
       &LinkRow::per},
  };
  for (const Gauge& g : kGauges) {
    prometheus_family(o, g.name, "gauge", g.help + scope);
    for (const LinkRow& r : rows) {
      if (const auto& v = r.*g.field)
        o << g.name << labels(r) << "} " << prometheus_number(*v) << '\n';
    }
  }
  prometheus_family(o, "rfsitl_link_frames_total", "counter",
                    "Frames on each link (tx -> rx) by outcome: received (decoded at rx) or "
                    "lost." +
                        scope);
  for (const LinkRow& r : rows) {
    o << "rfsitl_link_frames_total" << labels(r) << ",outcome=\"received\"} " << r.received << '\n'
      << "rfsitl_link_frames_total" << labels(r) << ",outcome=\"lost\"} " << r.lost << '\n';
  }
}

}  // namespace rfsitl::monitor
