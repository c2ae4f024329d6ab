// One I/O thread; per node a listening port whose connections send lines. The
// port's slot (io/port_slot.hpp) decides which connection is the node's feed:
// a newcomer takes over with its first complete line.
#include "rfsitl/position/location_port/location_port_source.hpp"

#include <utility>  // GCC 12 + C++20: before Boost.Asio

#include <atomic>
#include <boost/asio.hpp>
#include <chrono>
#include <map>
#include <mutex>
#include <stdexcept>
#include <thread>

#include <spdlog/spdlog.h>

#include "rfsitl/common/log_text.hpp"
#include "rfsitl/io/port_listener.hpp"
#include "rfsitl/position/location_port/location_line.hpp"

namespace rfsitl::position {
namespace {

namespace asio = boost::asio;
using tcp = asio::ip::tcp;
using Clock = std::chrono::steady_clock;

constexpr std::uint8_t kNewline[] = {'\n'};

/// Logs the first few problems in full, then one in a thousand, so a
/// misbehaving feed cannot flood the log; the counters still see every one.
bool should_log(std::uint64_t count) {
  return count <= 20 || count % 1000 == 0;
}

/// One node's port and counters. Counters are atomics: the I/O thread writes
/// them, counters() reads them from any thread.
struct NodeFeed {
  std::size_t index = 0;
  NodeId id = 1;
  std::uint16_t port = 0;
  double stale_after_s = 0.0;
  std::unique_ptr<io::PortListener> listener;
  std::atomic<std::uint64_t> updates{0};
  std::atomic<std::uint64_t> errors{0};
  std::atomic<std::uint64_t> connections{0};
  std::atomic<std::uint64_t> open_connections{0};
  std::atomic<std::uint64_t> overlong{0};
  std::atomic<std::int64_t> last_update_ns{-1};  // since the source's epoch; -1: none yet
};

/// One connection on a node's location port: lines in, reports to the sink.
class LocationSession final : public io::PortSession {
 public:
  LocationSession(tcp::socket socket, io::PortSlot& slot, NodeFeed& feed, PositionSink& sink,
                  Clock::time_point epoch)
      : PortSession(std::move(socket), slot), feed_(feed), sink_(sink), epoch_(epoch) {
    ++feed_.connections;
    ++feed_.open_connections;
  }

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
        ++feed_.overlong;
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
    --feed_.open_connections;
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
    sink_.report(feed_.index, StateReport{r.position, std::nullopt, std::nullopt});
    ++feed_.updates;
    feed_.last_update_ns.store(
        std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - epoch_).count());
  }

  void reject(const std::string& reason) {
    const std::uint64_t n = ++feed_.errors;
    if (should_log(n)) {
      // The reason quotes the line's own text.
      spdlog::warn("node {} location port {}: line {} rejected ({}); last good position kept",
                   feed_.id, feed_.port, line_number_, log_text(reason));
    }
  }

  NodeFeed& feed_;
  PositionSink& sink_;
  Clock::time_point epoch_;
  std::string line_;
  bool overlong_ = false;
  std::uint64_t line_number_ = 0;
};

class LocationPortSource final : public PositionSource {
 public:
  LocationPortSource(const SourceContext& context, const std::vector<SourceNode>& nodes)
      : bind_address_(context.bind_address) {
    std::map<std::uint16_t, NodeId> taken;
    for (const SourceNode& n : nodes) {
      const LocationPortSettings s = location_port_settings().build(n.settings);
      const std::uint16_t port = location_port_number(s, context.location_base, n.id);
      const auto [it, fresh] = taken.emplace(port, n.id);
      if (!fresh) {
        throw std::invalid_argument("nodes " + std::to_string(it->second) + " and " +
                                    std::to_string(n.id) + " both listen on location port " +
                                    std::to_string(port) + " (give each node its own port)");
      }
      auto feed = std::make_unique<NodeFeed>();
      feed->index = n.index;
      feed->id = n.id;
      feed->port = port;
      feed->stale_after_s = s.stale_after_s;
      feeds_.emplace(n.index, std::move(feed));
    }
  }

  ~LocationPortSource() override { stop(); }

  void start(PositionSink& sink) override {
    // Binding happens here, all ports before the thread starts: a port in use
    // fails the start with nothing left listening (destructors close the rest).
    for (auto& [index, feed] : feeds_) {
      NodeFeed& f = *feed;
      f.listener = std::make_unique<io::PortListener>(
          io_, bind_address_, io::PortName{"location", f.id, f.port},
          [this, &f, &sink](tcp::socket socket, io::PortSlot& slot) {
            return std::make_shared<LocationSession>(std::move(socket), slot, f, sink, epoch_);
          });
    }
    for (auto& [index, feed] : feeds_) feed->listener->start();
    thread_ = std::thread([this] { io_.run(); });
  }

  void stop() override {
    if (!thread_.joinable()) return;
    asio::post(io_, [this] {
      for (auto& [index, feed] : feeds_) feed->listener->close();
      io_.stop();
    });
    thread_.join();
  }

  std::optional<SourceCounters> counters(std::size_t index) const override {
    const auto it = feeds_.find(index);
    if (it == feeds_.end()) return std::nullopt;
    const NodeFeed& f = *it->second;
    SourceCounters c;
    c.updates = f.updates.load();
    c.errors = f.errors.load();
    const std::uint64_t connections = f.connections.load();
    c.reconnects = connections > 0 ? connections - 1 : 0;
    c.connected = f.open_connections.load() > 0;
    const std::int64_t last = f.last_update_ns.load();
    if (last >= 0) {
      const auto now = std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - epoch_);
      c.last_update_age_s = 1e-9 * static_cast<double>(now.count() - last);
      c.stale = f.stale_after_s > 0 && *c.last_update_age_s > f.stale_after_s;
    }
    c.detail = {{"connections", connections}, {"overlong_lines", f.overlong.load()}};
    return c;
  }

  std::string where(std::size_t index) const override {
    const auto it = feeds_.find(index);
    if (it == feeds_.end()) return "";
    return bind_address_ + ":" + std::to_string(it->second->port);
  }

 private:
  std::string bind_address_;
  Clock::time_point epoch_ = Clock::now();
  asio::io_context io_;
  std::map<std::size_t, std::unique_ptr<NodeFeed>> feeds_;
  std::thread thread_;
};

}  // namespace

std::unique_ptr<PositionSource> make_location_port_source(const SourceContext& context,
                                                          const std::vector<SourceNode>& nodes) {
  return std::make_unique<LocationPortSource>(context, nodes);
}

}  // namespace rfsitl::position
