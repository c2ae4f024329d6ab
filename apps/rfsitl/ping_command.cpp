/// `rfsitl ping`: the paper's COM manager. It plays the agents of nodes A and B
/// on their net ports: A sends S-byte packets to B one at a time, B answers each
/// with a short acknowledgement carrying the sequence number, and A records the
/// round-trip time. Exit status: 0 when at least one acknowledgement came back,
/// 1 when none did (or the connection failed), 2 when it refused to start.
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "commands.hpp"
#include "rfsitl/common/percentile.hpp"
#include "rfsitl/common/probe_payload.hpp"
#include "rfsitl/io/agent_control.hpp"
#include "rfsitl/io/net_framing.hpp"

namespace rfsitl::app {
namespace {

using Clock = std::chrono::steady_clock;

constexpr ProbeMagic kPingMagic{'R', 'F', 'P', '1'};
constexpr ProbeMagic kAckMagic{'R', 'F', 'A', '1'};
constexpr std::size_t kMaxPayload = 65535;
// rfsitl's own net ports answer at once; a program that owns its port (a GNU
// Radio node) never does, and ping then goes on without the checks.
constexpr double kStatusTimeoutS = 2.0;

struct PingOptions {
  unsigned src = 1;
  unsigned dst = 2;
  unsigned count = 10;
  std::size_t size = 80;
  double timeout_s = 1.0;
  double interval_s = 0.0;
  double connect_timeout_s = 10.0;
  std::string host = "127.0.0.1";
  std::uint16_t net_base = 15763;
  std::string csv;
  bool quiet = false;
  bool take_over = false;
};

/// A TCP connection to one net port, with the framing parser for its stream.
class AgentLink {
 public:
  /// Connects to the first of `ports` that accepts, retrying all of them for
  /// `timeout_s` (the emulator may still be starting); returns it and its
  /// index in `ports`. Throws naming the last port's error when none did.
  static std::pair<std::unique_ptr<AgentLink>, std::size_t> connect_first(
      const std::string& host, std::span<const std::uint16_t> ports, double timeout_s) {
    const auto deadline = Clock::now() + std::chrono::duration<double>(timeout_s);
    std::string last_error;
    for (;;) {
      for (std::size_t k = 0; k < ports.size(); ++k) {
        if (const int fd = try_connect(host, ports[k], last_error); fd >= 0) {
          return {std::unique_ptr<AgentLink>(new AgentLink(fd)), k};
        }
      }
      if (Clock::now() > deadline) {
        throw std::runtime_error("cannot connect to net port " + host + ":" +
                                 std::to_string(ports.back()) + ": " + last_error);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  }
  ~AgentLink() {
    if (fd_ >= 0) ::close(fd_);
  }
  AgentLink(const AgentLink&) = delete;
  AgentLink& operator=(const AgentLink&) = delete;

  int fd() const { return fd_; }

  void send(const NetFrame& f) {
    const auto bytes = io::encode_net_frame(f);
    std::size_t off = 0;
    while (off < bytes.size()) {
      const ssize_t n = ::send(fd_, bytes.data() + off, bytes.size() - off, MSG_NOSIGNAL);
      if (n <= 0) throw std::runtime_error(std::string("send failed: ") + std::strerror(errno));
      off += static_cast<std::size_t>(n);
    }
  }

  /// Asks the emulator about this port (agent_control.hpp), once per
  /// connection (later calls return the first answer); nullopt when nothing
  /// answers within `timeout_s` (a port an external program serves).
  const std::optional<io::PortStatus>& status(double timeout_s) {
    if (status_asked_) return status_;
    status_asked_ = true;
    send(io::make_control_frame(io::kStatusRequest));
    const std::optional<NetFrame> reply = await_control(timeout_s);
    if (!reply) return status_;
    status_ = io::parse_status_reply(io::control_text(*reply));
    if (!status_) {
      throw std::runtime_error("the emulator's net port answered the status request with '" +
                               std::string(io::control_text(*reply)) + "'");
    }
    return status_;
  }

  /// Makes this connection the port's agent, replacing any other.
  void take(double timeout_s) {
    send(io::make_control_frame(io::kTakeRequest));
    if (!await_control(timeout_s)) {
      throw std::runtime_error("no answer to the take-over request within " +
                               std::to_string(timeout_s) + " s");
    }
  }

  /// Reads what is available and returns the frames completed by it.
  std::vector<NetFrame> receive() {
    std::uint8_t buf[8192];
    const ssize_t n = ::recv(fd_, buf, sizeof buf, 0);
    if (n == 0) throw std::runtime_error("the emulator closed the connection");
    if (n < 0) throw std::runtime_error(std::string("recv failed: ") + std::strerror(errno));
    std::vector<NetFrame> frames;
    std::vector<io::FramingError> errors;
    parser_.feed({buf, static_cast<std::size_t>(n)}, frames, errors);
    return frames;
  }

 private:
  explicit AgentLink(int fd) : fd_(fd), parser_(kMaxPayload) {
    const int one = 1;
    setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  }

  std::optional<NetFrame> await_control(double timeout_s) {
    const auto deadline = Clock::now() + std::chrono::duration<double>(timeout_s);
    while (Clock::now() < deadline) {
      pollfd fds{fd_, POLLIN, 0};
      const auto left =
          std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
      if (::poll(&fds, 1, static_cast<int>(std::max<long>(1, left.count()))) <= 0) continue;
      for (NetFrame& f : receive()) {
        if (io::is_control_frame(f)) return std::move(f);
      }
    }
    return std::nullopt;
  }

  static int try_connect(const std::string& host, std::uint16_t port, std::string& error) {
    addrinfo hints{};
    hints.ai_socktype = SOCK_STREAM;
    addrinfo* res = nullptr;
    const int rc = getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &res);
    if (rc != 0) {
      error = gai_strerror(rc);
      return -1;
    }
    int fd = -1;
    for (addrinfo* a = res; a != nullptr && fd < 0; a = a->ai_next) {
      fd = ::socket(a->ai_family, a->ai_socktype, a->ai_protocol);
      if (fd >= 0 && ::connect(fd, a->ai_addr, a->ai_addrlen) != 0) {
        error = std::strerror(errno);
        ::close(fd);
        fd = -1;
      }
    }
    freeaddrinfo(res);
    return fd;
  }

  int fd_ = -1;
  io::NetFrameParser parser_;
  bool status_asked_ = false;
  std::optional<io::PortStatus> status_;
};

/// Sends one ping and serves both agents until its ack returns or time runs out.
std::optional<double> ping_once(AgentLink& a, AgentLink& b, const PingOptions& o,
                                std::uint32_t seq) {
  const auto src = static_cast<NodeId>(o.src);
  const auto dst = static_cast<NodeId>(o.dst);
  const auto sent = Clock::now();
  a.send(NetFrame{src, dst, make_probe(kPingMagic, seq, o.size)});
  const auto deadline = sent + std::chrono::duration<double>(o.timeout_s);
  while (Clock::now() < deadline) {
    pollfd fds[2] = {{a.fd(), POLLIN, 0}, {b.fd(), POLLIN, 0}};
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
    if (::poll(fds, 2, static_cast<int>(std::max<long>(1, left.count()))) <= 0) continue;
    if (fds[1].revents != 0) {
      for (const NetFrame& f : b.receive()) {
        // B's agent answers every ping it hears, late ones included.
        if (const auto s = read_probe(f.payload, kPingMagic); s && f.src == src) {
          b.send(NetFrame{dst, src, make_probe(kAckMagic, *s, 8)});
        }
      }
    }
    if (fds[0].revents != 0) {
      for (const NetFrame& f : a.receive()) {
        if (const auto s = read_probe(f.payload, kAckMagic); s && *s == seq && f.src == dst) {
          return std::chrono::duration<double, std::milli>(Clock::now() - sent).count();
        }
      }
    }
  }
  return std::nullopt;
}

/// Checks both ports before using them: refuses when an agent is connected
/// (unless --take-over) or when --size is beyond what a port accepts, then
/// takes both. Returns 0 or the exit code.
int claim_ports(AgentLink& a, AgentLink& b, const PingOptions& o) {
  const std::pair<AgentLink*, unsigned> ports[] = {{&a, o.src}, {&b, o.dst}};
  bool checked[2] = {false, false};
  for (std::size_t k = 0; k < 2; ++k) {
    const auto& [link, id] = ports[k];
    const std::optional<io::PortStatus>& answer = link->status(kStatusTimeoutS);
    if (!answer) {
      std::fprintf(stderr,
                   "rfsitl ping: node %u's net port does not answer control frames (a port "
                   "an external program serves?): not checked\n",
                   id);
      continue;
    }
    checked[k] = true;
    const io::PortStatus& st = *answer;
    if (st.agent_connected && !o.take_over) {
      std::fprintf(stderr,
                   "rfsitl ping: node %u's net port has an agent connected; ping would replace "
                   "it (the agent's connection is closed). Stop the agent, or pass --take-over\n",
                   id);
      return 2;
    }
    const std::size_t need = id == o.src ? o.size : 8;
    if (need > st.max_payload) {
      std::fprintf(stderr,
                   "rfsitl ping: --size %zu is more than node %u accepts (phy.max_payload_bytes "
                   "= %zu)\n",
                   need, id, st.max_payload);
      return 2;
    }
  }
  if (checked[0]) a.take(o.connect_timeout_s);
  if (checked[1]) b.take(o.connect_timeout_s);
  return 0;
}

/// 2 (after saying so) when the run `link`'s port belongs to has no node
/// --src or --dst; 0 otherwise, or when the port does not say which nodes
/// there are (an older emulator, a port another program serves).
int check_nodes_exist(AgentLink& link, const PingOptions& o) {
  const std::optional<io::PortStatus>& st = link.status(kStatusTimeoutS);
  if (!st || st->nodes.empty()) return 0;
  for (const unsigned id : {o.src, o.dst}) {
    if (!std::binary_search(st->nodes.begin(), st->nodes.end(), id)) {
      std::fprintf(stderr, "rfsitl ping: node %u is not in this run (nodes: %s)\n", id,
                   io::id_list_text(st->nodes).c_str());
      return 2;
    }
  }
  return 0;
}

int run_ping(const PingOptions& o) {
  if (o.src == o.dst) {
    std::fprintf(stderr, "rfsitl ping: --src and --dst must differ\n");
    return 2;
  }
  std::vector<std::optional<double>> rtts;
  try {
    // Whichever port answers first says which nodes the run has: a node that
    // does not exist is named at once, not after the connect timeout.
    const std::uint16_t ports[2] = {static_cast<std::uint16_t>(o.net_base + 10 * o.src),
                                    static_cast<std::uint16_t>(o.net_base + 10 * o.dst)};
    auto [first, k] = AgentLink::connect_first(o.host, ports, o.connect_timeout_s);
    if (const int rc = check_nodes_exist(*first, o); rc != 0) return rc;
    auto second =
        AgentLink::connect_first(o.host, std::span(ports).subspan(1 - k, 1), o.connect_timeout_s)
            .first;
    AgentLink& a = k == 0 ? *first : *second;
    AgentLink& b = k == 0 ? *second : *first;
    if (const int rc = claim_ports(a, b, o); rc != 0) return rc;
    for (std::uint32_t seq = 0; seq < o.count; ++seq) {
      const auto rtt = ping_once(a, b, o, seq);
      rtts.push_back(rtt);
      if (!o.quiet) {
        if (rtt) {
          std::printf("%zu bytes %u -> %u seq=%u rtt=%.3f ms\n", o.size, o.src, o.dst, seq, *rtt);
        } else {
          std::printf("%zu bytes %u -> %u seq=%u lost (no ack within %.3f s)\n", o.size, o.src,
                      o.dst, seq, o.timeout_s);
        }
        std::fflush(stdout);
      }
      if (o.interval_s > 0) {
        std::this_thread::sleep_for(std::chrono::duration<double>(o.interval_s));
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rfsitl ping: %s\n", e.what());
    return 1;
  }
  if (!o.csv.empty()) {
    std::ofstream csv(o.csv);
    csv << "seq,rtt_ms,status\n";
    for (std::size_t i = 0; i < rtts.size(); ++i) {
      csv << i << "," << (rtts[i] ? std::to_string(*rtts[i]) : "") << ","
          << (rtts[i] ? "ok" : "lost") << "\n";
    }
    if (!csv) std::fprintf(stderr, "rfsitl ping: cannot write %s\n", o.csv.c_str());
  }
  std::vector<double> ok;
  for (const auto& r : rtts) {
    if (r) ok.push_back(*r);
  }
  std::sort(ok.begin(), ok.end());
  double mean = NAN;
  if (!ok.empty()) {
    mean = 0;
    for (double v : ok) mean += v;
    mean /= static_cast<double>(ok.size());
  }
  std::printf("rtt_ms mean=%.3f p10=%.3f p50=%.3f p90=%.3f lost=%zu/%u\n", mean,
              percentile(ok, 0.1), percentile(ok, 0.5), percentile(ok, 0.9),
              rtts.size() - ok.size(), o.count);
  if (ok.empty()) {
    std::fprintf(stderr, "rfsitl ping: no acknowledgement came back (%u sent)\n", o.count);
    return 1;
  }
  return 0;
}

}  // namespace

std::function<int()> add_ping_command(CLI::App& parent) {
  auto opts = std::make_shared<PingOptions>();
  CLI::App* cmd = parent.add_subcommand(
      "ping", "Measure round-trip times between two nodes, acting as both of their agents");
  cmd->add_option("--src", opts->src, "Node A (sends the packets)")
      ->required()
      ->check(CLI::Range(1, int{kMaxNodeId}));
  cmd->add_option("--dst", opts->dst, "Node B (answers with acknowledgements)")
      ->required()
      ->check(CLI::Range(1, int{kMaxNodeId}));
  cmd->add_option("--count", opts->count, "Packets to send")
      ->check(CLI::Range(1U, 1000000U))
      ->capture_default_str();
  cmd->add_option("--size", opts->size, "Payload bytes per packet (>= 8)")
      ->check(CLI::Range(std::size_t{8}, kMaxPayload))
      ->capture_default_str();
  cmd->add_option("--timeout", opts->timeout_s, "Seconds to wait for each acknowledgement")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--interval", opts->interval_s, "Pause between packets in seconds")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--connect-timeout", opts->connect_timeout_s,
                  "Seconds to keep retrying the connection to the emulator")
      ->capture_default_str();
  cmd->add_option("--host", opts->host, "Emulator address")
      ->type_name("HOST")
      ->capture_default_str();
  cmd->add_option("--net-base", opts->net_base, "Net port base of the emulator")
      ->capture_default_str();
  cmd->add_option("--csv", opts->csv, "Write every packet's RTT to this CSV file")
      ->type_name("PATH");
  cmd->add_flag("--quiet,-q", opts->quiet, "Print only the summary line");
  cmd->add_flag("--take-over", opts->take_over,
                "Replace agents connected to the two net ports (default: refuse)");
  return [opts] { return run_ping(*opts); };
}

}  // namespace rfsitl::app
