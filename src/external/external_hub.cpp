#include "rfsitl/external/external_hub.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <map>
#include <stdexcept>
#include <thread>

#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include "rfsitl/external/repeat_limiter.hpp"

namespace rfsitl::external {

const char* role_name(Role role) {
  return role == Role::kSamples ? "samples" : "transceiver";
}

namespace {

constexpr int kHelloTimeoutMs = 2000;

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
                   p.key.empty() ? std::string("other reasons") : p.key);
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
    sockaddr_un addr{};
    if (path.empty() || path.size() >= sizeof addr.sun_path) {
      throw std::runtime_error("external socket path must be 1.." +
                               std::to_string(sizeof addr.sun_path - 1) + " bytes: '" + path + "'");
    }
    addr.sun_family = AF_UNIX;
    std::memcpy(addr.sun_path, path.c_str(), path.size() + 1);
    const int fd = ::socket(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0);
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

  void accept_loop() {
    while (!stopping_.load()) {
      pollfd p[2] = {{listen_fd_, POLLIN, 0}, {wake_pipe_[0], POLLIN, 0}};
      if (::poll(p, 2, -1) < 0) continue;
      if (p[1].revents != 0) return;
      const int fd = ::accept4(listen_fd_, nullptr, nullptr, SOCK_CLOEXEC);
      if (fd >= 0) admit(MessageChannel(fd));
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
    switch (v.action) {
      case RepeatLimiter::Action::kLog:
        spdlog::warn("external socket {}: refused a connection: {}", path, why);
        break;
      case RepeatLimiter::Action::kLogLast:
        spdlog::warn(
            "external socket {}: refused a connection: {} (further refusals {} are logged "
            "once per {:.0f} s with a count)",
            path, why, v.other_keys ? "for new reasons" : "for this reason", period_s);
        break;
      case RepeatLimiter::Action::kSummarize:
        spdlog::warn("external socket {}: refused {} more connection(s) in the last {:.1f} s: {}{}",
                     path, v.repeats, v.seconds,
                     v.other_keys ? "various reasons, the latest: " : "", why);
        break;
      case RepeatLimiter::Action::kQuiet:
        break;
    }
  }

  // Handshakes one connection on the accept thread; a slow peer delays the next
  // admission by at most kHelloTimeoutMs.
  void admit(MessageChannel ch) {
    Message hello;
    const RecvStatus st = ch.receive(hello, kHelloTimeoutMs);
    if (st == RecvStatus::kClosed) return;  // a probe (e.g. another emulator checking the path)
    if (st != RecvStatus::kOk || hello.type() != MsgType::kHello) {
      return reject(ch,
                    "expected a hello message within " + std::to_string(kHelloTimeoutMs) + " ms");
    }
    nlohmann::json j;
    unsigned id = 0;
    std::string role;
    std::string program;
    try {
      j = nlohmann::json::parse(hello.extra_text());
      id = j.at("node_id").get<unsigned>();
      role = j.at("role").get<std::string>();
      program = j.value("program", std::string("external"));
    } catch (const nlohmann::json::exception& e) {
      return reject(ch, std::string("bad hello JSON: ") + e.what());
    }
    const auto it = id <= kMaxNodeId ? specs_.find(static_cast<NodeId>(id)) : specs_.end();
    if (it == specs_.end()) {
      std::string ids;
      for (const auto& [nid, spec] : specs_) ids += (ids.empty() ? "" : ", ") + std::to_string(nid);
      return reject(ch, "node " + std::to_string(id) +
                            " is not an external node of this scenario (external nodes: " +
                            (ids.empty() ? "none" : ids) + ")");
    }
    const ExternalNodeSpec& spec = it->second;
    if (role != role_name(spec.role)) {
      return reject(ch, "node " + std::to_string(id) + " expects role '" + role_name(spec.role) +
                            "', the program connected as '" + role + "'");
    }
    nlohmann::json welcome = {{"protocol", kProtocolVersion},
                              {"node_id", id},
                              {"sample_rate_hz", settings_.sample_rate_hz},
                              {"tick_samples", settings_.tick_samples},
                              {"time_mode", settings_.virtual_time ? "virtual" : "realtime"}};
    if (spec.role == Role::kTransceiver) welcome["phy"] = nlohmann::json::parse(spec.phy_json);
    const std::string text = welcome.dump();
    MsgHeader h;
    h.type = static_cast<std::uint16_t>(MsgType::kWelcome);
    if (!ch.send(h, {}, {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()})) return;
    links_.at(spec.index)->offer(std::move(ch), program);
  }

  HubSettings settings_;
  std::map<NodeId, ExternalNodeSpec> specs_;
  std::map<std::size_t, std::shared_ptr<NodeLink>> links_;
  int listen_fd_ = -1;
  int wake_pipe_[2] = {-1, -1};
  std::atomic<bool> stopping_{false};
  std::atomic<std::uint64_t> rejected_{0};
  RepeatLimiter refusal_log_;  // accept thread only (and the destructor after it)
  std::thread thread_;
};

}  // namespace

std::unique_ptr<ExternalHub> make_external_hub(const HubSettings& settings,
                                               const std::vector<ExternalNodeSpec>& nodes) {
  return std::make_unique<Hub>(settings, nodes);
}

}  // namespace rfsitl::external
