#include "rfsitl/external/handshake.hpp"

#include <cmath>
#include <string_view>

#include <nlohmann/json.hpp>

#include "rfsitl/external/wire_protocol.hpp"

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

}  // namespace

std::string hello_json(const Hello& hello) {
  return Json{{"node_id", hello.node_id}, {"role", hello.role}, {"program", hello.program}}.dump(
      -1, ' ', false, Json::error_handler_t::replace);
}

Hello read_hello(const std::string& text) {
  const Json j = parse_object(text);
  Hello h;
  h.node_id = node_id_of(j);
  h.role = text_of(j, "role");
  if (j.contains("program")) h.program = text_of(j, "program");
  return h;
}

std::string welcome_json(const Welcome& welcome) {
  Json j = {{"protocol", kProtocolVersion},
            {"node_id", welcome.node_id},
            {"sample_rate_hz", welcome.sample_rate_hz},
            {"tick_samples", welcome.tick_samples},
            {"time_mode", welcome.virtual_time ? "virtual" : "realtime"}};
  if (!welcome.phy_json.empty()) j["phy"] = Json::parse(welcome.phy_json);
  return j.dump();
}

Welcome read_welcome(const std::string& text) {
  const Json j = parse_object(text);
  // Compared as a number: any other value, integral or not, is another protocol.
  if (const Json& p = field(j, "protocol"); !p.is_number() || p.get<double>() != kProtocolVersion) {
    throw HandshakeError("protocol " + shown(p) + ", this program speaks " +
                         std::to_string(kProtocolVersion));
  }
  Welcome w;
  w.node_id = node_id_of(j);
  const Json& rate = field(j, "sample_rate_hz");
  if (!rate.is_number() || !(rate.get<double>() > 0.0) || !std::isfinite(rate.get<double>())) {
    throw HandshakeError("sample_rate_hz: expected a finite number > 0, got " + shown(rate));
  }
  w.sample_rate_hz = rate.get<double>();
  w.tick_samples =
      static_cast<std::uint32_t>(integer_in(j, "tick_samples", 1, kMaxExternalTickSamples));
  const std::string mode = text_of(j, "time_mode");
  if (mode != "virtual" && mode != "realtime") {
    throw HandshakeError("time_mode: expected \"realtime\" or \"virtual\", got " +
                         shown(field(j, "time_mode")));
  }
  w.virtual_time = mode == "virtual";
  if (const auto it = j.find("phy"); it != j.end()) {
    if (!it->is_object()) throw HandshakeError("phy: expected a JSON object, got " + shown(*it));
    w.phy_json = it->dump();
  }
  return w;
}

}  // namespace rfsitl::external
