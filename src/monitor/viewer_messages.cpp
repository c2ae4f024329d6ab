#include "viewer_messages.hpp"

#include <cmath>

#include <nlohmann/json.hpp>

namespace rfsitl::monitor {

using Json = nlohmann::json;

std::string spectrum_message(NodeId node, double virtual_s, double sample_rate_hz,
                             const std::vector<float>& bins_db) {
  Json bins = Json::array();
  for (const float b : bins_db) bins.push_back(std::round(b * 10.0F) / 10.0F);
  return Json{{"type", "spectrum"},
              {"node", node},
              {"virtual_s", virtual_s},
              {"sample_rate_hz", sample_rate_hz},
              {"bins_db", bins}}
      .dump();
}

std::string constellation_message(NodeId node, const Constellation& c, double sample_rate_hz) {
  Json points = Json::array();
  for (const cf32 p : c.points) {
    points.push_back(
        {std::round(p.real() * 1000.0F) / 1000.0F, std::round(p.imag() * 1000.0F) / 1000.0F});
  }
  return Json{{"type", "constellation"},
              {"node", node},
              {"virtual_s", static_cast<double>(c.time) / sample_rate_hz},
              {"src", c.src},
              {"dst", c.dst},
              {"serial", c.serial},
              {"valid", c.payload_valid},
              {"points", points}}
      .dump();
}

std::string dashboard_metrics_text(std::size_t viewers, std::uint64_t messages_dropped,
                                   std::uint64_t control_refused) {
  return "# HELP rfsitl_dashboard_viewers Dashboard viewers connected now.\n"
         "# TYPE rfsitl_dashboard_viewers gauge\n"
         "rfsitl_dashboard_viewers " +
         std::to_string(viewers) +
         "\n# HELP rfsitl_dashboard_messages_dropped_total Messages not sent to viewers that "
         "did not keep up (replaced by newer ones or dropped to bound their queues).\n"
         "# TYPE rfsitl_dashboard_messages_dropped_total counter\n"
         "rfsitl_dashboard_messages_dropped_total " +
         std::to_string(messages_dropped) +
         "\n# HELP rfsitl_dashboard_control_refused_total Moves refused because they did not "
         "carry the dashboard's control token or carried a wrong one.\n"
         "# TYPE rfsitl_dashboard_control_refused_total counter\n"
         "rfsitl_dashboard_control_refused_total " +
         std::to_string(control_refused) + "\n";
}

}  // namespace rfsitl::monitor
