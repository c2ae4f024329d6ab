/// Dashboard HTTP: arbitrary bytes from a client, parsed as the dashboard's
/// session parses them (Beast's request_parser, 64 KiB body limit), then
/// refused (Server::refusal: Host and Origin checks) or answered by
/// Server::handle, as HttpSession::on_read does. Up to four pipelined requests
/// per input, as on a keep-alive connection. The server is bound to 127.0.0.1.
///
/// Checks, per request:
///  - a request whose Host is absent or not this server, or whose Origin is
///    another site, is refused (421 or 403) and never reaches handle();
///  - the status is one of 200, 400, 403, 404, 405, 421, the body is not empty and
///    Content-Length matches it; an error's body is JSON {"error": "..."};
///  - GET /api/stats and /api/snapshot answer valid JSON;
///  - a POST that moves a node (200) named that node's id in its target as a
///    plain decimal number; every node's position stays finite.
#include "dashboard_harness.hpp"

namespace http = boost::beast::http;
namespace websocket = boost::beast::websocket;
using rfsitl::fuzz::DashboardFixture;
using rfsitl::fuzz::fixture;
using Json = nlohmann::json;

namespace {

bool same_position(const std::optional<rfsitl::Ecef>& a, const std::optional<rfsitl::Ecef>& b) {
  return a.has_value() == b.has_value() && (!a || (a->x == b->x && a->y == b->y && a->z == b->z));
}

bool same_positions(const std::vector<std::optional<rfsitl::Ecef>>& a,
                    const std::vector<std::optional<rfsitl::Ecef>>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (!same_position(a[i], b[i])) return false;
  }
  return true;
}

void check_response(DashboardFixture& f, const http::request<http::string_body>& req,
                    const http::response<http::string_body>& res,
                    const std::vector<std::optional<rfsitl::Ecef>>& before) {
  const unsigned status = res.result_int();
  FUZZ_CHECK(status == 200 || status == 400 || status == 403 || status == 404 || status == 405 ||
                 status == 421,
             "status %u", status);
  FUZZ_CHECK(!res.body().empty(), "empty body (status %u)", status);
  const auto length = res.find(http::field::content_length);
  FUZZ_CHECK(length != res.end() && length->value() == std::to_string(res.body().size()),
             "Content-Length does not match a %zu-byte body", res.body().size());
  std::string target(req.target());
  if (const auto q = target.find('?'); q != std::string::npos) target.resize(q);
  if (status != 200) {
    const Json j = Json::parse(res.body(), nullptr, false);
    FUZZ_CHECK(j.is_object() && j.contains("error") && j["error"].is_string(),
               "error body is not {\"error\": ...}: %s", res.body().c_str());
  } else if (req.method() == http::verb::get &&
             (target == "/api/stats" || target == "/api/snapshot")) {
    FUZZ_CHECK(!Json::parse(res.body(), nullptr, false).is_discarded(), "%s is not JSON",
               target.c_str());
  }
  if (req.method() == http::verb::post && status == 200) {
    // Which node moved: the id in the target must be that node's.
    static constexpr std::string_view kPrefix = "/api/nodes/";
    static constexpr std::string_view kSuffix = "/position";
    FUZZ_CHECK(target.starts_with(kPrefix) && target.ends_with(kSuffix), "POST %s answered 200",
               target.c_str());
    const std::string id_text =
        target.substr(kPrefix.size(), target.size() - kPrefix.size() - kSuffix.size());
    const auto after = f.engine->positions();
    const auto& ids = f.engine->node_ids();
    // Before the engine's first tick it reports no positions at all: a move
    // is then only pending, with nothing to compare yet.
    for (std::size_t i = 0; i < ids.size() && i < before.size() && i < after.size(); ++i) {
      if (!same_position(before[i], after[i])) {
        FUZZ_CHECK(DashboardFixture::names_node(id_text, ids[i]), "POST %s moved node %u",
                   target.c_str(), unsigned{ids[i]});
      }
    }
  }
  f.check_positions();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  DashboardFixture& f = fixture();
  std::string_view rest(reinterpret_cast<const char*>(data), size);
  for (int n = 0; n < 4 && !rest.empty(); ++n) {
    http::request_parser<http::string_body> parser;
    parser.body_limit(rfsitl::monitor::kMaxRequestBytes);
    parser.eager(true);
    boost::beast::error_code ec;
    while (!parser.is_done()) {
      const std::size_t used = parser.put(boost::asio::buffer(rest.data(), rest.size()), ec);
      rest.remove_prefix(used);
      if (ec == http::error::need_more) ec = {};
      if (ec) break;
      if (used == 0 && !parser.is_done()) {
        parser.put_eof(ec);  // all bytes given and more needed: the client stopped sending
        break;
      }
    }
    if (ec || !parser.is_done()) return 0;  // the session closes the connection
    const http::request<http::string_body> req = parser.release();
    const auto before = f.engine->positions();
    http::status refused{};
    const std::string why = f.server->refusal(req, refused);
    if (!why.empty()) {
      FUZZ_CHECK(refused == http::status::forbidden || refused == http::status::misdirected_request,
                 "refused with status %u", static_cast<unsigned>(refused));
      const auto res = rfsitl::monitor::Server::error_response(req, refused, why);
      check_response(f, req, res, before);
      FUZZ_CHECK(same_positions(f.engine->positions(), before), "a refused request moved a node");
      if (!res.keep_alive()) return 0;
      continue;
    }
    const auto host = req.find(http::field::host);
    FUZZ_CHECK(host != req.end(), "served a request without Host");
    if (websocket::is_upgrade(req) && req.target() == "/ws") {
      return 0;  // handed to a WebSocket session (dashboard_ws_fuzzer)
    }
    const auto res = f.server->handle(req);
    check_response(f, req, res, before);
    if (!res.keep_alive()) return 0;
  }
  return 0;
}
