#include "rfsitl/monitor/node_counter_report.hpp"

#include <algorithm>
#include <cstdio>

#include "rfsitl/engine/node_counter_fields.hpp"
#include "rfsitl/monitor/stats_report.hpp"

namespace rfsitl::monitor {
namespace {

using engine::kLossReasons;
using engine::kNodeCounterFields;
using engine::NodeCounterField;
using Snapshot = engine::NodeCountersSnapshot;

/// A by-reason field's per-reason numbers.
const std::array<std::uint64_t, engine::kNumLossReasons>& reasons_of(const NodeCounterField& f,
                                                                     const Snapshot& c) {
  return c.*f.by_reason;
}

/// The fields the end-of-run table shows: all but those hidden while zero.
std::vector<const NodeCounterField*> table_fields(std::span<const Snapshot> c) {
  std::vector<const NodeCounterField*> shown;
  for (const NodeCounterField& f : kNodeCounterFields) {
    if (f.table_hides_zero &&
        std::all_of(c.begin(), c.end(), [&f](const Snapshot& s) { return f.read(s) == 0; })) {
      continue;
    }
    shown.push_back(&f);
  }
  return shown;
}

}  // namespace

std::vector<Snapshot> all_node_counters(engine::Engine& e) {
  std::vector<Snapshot> out;
  out.reserve(e.num_nodes());
  for (std::size_t i = 0; i < e.num_nodes(); ++i) {
    out.push_back(e.counters(i).snapshot());
    out.back().queue_depth = e.queue_depth(i);
  }
  return out;
}

nlohmann::json node_counters_json(const Snapshot& c) {
  nlohmann::json n = nlohmann::json::object();
  for (const NodeCounterField& f : kNodeCounterFields) {
    auto& v = n[std::string(f.key)];
    if (f.by_reason == nullptr) {
      v = f.read(c);
      continue;
    }
    v = nlohmann::json::object();
    for (std::size_t r = 0; r < kLossReasons.size(); ++r) {
      v[std::string(kLossReasons[r].key)] = reasons_of(f, c)[r];
    }
  }
  return n;
}

void write_node_counter_metrics(std::ostream& o, std::span<const NodeId> ids,
                                std::span<const Snapshot> c) {
  for (const NodeCounterField& f : kNodeCounterFields) {
    prometheus_family(o, f.metric, engine::counter_kind_name(f.kind), f.help);
    for (std::size_t i = 0; i < c.size() && i < ids.size(); ++i) {
      const std::string node = "node=\"" + std::to_string(unsigned{ids[i]}) + "\"";
      if (f.by_reason == nullptr) {
        o << f.metric << '{' << node << "} " << f.read(c[i]) << '\n';
        continue;
      }
      for (std::size_t r = 0; r < kLossReasons.size(); ++r) {
        o << f.metric << '{' << node << ",reason=\"" << prometheus_label_value(kLossReasons[r].key)
          << "\"} " << reasons_of(f, c[i])[r] << '\n';
      }
    }
  }
}

std::string node_counters_table(std::span<const NodeId> ids, std::span<const Snapshot> c) {
  struct Column {
    std::string title;
    const NodeCounterField* field;
    std::size_t reason;  // by-reason fields only
  };
  std::vector<Column> columns;
  for (const NodeCounterField* f : table_fields(c)) {
    if (f->by_reason == nullptr) {
      columns.push_back({std::string(f->column), f, 0});
      continue;
    }
    for (std::size_t r = 0; r < kLossReasons.size(); ++r) {
      columns.push_back({std::string(f->column) + ":" + std::string(kLossReasons[r].column), f, r});
    }
  }
  const auto width = [](const Column& col) {
    return static_cast<int>(std::max<std::size_t>(8, col.title.size()));
  };
  std::string out;
  char buf[64];
  std::snprintf(buf, sizeof buf, "%5s", "node");
  out += buf;
  for (const Column& col : columns) {
    std::snprintf(buf, sizeof buf, " %*s", width(col), col.title.c_str());
    out += buf;
  }
  out += '\n';
  for (std::size_t i = 0; i < c.size() && i < ids.size(); ++i) {
    std::snprintf(buf, sizeof buf, "%5u", unsigned{ids[i]});
    out += buf;
    for (const Column& col : columns) {
      const NodeCounterField& f = *col.field;
      const std::uint64_t v =
          f.by_reason == nullptr ? f.read(c[i]) : reasons_of(f, c[i])[col.reason];
      std::snprintf(buf, sizeof buf, " %*llu", width(col), static_cast<unsigned long long>(v));
      out += buf;
    }
    out += '\n';
  }
  return out;
}

std::string node_counters_legend(std::span<const Snapshot> c) {
  std::string out = "columns:\n";
  for (const NodeCounterField* f : table_fields(c)) {
    std::string title(f->column);
    std::string help(f->help);
    if (f->by_reason != nullptr) {
      title += ":R";
      help += " R:";
      for (std::size_t r = 0; r < kLossReasons.size(); ++r) {
        help += std::string(r == 0 ? " " : ", ") + std::string(kLossReasons[r].column) + " " +
                std::string(kLossReasons[r].label);
      }
      help += ".";
    }
    char buf[32];
    std::snprintf(buf, sizeof buf, "  %-14s ", title.c_str());
    out += buf + help + "\n";
  }
  return out;
}

nlohmann::json node_counter_fields_json() {
  nlohmann::json fields = nlohmann::json::array();
  for (const NodeCounterField& f : kNodeCounterFields) {
    nlohmann::json j = {{"key", f.key},
                        {"label", f.label},
                        {"help", f.help},
                        {"kind", engine::counter_kind_name(f.kind)}};
    if (f.by_reason != nullptr) {
      j["reasons"] = nlohmann::json::array();
      for (const engine::LossReasonInfo& r : kLossReasons) {
        j["reasons"].push_back({{"key", r.key}, {"label", r.label}, {"help", r.help}});
      }
    }
    fields.push_back(std::move(j));
  }
  return fields;
}

}  // namespace rfsitl::monitor
