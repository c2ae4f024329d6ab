/// Real-time capacity load: plays the agents of nodes 1..N on their net ports.
/// Every node pings a random other node `--rate` times per second: once in each
/// slot of 1/rate seconds, at a uniformly random time within the slot (drawn anew
/// for every slot, so that no two nodes stay in step and collide every time).
/// The destination's agent answers each ping it receives with a short
/// acknowledgement, and the source records the round-trip time.
///
///   rfsitl_swarm_load --nodes N --net-base P [--duration 60] [--json F] [--csv F]
///
/// Framing is UB-ANC's ([src][dst][payload]\r\r\n\n). Sending stops after
/// --duration wall seconds; acknowledgements are then awaited for --timeout s.
/// A ping whose acknowledgement arrives after --timeout counts as lost.
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <arpa/inet.h>
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "rfsitl/common/percentile.hpp"
#include "rfsitl/common/probe_payload.hpp"
#include "rfsitl/io/net_framing.hpp"

namespace {

using namespace rfsitl;
using Clock = std::chrono::steady_clock;

constexpr ProbeMagic kPingMagic{'R', 'F', 'S', 'P'};
constexpr ProbeMagic kAckMagic{'R', 'F', 'S', 'A'};

struct Options {
  unsigned nodes = 8;
  std::uint16_t net_base = 15763;
  std::string host = "127.0.0.1";
  double duration_s = 60.0;
  double rate_hz = 1.0;
  std::size_t size = 80;
  std::size_t ack_size = 8;
  double timeout_s = 1.0;
  double connect_timeout_s = 20.0;
  std::uint64_t seed = 1;
  std::string json;
  std::string csv;
};

int connect_to(const std::string& host, std::uint16_t port, double timeout_s) {
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(port);
  if (inet_pton(AF_INET, host.c_str(), &addr.sin_addr) != 1) {
    throw std::runtime_error("not an IPv4 address: " + host);
  }
  const auto deadline = Clock::now() + std::chrono::duration<double>(timeout_s);
  for (;;) {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    if (fd < 0) throw std::runtime_error(std::string("socket: ") + std::strerror(errno));
    if (::connect(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) == 0) {
      const int one = 1;
      setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
      return fd;
    }
    const std::string err = std::strerror(errno);
    ::close(fd);
    if (Clock::now() > deadline) {
      throw std::runtime_error("cannot connect to " + host + ":" + std::to_string(port) + ": " +
                               err);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

/// One ping: who sent it to whom, when, and its fate.
struct PingRecord {
  unsigned src = 0;
  unsigned dst = 0;
  double sent_s = 0.0;  ///< since the load started
  std::optional<double> rtt_ms;
  bool delivered = false;  ///< the destination's agent received it
};

/// The agent of one node: its connection and stream parser.
struct Agent {
  NodeId id = 0;
  int fd = -1;
  io::NetFrameParser parser{65535};
  Clock::time_point next_ping;
  std::uint64_t slot = 0;                            ///< the slot next_ping lies in
  std::map<std::uint32_t, std::size_t> outstanding;  ///< seq -> index in records
};

class SwarmLoad {
 public:
  explicit SwarmLoad(const Options& o) : o_(o), rng_(o.seed) {
    agents_.resize(o.nodes);
    for (unsigned i = 0; i < o.nodes; ++i) {
      agents_[i].id = static_cast<NodeId>(i + 1);
      agents_[i].fd = connect_to(o.host, static_cast<std::uint16_t>(o.net_base + 10 * (i + 1)),
                                 o.connect_timeout_s);
    }
  }
  ~SwarmLoad() {
    for (auto& a : agents_) {
      if (a.fd >= 0) ::close(a.fd);
    }
  }
  SwarmLoad(const SwarmLoad&) = delete;
  SwarmLoad& operator=(const SwarmLoad&) = delete;

  void run() {
    start_ = Clock::now();
    for (auto& a : agents_) a.next_ping = slot_time(0);
    const auto stop_sending = start_ + seconds(o_.duration_s);
    const auto stop_all = stop_sending + seconds(o_.timeout_s);
    std::vector<pollfd> fds(agents_.size());
    for (;;) {
      const auto now = Clock::now();
      if (now >= stop_all) break;
      auto wake = stop_all;
      for (std::size_t i = 0; i < agents_.size(); ++i) {
        Agent& a = agents_[i];
        if (a.next_ping < stop_sending) {
          if (a.next_ping <= now) {
            send_ping(i);
            a.next_ping = slot_time(++a.slot);
          }
          if (a.next_ping < stop_sending) wake = std::min(wake, a.next_ping);
        }
        fds[i] = {a.fd, POLLIN, 0};
      }
      const auto wait = std::chrono::duration_cast<std::chrono::nanoseconds>(wake - Clock::now());
      const timespec ts{static_cast<time_t>(std::max<long long>(0, wait.count()) / 1000000000),
                        static_cast<long>(std::max<long long>(0, wait.count()) % 1000000000)};
      if (::ppoll(fds.data(), fds.size(), &ts, nullptr) <= 0) continue;
      for (std::size_t i = 0; i < agents_.size(); ++i) {
        if (fds[i].revents != 0) receive(i);
      }
    }
  }

  const std::vector<PingRecord>& records() const { return records_; }
  std::uint64_t acks_sent() const { return acks_sent_; }
  std::uint64_t late_acks() const { return late_acks_; }
  std::uint64_t stray_frames() const { return stray_; }

 private:
  static Clock::duration seconds(double s) {
    return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
  }

  /// A uniformly random instant in slot k.
  Clock::time_point slot_time(std::uint64_t k) {
    std::uniform_real_distribution<double> within(0.0, 1.0);
    return start_ + seconds((static_cast<double>(k) + within(rng_)) / o_.rate_hz);
  }

  void send_frame(Agent& a, const NetFrame& f) {
    const auto bytes = io::encode_net_frame(f);
    std::size_t off = 0;
    while (off < bytes.size()) {
      const ssize_t n = ::send(a.fd, bytes.data() + off, bytes.size() - off, MSG_NOSIGNAL);
      if (n <= 0) throw std::runtime_error(std::string("send: ") + std::strerror(errno));
      off += static_cast<std::size_t>(n);
    }
  }

  void send_ping(std::size_t i) {
    Agent& a = agents_[i];
    std::uniform_int_distribution<unsigned> pick(0, o_.nodes - 2);
    unsigned j = pick(rng_);
    if (j >= i) ++j;  // any node but the sender
    const auto seq = static_cast<std::uint32_t>(records_.size());
    const auto now = Clock::now();
    records_.push_back({a.id, agents_[j].id, std::chrono::duration<double>(now - start_).count(),
                        std::nullopt, false});
    sent_at_.push_back(now);
    a.outstanding[seq] = records_.size() - 1;
    send_frame(a, NetFrame{a.id, agents_[j].id, make_probe(kPingMagic, seq, o_.size)});
  }

  void receive(std::size_t i) {
    Agent& a = agents_[i];
    std::uint8_t buf[8192];
    const ssize_t n = ::recv(a.fd, buf, sizeof buf, 0);
    if (n == 0) throw std::runtime_error("the emulator closed node " + std::to_string(a.id));
    if (n < 0) throw std::runtime_error(std::string("recv: ") + std::strerror(errno));
    const auto now = Clock::now();
    std::vector<NetFrame> frames;
    std::vector<io::FramingError> errors;
    a.parser.feed({buf, static_cast<std::size_t>(n)}, frames, errors);
    for (const NetFrame& f : frames) {
      if (const auto seq = read_probe(f.payload, kPingMagic); seq && *seq < records_.size()) {
        records_[*seq].delivered = true;  // answer every ping heard, late ones included
        send_frame(a, NetFrame{a.id, f.src, make_probe(kAckMagic, *seq, o_.ack_size)});
        ++acks_sent_;
      } else if (const auto ack = read_probe(f.payload, kAckMagic); ack) {
        const auto it = a.outstanding.find(*ack);
        if (it == a.outstanding.end()) {
          ++stray_;
          continue;
        }
        const double rtt = std::chrono::duration<double, std::milli>(now - sent_at_[*ack]).count();
        if (rtt <= 1e3 * o_.timeout_s) {
          records_[it->second].rtt_ms = rtt;
        } else {
          ++late_acks_;
        }
        a.outstanding.erase(it);
      } else {
        ++stray_;
      }
    }
  }

  Options o_;
  std::mt19937_64 rng_;
  std::vector<Agent> agents_;
  std::vector<PingRecord> records_;
  std::vector<Clock::time_point> sent_at_;
  Clock::time_point start_;
  std::uint64_t acks_sent_ = 0;
  std::uint64_t late_acks_ = 0;
  std::uint64_t stray_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Capacity load: every node pings a random other node once per second"};
  Options o;
  app.add_option("--nodes", o.nodes, "Nodes 1..N to play")->required()->check(CLI::Range(2, 250));
  app.add_option("--net-base", o.net_base, "Net port base of the emulator")->capture_default_str();
  app.add_option("--host", o.host, "Emulator IPv4 address")->capture_default_str();
  app.add_option("--duration", o.duration_s, "Wall seconds of sending")->capture_default_str();
  app.add_option("--rate", o.rate_hz, "Pings per node per second")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--size", o.size, "Ping payload bytes (>= 8)")
      ->check(CLI::Range(8, 2048))
      ->capture_default_str();
  app.add_option("--ack-size", o.ack_size, "Acknowledgement payload bytes (>= 8)")
      ->check(CLI::Range(8, 2048))
      ->capture_default_str();
  app.add_option("--timeout", o.timeout_s, "Seconds an acknowledgement may take")
      ->capture_default_str();
  app.add_option("--connect-timeout", o.connect_timeout_s, "Seconds to retry connecting")
      ->capture_default_str();
  app.add_option("--seed", o.seed, "Seed of send times and destinations")->capture_default_str();
  app.add_option("--json", o.json, "Write the summary as JSON to this file");
  app.add_option("--csv", o.csv, "Write every ping (src, dst, sent_s, rtt_ms, status)");
  CLI11_PARSE(app, argc, argv);

  std::vector<PingRecord> records;
  std::uint64_t acks_sent = 0;
  std::uint64_t late = 0;
  std::uint64_t stray = 0;
  try {
    SwarmLoad load(o);
    load.run();
    records = load.records();
    acks_sent = load.acks_sent();
    late = load.late_acks();
    stray = load.stray_frames();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "swarm_load: %s\n", e.what());
    return 1;
  }
  std::vector<double> rtts;
  std::uint64_t delivered = 0;
  for (const auto& r : records) {
    if (r.rtt_ms) rtts.push_back(*r.rtt_ms);
    delivered += r.delivered ? 1 : 0;
  }
  std::sort(rtts.begin(), rtts.end());
  const auto sent = static_cast<double>(records.size());
  const double frames_sent = sent + static_cast<double>(acks_sent);
  // An ack that arrived (in time or late) was delivered; stray acks are none of ours.
  const double frames_delivered =
      static_cast<double>(delivered) + static_cast<double>(rtts.size() + late);
  nlohmann::json j;
  j["nodes"] = o.nodes;
  j["duration_s"] = o.duration_s;
  j["pings_sent"] = records.size();
  j["pings_delivered"] = delivered;
  j["acks_sent"] = acks_sent;
  j["acked"] = rtts.size();
  j["late_acks"] = late;
  j["stray_frames"] = stray;
  j["round_trip_ratio"] = sent > 0 ? static_cast<double>(rtts.size()) / sent : NAN;
  j["delivery_ratio"] = frames_sent > 0 ? frames_delivered / frames_sent : NAN;
  double mean = NAN;
  if (!rtts.empty()) {
    mean = 0.0;
    for (double v : rtts) mean += v;
    mean /= static_cast<double>(rtts.size());
  }
  j["rtt_ms"] = {{"mean", mean},
                 {"p10", percentile(rtts, 0.1)},
                 {"p50", percentile(rtts, 0.5)},
                 {"p90", percentile(rtts, 0.9)},
                 {"p99", percentile(rtts, 0.99)},
                 {"max", rtts.empty() ? NAN : rtts.back()}};
  std::printf(
      "swarm_load: nodes=%u pings=%zu delivered=%llu acked=%zu late=%llu delivery_ratio=%.4f "
      "round_trip_ratio=%.4f rtt_ms mean=%.3f p10=%.3f p50=%.3f p90=%.3f p99=%.3f\n",
      o.nodes, records.size(), static_cast<unsigned long long>(delivered), rtts.size(),
      static_cast<unsigned long long>(late), j["delivery_ratio"].get<double>(),
      j["round_trip_ratio"].get<double>(), mean, percentile(rtts, 0.1), percentile(rtts, 0.5),
      percentile(rtts, 0.9), percentile(rtts, 0.99));
  if (!o.json.empty()) {
    std::ofstream(o.json) << j.dump(2) << "\n";
  }
  if (!o.csv.empty()) {
    std::ofstream csv(o.csv);
    csv << "seq,src,dst,sent_s,rtt_ms,status\n";
    for (std::size_t i = 0; i < records.size(); ++i) {
      const auto& r = records[i];
      csv << i << "," << r.src << "," << r.dst << "," << r.sent_s << ","
          << (r.rtt_ms ? std::to_string(*r.rtt_ms) : "") << ","
          << (r.rtt_ms ? "ok" : (r.delivered ? "ack_lost" : "lost")) << "\n";
    }
  }
  return 0;
}
