#include <utility>  // GCC 12 + C++20: before Boost.Asio

#include <algorithm>
#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <charconv>
#include <chrono>
#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include "rfsitl/common/build_version.hpp"
#include "rfsitl/common/geodesy.hpp"
#include "rfsitl/common/log_text.hpp"
#include "rfsitl/monitor/control_token.hpp"
#include "rfsitl/monitor/dashboard.hpp"
#include "rfsitl/monitor/json_text.hpp"
#include "rfsitl/monitor/link_table.hpp"
#include "rfsitl/monitor/node_counter_report.hpp"
#include "rfsitl/monitor/position_request.hpp"
#include "rfsitl/monitor/request_checks.hpp"
#include "rfsitl/monitor/stats_report.hpp"
#include "rfsitl/monitor/viewer_queue.hpp"
#include "rfsitl/registry/phy_registry.hpp"
#include "viewer_messages.hpp"
#include "web_assets.hpp"

namespace rfsitl::monitor {
namespace {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;
using Json = nlohmann::json;

/// Requests and viewer messages (a watch or a move is a few dozen bytes).
constexpr std::size_t kMaxRequestBytes = 64 * 1024;

class Server;

class ViewerSession : public std::enable_shared_from_this<ViewerSession> {
 public:
  /// `control_refusal`: why this viewer may not move nodes ("" when it may, as
  /// far as the control token goes), decided once from its upgrade request.
  ViewerSession(tcp::socket socket, Server& server, std::string control_refusal)
      : ws_(std::move(socket)), server_(server), control_refusal_(std::move(control_refusal)) {}
  void start(http::request<http::string_body> request);
  /// Queues a message. A viewer that cannot keep up loses the oldest ones
  /// (a snapshot or spectrum is replaced by the next), so its queue stays
  /// bounded (ViewerQueue).
  void send(OutgoingMessage message);
  void send_event(std::string text) {
    send({std::make_shared<const std::string>(std::move(text)), MessageKind::kEvent});
  }
  /// A snapshot this viewer lost carried the link matrix: its next must too.
  bool take_lost_snr() { return queue_.take_lost_snr(); }
  std::optional<std::size_t> watching() const { return watching_; }
  SampleTime last_constellation = -1;
  const std::string& control_refusal() const { return control_refusal_; }
  void close();

 private:
  void read();
  void on_message(const std::string& text);
  void write_next();
  void finish();

  websocket::stream<beast::tcp_stream> ws_;
  Server& server_;
  std::string control_refusal_;
  beast::flat_buffer buffer_;
  ViewerQueue queue_;
  std::optional<std::size_t> watching_;
  bool finished_ = false;
  bool warned_ = false;  // about dropped messages, once per viewer
};

class Server final : public Dashboard {
 public:
  Server(const DashboardSettings& settings, const scenario::Scenario& s, engine::Engine& e)
      : settings_(settings),
        scenario_(s),
        engine_(e),
        view_(e.node_ids()),
        per_curves_(declared_per_curves(s)),
        timer_(io_) {
    for (std::size_t i = 0; i < s.nodes.size(); ++i) {
      const scenario::PhyChoice& phy = s.phy_of(i);
      sensitivity_.push_back(
          phy.external_program()
              ? NAN
              : phy::make_transceiver(phy.type, phy.settings)->sensitivity_snr_db());
    }
    listen();
    engine_.add_observer(view_);
    schedule_push();
    thread_ = std::thread([this] { io_.run(); });
  }

  ~Server() override {
    asio::post(io_, [this] {
      acceptor_.close();
      timer_.cancel();
      for (const auto& w : viewers_) {
        if (auto v = w.lock()) v->close();
      }
      io_.stop();
    });
    thread_.join();
  }

  std::string url() const override {
    const bool v6 = settings_.bind_address.find(':') != std::string::npos;
    return "http://" + (v6 ? "[" + settings_.bind_address + "]" : settings_.bind_address) + ":" +
           std::to_string(port_) + "/";
  }
  std::uint16_t port() const override { return port_; }
  std::size_t viewers() const override { return viewer_count_.load(); }
  std::uint64_t messages_dropped() const override { return dropped_.load(); }
  std::size_t peak_send_queue() const override { return peak_queue_.load(); }
  std::uint64_t control_refused() const override { return control_refused_.load(); }

  // ---- called on the I/O thread by sessions --------------------------------------
  void add_viewer(const std::shared_ptr<ViewerSession>& v) {
    viewers_.push_back(v);
    viewer_count_.store(viewers_.size());
    // "control": whether this viewer may move nodes; with control on but
    // without the token, "control_refused" says why not.
    const bool may_control = settings_.control && v->control_refusal().empty();
    Json hello = {{"type", "hello"},
                  {"scenario", scenario_.name},
                  {"rfsitl_version", build_version()},
                  {"control", may_control},
                  {"sample_rate_hz", scenario_.timing.sample_rate_hz},
                  {"spectrum_bins", LiveView::kSpectrumBins},
                  {"node_ids", engine_.node_ids()},
                  {"counters", node_counter_fields_json()}};
    if (settings_.control && !may_control) hello["control_refused"] = v->control_refusal();
    v->send({std::make_shared<const std::string>(json_text(hello)), MessageKind::kEssential});
    // A new viewer needs the link matrix, which later snapshots carry only
    // when something moved.
    v->send(
        {std::make_shared<const std::string>(json_text(snapshot_json(
             scenario_, engine_, view_, sensitivity_, settings_.control, true, settings_.sources))),
         MessageKind::kSnapshot, true});
  }

  /// A viewer's queue dropped `n` messages and has held up to `peak`.
  void note_queue(std::uint64_t n, std::size_t peak) {
    dropped_.fetch_add(n);
    std::size_t old = peak_queue_.load();
    while (old < peak && !peak_queue_.compare_exchange_weak(old, peak)) {
    }
  }

  void remove_viewer(ViewerSession* v) {
    std::erase_if(viewers_, [v](const auto& w) {
      const auto p = w.lock();
      return !p || p.get() == v;
    });
    viewer_count_.store(viewers_.size());
  }

  bool control_on() const { return settings_.control; }

  void watch(std::optional<std::size_t> node, int delta) {
    if (node) view_.watch(*node, delta);
  }

  std::optional<std::size_t> node_index(const Json& id) const {
    // Compared at full width: a narrowing cast first would let 2^32 + 2 reach node 2.
    if (!id.is_number_unsigned() || id.get<std::uint64_t>() > kMaxNodeId) return std::nullopt;
    return engine_.index_of(static_cast<NodeId>(id.get<std::uint64_t>()));
  }

  /// Moves a node as a location feed would, within the same limits; returns an
  /// error text of our own or "". A position without altitude (z or alt)
  /// keeps the node's current one.
  std::string move_node(std::size_t index, const Json& where) {
    if (!settings_.control) {
      return "control is off: start the emulator with --dashboard-control to move nodes";
    }
    // Before the engine's first tick it has no positions yet: the scenario's.
    const auto positions = engine_.positions();
    std::optional<Ecef> current;
    if (index < positions.size()) {
      current = positions[index];
    } else if (const auto& initial = scenario_.nodes.at(index).initial_position) {
      current = to_ecef(*initial, scenario_.channel.origin);
    }
    const double z = current ? ecef_to_local(*current, scenario_.channel.origin).z_m : 0.0;
    const double alt = current ? ecef_to_geodetic(*current).alt_m : 0.0;
    const PositionRequest r = read_position_request(where, z, alt);
    if (!r.position) return "bad position: " + r.error;
    engine_.set_position(index, to_ecef(*r.position, scenario_.channel.origin));
    spdlog::info("dashboard: node {} moved by a viewer", engine_.node_ids()[index]);
    return "";
  }

  /// Why a control request `req` (a move, or the /ws upgrade that may later
  /// send moves) lacks the control token, or "" when it has it or none is needed.
  std::string control_token_refusal_of(const http::request<http::string_body>& req) const {
    if (settings_.control_token.empty()) return "";
    const auto it = req.find(http::field::authorization);
    std::optional<std::string_view> authorization;
    if (it != req.end()) authorization = std::string_view(it->value().data(), it->value().size());
    return control_token_refusal(std::string_view(req.target().data(), req.target().size()),
                                 authorization, settings_.control_token);
  }

  /// A control request was refused for want of the token: counted, and logged
  /// the first few times (a client retrying must not flood the log).
  void note_control_refused(const std::string& why, const std::string& who) {
    const std::uint64_t n = control_refused_.fetch_add(1) + 1;
    if (n <= 20 || n % 1000 == 0) {
      spdlog::warn("dashboard: a move from {} refused ({} so far): {}", who, n, why);
    }
  }

  /// Why `req` must be refused ("" to serve it) and with which status: a Host
  /// that is not this server (DNS rebinding) or another site's Origin.
  std::string refusal(const http::request<http::string_body>& req, http::status& status) const {
    const auto header = [&](http::field f) -> std::optional<std::string_view> {
      const auto it = req.find(f);
      if (it == req.end()) return std::nullopt;
      return std::string_view(it->value().data(), it->value().size());
    };
    bool misdirected = false;
    std::string why = request_refusal(header(http::field::host), header(http::field::origin),
                                      settings_.bind_address, port_, misdirected);
    status = misdirected ? http::status::misdirected_request : http::status::forbidden;
    return why;
  }

  http::response<http::string_body> handle(const http::request<http::string_body>& req);

  /// The link table of the moment (link_table.hpp), PER for `payload_bytes`.
  std::vector<LinkRow> links(std::size_t payload_bytes) const {
    const auto positions = engine_.positions();
    const auto gains = engine_.link_gains();
    const auto outcomes = view_.link_outcomes();
    return link_rows({engine_.node_ids(), positions, gains, scenario_.channel.noise_variance,
                      &outcomes, per_curves_, payload_bytes});
  }

  /// {"error": message} with `status`.
  static http::response<http::string_body> error_response(
      const http::request<http::string_body>& req, http::status status,
      const std::string& message) {
    http::response<http::string_body> res{status, req.version()};
    res.keep_alive(req.keep_alive());
    res.set(http::field::server, "rfsitl");
    res.set(http::field::cache_control, "no-store");
    res.set(http::field::content_type, "application/json");
    res.body() = json_text(Json{{"error", message}});
    res.prepare_payload();
    return res;
  }

  /// The dashboard's own numbers, appended to /metrics.
  std::string dashboard_metrics() const {
    return dashboard_metrics_text(viewers(), messages_dropped(), control_refused());
  }

 private:
  void listen() {
    boost::system::error_code ec;
    // "localhost" is a valid bind address for the other ports too.
    const auto address = asio::ip::make_address(
        settings_.bind_address == "localhost" ? "127.0.0.1" : settings_.bind_address, ec);
    if (ec) {
      throw std::runtime_error("dashboard: bad bind address '" + settings_.bind_address +
                               "': " + ec.message());
    }
    const auto try_port = [&](std::uint16_t port) {
      acceptor_.close(ec);
      ec.clear();
      acceptor_.open(address.is_v6() ? tcp::v6() : tcp::v4(), ec);
      if (!ec) acceptor_.set_option(asio::socket_base::reuse_address(true), ec);
      if (!ec) acceptor_.bind(tcp::endpoint(address, port), ec);
      if (!ec) acceptor_.listen(asio::socket_base::max_listen_connections, ec);
      return !ec;
    };
    if (!try_port(settings_.port)) {
      const std::string first = ec.message();
      if (!settings_.fall_back_to_any_port || settings_.port == 0 || !try_port(0)) {
        throw std::runtime_error("dashboard port " + std::to_string(settings_.port) + " on " +
                                 settings_.bind_address + ": " + first);
      }
      spdlog::warn("dashboard: port {} is taken ({}); using port {} instead", settings_.port, first,
                   acceptor_.local_endpoint().port());
    }
    port_ = acceptor_.local_endpoint().port();
    accept();
  }

  void accept();

  void schedule_push() {
    timer_.expires_after(std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        std::chrono::duration<double>(settings_.push_interval_s)));
    timer_.async_wait([this](const boost::system::error_code& ec) {
      if (ec) return;
      push();
      schedule_push();
    });
  }

  void push();

  DashboardSettings settings_;
  const scenario::Scenario& scenario_;
  engine::Engine& engine_;
  LiveView view_;
  std::vector<phy::PerCurve> per_curves_;  // by node: its receiver's declared curve
  std::vector<double> sensitivity_;
  asio::io_context io_;
  tcp::acceptor acceptor_{io_};
  asio::steady_timer timer_;
  asio::steady_timer accept_retry_{io_};
  std::uint64_t accept_failures_ = 0;  // accept loop only
  std::uint16_t port_ = 0;
  std::vector<std::weak_ptr<ViewerSession>> viewers_;
  std::atomic<std::size_t> viewer_count_{0};
  std::atomic<std::uint64_t> dropped_{0};
  std::atomic<std::size_t> peak_queue_{0};
  std::atomic<std::uint64_t> control_refused_{0};
  std::vector<float> last_gains_;  // as of the latest snapshot pushed
  std::thread thread_;
};

// ---- plain HTTP ----------------------------------------------------------------------

/// A request target without its query ("/ws?token=..." -> "/ws").
std::string_view path_of(beast::string_view target) {
  const std::string_view t(target.data(), target.size());
  return t.substr(0, t.find('?'));
}

class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(tcp::socket socket, Server& server) : stream_(std::move(socket)), server_(server) {}
  void start() { read(); }

 private:
  void read() {
    parser_.emplace();
    parser_->body_limit(kMaxRequestBytes);
    stream_.expires_after(std::chrono::seconds(30));
    http::async_read(
        stream_, buffer_, *parser_,
        [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_read(ec); });
  }

  void on_read(beast::error_code ec) {
    if (ec) {
      stream_.socket().shutdown(tcp::socket::shutdown_send, ec);
      return;
    }
    auto req = parser_->release();
    http::status status{};
    if (const std::string why = server_.refusal(req, status); !why.empty()) {
      // All three quote the client's request (the reason its Host or Origin).
      // The target without its query: a control token must not reach the log.
      std::string target(req.target());
      target.resize(std::min(target.size(), target.find('?')));
      spdlog::warn("dashboard: {} {} refused: {}", log_text(std::string(req.method_string())),
                   log_text(target), log_text(why));
      return respond(Server::error_response(req, status, why), req.method());
    }
    if (websocket::is_upgrade(req) && path_of(req.target()) == "/ws") {
      stream_.expires_never();
      // Without the token the viewer may still watch; its moves are refused.
      std::make_shared<ViewerSession>(stream_.release_socket(), server_,
                                      server_.control_token_refusal_of(req))
          ->start(std::move(req));
      return;
    }
    respond(server_.handle(req), req.method());
  }

  /// Sends `response` to a `method` request: to HEAD without its body (its
  /// headers, Content-Length included, as GET's).
  void respond(http::response<http::string_body> response, http::verb method) {
    auto res = std::make_shared<http::response<http::string_body>>(std::move(response));
    if (method == http::verb::head) res->body().clear();
    http::async_write(stream_, *res,
                      [self = shared_from_this(), res](beast::error_code wec, std::size_t) {
                        if (!wec && res->keep_alive()) self->read();
                      });
  }

  beast::tcp_stream stream_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  Server& server_;
};

void Server::accept() {
  acceptor_.async_accept([this](beast::error_code ec, tcp::socket s) {
    if (ec == asio::error::operation_aborted || !acceptor_.is_open()) return;  // closed
    if (ec) {
      // Out of descriptors (EMFILE) and the like pass: try again shortly rather
      // than stop serving for good.
      // Logged the first 20 times, then one in 1000: a full descriptor table
      // lasts many retries.
      if (++accept_failures_ <= 20 || accept_failures_ % 1000 == 0) {
        spdlog::warn("dashboard: cannot accept a connection ({}); retrying in 100 ms ({} so far)",
                     ec.message(), accept_failures_);
      }
      accept_retry_.expires_after(std::chrono::milliseconds(100));
      accept_retry_.async_wait([this](const boost::system::error_code& wait_ec) {
        if (!wait_ec) accept();
      });
      return;
    }
    std::make_shared<HttpSession>(std::move(s), *this)->start();
    accept();
  });
}

http::response<http::string_body> Server::handle(const http::request<http::string_body>& req) {
  http::response<http::string_body> res;
  res.version(req.version());
  res.keep_alive(req.keep_alive());
  res.set(http::field::server, "rfsitl");
  res.set(http::field::cache_control, "no-store");
  const auto reply = [&](http::status status, std::string_view type, std::string body) {
    res.result(status);
    res.set(http::field::content_type, beast::string_view(type.data(), type.size()));
    res.body() = std::move(body);
    res.prepare_payload();
    return res;
  };
  const auto error = [&](http::status status, const std::string& message) {
    return error_response(req, status, message);
  };
  std::string target(req.target());
  if (const auto q = target.find('?'); q != std::string::npos) target.resize(q);
  // HEAD is answered as GET; HttpSession::respond leaves the body out
  // (Prometheus and load balancers probe with it).
  if (req.method() == http::verb::get || req.method() == http::verb::head) {
    if (target == "/") target = "/index.html";
    for (const WebAsset& a : web_assets()) {
      if (a.path == target) return reply(http::status::ok, a.content_type, std::string(a.body));
    }
    if (target == "/api/stats") {
      return reply(http::status::ok, "application/json",
                   json_text(stats_with_links_json(scenario_, engine_, settings_.sources)));
    }
    if (target == "/api/snapshot") {
      return reply(http::status::ok, "application/json",
                   json_text(snapshot_json(scenario_, engine_, view_, sensitivity_,
                                           settings_.control, true, settings_.sources)));
    }
    if (target == "/api/links") {
      const std::string_view full(req.target().data(), req.target().size());
      const std::size_t q = full.find('?');
      std::string why;
      const auto query =
          parse_link_query(q == std::string_view::npos ? "" : full.substr(q + 1), why);
      if (!query) return error(http::status::bad_request, why);
      return reply(http::status::ok, "application/json",
                   json_text(link_table_json(select_links(links(query->payload_bytes), *query),
                                             engine_.num_nodes(), *query,
                                             scenario_.channel.noise_variance)));
    }
    if (target == "/metrics") {
      std::ostringstream link_metrics;
      write_link_metrics(link_metrics, links(LinkQuery{}.payload_bytes), engine_.num_nodes());
      return reply(http::status::ok, "text/plain; version=0.0.4",
                   prometheus_text(scenario_, engine_, settings_.sources) + link_metrics.str() +
                       dashboard_metrics());
    }
    return error(http::status::not_found, "no such page: " + target);
  }
  // Host and Origin were checked before (HttpSession::on_read).
  static constexpr std::string_view kPrefix = "/api/nodes/";
  static constexpr std::string_view kSuffix = "/position";
  if (req.method() == http::verb::post && target.starts_with(kPrefix) &&
      target.ends_with(kSuffix)) {
    const std::string id_text =
        target.substr(kPrefix.size(), target.size() - kPrefix.size() - kSuffix.size());
    // Before anything about the node or the body is answered: a client without
    // the token learns nothing but that it needs one.
    if (settings_.control) {
      if (const std::string why = control_token_refusal_of(req); !why.empty()) {
        note_control_refused(why, "POST " + log_text(target));
        auto refused = error(http::status::unauthorized, why);
        refused.set(http::field::www_authenticate, "Bearer realm=\"rfsitl dashboard control\"");
        return refused;
      }
    }
    // Digits only (stoul would take " 2" and "-1"), parsed at full width.
    std::uint64_t id = 0;
    const auto [end, ec] = std::from_chars(id_text.data(), id_text.data() + id_text.size(), id);
    if (id_text.empty() || ec == std::errc::invalid_argument ||
        end != id_text.data() + id_text.size()) {
      return error(http::status::bad_request, "bad node id '" + log_text(id_text) + "'");
    }
    if (ec == std::errc::result_out_of_range) id = std::numeric_limits<std::uint64_t>::max();
    const auto index = node_index(Json(id));
    if (!index) return error(http::status::not_found, "no node " + id_text);
    const Json body = Json::parse(req.body(), nullptr, false);
    if (body.is_discarded()) {
      return error(http::status::bad_request,
                   "body is not JSON: expected {\"x\":..,\"y\":..,\"z\":..} or "
                   "{\"lat\":..,\"lon\":..,\"alt\":..}");
    }
    const std::string why = move_node(*index, body);
    if (!why.empty()) {
      return error(settings_.control ? http::status::bad_request : http::status::forbidden, why);
    }
    return reply(http::status::ok, "application/json", json_text(Json{{"ok", true}}));
  }
  auto refused = error(http::status::method_not_allowed, "unsupported request");
  refused.set(http::field::allow, target.starts_with(kPrefix) ? "POST" : "GET, HEAD");
  return refused;
}

void Server::push() {
  if (viewers_.empty()) return;
  view_.publish_spectra();
  // The SNR matrix (most of a big swarm's snapshot) only when the geometry changed.
  auto gains = engine_.link_gains();
  const bool moved = gains != last_gains_;
  last_gains_ = std::move(gains);
  const auto snapshot = [&](bool with_snr) {
    return std::make_shared<const std::string>(json_text(snapshot_json(
        scenario_, engine_, view_, sensitivity_, settings_.control, with_snr, settings_.sources)));
  };
  const auto latest = snapshot(moved);
  std::shared_ptr<const std::string> with_snr = moved ? latest : nullptr;
  std::map<std::size_t, std::shared_ptr<const std::string>> spectra;
  const double virtual_s = engine_.status().virtual_s;
  for (const auto& w : viewers_) {
    const auto v = w.lock();
    if (!v) continue;
    // A viewer that lost a snapshot with the link matrix gets it again.
    if (v->take_lost_snr()) {
      if (!with_snr) with_snr = snapshot(true);
      v->send({with_snr, MessageKind::kSnapshot, true});
    } else {
      v->send({latest, MessageKind::kSnapshot, moved});
    }
    const auto node = v->watching();
    if (!node) continue;
    auto& spectrum = spectra[*node];
    if (!spectrum) {
      const std::vector<float> db = view_.spectrum(*node);
      if (db.empty()) continue;  // nothing averaged yet
      spectrum = std::make_shared<const std::string>(spectrum_message(
          engine_.node_ids()[*node], virtual_s, scenario_.timing.sample_rate_hz, db));
    }
    v->send({spectrum, MessageKind::kSpectrum});
    const auto c = view_.constellation(*node);
    if (c && c->time != v->last_constellation) {
      v->last_constellation = c->time;
      v->send_event(
          constellation_message(engine_.node_ids()[*node], *c, scenario_.timing.sample_rate_hz));
    }
  }
}

// ---- WebSocket viewers ---------------------------------------------------------------

void ViewerSession::start(http::request<http::string_body> request) {
  ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
  ws_.auto_fragment(false);  // one frame per message: fewer writes for big snapshots
  ws_.read_message_max(kMaxRequestBytes);
  ws_.async_accept(request, [self = shared_from_this()](beast::error_code ec) {
    if (ec) return;
    // One I/O thread runs every session and the server: no locking needed.
    self->server_.add_viewer(self);
    self->read();
  });
}

void ViewerSession::read() {
  ws_.async_read(buffer_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
    if (ec) return self->finish();
    const std::string text = beast::buffers_to_string(self->buffer_.data());
    self->buffer_.consume(self->buffer_.size());
    self->on_message(text);
    self->read();
  });
}

void ViewerSession::on_message(const std::string& text) {
  const Json m = Json::parse(text, nullptr, false);
  const auto reply_error = [this](const std::string& why) {
    send_event(json_text(Json{{"type", "error"}, {"message", why}}));
  };
  if (m.is_discarded() || !m.is_object() || !m.contains("type")) {
    return reply_error("messages are JSON objects with a \"type\"");
  }
  if (!m.contains("node")) return reply_error("messages need a \"node\"");
  const auto node = server_.node_index(m["node"]);
  if (m["type"] == "watch") {
    if (!node && !m["node"].is_null()) return reply_error("watch: unknown node");
    server_.watch(watching_, -1);
    watching_ = node;
    server_.watch(watching_, +1);
    last_constellation = -1;
  } else if (m["type"] == "move") {
    if (!control_refusal_.empty() && server_.control_on()) {
      beast::error_code ec;
      const auto peer = beast::get_lowest_layer(ws_).socket().remote_endpoint(ec);
      server_.note_control_refused(control_refusal_, ec ? std::string("a viewer")
                                                        : "viewer " + peer.address().to_string() +
                                                              ":" + std::to_string(peer.port()));
      return reply_error(control_refusal_);
    }
    if (!node) return reply_error("move: unknown node");
    const std::string why = server_.move_node(*node, m);
    if (!why.empty()) reply_error(why);
  } else {
    reply_error("unknown message type");
  }
}

void ViewerSession::send(OutgoingMessage message) {
  if (finished_) return;
  const std::size_t dropped = queue_.push(std::move(message));
  server_.note_queue(dropped, queue_.peak());
  if (dropped > 0 && !warned_) {
    warned_ = true;
    beast::error_code ec;
    const auto peer = beast::get_lowest_layer(ws_).socket().remote_endpoint(ec);
    spdlog::warn(
        "dashboard: viewer {}:{} is not reading its messages; dropping the oldest to keep at most "
        "{} queued (counted in rfsitl_dashboard_messages_dropped_total)",
        ec ? std::string("?") : peer.address().to_string(), ec ? 0 : peer.port(),
        ViewerQueue::kCapacity);
  }
  if (!queue_.writing()) write_next();
}

void ViewerSession::write_next() {
  ws_.text(true);
  const auto text = queue_.start_front().text;  // kept alive until the write completes
  ws_.async_write(asio::buffer(*text),
                  [self = shared_from_this(), text](beast::error_code ec, std::size_t) {
                    if (ec) return self->finish();
                    self->queue_.pop_front();
                    if (!self->queue_.empty()) self->write_next();
                  });
}

void ViewerSession::finish() {
  if (finished_) return;
  finished_ = true;
  queue_.clear();
  server_.watch(watching_, -1);
  watching_.reset();
  server_.remove_viewer(this);
}

void ViewerSession::close() {
  beast::error_code ec;
  beast::get_lowest_layer(ws_).socket().close(ec);
}

}  // namespace

std::unique_ptr<Dashboard> start_dashboard(const DashboardSettings& settings,
                                           const scenario::Scenario& scenario,
                                           engine::Engine& engine) {
  return std::make_unique<Server>(settings, scenario, engine);
}

}  // namespace rfsitl::monitor
