#include "rfsitl/io/node_servers.hpp"

#include <algorithm>
#include <utility>  // GCC 12 + C++20: before Boost.Asio

#include <array>
#include <boost/asio.hpp>
#include <deque>
#include <span>
#include <thread>
#include <vector>

#include <spdlog/spdlog.h>

#include "rfsitl/channel/geodesy.hpp"
#include "rfsitl/io/location_parser.hpp"
#include "rfsitl/io/net_framing.hpp"

namespace rfsitl::io {
namespace {

namespace asio = boost::asio;
using tcp = asio::ip::tcp;

constexpr std::size_t kReadChunk = 64 * 1024;
constexpr std::size_t kMaxWriteBacklogBytes = 4 * 1024 * 1024;
constexpr std::size_t kMaxLocationLine = 4096;

/// Logs the first few problems of a kind in full, then one in a thousand, so a
/// misbehaving client cannot flood the log; the counters still see every one.
bool should_log(std::uint64_t count) {
  return count <= 20 || count % 1000 == 0;
}

/// A client connection on one node's port. It reads until the peer closes and
/// hands every chunk to consume(); pending handlers share its ownership.
class PortSession : public std::enable_shared_from_this<PortSession> {
 public:
  PortSession(tcp::socket socket, std::size_t node, NodeId id, std::uint16_t port,
              engine::Engine& engine)
      : socket_(std::move(socket)), node_(node), id_(id), port_(port), engine_(engine) {}
  virtual ~PortSession() = default;
  PortSession(const PortSession&) = delete;
  PortSession& operator=(const PortSession&) = delete;

  void start() { read(); }

  void close() {
    boost::system::error_code ignored;
    socket_.shutdown(tcp::socket::shutdown_both, ignored);
    socket_.close(ignored);
  }

  bool open() const { return socket_.is_open(); }

 protected:
  virtual void consume(std::span<const std::uint8_t> bytes) = 0;

  tcp::socket socket_;
  std::size_t node_;
  NodeId id_;
  std::uint16_t port_;
  engine::Engine& engine_;

 private:
  void read() {
    socket_.async_read_some(
        asio::buffer(buf_),
        [self = shared_from_this()](const boost::system::error_code& ec, std::size_t n) {
          if (ec) {
            self->close();
            return;
          }
          self->consume({self->buf_.data(), n});
          self->read();
        });
  }

  std::vector<std::uint8_t> buf_ = std::vector<std::uint8_t>(kReadChunk);
};

/// One agent connection on a net port: frames in, decoded frames out.
class NetSession final : public PortSession {
 public:
  NetSession(tcp::socket socket, std::size_t node, NodeId id, std::uint16_t port,
             engine::Engine& engine)
      : PortSession(std::move(socket), node, id, port, engine), parser_(engine.max_payload(node)) {}

  /// Queues a frame for the agent; false when the backlog is full.
  bool send(const NetFrame& frame) {
    if (backlog_bytes_ > kMaxWriteBacklogBytes) return false;
    writes_.push_back(encode_net_frame(frame));
    backlog_bytes_ += writes_.back().size();
    if (writes_.size() == 1) write_next();
    return true;
  }

 private:
  void consume(std::span<const std::uint8_t> bytes) override {
    frames_.clear();
    errors_.clear();
    parser_.feed(bytes, frames_, errors_);
    engine::NodeCounters& c = engine_.counters(node_);
    for (const FramingError& e : errors_) {
      engine::NodeCounters::bump(c.framing_errors);
      if (should_log(c.framing_errors.load())) {
        spdlog::warn("node {} net port {}: frame rejected: {}", id_, port_, e.message);
      }
    }
    for (NetFrame& f : frames_) {
      if (!engine_.submit(node_, std::move(f)) && should_log(c.queue_dropped.load())) {
        spdlog::warn("node {} net port {}: TX queue full, frame dropped", id_, port_);
      }
    }
  }

  void write_next() {
    asio::async_write(socket_, asio::buffer(writes_.front()),
                      [self = std::static_pointer_cast<NetSession>(shared_from_this())](
                          const boost::system::error_code& ec, std::size_t) {
                        self->backlog_bytes_ -= self->writes_.front().size();
                        self->writes_.pop_front();
                        if (ec) {
                          self->close();
                          self->writes_.clear();
                          self->backlog_bytes_ = 0;
                          return;
                        }
                        if (!self->writes_.empty()) self->write_next();
                      });
  }

  NetFrameParser parser_;
  std::vector<NetFrame> frames_;
  std::vector<FramingError> errors_;
  std::deque<std::vector<std::uint8_t>> writes_;
  std::size_t backlog_bytes_ = 0;
};

/// One location feed: lines in, positions to the engine.
class LocationSession final : public PortSession {
 public:
  LocationSession(tcp::socket socket, std::size_t node, NodeId id, std::uint16_t port,
                  engine::Engine& engine, const GeodeticPosition& origin)
      : PortSession(std::move(socket), node, id, port, engine), origin_(origin) {}

 private:
  void consume(std::span<const std::uint8_t> bytes) override {
    for (const std::uint8_t byte : bytes) {
      const auto ch = static_cast<char>(byte);
      if (ch != '\n') {
        if (line_.size() < kMaxLocationLine) {
          line_.push_back(ch);
        } else {
          overlong_ = true;
        }
        continue;
      }
      ++line_number_;
      if (overlong_) {
        reject("line longer than " + std::to_string(kMaxLocationLine) + " bytes");
      } else {
        handle_line();
      }
      line_.clear();
      overlong_ = false;
    }
  }

  void handle_line() {
    const LocationParseResult r = parse_location_line(line_);
    if (r.blank) return;
    if (!r.position) {
      reject(r.error);
      return;
    }
    engine_.set_position(node_, channel::to_ecef(*r.position, origin_));
    engine::NodeCounters::bump(engine_.counters(node_).location_updates);
  }

  void reject(const std::string& reason) {
    auto& errors = engine_.counters(node_).location_errors;
    engine::NodeCounters::bump(errors);
    if (should_log(errors.load())) {
      spdlog::warn("node {} location port {}: line {} rejected ({}); last good position kept", id_,
                   port_, line_number_, reason);
    }
  }

  GeodeticPosition origin_;
  std::string line_;
  bool overlong_ = false;
  std::uint64_t line_number_ = 0;
};

class AsioNodeServers final : public NodeServers {
 public:
  explicit AsioNodeServers(const ServerConfig& config) : config_(config) {}
  ~AsioNodeServers() override { stop(); }

  void start(engine::Engine& engine) override {
    engine_ = &engine;
    const auto& ids = engine.node_ids();
    net_.resize(ids.size());
    loc_.resize(ids.size());
    for (std::size_t i = 0; i < ids.size(); ++i) {
      const bool own_net_port =
          std::find(config_.external_net_ports.begin(), config_.external_net_ports.end(), ids[i]) ==
          config_.external_net_ports.end();
      if (own_net_port) {
        net_[i].acceptor = listen(net_port(config_, ids[i]), "net", ids[i]);
        accept_net(i);
      }
      loc_[i].acceptor = listen(loc_port(config_, ids[i]), "location", ids[i]);
      accept_loc(i);
    }
    thread_ = std::thread([this] { io_.run(); });
  }

  void stop() override {
    if (!thread_.joinable()) return;
    asio::post(io_, [this] {
      for (auto& p : net_) {
        if (p.session) p.session->close();
        if (p.acceptor) p.acceptor->close();
      }
      for (auto& p : loc_) {
        if (p.session) p.session->close();
        if (p.acceptor) p.acceptor->close();
      }
      io_.stop();
    });
    thread_.join();
  }

  void deliver(std::size_t node, NetFrame&& frame) override {
    asio::post(io_, [this, node, f = std::move(frame)] {
      auto& session = net_[node].session;
      if (!session || !session->open() || !session->send(f)) {
        engine::NodeCounters::bump(engine_->counters(node).to_agent_dropped);
      }
    });
  }

 private:
  struct NetPort {
    std::unique_ptr<tcp::acceptor> acceptor;
    std::shared_ptr<NetSession> session;
  };
  struct LocPort {
    std::unique_ptr<tcp::acceptor> acceptor;
    std::shared_ptr<LocationSession> session;
  };

  std::unique_ptr<tcp::acceptor> listen(std::uint16_t port, const char* role, NodeId id) {
    const std::string where = std::string(role) + " port " + std::to_string(port) + " of node " +
                              std::to_string(id) + " on " + config_.bind_address;
    boost::system::error_code ec;
    tcp::resolver resolver(io_);
    const auto endpoints = resolver.resolve(config_.bind_address, std::to_string(port),
                                            tcp::resolver::numeric_service, ec);
    if (ec || endpoints.empty())
      throw PortError(where + ": cannot resolve address: " + ec.message());
    auto acceptor = std::make_unique<tcp::acceptor>(io_);
    const tcp::endpoint ep = endpoints.begin()->endpoint();
    acceptor->open(ep.protocol(), ec);
    if (!ec) acceptor->set_option(tcp::acceptor::reuse_address(true), ec);
    if (!ec) acceptor->bind(ep, ec);
    if (!ec) acceptor->listen(asio::socket_base::max_listen_connections, ec);
    if (ec) throw PortError(where + ": " + ec.message());
    return acceptor;
  }

  // A new connection replaces the previous one (DESIGN.md section 3).
  void accept_net(std::size_t i) {
    net_[i].acceptor->async_accept([this, i](const boost::system::error_code& ec,
                                             tcp::socket socket) {
      if (ec) return;  // acceptor closed
      socket.set_option(tcp::no_delay(true));
      if (net_[i].session) net_[i].session->close();
      const NodeId id = engine_->node_ids()[i];
      net_[i].session =
          std::make_shared<NetSession>(std::move(socket), i, id, net_port(config_, id), *engine_);
      net_[i].session->start();
      accept_net(i);
    });
  }

  void accept_loc(std::size_t i) {
    loc_[i].acceptor->async_accept(
        [this, i](const boost::system::error_code& ec, tcp::socket socket) {
          if (ec) return;
          if (loc_[i].session) loc_[i].session->close();
          const NodeId id = engine_->node_ids()[i];
          loc_[i].session = std::make_shared<LocationSession>(
              std::move(socket), i, id, loc_port(config_, id), *engine_, config_.origin);
          loc_[i].session->start();
          accept_loc(i);
        });
  }

  ServerConfig config_;
  asio::io_context io_;
  engine::Engine* engine_ = nullptr;
  std::vector<NetPort> net_;
  std::vector<LocPort> loc_;
  std::thread thread_;
};

}  // namespace

std::unique_ptr<NodeServers> make_node_servers(const ServerConfig& config) {
  return std::make_unique<AsioNodeServers>(config);
}

}  // namespace rfsitl::io
