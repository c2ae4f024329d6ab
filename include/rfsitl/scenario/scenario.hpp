#pragma once
/// Everything a run needs, as read from a scenario file (YAML) or built from
/// defaults. Units are in the field names.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "rfsitl/common/position.hpp"
#include "rfsitl/common/types.hpp"

namespace rfsitl::scenario {

/// Transceiver type and parameters. Fields that a type does not use are ignored.
struct PhyConfig {
  std::string type = "gmsk";  ///< "gmsk", "gmsk-liquid", "ofdm", "dsss" or "external"
  /// Where a built-in transceiver runs: "inline" (a worker thread of the
  /// emulator) or "child" (its own `rfsitl node` process: the split
  /// architecture). Type "external" is always another program.
  std::string process = "inline";
  unsigned rate_mbps = 6;             ///< ofdm: 802.11a/g rate at 20 MHz (6 ... 54)
  std::string code = "barker11";      ///< dsss: barker11, mseq<N>, gold<N>[:k]
  std::string modulation = "dbpsk";   ///< dsss: dbpsk or dqpsk
  unsigned samples_per_chip = 1;      ///< dsss: 1..8
  bool adaptive = false;              ///< dsss: cognitive code adaptation (Gold codes)
  unsigned samples_per_symbol = 2;    ///< k, >= 2
  unsigned filter_delay_symbols = 3;  ///< m, 1..16
  float bandwidth_time = 0.5F;        ///< BT, (0, 1)
  std::size_t max_payload_bytes = 2048;
  std::size_t tx_queue_frames = 64;  ///< bounded TX queue per node
};

struct NodeConfig {
  NodeId id = 1;
  /// Where the node starts; nullopt until its location feed reports (no links meanwhile).
  std::optional<Position> initial_position;
  /// This node's transceiver, when it differs from the scenario's `phy`.
  std::optional<PhyConfig> phy;
};

struct ChannelConfig {
  std::string model = "paper";      ///< c = (1+j)/sqrt2 * (d+1)^-exponent
  double path_loss_exponent = 3.0;  ///< applied to amplitude, as in the paper
  double noise_variance = 1e-12;    ///< sigma^2 = E|eta|^2 (-120 dB)
  bool shared_noise = false;        ///< the paper's one noise source for all receivers
  GeodeticPosition origin{43.0008, -78.7890, 0.0};  ///< where local x/y/z = 0
};

enum class TimeMode { kRealTime, kVirtual };

struct TimingConfig {
  TimeMode mode = TimeMode::kRealTime;
  double speed = 1.0;                ///< virtual seconds per wall second (real-time mode)
  double sample_rate_hz = 1e6;       ///< fs
  std::uint32_t tick_samples = 250;  ///< B
  double duration_s = 0.0;           ///< virtual seconds to run; 0 = until a signal
};

struct PortConfig {
  std::string bind_address = "127.0.0.1";
  std::uint16_t net_base = 15763;  ///< net port of node n: net_base + 10 n
  std::uint16_t loc_base = 15766;  ///< location port of node n: loc_base + 10 n
};

struct EngineConfig {
  unsigned threads = 0;             ///< worker threads; 0 = one per core
  bool skip_idle_receivers = true;  ///< see Engine for the exact condition
  double stats_interval_s = 5.0;    ///< wall seconds between stats lines; 0 = off
};

/// Nodes whose transceiver is another process (type external or process child).
struct ExternalConfig {
  std::string socket_path;        ///< Unix socket; empty = /tmp/rfsitl-<net_base>.sock
  double reply_timeout_s = 1.0;   ///< a process silent this long is dropped
  double start_timeout_s = 30.0;  ///< how long the run waits for every one to join first
  bool restart_children = true;   ///< restart an `rfsitl node` child that dies
};

/// A frame injected by the emulator itself at a virtual time (batch runs, tests).
struct TrafficItem {
  double at_s = 0.0;
  NodeId src = 1;
  NodeId dst = 2;
  std::size_t size_bytes = 80;
  unsigned repeat = 1;
  double interval_s = 0.0;
};

struct Scenario {
  std::string name = "default";
  std::uint64_t seed = 1;
  std::vector<NodeConfig> nodes;
  PhyConfig phy;
  ChannelConfig channel;
  TimingConfig timing;
  PortConfig ports;
  EngineConfig engine;
  ExternalConfig external;
  std::vector<TrafficItem> traffic;

  const PhyConfig& phy_of(std::size_t node) const {
    return nodes[node].phy ? *nodes[node].phy : phy;
  }
  /// True when node `node`'s transceiver is another process.
  bool runs_externally(std::size_t node) const {
    const PhyConfig& p = phy_of(node);
    return p.type == "external" || p.process == "child";
  }
};

}  // namespace rfsitl::scenario
