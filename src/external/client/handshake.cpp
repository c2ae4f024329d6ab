#include "rfsitl/external/client/handshake.hpp"

#include <cmath>
#include <string_view>

#include <nlohmann/json.hpp>

#include "rfsitl/external/client/tx_report.hpp"
#include "rfsitl/external/client/wire_protocol.hpp"

namespace rfsitl::external {
namespace {

using Json = nlohmann::json;

/// A value as it was sent, for an error message: its JSON text (strings quoted
/// and escaped), cut to a readable length.
std::string shown(const Json& v) {
  constexpr std::size_t kMax = 40;
  std::string t = v.dump(-1, ' ', false, Json::error_handler_t::replace);
  if (t.size() > kMax) t = t.substr(0, kMax) + "...";
  return t;
}

Json parse_object(const std::string& text) {
  Json j;
  try {
    j = Json::parse(text);
  } catch (const Json::parse_error& e) {
    throw HandshakeError("not JSON (syntax error at byte " + std::to_string(e.byte) + ")");
  } catch (const Json::exception&) {  // out_of_range: 1e400
    throw HandshakeError("not JSON (a number beyond any double)");
  }
  if (!j.is_object()) throw HandshakeError("expected a JSON object, got " + shown(j));
  return j;
}

const Json& field(const Json& j, std::string_view key) {
  const auto it = j.find(key);
  if (it == j.end()) throw HandshakeError(std::string(key) + ": missing");
  return *it;
}

/// The integer under `key`, within [lo, hi]. The range is checked on the value
/// as a double (every JSON number converts to one exactly enough and without
/// undefined behaviour), so only a value known to fit is ever cast.
/// Precondition: hi < 2^53, so that hi itself is exact as a double.
std::uint64_t integer_in(const Json& j, std::string_view key, std::uint64_t lo, std::uint64_t hi) {
  const Json& v = field(j, key);
  if (!v.is_number()) {
    throw HandshakeError(std::string(key) + ": expected an integer, got " + shown(v));
  }
  const double d = v.get<double>();
  if (!(d >= static_cast<double>(lo) && d <= static_cast<double>(hi))) {  // NaN fails too
    throw HandshakeError(std::string(key) + " " + shown(v) + " out of range " + std::to_string(lo) +
                         ".." + std::to_string(hi));
  }
  if (d != std::floor(d)) {
    throw HandshakeError(std::string(key) + ": expected an integer, got " + shown(v));
  }
  return static_cast<std::uint64_t>(d);
}

std::string text_of(const Json& j, std::string_view key) {
  const Json& v = field(j, key);
  if (!v.is_string())
    throw HandshakeError(std::string(key) + ": expected a string, got " + shown(v));
  return v.get<std::string>();
}

NodeId node_id_of(const Json& j) {
  return static_cast<NodeId>(integer_in(j, "node_id", kMinNodeId, kMaxNodeId));
}

double positive_finite(const Json& j, std::string_view key) {
  const Json& v = field(j, key);
  if (!v.is_number() || !(v.get<double>() > 0.0) || !std::isfinite(v.get<double>())) {
    throw HandshakeError(std::string(key) + ": expected a finite number > 0, got " + shown(v));
  }
  return v.get<double>();
}

std::uint32_t tick_samples_of(const Json& j) {
  return static_cast<std::uint32_t>(integer_in(j, "tick_samples", 1, kMaxExternalTickSamples));
}

/// true for "virtual", false for "realtime".
bool virtual_time_of(const Json& j) {
  const std::string mode = text_of(j, "time_mode");
  if (mode != "virtual" && mode != "realtime") {
    throw HandshakeError("time_mode: expected \"realtime\" or \"virtual\", got " +
                         shown(field(j, "time_mode")));
  }
  return mode == "virtual";
}

bool boolean_of(const Json& j, std::string_view key) {
  const Json& v = field(j, key);
  if (!v.is_boolean()) {
    throw HandshakeError(std::string(key) + ": expected true or false, got " + shown(v));
  }
  return v.get<bool>();
}

const char* time_mode_name(bool virtual_time) {
  return virtual_time ? "virtual" : "realtime";
}

/// Checks that `key` is the number `version` (compared as a number: any other
/// value, integral or not, is another protocol).
void check_version(const Json& j, std::string_view key, int version) {
  if (const Json& p = field(j, key); !p.is_number() || p.get<double>() != version) {
    throw HandshakeError(std::string(key) + " " + shown(p) + ", this program speaks " +
                         std::to_string(version));
  }
}

}  // namespace

std::string hello_json(const Hello& hello) {
  Json j = {{"node_id", hello.node_id}, {"role", hello.role}, {"program", hello.program}};
  if (hello.exclusive) j["exclusive"] = true;
  return j.dump(-1, ' ', false, Json::error_handler_t::replace);
}

Hello read_hello(const std::string& text) {
  const Json j = parse_object(text);
  Hello h;
  h.node_id = node_id_of(j);
  h.role = text_of(j, "role");
  if (j.contains("program")) h.program = text_of(j, "program");
  if (j.contains("exclusive")) h.exclusive = boolean_of(j, "exclusive");
  return h;
}

std::string welcome_json(const Welcome& welcome) {
  Json j = {{"protocol", kProtocolVersion},
            {"node_id", welcome.node_id},
            {"sample_rate_hz", welcome.sample_rate_hz},
            {"tick_samples", welcome.tick_samples},
            {"time_mode", time_mode_name(welcome.virtual_time)}};
  if (!welcome.phy_json.empty()) j["phy"] = Json::parse(welcome.phy_json);
  if (welcome.tx_report != 0) j["tx_report"] = welcome.tx_report;
  return j.dump();
}

Welcome read_welcome(const std::string& text) {
  const Json j = parse_object(text);
  check_version(j, "protocol", kProtocolVersion);
  Welcome w;
  w.node_id = node_id_of(j);
  w.sample_rate_hz = positive_finite(j, "sample_rate_hz");
  w.tick_samples = tick_samples_of(j);
  w.virtual_time = virtual_time_of(j);
  if (const auto it = j.find("phy"); it != j.end()) {
    if (!it->is_object()) throw HandshakeError("phy: expected a JSON object, got " + shown(*it));
    w.phy_json = it->dump();
  }
  if (j.contains("tx_report")) {
    w.tx_report = static_cast<std::uint32_t>(integer_in(j, "tx_report", 0, kMaxTxReportVersion));
  }
  return w;
}

std::string discovery_request_json(const DiscoveryRequest& request) {
  return Json{{"discovery", kDiscoveryVersion}, {"program", request.program}}.dump(
      -1, ' ', false, Json::error_handler_t::replace);
}

DiscoveryRequest read_discovery_request(const std::string& text) {
  const Json j = parse_object(text);
  check_version(j, "discovery", kDiscoveryVersion);
  DiscoveryRequest r;
  if (j.contains("program")) r.program = text_of(j, "program");
  return r;
}

std::string discovery_json(const std::vector<DiscoveredNode>& nodes) {
  Json list = Json::array();
  for (const auto& n : nodes) {
    list.push_back({{"node_id", n.node_id},
                    {"label", n.label},
                    {"role", n.role},
                    {"sample_rate_hz", n.sample_rate_hz},
                    {"tick_samples", n.tick_samples},
                    {"carrier_hz", n.carrier_hz},
                    {"time_mode", time_mode_name(n.virtual_time)},
                    {"claimed", n.claimed}});
  }
  return Json{{"discovery", kDiscoveryVersion}, {"nodes", std::move(list)}}.dump(
      -1, ' ', false, Json::error_handler_t::replace);
}

std::vector<DiscoveredNode> read_discovery(const std::string& text) {
  const Json j = parse_object(text);
  check_version(j, "discovery", kDiscoveryVersion);
  const Json& list = field(j, "nodes");
  if (!list.is_array()) throw HandshakeError("nodes: expected a JSON array, got " + shown(list));
  std::vector<DiscoveredNode> nodes;
  for (const Json& e : list) {
    if (!e.is_object()) throw HandshakeError("nodes: expected objects, got " + shown(e));
    DiscoveredNode n;
    n.node_id = node_id_of(e);
    n.label = text_of(e, "label");
    n.role = text_of(e, "role");
    n.sample_rate_hz = positive_finite(e, "sample_rate_hz");
    n.tick_samples = tick_samples_of(e);
    n.carrier_hz = positive_finite(e, "carrier_hz");
    n.virtual_time = virtual_time_of(e);
    n.claimed = boolean_of(e, "claimed");
    nodes.push_back(std::move(n));
  }
  return nodes;
}

}  // namespace rfsitl::external
