#include "rfsitl/external/external_hub.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <map>
#include <optional>
#include <stdexcept>
#include <thread>
#include <vector>

#include <spdlog/spdlog.h>

#include "rfsitl/common/log_text.hpp"
#include "rfsitl/common/unix_socket_path.hpp"
#include "rfsitl/external/client/handshake.hpp"
#include "rfsitl/external/client/tx_report.hpp"
#include "rfsitl/external/repeat_limiter.hpp"

namespace rfsitl::external {

const char* role_name(Role role) {
  return role == Role::kSamples ? "samples" : "transceiver";
}

namespace {

using Clock = std::chrono::steady_clock;

/// How long the listener rests after accept() ran out of descriptors (it stays
/// readable meanwhile, so polling it again at once would only spin).
constexpr auto kAcceptRetry = std::chrono::milliseconds(100);

class Hub final : public ExternalHub {
 public:
  Hub(const HubSettings& settings, const std::vector<ExternalNodeSpec>& nodes)
      : settings_(settings) {
    for (const auto& n : nodes) {
      specs_[n.id] = n;
      links_[n.index] = std::make_shared<NodeLink>(n.id, settings.reply_timeout_ms);
    }
    listen_fd_ = bind_socket(settings.socket_path);
    if (::pipe2(wake_pipe_, O_CLOEXEC) != 0) {
      ::close(listen_fd_);
      throw std::runtime_error(std::string("pipe2(): ") + std::strerror(errno));
    }
    thread_ = std::thread([this] { accept_loop(); });
  }

  ~Hub() override {
    stopping_.store(true);
    const char b = 1;
    [[maybe_unused]] const auto n = ::write(wake_pipe_[1], &b, 1);
    thread_.join();
    // Refusals that only a later summary line would have reported.
    for (const auto& p : refusal_log_.take_pending()) {
      spdlog::warn("external socket {}: refused {} more connection(s) since the last report: {}",
                   settings_.socket_path, p.repeats,
                   p.key.empty() ? std::string("other reasons") : log_text(p.key));
    }
    ::close(listen_fd_);
    ::close(wake_pipe_[0]);
    ::close(wake_pipe_[1]);
    ::unlink(settings_.socket_path.c_str());
  }

  const std::string& socket_path() const override { return settings_.socket_path; }

  std::shared_ptr<NodeLink> link(std::size_t index) const override {
    const auto it = links_.find(index);
    return it == links_.end() ? nullptr : it->second;
  }

  std::vector<NodeId> never_joined() const override {
    std::vector<NodeId> missing;
    for (const auto& [index, l] : links_) {
      if (!l->ever_joined()) missing.push_back(l->id());
    }
    return missing;
  }

  std::uint64_t rejected() const override { return rejected_.load(); }

 private:
  static int bind_socket(const std::string& path) {
    if (const std::string why = unix_socket_path_error(path); !why.empty()) {
      throw std::runtime_error("external socket path '" + path + "' " + why);
    }
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    std::memcpy(addr.sun_path, path.c_str(), path.size() + 1);
    // Non-blocking: a connection that goes away between poll() and accept()
    // must not stall the accept thread.
    const int fd = ::socket(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
    if (fd < 0) throw std::runtime_error(std::string("socket(): ") + std::strerror(errno));
    const auto* sa = reinterpret_cast<const sockaddr*>(&addr);
    int rc = ::bind(fd, sa, sizeof addr);
    if (rc != 0 && errno == EADDRINUSE) {
      // Something is there. Only a socket nobody listens on (left by an
      // emulator that died) is replaced; anything else is not ours to delete.
      struct stat st {};
      const bool is_socket = ::lstat(path.c_str(), &st) == 0 && S_ISSOCK(st.st_mode);
      const int probe = ::socket(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0);
      const bool refused = ::connect(probe, sa, sizeof addr) != 0 && errno == ECONNREFUSED;
      ::close(probe);
      if (!is_socket || !refused) {
        ::close(fd);
        throw std::runtime_error(
            "external socket " + path +
            (is_socket ? " is in use by another running program (another emulator?)"
                       : " exists and is not a socket; remove it or choose another path"));
      }
      ::unlink(path.c_str());
      rc = ::bind(fd, sa, sizeof addr);
    }
    if (rc != 0 || ::chmod(path.c_str(), 0600) != 0 || ::listen(fd, 64) != 0) {
      const int err = errno;
      ::close(fd);
      throw std::runtime_error("cannot listen on external socket " + path + ": " +
                               std::strerror(err));
    }
    return fd;
  }

  // One thread, one poll() over the listener and every connection that has not
  // said hello yet: each connection has its own deadline, so a silent one
  // delays nobody (a rejoining node is admitted as soon as its hello arrives).
  void accept_loop() {
    std::vector<pollfd> fds;
    while (!stopping_.load()) {
      const bool accepting = Clock::now() >= accept_resumes_;
      fds.assign({{wake_pipe_[0], POLLIN, 0}, {accepting ? listen_fd_ : -1, POLLIN, 0}});
      for (const auto& w : waiting_) fds.push_back({w.channel.fd(), POLLIN, 0});
      if (::poll(fds.data(), fds.size(), poll_timeout_ms()) < 0 && errno != EINTR) {
        spdlog::error("external socket {}: poll(): {}", settings_.socket_path,
                      std::strerror(errno));
        return;
      }
      if (fds[0].revents != 0) return;
      // From the back, so that the indexes still to visit stay valid.
      for (std::size_t i = waiting_.size(); i-- > 0;) {
        if (fds[2 + i].revents != 0 && settle(waiting_[i].channel)) {
          waiting_.erase(waiting_.begin() + static_cast<std::ptrdiff_t>(i));
        }
      }
      refuse_silent(Clock::now());
      if (fds[1].revents != 0) accept_one();
    }
  }

  // Until the nearest hello deadline or the end of an accept pause; -1: none.
  int poll_timeout_ms() const {
    std::optional<Clock::time_point> next;
    if (accept_resumes_ > Clock::now()) next = accept_resumes_;
    for (const auto& w : waiting_) {
      if (!next || w.deadline < *next) next = w.deadline;
    }
    if (!next) return -1;
    const auto wait = std::chrono::ceil<std::chrono::milliseconds>(*next - Clock::now());
    return static_cast<int>(std::max<std::chrono::milliseconds::rep>(wait.count(), 0));
  }

  void accept_one() {
    const int fd = ::accept4(listen_fd_, nullptr, nullptr, SOCK_CLOEXEC);
    if (fd < 0) {
      if (errno == EMFILE || errno == ENFILE || errno == ENOBUFS || errno == ENOMEM) {
        accept_resumes_ = Clock::now() + kAcceptRetry;
      }
      return;  // EAGAIN, ECONNABORTED: the connection went away; nothing to do
    }
    if (waiting_.size() >= kMaxWaitingHellos) {
      reject(waiting_.front().channel,
             "more than " + std::to_string(kMaxWaitingHellos) +
                 " connections waiting to say hello; this one waited longest");
      waiting_.erase(waiting_.begin());
    }
    waiting_.push_back(
        {MessageChannel(fd), Clock::now() + std::chrono::milliseconds(settings_.hello_timeout_ms)});
  }

  // Refuses, oldest first, the connections whose hello is overdue.
  void refuse_silent(Clock::time_point now) {
    while (!waiting_.empty() && waiting_.front().deadline <= now) {
      reject(waiting_.front().channel, "expected a hello message within " +
                                           std::to_string(settings_.hello_timeout_ms) + " ms");
      waiting_.erase(waiting_.begin());
    }
  }

  void reject(MessageChannel& ch, const std::string& why) {
    rejected_.fetch_add(1);
    log_refusal(why);
    MsgHeader h;
    h.type = static_cast<std::uint16_t>(MsgType::kReject);
    ch.send(h, {}, {reinterpret_cast<const std::uint8_t*>(why.data()), why.size()});
  }

  // A process in the wrong role (or for an unknown node) reconnects again and
  // again: the first refusals of each reason are logged in full, then one line
  // with a count per period, so the log stays readable; rejected_ counts all.
  void log_refusal(const std::string& why) {
    const auto v = refusal_log_.record(why, RepeatLimiter::Clock::now());
    const std::string& path = settings_.socket_path;
    const double period_s =
        std::chrono::duration<double>(refusal_log_.settings().summary_every).count();
    // `why` quotes the client's own words (its role, a bad value).
    switch (v.action) {
      case RepeatLimiter::Action::kLog:
        spdlog::warn("external socket {}: refused a connection: {}", path, log_text(why));
        break;
      case RepeatLimiter::Action::kLogLast:
        spdlog::warn(
            "external socket {}: refused a connection: {} (further refusals {} are logged "
            "once per {:.0f} s with a count)",
            path, log_text(why), v.other_keys ? "for new reasons" : "for this reason", period_s);
        break;
      case RepeatLimiter::Action::kSummarize:
        spdlog::warn("external socket {}: refused {} more connection(s) in the last {:.1f} s: {}{}",
                     path, v.repeats, v.seconds,
                     v.other_keys ? "various reasons, the latest: " : "", log_text(why));
        break;
      case RepeatLimiter::Action::kQuiet:
        break;
    }
  }

  // A waiting connection became readable: its hello (admitted or refused), a
  // discovery request (answered), a hang-up, or anything else (refused). Returns false when nothing
  // was there after all, so that it keeps waiting.
  bool settle(MessageChannel& ch) {
    Message hello;
    const RecvStatus st = ch.receive(hello, 0);
    if (st == RecvStatus::kTimeout) return false;
    // A hang-up without a word: a probe (e.g. another emulator checking the path).
    if (st == RecvStatus::kClosed) return true;
    if (st == RecvStatus::kMalformed) {
      reject(ch, "expected a hello message, got a malformed message");
    } else if (hello.type() == MsgType::kDiscover) {
      answer_discovery(ch, hello);
    } else if (hello.type() != MsgType::kHello) {
      reject(ch,
             std::string("expected a hello message, got ") + message_type_name(hello.header.type));
    } else {
      admit(std::move(ch), hello);
    }
    return true;
  }

  void admit(MessageChannel ch, const Message& message) {
    Hello hello;
    try {
      hello = read_hello(message.extra_text());
    } catch (const HandshakeError& e) {
      return reject(ch, std::string("bad hello JSON: ") + e.what());
    }
    const auto it = specs_.find(hello.node_id);
    if (it == specs_.end()) {
      std::string ids;
      for (const auto& [nid, spec] : specs_) ids += (ids.empty() ? "" : ", ") + std::to_string(nid);
      return reject(ch, "node " + std::to_string(hello.node_id) +
                            " is not an external node of this scenario (external nodes: " +
                            (ids.empty() ? "none" : ids) + ")");
    }
    const ExternalNodeSpec& spec = it->second;
    if (hello.role != role_name(spec.role)) {
      return reject(ch, "node " + std::to_string(hello.node_id) + " expects role '" +
                            role_name(spec.role) + "', the program connected as '" + hello.role +
                            "'");
    }
    // This thread alone admits, so the check and the offer below are one step
    // for every other hello: of two processes that ask for the node at the
    // same instant, exclusively, the second is refused.
    if (hello.exclusive && links_.at(spec.index)->claimed()) {
      return reject(ch, "node " + std::to_string(hello.node_id) +
                            " is already claimed by another program (this program asked for it "
                            "exclusively; taking it over would drop the other)");
    }
    const bool samples = spec.role == Role::kSamples;
    const std::string text = welcome_json(
        {spec.id, settings_.sample_rate_hz, settings_.tick_samples, settings_.virtual_time,
         samples ? std::string() : spec.phy_json, samples ? kTxReportVersion : 0U});
    MsgHeader h;
    h.type = static_cast<std::uint16_t>(MsgType::kWelcome);
    if (!ch.send(h, {}, {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()})) return;
    links_.at(spec.index)->offer(std::move(ch), std::move(hello.program));
  }

  // Lists the external nodes and closes (the caller drops `ch`): nothing is
  // claimed, so a SoapySDR find or a dashboard can ask as often as it likes.
  void answer_discovery(MessageChannel& ch, const Message& message) {
    try {
      read_discovery_request(message.extra_text());
    } catch (const HandshakeError& e) {
      return reject(ch, std::string("bad discovery request JSON: ") + e.what());
    }
    std::vector<DiscoveredNode> nodes;
    for (const auto& [id, spec] : specs_) {
      nodes.push_back({id, settings_.scenario_name + " node " + std::to_string(id),
                       role_name(spec.role), settings_.sample_rate_hz, settings_.tick_samples,
                       settings_.carrier_hz, settings_.virtual_time,
                       links_.at(spec.index)->claimed()});
    }
    const std::string text = discovery_json(nodes);
    MsgHeader h;
    h.type = static_cast<std::uint16_t>(MsgType::kDiscovery);
    ch.send(h, {}, {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()});
  }

  /// A connection that has not said hello yet, and when it must have.
  struct Waiting {
    MessageChannel channel;
    Clock::time_point deadline;
  };

  HubSettings settings_;
  std::map<NodeId, ExternalNodeSpec> specs_;
  std::map<std::size_t, std::shared_ptr<NodeLink>> links_;
  int listen_fd_ = -1;
  int wake_pipe_[2] = {-1, -1};
  std::atomic<bool> stopping_{false};
  std::atomic<std::uint64_t> rejected_{0};
  RepeatLimiter refusal_log_;           // accept thread only (and the destructor after it)
  std::vector<Waiting> waiting_;        // accept thread only; deadlines in accept order
  Clock::time_point accept_resumes_{};  // accept thread only
  std::thread thread_;
};

}  // namespace

std::unique_ptr<ExternalHub> make_external_hub(const HubSettings& settings,
                                               const std::vector<ExternalNodeSpec>& nodes) {
  return std::make_unique<Hub>(settings, nodes);
}

}  // namespace rfsitl::external
