#pragma once
/// Shared by the dashboard fuzzers. The dashboard's request handling (Server::handle
/// for HTTP, ViewerSession::on_message for WebSocket) lives in the anonymous
/// namespace of src/monitor/dashboard_server.cpp, and the only public entry point
/// starts a TCP server. So this harness compiles that file into the fuzzer, with
/// `private` read as `public` for its classes only (every header it uses is
/// included first, untouched), builds one Server over an engine that never runs,
/// and stops the server's I/O thread: the fuzzer calls the handlers directly on
/// its own thread, with nothing else running. It follows the session code of
/// dashboard_server.cpp (refusal, upgrade, handle; on_message, send); when that
/// changes, this harness may need to follow.
///
/// The pure parts already in the monitor library (request_checks.hpp,
/// position_request.hpp) are reached through these handlers. What would make the
/// rest reachable without this: a function of the library such as
/// `Response handle_request(DashboardState&, const Request&)` and
/// `std::optional<std::string> handle_viewer_message(DashboardState&, text)`.
#include <utility>  // GCC 12 + C++20: before Boost.Asio

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <chrono>
#include <cmath>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include "rfsitl/common/geodesy.hpp"
#include "rfsitl/engine/engine.hpp"
#include "rfsitl/monitor/dashboard.hpp"
#include "rfsitl/monitor/link_table.hpp"
#include "rfsitl/monitor/live_view.hpp"
#include "rfsitl/monitor/position_request.hpp"
#include "rfsitl/monitor/request_checks.hpp"
#include "rfsitl/monitor/stats_report.hpp"
#include "rfsitl/monitor/viewer_queue.hpp"
#include "rfsitl/registry/phy_registry.hpp"
#include "rfsitl/scenario/default_formation.hpp"
#include "rfsitl/scenario/scenario.hpp"
#include "viewer_messages.hpp"
#include "web_assets.hpp"

#define private public
#include "../src/monitor/dashboard_server.cpp"  // NOLINT(bugprone-suspicious-include)
#undef private

#include "fuzz_check.hpp"

namespace rfsitl::fuzz {

class NullSink final : public engine::FrameSink {
 public:
  void deliver(std::size_t, NetFrame&&) override {}
};

/// Nodes 1..4 in the default formation plus node 9 without a position; control
/// on, so that move requests reach move_node. The engine runs one millisecond of
/// virtual time first, so the server answers as it does during a run; with
/// RFSITL_FUZZ_BEFORE_RUN=1 in the environment it does not, and the server
/// answers as it does before Engine::run (`rfsitl run` serves the dashboard
/// while it waits for external nodes to join).
struct DashboardFixture {
  scenario::Scenario scenario;
  NullSink sink;
  std::unique_ptr<engine::Engine> engine;
  monitor::Server* server = nullptr;

  DashboardFixture() {
    spdlog::set_level(spdlog::level::off);
    scenario.name = "fuzz";
    scenario.timing.mode = scenario::TimeMode::kVirtual;
    scenario.timing.duration_s = 0.001;
    scenario.nodes = scenario::default_formation(4, scenario.channel);
    scenario::NodeConfig lost;
    lost.id = 9;
    scenario.nodes.push_back(lost);
    engine = engine::make_engine(scenario, sink);
    const char* before_run = std::getenv("RFSITL_FUZZ_BEFORE_RUN");
    monitor::DashboardSettings settings;
    settings.port = 0;
    settings.control = true;
    server = new monitor::Server(settings, scenario, *engine);  // never destroyed
    // Stop serving: from here on only the fuzzer's thread touches the server.
    server->io_.stop();
    server->thread_.join();
    if (before_run == nullptr || std::string(before_run) != "1") {
      const std::atomic<bool> stop{false};
      engine->run(stop);
    }
  }

  /// Every known position stays finite (a move must never store NaN or inf).
  void check_positions() const {
    for (const auto& p : engine->positions()) {
      if (p) {
        FUZZ_CHECK(std::isfinite(p->x) && std::isfinite(p->y) && std::isfinite(p->z),
                   "a node's position is not finite");
      }
    }
  }

  /// True when `text` names node `id` as a plain decimal (optional '+', leading zeros).
  static bool names_node(std::string_view text, NodeId id) {
    if (!text.empty() && text.front() == '+') text.remove_prefix(1);
    if (text.empty()) return false;
    for (const char c : text) {
      if (c < '0' || c > '9') return false;
    }
    while (text.size() > 1 && text.front() == '0') text.remove_prefix(1);
    return text == std::to_string(unsigned{id});
  }
};

inline DashboardFixture& fixture() {
  static DashboardFixture* f = new DashboardFixture;  // lives until exit
  return *f;
}

}  // namespace rfsitl::fuzz
