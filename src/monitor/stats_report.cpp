#include "rfsitl/monitor/stats_report.hpp"

#include <charconv>
#include <cmath>
#include <sstream>

#include "rfsitl/channel/geodesy.hpp"
#include "rfsitl/monitor/node_counter_report.hpp"

namespace rfsitl::monitor {
namespace {

/// Rounds to `decimals` places (multiplying by 10^d, not dividing by 10^-d,
/// keeps the printed number short).
double round_to(double v, int decimals) {
  const double scale = std::pow(10.0, decimals);
  return std::round(v * scale) / scale;
}

}  // namespace

nlohmann::json stats_json(const scenario::Scenario& s, engine::Engine& e) {
  const engine::EngineStatus st = e.status();
  nlohmann::json j;
  j["scenario"] = s.name;
  j["sample_rate_hz"] = s.timing.sample_rate_hz;
  j["virtual_s"] = st.virtual_s;
  j["wall_s"] = st.wall_s;
  j["lag_s"] = st.lag_s;
  j["max_lag_s"] = st.max_lag_s;
  j["late_ticks"] = st.late_ticks;
  j["late_decodes"] = st.late_decodes;
  j["receiver_ticks_run"] = st.receiver_ticks_run;
  j["receiver_ticks_skipped"] = st.receiver_ticks_skipped;
  j["receiver_ticks_blanked"] = st.receiver_ticks_blanked;
  j["nodes"] = nlohmann::json::array();
  const auto counters = all_node_counters(e);
  for (std::size_t i = 0; i < counters.size(); ++i) {
    nlohmann::json n = node_counters_json(counters[i]);
    n["id"] = e.node_ids()[i];
    n["phy"] = s.phy_of(i).type;
    j["nodes"].push_back(std::move(n));
  }
  return j;
}

nlohmann::json snapshot_json(const scenario::Scenario& s, engine::Engine& e, const LiveView& view,
                             const std::vector<double>& sensitivity_db, bool control,
                             bool with_snr) {
  nlohmann::json j = stats_json(s, e);
  j["type"] = "snapshot";
  j["control"] = control;
  j["noise_db"] = 10.0 * std::log10(std::max(s.channel.noise_variance, 1e-300));
  const auto positions = e.positions();
  for (std::size_t i = 0; i < positions.size() && i < j["nodes"].size(); ++i) {
    auto& n = j["nodes"][i];
    n["sensitivity_db"] = i < sensitivity_db.size() && std::isfinite(sensitivity_db[i])
                              ? nlohmann::json(sensitivity_db[i])
                              : nlohmann::json(nullptr);
    if (!positions[i]) {
      n["position"] = nullptr;
      continue;
    }
    const LocalPosition l = channel::ecef_to_local(*positions[i], s.channel.origin);
    const GeodeticPosition g = channel::ecef_to_geodetic(*positions[i]);
    n["position"] = {{"x", round_to(l.x_m, 2)},       {"y", round_to(l.y_m, 2)},
                     {"z", round_to(l.z_m, 2)},       {"lat", round_to(g.lat_deg, 7)},
                     {"lon", round_to(g.lon_deg, 7)}, {"alt", round_to(g.alt_m, 2)}};
  }
  const std::size_t n = e.num_nodes();
  const auto outcomes = view.link_outcomes();
  j["links"] = {{"n", n}, {"received", outcomes.received}, {"lost", outcomes.lost}};
  if (!with_snr) return j;
  const auto gains = e.link_gains();
  const double noise = s.channel.noise_variance;
  nlohmann::json snr = nlohmann::json::array();
  for (std::size_t k = 0; k < n * n && k < gains.size(); ++k) {
    const bool self = k / n == k % n;
    if (self || gains[k] <= 0.0F || noise <= 0.0) {
      snr.push_back(nullptr);
    } else {
      snr.push_back(round_to(10.0 * std::log10(gains[k] / noise), 1));
    }
  }
  j["links"]["snr_db"] = std::move(snr);
  return j;
}

std::string prometheus_label_value(std::string_view v) {
  std::string out;
  out.reserve(v.size());
  for (const char ch : v) {
    if (ch == '\\') {
      out += "\\\\";
    } else if (ch == '"') {
      out += "\\\"";
    } else if (ch == '\n') {
      out += "\\n";
    } else {
      out += ch;
    }
  }
  return out;
}

std::string prometheus_help_text(std::string_view v) {
  std::string out;
  out.reserve(v.size());
  for (const char ch : v) {
    if (ch == '\\') {
      out += "\\\\";
    } else if (ch == '\n') {
      out += "\\n";
    } else {
      out += ch;
    }
  }
  return out;
}

void prometheus_family(std::ostream& o, std::string_view name, std::string_view type,
                       std::string_view help) {
  o << "# HELP " << name << ' ' << prometheus_help_text(help) << "\n# TYPE " << name << ' ' << type
    << '\n';
}

namespace {

/// The shortest text that reads back as `v` (a stream's default 6 digits
/// would print a day of virtual time as 86400 but a month as 2.592e+06).
std::string number(double v) {
  if (std::isnan(v)) return "NaN";
  if (std::isinf(v)) return v > 0 ? "+Inf" : "-Inf";
  char buf[32];
  return {buf, std::to_chars(buf, buf + sizeof(buf), v).ptr};
}

}  // namespace

std::string prometheus_text(const scenario::Scenario& s, engine::Engine& e) {
  std::ostringstream o;
  const auto family = [&o](std::string_view name, std::string_view type, std::string_view help) {
    prometheus_family(o, name, type, help);
  };
  const engine::EngineStatus st = e.status();
  family("rfsitl_virtual_seconds", "gauge", "Virtual time emulated so far.");
  o << "rfsitl_virtual_seconds " << number(st.virtual_s) << '\n';
  family("rfsitl_wall_seconds", "gauge", "Wall-clock time since the run started.");
  o << "rfsitl_wall_seconds " << number(st.wall_s) << '\n';
  family("rfsitl_realtime_lag_seconds", "gauge", "How late the latest tick started (real time).");
  o << "rfsitl_realtime_lag_seconds " << number(st.lag_s) << '\n';
  family("rfsitl_realtime_lag_max_seconds", "gauge", "Worst real-time lag so far.");
  o << "rfsitl_realtime_lag_max_seconds " << number(st.max_lag_s) << '\n';
  family("rfsitl_late_ticks_total", "counter", "Ticks started more than a tick late.");
  o << "rfsitl_late_ticks_total " << st.late_ticks << '\n';
  family("rfsitl_late_decodes_total", "counter",
         "Decodes after their verdict was due (not delivered).");
  o << "rfsitl_late_decodes_total " << st.late_decodes << '\n';
  family("rfsitl_receiver_ticks_total", "counter", "Receiver-ticks by what happened to them.");
  o << "rfsitl_receiver_ticks_total{state=\"run\"} " << st.receiver_ticks_run << '\n'
    << "rfsitl_receiver_ticks_total{state=\"skipped\"} " << st.receiver_ticks_skipped << '\n'
    << "rfsitl_receiver_ticks_total{state=\"blanked\"} " << st.receiver_ticks_blanked << '\n';
  // Every per-node number of stats_json, under the same meaning.
  const auto counters = all_node_counters(e);
  write_node_counter_metrics(o, e.node_ids(), counters);
  family("rfsitl_node_info", "gauge", "Each node's PHY (value always 1).");
  for (std::size_t i = 0; i < counters.size(); ++i) {
    o << "rfsitl_node_info{node=\"" << unsigned{e.node_ids()[i]} << "\",phy=\""
      << prometheus_label_value(s.phy_of(i).type) << "\"} 1\n";
  }
  family("rfsitl_info", "gauge", "The running scenario (value always 1).");
  o << "rfsitl_info{scenario=\"" << prometheus_label_value(s.name) << "\",nodes=\"" << e.num_nodes()
    << "\"} 1\n";
  return o.str();
}

}  // namespace rfsitl::monitor
