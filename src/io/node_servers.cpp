#include "rfsitl/io/node_servers.hpp"

#include <algorithm>
#include <utility>  // GCC 12 + C++20: before Boost.Asio

#include <array>
#include <boost/asio.hpp>
#include <chrono>
#include <deque>
#include <span>
#include <thread>
#include <vector>

#include <spdlog/spdlog.h>

#include "rfsitl/channel/geodesy.hpp"
#include "rfsitl/common/log_text.hpp"
#include "rfsitl/io/agent_control.hpp"
#include "rfsitl/io/location_parser.hpp"
#include "rfsitl/io/net_framing.hpp"
#include "rfsitl/io/port_slot.hpp"

namespace rfsitl::io {
namespace {

namespace asio = boost::asio;
using tcp = asio::ip::tcp;

constexpr std::size_t kReadChunk = 64 * 1024;
constexpr std::size_t kMaxWriteBacklogBytes = 4 * 1024 * 1024;
constexpr std::size_t kMaxLocationLine = 4096;
constexpr std::chrono::milliseconds kAcceptRetry{100};
constexpr std::uint8_t kNewline[] = {'\n'};

/// Logs the first few problems of a kind in full, then one in a thousand, so a
/// misbehaving client cannot flood the log; the counters still see every one.
bool should_log(std::uint64_t count) {
  return count <= 20 || count % 1000 == 0;
}

/// A client connection on one node's port. It reads until the peer closes and
/// hands every chunk to consume(); pending handlers share its ownership. Its
/// port's slot decides whether it is the port's agent (port_slot.hpp).
class PortSession : public SlotMember, public std::enable_shared_from_this<PortSession> {
 public:
  PortSession(tcp::socket socket, std::size_t node, NodeId id, std::uint16_t port,
              engine::Engine& engine, PortSlot& slot)
      : socket_(std::move(socket)),
        node_(node),
        id_(id),
        port_(port),
        engine_(engine),
        slot_(slot) {}
  PortSession(const PortSession&) = delete;
  PortSession& operator=(const PortSession&) = delete;

  void start() { read(); }

  void close() override {
    boost::system::error_code ignored;
    socket_.shutdown(tcp::socket::shutdown_both, ignored);
    socket_.close(ignored);
  }

  bool open() const override { return socket_.is_open(); }

 protected:
  virtual void consume(std::span<const std::uint8_t> bytes) = 0;

  /// The connection has ended: account for what it left unfinished.
  virtual void finish() = 0;

  /// Makes this connection the port's agent if it is not yet; false when it
  /// can no longer be (it was closed meanwhile).
  bool claim(const char* why) {
    slot_.claim(this, why);
    return slot_.is_agent(this);
  }

  tcp::socket socket_;
  std::size_t node_;
  NodeId id_;
  std::uint16_t port_;
  engine::Engine& engine_;
  PortSlot& slot_;

 private:
  void read() {
    socket_.async_read_some(
        asio::buffer(buf_),
        [self = shared_from_this()](const boost::system::error_code& ec, std::size_t n) {
          if (ec) {
            self->close();
            self->finish();
            self->slot_.closed(self.get());
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
             engine::Engine& engine, PortSlot& slot)
      : PortSession(std::move(socket), node, id, port, engine, slot),
        parser_(engine.max_payload(node)) {}

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
    for (const FramingError& e : errors_) reject(e.message);
    for (NetFrame& f : frames_) {
      if (is_control_frame(f)) {
        answer_control(control_text(f));
        continue;
      }
      if (!claim("sent a frame")) return;
      if (f.src != id_) {
        // The ledger, traces and the receiver's agent all trust src: a frame
        // that claims another sender is refused rather than misattributed.
        reject("src byte " + std::to_string(f.src) + " is not this port's node id " +
               std::to_string(id_));
        continue;
      }
      if (f.dst == id_) {
        reject("dst " + std::to_string(f.dst) +
               " is this node itself (a radio does not hear its own transmission)");
        continue;
      }
      if (!engine_.submit(node_, std::move(f)) && should_log(c.queue_dropped.load())) {
        spdlog::warn("node {} net port {}: TX queue full, frame dropped", id_, port_);
      }
    }
  }

  void finish() override {
    if (parser_.buffered() > 0) {
      reject("connection ended inside a frame (" + std::to_string(parser_.buffered()) +
             " bytes without a terminator)");
    }
  }

  void reject(const std::string& why) {
    auto& errors = engine_.counters(node_).framing_errors;
    engine::NodeCounters::bump(errors);
    if (should_log(errors.load())) {
      spdlog::warn("node {} net port {}: frame rejected: {}", id_, port_, why);
    }
  }

  void answer_control(std::string_view request) {
    std::string reply;
    if (request == kStatusRequest) {
      reply = format_status_reply({id_, slot_.held_by_other(this), engine_.max_payload(node_)});
    } else if (request == kTakeRequest) {
      claim("asked to take over");
      reply = std::string(kTakenReply);
    } else {
      reply = "rfsitl error unknown request";
    }
    send(make_control_frame(reply));
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
                  engine::Engine& engine, PortSlot& slot, const GeodeticPosition& origin)
      : PortSession(std::move(socket), node, id, port, engine, slot), origin_(origin) {}

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
      if (!claim("sent a position")) return;
      if (overlong_) {
        reject("line longer than " + std::to_string(kMaxLocationLine) + " bytes");
      } else {
        handle_line();
      }
      line_.clear();
      overlong_ = false;
    }
  }

  // A last line without its newline (`echo -n`, a feed that stops mid-write)
  // is still a line: used if it parses, counted as an error if not.
  void finish() override {
    if (line_.empty() && !overlong_) return;
    if (slot_.is_agent(this)) {
      consume(std::span<const std::uint8_t>(kNewline));
    } else {
      ++line_number_;  // a waiting connection may not move the node on its way out
      reject("connection ended before its first complete line");
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
      // The reason quotes the line's own text.
      spdlog::warn("node {} location port {}: line {} rejected ({}); last good position kept", id_,
                   port_, line_number_, log_text(reason));
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
      if (own_net_port) open_port(net_[i], net_port(config_, ids[i]), "net", i);
      open_port(loc_[i], loc_port(config_, ids[i]), "location", i);
    }
    thread_ = std::thread([this] { io_.run(); });
  }

  void stop() override {
    if (!thread_.joinable()) return;
    asio::post(io_, [this] {
      for (auto* ports : {&net_, &loc_}) {
        for (auto& p : *ports) {
          if (p.slot) p.slot->close_all();
          if (p.acceptor) p.acceptor->close();
          if (p.retry) p.retry->cancel();
        }
      }
      io_.stop();
    });
    thread_.join();
  }

  void deliver(std::size_t node, NetFrame&& frame) override {
    asio::post(io_, [this, node, f = std::move(frame)] {
      // Only NetSessions are admitted to a net port's slot.
      auto* agent =
          net_[node].slot ? static_cast<NetSession*>(net_[node].slot->agent().get()) : nullptr;
      if (agent == nullptr || !agent->open() || !agent->send(f)) {
        engine::NodeCounters::bump(engine_->counters(node).to_agent_dropped);
      }
    });
  }

 private:
  struct Port {
    std::unique_ptr<tcp::acceptor> acceptor;
    std::unique_ptr<PortSlot> slot;
    std::unique_ptr<asio::steady_timer> retry;  ///< re-arms accept after a failure
    bool net = false;
    std::uint16_t number = 0;
  };

  void open_port(Port& p, std::uint16_t number, const char* role, std::size_t i) {
    const NodeId id = engine_->node_ids()[i];
    p.acceptor = listen(number, role, id);
    p.slot = std::make_unique<PortSlot>("node " + std::to_string(id) + " " + role + " port " +
                                        std::to_string(number));
    p.retry = std::make_unique<asio::steady_timer>(io_);
    p.net = std::string_view(role) == "net";
    p.number = number;
    accept(p, i);
  }

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

  // A new connection is admitted to the port's slot, which decides when it
  // becomes the agent (port_slot.hpp).
  void accept(Port& p, std::size_t i) {
    p.acceptor->async_accept(
        [this, &p, i](const boost::system::error_code& ec, tcp::socket socket) {
          if (ec) return accept_failed(p, i, ec);
          const NodeId id = engine_->node_ids()[i];
          std::shared_ptr<PortSession> session;
          if (p.net) {
            socket.set_option(tcp::no_delay(true));
            session =
                std::make_shared<NetSession>(std::move(socket), i, id, p.number, *engine_, *p.slot);
          } else {
            session = std::make_shared<LocationSession>(std::move(socket), i, id, p.number,
                                                        *engine_, *p.slot, config_.origin);
          }
          p.slot->admit(session);
          session->start();
          accept(p, i);
        });
  }

  // Out of descriptors (EMFILE, ENFILE) or any other transient failure: the
  // listener must not go deaf for the rest of the run. It retries after a
  // pause, so that a full descriptor table does not turn into a busy loop.
  void accept_failed(Port& p, std::size_t i, const boost::system::error_code& ec) {
    if (ec == asio::error::operation_aborted || !p.acceptor->is_open()) return;  // shutdown
    ++accept_failures_;
    if (should_log(accept_failures_)) {
      spdlog::warn("{}: cannot accept a connection ({}); retrying in {} ms", p.slot->where(),
                   ec.message(), kAcceptRetry.count());
    }
    // The port's own timer: nothing to allocate while descriptors (or memory) are short.
    p.retry->expires_after(kAcceptRetry);
    p.retry->async_wait([this, &p, i](const boost::system::error_code& wait_ec) {
      if (!wait_ec && p.acceptor->is_open()) accept(p, i);
    });
  }

  ServerConfig config_;
  asio::io_context io_;
  engine::Engine* engine_ = nullptr;
  std::vector<Port> net_;
  std::vector<Port> loc_;
  std::uint64_t accept_failures_ = 0;
  std::thread thread_;
};

}  // namespace

std::unique_ptr<NodeServers> make_node_servers(const ServerConfig& config) {
  return std::make_unique<AsioNodeServers>(config);
}

}  // namespace rfsitl::io
