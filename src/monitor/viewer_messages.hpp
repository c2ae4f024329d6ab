#pragma once
/// Texts the dashboard server sends that depend only on their arguments: the
/// spectrum and constellation messages of a watched node and the dashboard's
/// own /metrics families (kept out of dashboard_server.cpp, which is long).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "rfsitl/common/types.hpp"
#include "rfsitl/monitor/live_view.hpp"

namespace rfsitl::monitor {

/// {"type":"spectrum","node","virtual_s","sample_rate_hz","bins_db"}, bins
/// rounded to 0.1 dB.
std::string spectrum_message(NodeId node, double virtual_s, double sample_rate_hz,
                             const std::vector<float>& bins_db);

/// {"type":"constellation","node","virtual_s","src","dst","serial","valid",
/// "points"}, points rounded to 0.001.
std::string constellation_message(NodeId node, const Constellation& c, double sample_rate_hz);

/// The rfsitl_dashboard_* families of /metrics.
std::string dashboard_metrics_text(std::size_t viewers, std::uint64_t messages_dropped,
                                   std::uint64_t control_refused);

}  // namespace rfsitl::monitor
