// One I/O thread, one VehicleLink per node: TCP endpoints connect and
// reconnect with backoff, UDP endpoints listen and answer whoever sent last.
#include "rfsitl/position/mavlink_source/mavlink_source.hpp"

#include <utility>  // GCC 12 + C++20: before Boost.Asio

#include <array>
#include <boost/asio.hpp>
#include <chrono>
#include <map>
#include <mutex>
#include <stdexcept>
#include <thread>

#include <spdlog/spdlog.h>

#include "rfsitl/common/retry_backoff.hpp"
#include "rfsitl/position/mavlink_source/vehicle_link.hpp"

namespace rfsitl::position {
namespace {

namespace asio = boost::asio;
using asio::ip::tcp;
using asio::ip::udp;
using Clock = std::chrono::steady_clock;

constexpr auto kPollPeriod = std::chrono::milliseconds(100);
/// Frames waiting to be sent beyond this are dropped (a vehicle that does not
/// read); heartbeats and requests are small and repeat anyway.
constexpr std::size_t kMaxPendingBytes = 64 * 1024;

std::chrono::milliseconds to_ms(double s) {
  return std::chrono::milliseconds(static_cast<std::int64_t>(s * 1e3));
}

/// One node's link and its socket. All members are touched on the I/O thread
/// only, except what `mutex` guards (read by counters()).
class NodeLink {
 public:
  NodeLink(asio::io_context& io, const SourceNode& node, MavlinkEndpoint endpoint,
           const MavlinkSourceSettings& s, Clock::time_point epoch)
      : io_(io),
        index_(node.index),
        id_(node.id),
        endpoint_(std::move(endpoint)),
        epoch_(epoch),
        stale_after_s_(s.stale_after_s),
        link_(
            VehicleLinkSettings{s.rate_hz, static_cast<std::uint8_t>(s.sysid), 191},
            [this](const std::string& line) {
              spdlog::warn("node {} mavlink {}: {}", id_, endpoint_.text(), line);
            },
            [this](const std::string& line) {
              spdlog::info("node {} mavlink {}: {}", id_, endpoint_.text(), line);
            }),
        timer_(io),
        backoff_(to_ms(kMavlinkReconnectFirstS), to_ms(kMavlinkReconnectMaxS)),
        tcp_(io),
        udp_(io) {}

  /// Opens the endpoint (UDP binds now, so that a taken port fails the start).
  void start(PositionSink& sink) {
    sink_ = &sink;
    if (endpoint_.transport == MavlinkTransport::kUdpListen) {
      udp::resolver r(io_);
      boost::system::error_code ec;
      const auto results = r.resolve(endpoint_.host, std::to_string(endpoint_.port), ec);
      if (ec || results.empty()) fail("cannot resolve " + endpoint_.host, ec);
      const udp::endpoint local = *results.begin();
      udp_.open(local.protocol(), ec);
      if (!ec) udp_.bind(local, ec);
      if (ec) fail("cannot listen", ec);
      receive_udp();
    } else {
      connect_tcp();
    }
    tick();
  }

  void close() {
    boost::system::error_code ignored;
    timer_.cancel();
    tcp_.close(ignored);
    udp_.close(ignored);
  }

  SourceCounters counters() const {
    std::lock_guard lock(mutex_);
    SourceCounters c;
    const VehicleLinkCounters& v = counters_;
    c.updates = v.positions;
    c.errors = v.parser.bad_crc + v.parser.bad_length + v.parser.bad_incompat_flags +
               v.parser.truncated + v.bad_coordinates;
    c.ignored = v.no_fix + v.other_system + v.other_component;
    c.reconnects = v.connections > 0 ? v.connections - 1 : 0;
    c.connected = connected_;
    if (last_position_s_) {
      c.last_update_age_s = now_s() - *last_position_s_;
      c.stale = *c.last_update_age_s > stale_after_s_;
    }
    c.detail = {{"positions", v.positions},
                {"attitudes", v.attitudes},
                {"no_fix", v.no_fix},
                {"bad_coordinates", v.bad_coordinates},
                {"other_system", v.other_system},
                {"other_component", v.other_component},
                {"frames", v.parser.frames},
                {"bad_crc", v.parser.bad_crc},
                {"bad_length", v.parser.bad_length},
                {"bad_incompat_flags", v.parser.bad_incompat_flags},
                {"truncated", v.parser.truncated},
                {"garbage_bytes", v.parser.garbage_bytes},
                {"rejected_bytes", v.parser.rejected_bytes},
                {"unknown_id", v.parser.unknown_id},
                {"heartbeats_sent", v.heartbeats_sent},
                {"interval_requests", v.interval_requests},
                {"stream_requests", v.stream_requests},
                {"interval_refused", v.interval_refused},
                {"connections", v.connections}};
    return c;
  }

  std::string where() const {
    std::lock_guard lock(mutex_);
    std::string w = endpoint_.text();
    if (vehicle_) w += ", system " + std::to_string(*vehicle_);
    return w;
  }

 private:
  [[noreturn]] void fail(const std::string& what, const boost::system::error_code& ec) const {
    throw std::runtime_error("node " + std::to_string(id_) + " mavlink " + endpoint_.text() + ": " +
                             what + (ec ? ": " + ec.message() : ""));
  }

  double now_s() const { return std::chrono::duration<double>(Clock::now() - epoch_).count(); }

  void connect_tcp() {
    auto resolver = std::make_shared<tcp::resolver>(io_);
    resolver->async_resolve(
        endpoint_.host, std::to_string(endpoint_.port),
        [this, resolver](const boost::system::error_code& ec, tcp::resolver::results_type r) {
          if (ec) return retry_tcp(ec);
          asio::async_connect(
              tcp_, r, [this](const boost::system::error_code& cec, const tcp::endpoint&) {
                if (cec) return retry_tcp(cec);
                boost::system::error_code ignored;
                tcp_.set_option(tcp::no_delay(true), ignored);
                backoff_.reset();
                spdlog::info("node {} mavlink {}: connected", id_, endpoint_.text());
                up(true);
                link_.connected(now_s());
                read_tcp();
                flush();
              });
        });
  }

  void retry_tcp(const boost::system::error_code& ec) {
    if (ec == asio::error::operation_aborted || closing_) return;
    boost::system::error_code ignored;
    tcp_.close(ignored);
    const bool was_up = connected_;
    up(false);
    if (was_up)
      spdlog::warn("node {} mavlink {}: {}; reconnecting", id_, endpoint_.text(), ec.message());
    auto wait = std::make_shared<asio::steady_timer>(io_, backoff_.next());
    wait->async_wait([this, wait](const boost::system::error_code& wec) {
      if (!wec && !closing_) connect_tcp();
    });
  }

  void read_tcp() {
    tcp_.async_read_some(asio::buffer(buf_),
                         [this](const boost::system::error_code& ec, std::size_t n) {
                           if (ec) return retry_tcp(ec);
                           take(std::span<const std::uint8_t>(buf_.data(), n));
                           read_tcp();
                         });
  }

  void receive_udp() {
    udp_.async_receive_from(asio::buffer(buf_), sender_,
                            [this](const boost::system::error_code& ec, std::size_t n) {
                              if (ec == asio::error::operation_aborted || closing_) return;
                              if (!ec) {
                                if (!peer_ || *peer_ != sender_) {
                                  // A new peer is a new conversation: greet it, ask again.
                                  peer_ = sender_;
                                  up(true);
                                  link_.connected(now_s());
                                }
                                take(std::span<const std::uint8_t>(buf_.data(), n));
                              }
                              receive_udp();
                            });
  }

  void take(std::span<const std::uint8_t> bytes) {
    reports_.clear();
    link_.receive(bytes, now_s(), reports_);
    for (const StateReport& r : reports_) sink_->report(index_, r);
    publish();
    flush();
  }

  void up(bool connected) {
    std::lock_guard lock(mutex_);
    connected_ = connected;
  }

  void publish() {
    std::lock_guard lock(mutex_);
    counters_ = link_.counters();
    vehicle_ = link_.vehicle();
    last_position_s_ = link_.last_position_s();
  }

  // Sends what the link has due (heartbeats, requests).
  void flush() {
    if (closing_) return;
    std::vector<std::uint8_t> due;
    link_.poll(now_s(), due);
    publish();
    if (due.empty()) return;
    if (endpoint_.transport == MavlinkTransport::kUdpListen) {
      if (!peer_) return;
      boost::system::error_code ignored;  // a lost datagram is retried by the link
      udp_.send_to(asio::buffer(due), *peer_, 0, ignored);
      return;
    }
    if (!tcp_.is_open()) return;
    if (pending_.size() + due.size() > kMaxPendingBytes) return;
    pending_.insert(pending_.end(), due.begin(), due.end());
    if (!writing_) write_tcp();
  }

  void write_tcp() {
    writing_ = true;
    auto out = std::make_shared<std::vector<std::uint8_t>>(std::move(pending_));
    pending_.clear();
    asio::async_write(tcp_, asio::buffer(*out),
                      [this, out](const boost::system::error_code& ec, std::size_t) {
                        writing_ = false;
                        if (ec) return;  // the read side sees the failure and reconnects
                        if (!pending_.empty()) write_tcp();
                      });
  }

  void tick() {
    timer_.expires_after(kPollPeriod);
    timer_.async_wait([this](const boost::system::error_code& ec) {
      if (ec || closing_) return;
      flush();
      tick();
    });
  }

 public:
  bool closing_ = false;

 private:
  asio::io_context& io_;
  std::size_t index_;
  NodeId id_;
  MavlinkEndpoint endpoint_;
  Clock::time_point epoch_;
  double stale_after_s_;
  VehicleLink link_;
  asio::steady_timer timer_;
  RetryBackoff backoff_;
  tcp::socket tcp_;
  udp::socket udp_;
  udp::endpoint sender_;
  std::optional<udp::endpoint> peer_;
  std::array<std::uint8_t, 4096> buf_{};
  std::vector<StateReport> reports_;
  std::vector<std::uint8_t> pending_;
  bool writing_ = false;
  PositionSink* sink_ = nullptr;

  mutable std::mutex mutex_;
  VehicleLinkCounters counters_;
  std::optional<std::uint8_t> vehicle_;
  std::optional<double> last_position_s_;
  bool connected_ = false;
};

class MavlinkSource final : public PositionSource {
 public:
  explicit MavlinkSource(const std::vector<SourceNode>& nodes) {
    const auto epoch = Clock::now();
    std::map<std::string, NodeId> taken;
    for (const SourceNode& n : nodes) {
      const MavlinkSourceSettings s = mavlink_source_settings().build(n.settings);
      std::string why;
      const auto parsed = parse_mavlink_endpoint(s.endpoint, why);
      if (!parsed) throw std::invalid_argument("node " + std::to_string(n.id) + ": " + why);
      const auto mine = parsed->for_node(n.id);
      if (!mine) {
        throw std::invalid_argument("node " + std::to_string(n.id) + ": mavlink endpoint " +
                                    parsed->text() + " gives a port above 65535 for this node");
      }
      const auto [it, fresh] = taken.emplace(mine->text(), n.id);
      if (!fresh) {
        throw std::invalid_argument("nodes " + std::to_string(it->second) + " and " +
                                    std::to_string(n.id) + " both follow mavlink " + mine->text() +
                                    " (give each node its own port, or a +STEP)");
      }
      links_.emplace(n.index, std::make_unique<NodeLink>(io_, n, *mine, s, epoch));
    }
  }

  ~MavlinkSource() override { stop(); }

  void start(PositionSink& sink) override {
    try {
      for (auto& [index, link] : links_) link->start(sink);
    } catch (...) {
      for (auto& [index, link] : links_) link->close();
      throw;
    }
    thread_ = std::thread([this] { io_.run(); });
  }

  void stop() override {
    if (stopped_) return;
    stopped_ = true;
    io_.stop();
    if (thread_.joinable()) thread_.join();
    // The I/O thread is gone: closing here races with nothing.
    for (auto& [index, link] : links_) {
      link->closing_ = true;
      link->close();
    }
  }

  std::optional<SourceCounters> counters(std::size_t index) const override {
    const auto it = links_.find(index);
    if (it == links_.end()) return std::nullopt;
    return it->second->counters();
  }

  std::string where(std::size_t index) const override {
    const auto it = links_.find(index);
    return it == links_.end() ? "" : it->second->where();
  }

 private:
  asio::io_context io_;
  std::map<std::size_t, std::unique_ptr<NodeLink>> links_;
  std::thread thread_;
  bool stopped_ = false;
};

}  // namespace

std::unique_ptr<PositionSource> make_mavlink_source(const std::vector<SourceNode>& nodes) {
  return std::make_unique<MavlinkSource>(nodes);
}

}  // namespace rfsitl::position
