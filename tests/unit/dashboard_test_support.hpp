#pragma once
// Drives a real dashboard server over loopback without a browser: plain HTTP
// requests and WebSocket clients with Boost.Beast (synchronous; the server has
// its own I/O thread).
#include <utility>  // GCC 12 + C++20: before Boost.Asio

// GCC 12 at -O2 sees Beast's response parser (which only clients use) read a
// boost::optional it may not have set: a known false positive.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#pragma GCC diagnostic pop
#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "monitor_test_scenario.hpp"
#include "rfsitl/engine/engine.hpp"
#include "rfsitl/monitor/dashboard.hpp"
#include "rfsitl/scenario/scenario.hpp"

namespace rfsitl::monitor::test {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;
using Headers = std::map<http::field, std::string>;

/// A scenario, its engine (not running) and a dashboard on a free port of 127.0.0.1.
struct LiveDashboard {
  explicit LiveDashboard(DashboardSettings settings = {}, scenario::Scenario sc = two_nodes())
      : s(std::move(sc)), engine(engine::make_engine(s, sink)) {
    settings.bind_address = "127.0.0.1";
    settings.port = 0;
    dashboard = start_dashboard(settings, s, *engine);
  }
  std::uint16_t port() const { return dashboard->port(); }
  std::string host() const { return "127.0.0.1:" + std::to_string(port()); }

  scenario::Scenario s;
  NullSink sink;
  std::unique_ptr<engine::Engine> engine;
  std::unique_ptr<Dashboard> dashboard;
};

/// One request on a new connection. Host defaults to 127.0.0.1:PORT; a header
/// given as "" is left out.
inline http::response<http::string_body> request(std::uint16_t port, http::verb verb,
                                                 const std::string& target,
                                                 const std::string& body = "",
                                                 const Headers& headers = {}) {
  asio::io_context io;
  beast::tcp_stream stream(io);
  stream.expires_after(std::chrono::seconds(20));  // a hung server fails the test, not hangs it
  stream.connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port));
  http::request<http::string_body> req{verb, target, 11};
  req.set(http::field::host, "127.0.0.1:" + std::to_string(port));
  for (const auto& [field, value] : headers) {
    if (value.empty()) {
      req.erase(field);
    } else {
      req.set(field, value);
    }
  }
  if (!body.empty()) {
    req.set(http::field::content_type, "application/json");
    req.body() = body;
  }
  req.prepare_payload();
  http::write(stream, req);
  beast::flat_buffer buffer;
  http::response<http::string_body> res;
  http::read(stream, buffer, res);
  beast::error_code ec;
  stream.socket().shutdown(tcp::socket::shutdown_both, ec);
  return res;
}

/// A WebSocket client of /ws; `headers` decorate the upgrade request.
struct Viewer {
  asio::io_context io;
  websocket::stream<tcp::socket> ws{io};

  /// Connects and upgrades; the error of the handshake (or none).
  beast::error_code connect(std::uint16_t port, const Headers& headers = {},
                            std::function<void(tcp::socket&)> before_connect = {}) {
    beast::error_code ec;
    ws.next_layer().open(tcp::v4(), ec);
    if (before_connect) before_connect(ws.next_layer());
    ws.next_layer().connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port), ec);
    if (ec) return ec;
    ws.set_option(websocket::stream_base::decorator([headers](websocket::request_type& req) {
      for (const auto& [field, value] : headers) req.set(field, value);
    }));
    ws.handshake(res, "127.0.0.1:" + std::to_string(port), "/ws", ec);
    return ec;
  }
  /// The next text message.
  std::string read() {
    beast::flat_buffer buffer;
    ws.read(buffer);
    return beast::buffers_to_string(buffer.data());
  }
  void write(const std::string& text) {
    ws.text(true);
    ws.write(asio::buffer(text));
  }
  /// write(), giving up after `timeout` (a server that stopped reading): false
  /// then, and the stream is unusable.
  bool write_for(const std::string& text, std::chrono::milliseconds timeout) {
    ws.text(true);
    bool done = false;
    beast::error_code result;
    ws.async_write(asio::buffer(text), [&](beast::error_code ec, std::size_t) {
      done = true;
      result = ec;
    });
    io.restart();
    io.run_for(timeout);
    if (!done) {
      beast::error_code ignored;
      ws.next_layer().close(ignored);
      io.restart();
      io.run();
      return false;
    }
    return !result;
  }
  websocket::response_type res;
};

/// Polls `condition` until it holds or `timeout` passes; its final value.
inline bool wait_for(const std::function<bool()>& condition,
                     std::chrono::milliseconds timeout = std::chrono::seconds(20)) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!condition()) {
    if (std::chrono::steady_clock::now() > deadline) return condition();
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return true;
}

/// Sends an end mark (a message of type "end", which the server answers
/// "unknown message type") and reads up to its reply: the texts of the error
/// messages the viewer got before it, in order.
inline std::vector<std::string> errors_until_end(Viewer& v) {
  v.write(R"({"type": "end", "node": 1})");
  std::vector<std::string> errors;
  for (;;) {
    const nlohmann::json m = nlohmann::json::parse(v.read());
    if (m.at("type") != "error") continue;
    if (m.at("message") == "unknown message type") return errors;
    errors.push_back(m.at("message"));
  }
}

}  // namespace rfsitl::monitor::test
