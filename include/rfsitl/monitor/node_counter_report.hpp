#pragma once
/// The per-node counters in each report's form. Every function walks
/// engine::kNodeCounterFields, so a counter declared there shows up in all of
/// them under the names declared there.
#include <ostream>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rfsitl/common/types.hpp"
#include "rfsitl/engine/engine.hpp"
#include "rfsitl/engine/node_counters.hpp"

namespace rfsitl::monitor {

/// Every node's counters, in node order, queue_depth included (the engine's
/// queue holds that number, not an atomic counter).
std::vector<engine::NodeCountersSnapshot> all_node_counters(engine::Engine& e);

/// One node's counters as the summary JSON's nodes[i] carries them: one key
/// per field, by-reason fields as an object keyed by reason.
nlohmann::json node_counters_json(const engine::NodeCountersSnapshot& c);

/// Every field as a Prometheus family (HELP, TYPE), then one sample per node
/// labelled {node="ID"} (by-reason fields: one per node and reason="..").
/// `ids` and `c` are in node order and of the same size.
void write_node_counter_metrics(std::ostream& o, std::span<const NodeId> ids,
                                std::span<const engine::NodeCountersSnapshot> c);

/// The end-of-run table: a header line, then one line per node; a column per
/// field ("lost:sen" .. per reason for by-reason fields).
std::string node_counters_table(std::span<const NodeId> ids,
                                std::span<const engine::NodeCountersSnapshot> c);

/// What the table's columns mean: "columns:", then one line per field the
/// table shows for `c` ("  in             Frames the agent handed in."),
/// by-reason fields as "lost:R" with every reason's column and label.
std::string node_counters_legend(std::span<const engine::NodeCountersSnapshot> c);

/// The field list for viewers (the dashboard's hello): [{key, label, help,
/// kind}, ...] in order; by-reason fields add reasons: [{key, label, help}].
nlohmann::json node_counter_fields_json();

}  // namespace rfsitl::monitor
