#pragma once
/// What a run's summary JSON (`rfsitl run --summary-json`) gives the table:
/// every counter summed over the nodes and the derived figures. Wall-clock
/// figures (wall_s, lag) are left out: they differ from run to run.
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace rfsitl::campaign {

/// The derived figures, in the table's column order:
///  - delivery_ratio: frames delivered / frames handed in to the radio (empty
///    when none was handed in);
///  - delivered_per_s: frames delivered per virtual second.
/// The summary holds frame counts, not bytes or per-frame latency, so there is
/// no goodput in bits/s and no latency figure.
const std::vector<std::string>& derived_figure_names();

/// Counters (node counters summed over nodes, "lost.x" as "lost_x"; the run's
/// own: virtual_s, late_ticks, receiver_ticks_*) and the derived figures, as
/// the table writes them. Throws std::runtime_error when `summary` is not a
/// summary (no "nodes" list).
std::map<std::string, std::string> run_figures(const nlohmann::json& summary);

/// A double as the table writes it: the shortest text that reads back as it.
std::string figure_text(double v);

}  // namespace rfsitl::campaign
