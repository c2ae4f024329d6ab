#include "rfsitl/agent_port/ip_ports.hpp"

#include <poll.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <bitset>
#include <cerrno>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <thread>

#include <spdlog/spdlog.h>

#include "rfsitl/common/ip_prefix.hpp"
#include "rfsitl/ip/ethernet_frame.hpp"
#include "rfsitl/ip/network_namespace.hpp"
#include "rfsitl/ip/privileges.hpp"
#include "rfsitl/ip/run_registry.hpp"
#include "rfsitl/ip/tap_device.hpp"

namespace rfsitl::agent_port {
namespace {

/// Frames read from one interface per wake-up before the others get a turn.
constexpr int kReadBurst = 64;
/// Larger than any frame a TAP hands over (its MTU is at most the PHY's payload).
constexpr std::size_t kReadBufferBytes = 65536;
/// The largest MTU asked of the kernel (IP's own limit on a frame's payload).
constexpr std::size_t kMaxMtu = 65521;

/// Logs the first few problems of a kind in full, then one in a thousand, so a
/// misbehaving program cannot flood the log; the counters still see every one.
bool should_log(std::uint64_t count) {
  return count <= 20 || count % 1000 == 0;
}

std::string mac_text(const std::array<std::uint8_t, 6>& mac) {
  char buf[18];
  std::snprintf(buf, sizeof buf, "%02x:%02x:%02x:%02x:%02x:%02x", mac[0], mac[1], mac[2], mac[3],
                mac[4], mac[5]);
  return buf;
}

struct IpNode {
  IpNodeInfo info;
  std::optional<ip::NetworkNamespace> netns;
  std::optional<ip::TapDevice> tap;
  std::atomic<std::uint64_t> write_failures{0};
};

class IpPortsImpl final : public IpPorts {
 public:
  IpPortsImpl(const scenario::Scenario& s, engine::FrameSink& agents, IpPlacement placement)
      : scenario_(s),
        agents_(agents),
        prefix_(prefix_for(s.ports.net_base)),
        here_(std::move(placement.here)) {
    if (const auto missing = ip::missing_ip_privileges()) throw std::runtime_error(*missing);
    if (placement.claim) {
      claim_.emplace(ip::RunClaim::claim(prefix_));
      for (const std::string& name : claim_->removed_stale()) {
        spdlog::warn(
            "ip: removed network namespace {} left by an earlier run on net base {} "
            "that is gone",
            name, s.ports.net_base);
      }
    }
    for (const auto& n : s.nodes) known_.set(n.id);
  }

  ~IpPortsImpl() override { stop(); }

  void start(engine::Engine& engine) override {
    engine_ = &engine;
    const auto v4 = parse_ipv4_prefix(scenario_.ip.subnet);
    const auto v6 = parse_ipv6_prefix(scenario_.ip.ipv6_prefix);
    if (!v4 || !v6) throw std::runtime_error("ip: the scenario's subnet or IPv6 prefix is invalid");
    nodes_ = std::vector<IpNode>(scenario_.nodes.size());
    try {
      for (std::size_t i = 0; i < nodes_.size(); ++i) {
        if (serves(i)) open_node(i, *v4, *v6);
      }
    } catch (...) {
      close_all();
      throw;
    }
    info_.clear();
    for (const IpNode& n : nodes_) {
      if (n.tap) info_.push_back(n.info);
    }
    stop_fd_ = eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
    if (stop_fd_ < 0) {
      close_all();
      throw std::runtime_error(std::string("ip: eventfd: ") + std::strerror(errno));
    }
    reader_ = std::thread([this] { read_loop(); });
  }

  void stop() override {
    if (reader_.joinable()) {
      const std::uint64_t one = 1;
      (void)!write(stop_fd_, &one, sizeof one);
      reader_.join();
    }
    if (stop_fd_ >= 0) {
      close(stop_fd_);
      stop_fd_ = -1;
    }
    close_all();
  }

  const std::vector<IpNodeInfo>& nodes() const override { return info_; }
  const std::vector<std::string>& removed_stale() const override {
    static const std::vector<std::string> none;
    return claim_ ? claim_->removed_stale() : none;
  }

  nlohmann::json summary() const override {
    nlohmann::json j;
    j["prefix"] = prefix_;
    j["nodes"] = nlohmann::json::array();
    for (const IpNodeInfo& n : info_) j["nodes"].push_back(ip_node_json(n));
    j["removed_stale"] = removed_stale();
    j["frames_from_tap"] = from_tap_.load();
    j["frames_to_tap"] = to_tap_.load();
    return j;
  }

  /// Engine thread: Ethernet frames to the node's interface, the rest to the agents.
  void deliver(std::size_t node, NetFrame&& frame) override {
    if (frame.kind != FrameKind::kEthernet) {
      agents_.deliver(node, std::move(frame));
      return;
    }
    IpNode* n = node < nodes_.size() ? &nodes_[node] : nullptr;
    if (n != nullptr && n->tap && n->tap->write(frame.payload)) {
      to_tap_.fetch_add(1, std::memory_order_relaxed);
      return;
    }
    // The kernel refused it (its queue is full) or there is no interface yet.
    if (engine_ != nullptr) {
      engine::NodeCounters::bump(engine_->counters(node).to_agent_dropped);
    }
    const std::uint64_t k = n ? n->write_failures.fetch_add(1) + 1 : 1;
    if (should_log(k)) {
      spdlog::warn("ip: node {}: a decoded frame could not be written to its interface ({} so far)",
                   n ? n->info.id : 0, k);
    }
  }

 private:
  void open_node(std::size_t i, const Ipv4Prefix& v4, const Ipv6Prefix& v6) {
    const auto& cfg = scenario_.nodes[i];
    IpNode& n = nodes_[i];
    n.info.id = cfg.id;
    if (cfg.netns && cfg.netns->starts_with("pid:")) {
      // A container's namespace by one of its processes (validated: digits).
      n.netns.emplace(ip::NetworkNamespace::attach_pid(std::stoi(cfg.netns->substr(4))));
    } else if (cfg.netns) {
      n.netns.emplace(ip::NetworkNamespace::attach(*cfg.netns));
    } else {
      n.netns.emplace(ip::NetworkNamespace::create(prefix_ + "-" + std::to_string(cfg.id)));
    }
    n.info.netns = n.netns->name();
    n.info.netns_owned = n.netns->owned();
    ip::TapConfig tap;
    tap.name = scenario_.ip.interface;
    tap.mac = ip::node_mac(cfg.id);
    const std::size_t payload = engine_->max_payload(i);
    if (payload <= ip::kEthernetHeaderBytes + 68) {  // IPv4's minimum MTU is 68
      throw std::runtime_error("ip: node " + std::to_string(cfg.id) + ": its PHY carries " +
                               std::to_string(payload) +
                               " bytes per frame, too few for IP (at least 82)");
    }
    n.info.mtu = std::min(payload - ip::kEthernetHeaderBytes, kMaxMtu);
    tap.mtu = static_cast<unsigned>(n.info.mtu);
    const Ipv4Prefix a4 = node_address(v4, cfg.id);
    const Ipv6Prefix a6 = node_address(v6, cfg.id);
    tap.ipv4 = a4;  // the node's address, with the network's prefix length
    tap.ipv6 = a6;
    n.tap.emplace(ip::TapDevice::open(*n.netns, tap));
    n.info.interface = n.tap->name();
    n.info.mac = mac_text(tap.mac);
    n.info.ipv4 = to_string(a4) + "/" + std::to_string(v4.length);
    n.info.ipv6 = to_string(a6) + "/" + std::to_string(v6.length);
  }

  void close_all() {
    for (IpNode& n : nodes_) {
      n.tap.reset();
      if (n.netns && n.netns->owned()) {
        try {
          n.netns->remove();
        } catch (const std::exception& e) {
          spdlog::warn("ip: {}", e.what());
        }
      }
      n.netns.reset();
    }
  }

  bool serves(std::size_t i) const { return here_.empty() || (i < here_.size() && here_[i]); }

  /// The reader thread: every interface's frames to its node's TX queue.
  void read_loop() {
    std::vector<pollfd> fds;
    fds.push_back({stop_fd_, POLLIN, 0});
    // A node served elsewhere has no interface here: poll ignores fd -1.
    for (const IpNode& n : nodes_) fds.push_back({n.tap ? n.tap->fd() : -1, POLLIN, 0});
    std::vector<std::uint8_t> buf(kReadBufferBytes);
    for (;;) {
      if (poll(fds.data(), fds.size(), -1) < 0) {
        if (errno == EINTR) continue;
        spdlog::error("ip: poll: {}; the interfaces are no longer read", std::strerror(errno));
        return;
      }
      if (fds[0].revents != 0) return;
      for (std::size_t k = 1; k < fds.size(); ++k) {
        if (fds[k].revents == 0) continue;
        for (int burst = 0; burst < kReadBurst; ++burst) {
          std::size_t len = 0;
          try {
            len = nodes_[k - 1].tap->read(buf);
          } catch (const std::exception& e) {
            spdlog::error("ip: node {}: {}", nodes_[k - 1].info.id, e.what());
            fds[k].fd = -1;  // poll ignores it from now on
            break;
          }
          if (len == 0) break;
          from_interface(k - 1, std::span<const std::uint8_t>(buf.data(), len));
        }
      }
    }
  }

  void from_interface(std::size_t i, std::span<const std::uint8_t> frame) {
    IpNode& n = nodes_[i];
    const ip::Classified c = ip::classify_ethernet(frame, n.info.id, known_, n.info.mtu);
    if (c.verdict != ip::EthernetVerdict::kUnicast &&
        c.verdict != ip::EthernetVerdict::kBroadcast) {
      auto& refused = engine_->counters(i).ip_refused;
      const std::uint64_t k = refused.fetch_add(1, std::memory_order_relaxed) + 1;
      if (should_log(k)) {
        spdlog::warn(
            "ip: node {} ({}): frame of {} bytes, EtherType 0x{:04x}, refused: {} ({} "
            "refused so far)",
            n.info.id, n.info.interface, frame.size(), c.ether_type, ip::verdict_name(c.verdict),
            k);
      }
      return;
    }
    from_tap_.fetch_add(1, std::memory_order_relaxed);
    NetFrame f{n.info.id, c.dst, {frame.begin(), frame.end()}, FrameKind::kEthernet};
    if (!engine_->submit(i, std::move(f))) {
      auto& dropped = engine_->counters(i).queue_dropped;
      if (should_log(dropped.load(std::memory_order_relaxed))) {
        spdlog::warn("ip: node {}: TX queue full, frame from {} dropped", n.info.id,
                     n.info.interface);
      }
    }
  }

  const scenario::Scenario& scenario_;
  engine::FrameSink& agents_;
  std::string prefix_;
  std::vector<bool> here_;
  std::optional<ip::RunClaim> claim_;
  std::bitset<256> known_;
  engine::Engine* engine_ = nullptr;
  std::vector<IpNode> nodes_;
  std::vector<IpNodeInfo> info_;
  int stop_fd_ = -1;
  std::thread reader_;
  std::atomic<std::uint64_t> from_tap_{0};
  std::atomic<std::uint64_t> to_tap_{0};
};

}  // namespace

nlohmann::json ip_node_json(const IpNodeInfo& n) {
  return {{"id", n.id},
          {"netns", n.netns},
          {"netns_owned", n.netns_owned},
          {"interface", n.interface},
          {"mac", n.mac},
          {"ipv4", n.ipv4},
          {"ipv6", n.ipv6},
          {"mtu", n.mtu}};
}

std::vector<IpNodeInfo> ip_nodes_from_json(const nlohmann::json& nodes) {
  std::vector<IpNodeInfo> out;
  for (const auto& n : nodes) {
    IpNodeInfo i;
    i.id = n.at("id").get<NodeId>();
    i.netns = n.at("netns").get<std::string>();
    i.netns_owned = n.at("netns_owned").get<bool>();
    i.interface = n.at("interface").get<std::string>();
    i.mac = n.at("mac").get<std::string>();
    i.ipv4 = n.at("ipv4").get<std::string>();
    i.ipv6 = n.at("ipv6").get<std::string>();
    i.mtu = n.at("mtu").get<std::size_t>();
    out.push_back(std::move(i));
  }
  return out;
}

std::unique_ptr<IpPorts> make_ip_ports(const scenario::Scenario& scenario,
                                       engine::FrameSink& agents, IpPlacement placement) {
  return std::make_unique<IpPortsImpl>(scenario, agents, std::move(placement));
}

}  // namespace rfsitl::agent_port
