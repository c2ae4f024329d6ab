#include "rfsitl/monitor/stats_report.hpp"

#include <charconv>
#include <cmath>
#include <sstream>

#include "rfsitl/common/build_version.hpp"
#include "rfsitl/common/geodesy.hpp"
#include "rfsitl/monitor/node_counter_report.hpp"

namespace rfsitl::monitor {

double round_to(double v, int decimals) {
  const double scale = std::pow(10.0, decimals);
  return std::round(v * scale) / scale;
}

namespace {

nlohmann::json position_json(const std::optional<Ecef>& p, const GeodeticPosition& origin) {
  if (!p) return nullptr;
  const LocalPosition l = ecef_to_local(*p, origin);
  const GeodeticPosition g = ecef_to_geodetic(*p);
  return {{"x", round_to(l.x_m, 2)},       {"y", round_to(l.y_m, 2)},
          {"z", round_to(l.z_m, 2)},       {"lat", round_to(g.lat_deg, 7)},
          {"lon", round_to(g.lon_deg, 7)}, {"alt", round_to(g.alt_m, 2)}};
}

void add_motion(nlohmann::json& n, const position::NodeMotion& m) {
  if (const auto& v = m.velocity) {
    n["velocity"] = {{"east_mps", round_to(v->vx_mps, 3)},
                     {"north_mps", round_to(v->vy_mps, 3)},
                     {"up_mps", round_to(v->vz_mps, 3)}};
  }
  if (const auto& a = m.attitude) {
    n["attitude"] = {{"roll_rad", round_to(a->roll_rad, 4)},
                     {"pitch_rad", round_to(a->pitch_rad, 4)},
                     {"yaw_rad", round_to(a->yaw_rad, 4)}};
  }
}

nlohmann::json counts_json(const position::SourceCounters& c) {
  return {{"updates", c.updates}, {"errors", c.errors}};
}

// Where node i's positions come from: a mobility model or a live source (the
// location port by default), with its counters; for a node whose own source is
// another, also the location port's overrides.
nlohmann::json source_json(const scenario::Scenario& s, std::size_t i,
                           const position::SourceStatusFn& sources) {
  const auto status = sources ? sources(i) : std::nullopt;
  nlohmann::json j;
  if (const auto& m = s.nodes[i].mobility) {
    j = {{"type", "mobility"}, {"model", m->type}};
  } else if (!status) {
    return {{"type", s.source_of(i).type}};
  } else {
    const position::SourceCounters& c = status->counters;
    j = {{"type", status->type}, {"where", status->where},    {"connected", c.connected},
         {"stale", c.stale},     {"updates", c.updates},      {"errors", c.errors},
         {"ignored", c.ignored}, {"reconnects", c.reconnects}};
    j["last_update_age_s"] =
        c.last_update_age_s ? nlohmann::json(round_to(*c.last_update_age_s, 3)) : nullptr;
    nlohmann::json detail = nlohmann::json::object();
    for (const auto& [name, value] : c.detail) detail[name] = value;
    j["detail"] = std::move(detail);
  }
  if (status && status->overrides) j["overrides"] = counts_json(*status->overrides);
  return j;
}

/// 10 log10(gain / reference) per link, row-major, rounded to 0.1 dB; null for
/// a node itself, no link, or no reference (a noise-free channel's SNR).
nlohmann::json link_matrix_db(const std::vector<float>& gains, std::size_t n, double reference) {
  nlohmann::json out = nlohmann::json::array();
  for (std::size_t k = 0; k < n * n && k < gains.size(); ++k) {
    const bool self = k / n == k % n;
    if (self || gains[k] <= 0.0F || reference <= 0.0) {
      out.push_back(nullptr);
    } else {
      out.push_back(round_to(10.0 * std::log10(gains[k] / reference), 1));
    }
  }
  return out;
}

}  // namespace

nlohmann::json stats_json(const scenario::Scenario& s, engine::Engine& e,
                          const position::SourceStatusFn& sources) {
  const engine::EngineStatus st = e.status();
  nlohmann::json j;
  j["scenario"] = s.name;
  j["sample_rate_hz"] = s.timing.sample_rate_hz;
  j["tick_samples"] = s.timing.tick_samples;
  j["virtual_s"] = st.virtual_s;
  j["wall_s"] = st.wall_s;
  j["lag_s"] = st.lag_s;
  j["max_lag_s"] = st.max_lag_s;
  j["late_ticks"] = st.late_ticks;
  j["late_decodes"] = st.late_decodes;
  j["receiver_ticks_run"] = st.receiver_ticks_run;
  j["receiver_ticks_skipped"] = st.receiver_ticks_skipped;
  j["receiver_ticks_blanked"] = st.receiver_ticks_blanked;
  j["mobility_wall_s"] = st.mobility_wall_s;
  j["nodes"] = nlohmann::json::array();
  const auto counters = all_node_counters(e);
  const auto positions = e.positions();
  const auto motions = e.motions();
  for (std::size_t i = 0; i < counters.size(); ++i) {
    nlohmann::json n = node_counters_json(counters[i]);
    n["id"] = e.node_ids()[i];
    n["phy"] = s.phy_of(i).type;
    n["position"] = i < positions.size() ? position_json(positions[i], s.channel.origin)
                                         : nlohmann::json(nullptr);
    if (i < motions.size()) add_motion(n, motions[i]);
    n["source"] = source_json(s, i, sources);
    j["nodes"].push_back(std::move(n));
  }
  return j;
}

nlohmann::json snapshot_json(const scenario::Scenario& s, engine::Engine& e, const LiveView& view,
                             const std::vector<double>& sensitivity_db, bool control, bool with_snr,
                             const position::SourceStatusFn& sources) {
  nlohmann::json j = stats_json(s, e, sources);
  j["type"] = "snapshot";
  j["control"] = control;
  j["noise_db"] = 10.0 * std::log10(std::max(s.channel.noise_variance, 1e-300));
  for (std::size_t i = 0; i < j["nodes"].size(); ++i) {
    j["nodes"][i]["sensitivity_db"] = i < sensitivity_db.size() && std::isfinite(sensitivity_db[i])
                                          ? nlohmann::json(sensitivity_db[i])
                                          : nlohmann::json(nullptr);
  }
  const std::size_t n = e.num_nodes();
  const auto outcomes = view.link_outcomes();
  j["links"] = {{"n", n}, {"received", outcomes.received}, {"lost", outcomes.lost}};
  if (!with_snr) return j;
  j["links"]["snr_db"] = link_matrix_db(e.link_gains(), n, s.channel.noise_variance);
  return j;
}

nlohmann::json stats_with_links_json(const scenario::Scenario& s, engine::Engine& e,
                                     const position::SourceStatusFn& sources) {
  nlohmann::json j = stats_json(s, e, sources);
  const std::size_t n = e.num_nodes();
  const auto gains = e.link_gains();
  j["links"] = {{"n", n},
                {"gain_db", link_matrix_db(gains, n, 1.0)},
                {"snr_db", link_matrix_db(gains, n, s.channel.noise_variance)}};
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

std::string prometheus_number(double v) {
  if (std::isnan(v)) return "NaN";
  if (std::isinf(v)) return v > 0 ? "+Inf" : "-Inf";
  char buf[32];
  return {buf, std::to_chars(buf, buf + sizeof(buf), v).ptr};
}

// Every node's position, velocity, attitude and source as stats_json gives
// them (one reading of each, so the two cannot disagree): one gauge family per
// object, its members as a label.
void write_motion_metrics(std::ostream& o, const nlohmann::json& nodes) {
  struct Family {
    const char* key;
    const char* name;
    const char* label;
    const char* help;
  };
  static constexpr Family kFamilies[] = {
      {"position", "rfsitl_node_position", "coord",
       "Each node's position: x, y, z metres east, north, up of the scenario origin; lat, lon "
       "degrees; alt metres (absent while unknown)."},
      {"velocity", "rfsitl_node_velocity_mps", "axis", "Each node's velocity, east/north/up."},
      {"attitude", "rfsitl_node_attitude_rad", "angle", "Each node's roll, pitch and yaw."},
  };
  for (const Family& f : kFamilies) {
    prometheus_family(o, f.name, "gauge", f.help);
    for (const auto& n : nodes) {
      if (!n.contains(f.key) || n.at(f.key).is_null()) continue;
      for (const auto& [member, value] : n.at(f.key).items()) {
        o << f.name << "{node=\"" << n.at("id").get<unsigned>() << "\"," << f.label << "=\""
          << member << "\"} " << prometheus_number(value.get<double>()) << '\n';
      }
    }
  }
  prometheus_family(o, "rfsitl_node_source_info", "gauge",
                    "Where each node's positions come from (value always 1).");
  for (const auto& n : nodes) {
    o << "rfsitl_node_source_info{node=\"" << n.at("id").get<unsigned>() << "\",type=\""
      << prometheus_label_value(n.at("source").at("type").get<std::string>()) << "\"} 1\n";
  }
  prometheus_family(o, "rfsitl_position_source_events_total", "counter",
                    "A live position source's counts per node: updates, errors, ignored, "
                    "reconnects, its finer counts, and the location port's overrides "
                    "(override_updates, override_errors) of a node fed by another source.");
  for (const auto& n : nodes) {
    const auto& src = n.at("source");
    for (const char* key : {"updates", "errors", "ignored", "reconnects"}) {
      if (!src.contains(key)) continue;
      o << "rfsitl_position_source_events_total{node=\"" << n.at("id").get<unsigned>()
        << "\",event=\"" << key << "\"} " << src.at(key).get<std::uint64_t>() << '\n';
    }
    if (src.contains("overrides")) {
      for (const auto& [key, value] : src.at("overrides").items()) {
        o << "rfsitl_position_source_events_total{node=\"" << n.at("id").get<unsigned>()
          << "\",event=\"override_" << key << "\"} " << value.get<std::uint64_t>() << '\n';
      }
    }
    if (!src.contains("detail")) continue;
    for (const auto& [key, value] : src.at("detail").items()) {
      o << "rfsitl_position_source_events_total{node=\"" << n.at("id").get<unsigned>()
        << "\",event=\"" << prometheus_label_value(key) << "\"} " << value.get<std::uint64_t>()
        << '\n';
    }
  }
}

std::string prometheus_text(const scenario::Scenario& s, engine::Engine& e,
                            const position::SourceStatusFn& sources) {
  std::ostringstream o;
  const auto family = [&o](std::string_view name, std::string_view type, std::string_view help) {
    prometheus_family(o, name, type, help);
  };
  const engine::EngineStatus st = e.status();
  family("rfsitl_build_info", "gauge", "This program's version (value always 1).");
  o << "rfsitl_build_info{version=\"" << prometheus_label_value(build_version()) << "\"} 1\n";
  family("rfsitl_virtual_seconds", "gauge", "Virtual time emulated so far.");
  o << "rfsitl_virtual_seconds " << prometheus_number(st.virtual_s) << '\n';
  family("rfsitl_wall_seconds", "gauge", "Wall-clock time since the run started.");
  o << "rfsitl_wall_seconds " << prometheus_number(st.wall_s) << '\n';
  family("rfsitl_realtime_lag_seconds", "gauge", "How late the latest tick started (real time).");
  o << "rfsitl_realtime_lag_seconds " << prometheus_number(st.lag_s) << '\n';
  family("rfsitl_realtime_lag_max_seconds", "gauge", "Worst real-time lag so far.");
  o << "rfsitl_realtime_lag_max_seconds " << prometheus_number(st.max_lag_s) << '\n';
  family("rfsitl_late_ticks_total", "counter", "Ticks started more than a tick late.");
  o << "rfsitl_late_ticks_total " << st.late_ticks << '\n';
  family("rfsitl_late_decodes_total", "counter",
         "Decodes after their verdict was due (not delivered).");
  o << "rfsitl_late_decodes_total " << st.late_decodes << '\n';
  family("rfsitl_receiver_ticks_total", "counter", "Receiver-ticks by what happened to them.");
  o << "rfsitl_receiver_ticks_total{state=\"run\"} " << st.receiver_ticks_run << '\n'
    << "rfsitl_receiver_ticks_total{state=\"skipped\"} " << st.receiver_ticks_skipped << '\n'
    << "rfsitl_receiver_ticks_total{state=\"blanked\"} " << st.receiver_ticks_blanked << '\n';
  family("rfsitl_mobility_seconds_total", "counter", "Wall time spent evaluating mobility models.");
  o << "rfsitl_mobility_seconds_total " << prometheus_number(st.mobility_wall_s) << '\n';
  // Every per-node number of stats_json, under the same meaning.
  const auto counters = all_node_counters(e);
  write_node_counter_metrics(o, e.node_ids(), counters);
  family("rfsitl_node_info", "gauge", "Each node's PHY (value always 1).");
  for (std::size_t i = 0; i < counters.size(); ++i) {
    o << "rfsitl_node_info{node=\"" << unsigned{e.node_ids()[i]} << "\",phy=\""
      << prometheus_label_value(s.phy_of(i).type) << "\"} 1\n";
  }
  write_motion_metrics(o, stats_json(s, e, sources).at("nodes"));
  family("rfsitl_info", "gauge", "The running scenario (value always 1).");
  o << "rfsitl_info{scenario=\"" << prometheus_label_value(s.name) << "\",nodes=\"" << e.num_nodes()
    << "\"} 1\n";
  return o.str();
}

}  // namespace rfsitl::monitor
