#include "rfsitl/agent_port/net_ports.hpp"

#include <algorithm>
#include <utility>  // GCC 12 + C++20: before Boost.Asio

#include <boost/asio.hpp>
#include <deque>
#include <span>
#include <thread>
#include <vector>

#include <spdlog/spdlog.h>

#include "rfsitl/io/agent_control.hpp"
#include "rfsitl/io/net_framing.hpp"
#include "rfsitl/io/port_listener.hpp"

namespace rfsitl::agent_port {
namespace {

namespace asio = boost::asio;
using tcp = asio::ip::tcp;

constexpr std::size_t kMaxWriteBacklogBytes = 4 * 1024 * 1024;

/// Logs the first few problems of a kind in full, then one in a thousand, so a
/// misbehaving client cannot flood the log; the counters still see every one.
bool should_log(std::uint64_t count) {
  return count <= 20 || count % 1000 == 0;
}

/// One agent connection on a net port: frames in, decoded frames out.
class NetSession final : public io::PortSession {
 public:
  NetSession(tcp::socket socket, io::PortSlot& slot, std::size_t node, NodeId id,
             std::uint16_t port, engine::Engine& engine)
      : PortSession(std::move(socket), slot),
        node_(node),
        id_(id),
        port_(port),
        engine_(engine),
        parser_(engine.max_payload(node)) {}

  /// Queues a frame for the agent; false when the backlog is full.
  bool send(const NetFrame& frame) {
    if (backlog_bytes_ > kMaxWriteBacklogBytes) return false;
    writes_.push_back(io::encode_net_frame(frame));
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
    for (const io::FramingError& e : errors_) reject(e.message);
    for (NetFrame& f : frames_) {
      if (io::is_control_frame(f)) {
        answer_control(io::control_text(f));
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
    if (request == io::kStatusRequest) {
      // Every id of the run: a tool asking about another node learns whether it exists.
      std::vector<unsigned> ids(engine_.node_ids().begin(), engine_.node_ids().end());
      std::sort(ids.begin(), ids.end());
      reply = io::format_status_reply(
          {id_, slot_.held_by_other(this), engine_.max_payload(node_), std::move(ids)});
    } else if (request == io::kTakeRequest) {
      claim("asked to take over");
      reply = std::string(io::kTakenReply);
    } else {
      reply = "rfsitl error unknown request";
    }
    send(io::make_control_frame(reply));
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

  std::size_t node_;
  NodeId id_;
  std::uint16_t port_;
  engine::Engine& engine_;
  io::NetFrameParser parser_;
  std::vector<NetFrame> frames_;
  std::vector<io::FramingError> errors_;
  std::deque<std::vector<std::uint8_t>> writes_;
  std::size_t backlog_bytes_ = 0;
};

class AsioNetPorts final : public NetPorts {
 public:
  explicit AsioNetPorts(const NetPortsConfig& config) : config_(config) {}
  ~AsioNetPorts() override { stop(); }

  void start(engine::Engine& engine) override {
    engine_ = &engine;
    const auto& ids = engine.node_ids();
    ports_.resize(ids.size());
    for (std::size_t i = 0; i < ids.size(); ++i) {
      const auto& external = config_.external_net_ports;
      if (std::find(external.begin(), external.end(), ids[i]) != external.end()) continue;
      const auto& elsewhere = config_.elsewhere;
      if (std::find(elsewhere.begin(), elsewhere.end(), ids[i]) != elsewhere.end()) continue;
      const std::uint16_t number = net_port(config_, ids[i]);
      ports_[i] = std::make_unique<io::PortListener>(
          io_, config_.bind_address, io::PortName{"net", ids[i], number},
          [this, i, id = ids[i], number](tcp::socket socket, io::PortSlot& slot) {
            socket.set_option(tcp::no_delay(true));
            return std::make_shared<NetSession>(std::move(socket), slot, i, id, number, *engine_);
          });
      ports_[i]->start();
    }
    thread_ = std::thread([this] { io_.run(); });
  }

  void stop() override {
    if (!thread_.joinable()) return;
    asio::post(io_, [this] {
      for (auto& p : ports_) {
        if (p) p->close();
      }
      io_.stop();
    });
    thread_.join();
  }

  void deliver(std::size_t node, NetFrame&& frame) override {
    asio::post(io_, [this, node, f = std::move(frame)] {
      // Only NetSessions are admitted to a net port's slot.
      auto* agent =
          ports_[node] ? static_cast<NetSession*>(ports_[node]->slot().agent().get()) : nullptr;
      if (agent == nullptr || !agent->open() || !agent->send(f)) {
        engine::NodeCounters::bump(engine_->counters(node).to_agent_dropped);
      }
    });
  }

 private:
  NetPortsConfig config_;
  asio::io_context io_;
  engine::Engine* engine_ = nullptr;
  std::vector<std::unique_ptr<io::PortListener>> ports_;  // null: no net port of ours
  std::thread thread_;
};

}  // namespace

std::unique_ptr<NetPorts> make_net_ports(const NetPortsConfig& config) {
  return std::make_unique<AsioNetPorts>(config);
}

}  // namespace rfsitl::agent_port
