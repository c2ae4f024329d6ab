#pragma once
/// Everything a run needs, as read from a scenario file (YAML) or built from
/// defaults. Units are in the field names.
#include <concepts>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "rfsitl/channel/radio.hpp"
#include "rfsitl/common/position.hpp"
#include "rfsitl/common/types.hpp"
#include "rfsitl/config/settings.hpp"
#include "rfsitl/phy/phy_component.hpp"
#include "rfsitl/scenario/spectrum.hpp"

namespace rfsitl::scenario {

/// Where a built-in transceiver runs: a worker thread of the emulator, or its
/// own `rfsitl node` process (the split architecture). A PHY of kind
/// kExternalProgram is always another program, whatever this says.
enum class Process { kInline, kChild };

/// "inline" or "child".
std::string_view process_name(Process p);

/// A node's transceiver: which registered PHY (phy_registry.hpp), where it runs,
/// its TX queue, and the PHY's own declared settings. What the settings may be
/// is the PHY's business; the scenario module only checks them against the
/// PHY's declarations.
struct PhyChoice {
  std::string type = "gmsk";
  Process process = Process::kInline;
  std::size_t tx_queue_frames = 64;  ///< bounded TX queue per node (frames)
  config::Settings settings = phy_defaults("gmsk");

  /// The declared settings of `type` at their defaults (empty for an unknown type).
  static config::Settings phy_defaults(std::string_view type);

  /// PHY `type` at its defaults, e.g. PhyChoice::of("ofdm").with("rate_mbps", 24U).
  static PhyChoice of(std::string type) {
    PhyChoice p;
    p.settings = phy_defaults(type);
    p.type = std::move(type);
    return p;
  }
  /// This choice with one setting changed (for tests and tools; a scenario file
  /// is checked by the reader).
  PhyChoice with(std::string_view key, config::Value value) const {
    PhyChoice p = *this;
    p.settings.set(key, std::move(value));
    return p;
  }
  /// Integers: with("rate_mbps", 24U). (A template, so that a double such as
  /// 1.0 is not converted to an integer by overload resolution.)
  template <std::unsigned_integral U>
  PhyChoice with(std::string_view key, U value) const {
    return with(key, config::Value(std::uint64_t{value}));
  }

  /// The registered PHY. Precondition: `type` is registered (validated scenarios).
  const phy::PhyComponent& component() const;
  /// True when another program is the transceiver (type "external").
  bool external_program() const;
  /// True when the transceiver is another process: an external program or a child.
  bool runs_externally() const;
  /// The largest payload a frame carries (0 for an external program).
  std::size_t max_payload_bytes() const;
  /// A few words for the banner: "ofdm 24 Mbit/s", "gmsk", "gmsk-liquid samples_per_symbol=4".
  std::string label() const;

  bool operator==(const PhyChoice&) const = default;
};

/// A node's mobility model (position/mobility/mobility_component.hpp) and its
/// declared settings; the engine moves the node along it on the virtual clock.
struct MobilityChoice {
  std::string type;
  config::Settings settings;
  bool operator==(const MobilityChoice&) const = default;
};

/// A node's live position source (registry/position_source_registry.hpp) and
/// its declared settings; by default the location port (the node moves only
/// when a line arrives there, or on a dashboard drag).
struct PositionSourceChoice {
  static constexpr const char* kLocationPort = "location_port";
  std::string type = kLocationPort;
  config::Settings settings;  ///< those given; the others take the component's defaults
  bool is_location_port() const { return type == kLocationPort; }
  bool operator==(const PositionSourceChoice&) const = default;
};

struct NodeConfig {
  NodeId id = 1;
  /// Where the node starts; nullopt until its location feed reports (no links meanwhile).
  std::optional<Position> initial_position;
  /// This node's transceiver, when it differs from the scenario's `phy`.
  std::optional<PhyChoice> phy;
  /// How the node moves; nullopt: only its location feed (and the dashboard) move it.
  std::optional<MobilityChoice> mobility;
  /// This node's live source, when it differs from the scenario's `position`.
  std::optional<PositionSourceChoice> source;
  /// With IP: an existing network namespace (a container's) the node's TAP
  /// interface goes into, instead of one rfsitl makes and removes.
  std::optional<std::string> netns;
  /// Its frequencies and duplex (spectrum.hpp); nullopt: the shared band.
  std::optional<NodeTuning> tuning;

  /// Node `id` at `start` with everything else from the scenario (tests and
  /// benchmarks build nodes this way, so a new member does not break them).
  static NodeConfig at(NodeId id, std::optional<Position> start = std::nullopt) {
    NodeConfig n;
    n.id = id;
    n.initial_position = std::move(start);
    return n;
  }
};

/// One entry of `channel.stages`: a registered stage
/// (registry/channel_stage_registry.hpp) and its declared settings, all of them
/// (the stage's defaults merged with those given).
struct StageChoice {
  std::string type;
  config::Settings settings;
  bool operator==(const StageChoice&) const = default;
};

struct ChannelConfig {
  /// The chain every link goes through, in order. Empty: the paper's model,
  /// `model` with `path_loss_exponent` (the two keys are its short form).
  std::vector<StageChoice> stages;
  std::string model = "paper";      ///< c = (1+j)/sqrt2 * (d+1)^-exponent
  double path_loss_exponent = 3.0;  ///< applied to amplitude, as in the paper
  /// sigma^2 = E|eta|^2 (-120 dB), in mW like |c|^2; with `radio` given, the
  /// thermal noise k T0 fs NF (kept in step by the reader).
  double noise_variance = 1e-12;
  bool shared_noise = false;  ///< the paper's one noise source for all receivers
  GeodeticPosition origin{43.0008, -78.7890, 0.0};  ///< where local x/y/z = 0
  /// Effects on each radio's own samples, in order (channel/sample_stage.hpp):
  /// every transmitter's before mixing (channel.tx_stages), every receiver's
  /// after its noise (channel.rx_stages). `channel.impairments.tx` / `.rx` are
  /// read as a leading `impairments` stage here. Empty by default.
  std::vector<StageChoice> tx_stages;
  std::vector<StageChoice> rx_stages;
};

enum class TimeMode { kRealTime, kVirtual };

struct TimingConfig {
  TimeMode mode = TimeMode::kRealTime;
  /// Where `mode` was given ("six_uav.yaml:4", "--mode"); empty: the default.
  /// Errors about a mode that does not fit something else point there.
  std::string mode_given_at;
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
  double mobility_update_s = 0.01;  ///< virtual seconds between mobility model updates
};

/// Nodes whose transceiver is another process (type external or process child).
struct ExternalConfig {
  std::string socket_path;        ///< Unix socket; empty = /tmp/rfsitl-<net_base>.sock
  double reply_timeout_s = 1.0;   ///< a process silent this long is dropped
  double start_timeout_s = 30.0;  ///< how long the run waits for every one to join first
  bool restart_children = true;   ///< restart an `rfsitl node` child that dies
};

/// The MAC of every node (`mac: {type: csma, ...}`): a registered MAC
/// (mac_registry.hpp) and its declared settings. "none" is the paper's.
struct MacChoice {
  std::string type = "none";
  config::Settings settings;  ///< checked against the MAC's declarations by the reader
};

/// IP on every node (`ip:`, `rfsitl run --ip`): a network namespace per node
/// holding a TAP interface whose Ethernet frames cross the radio channel.
struct IpConfig {
  bool enabled = false;
  /// IPv4 network of the nodes' interfaces; a node's host part is its id.
  std::string subnet = "10.77.0.0/24";
  /// IPv6 network (a /64 or shorter); a node's interface identifier is its id.
  std::string ipv6_prefix = "fd72:6673:6974:1::/64";
  std::string interface = "rf0";  ///< the TAP interface's name in each namespace
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
  /// The scenario file's folder (files it names are relative to it); "" = the
  /// working directory.
  std::string source_dir;
  std::uint64_t seed = 1;
  std::vector<NodeConfig> nodes;
  PhyChoice phy;
  ChannelConfig channel;
  /// The link budget in physical units; nullopt: transmitters have 0 dBm (unit
  /// power) and the noise is channel.noise_variance, as in the paper.
  std::optional<channel::RadioSettings> radio;
  TimingConfig timing;
  PortConfig ports;
  EngineConfig engine;
  ExternalConfig external;
  IpConfig ip;
  MacChoice mac;
  std::vector<TrafficItem> traffic;
  /// The live source of every node without its own `source` or `mobility`.
  PositionSourceChoice position_source;
  /// Named channel plans the nodes' `channel:` keys pick from.
  SpectrumConfig spectrum;

  const PhyChoice& phy_of(std::size_t node) const {
    return nodes[node].phy ? *nodes[node].phy : phy;
  }
  /// Node `node`'s live source; a node with a mobility model has none (the
  /// location port only).
  PositionSourceChoice source_of(std::size_t node) const {
    if (nodes[node].source) return *nodes[node].source;
    if (nodes[node].mobility) return {};
    return position_source;
  }
  /// True when node `node`'s transceiver is another process.
  bool runs_externally(std::size_t node) const { return phy_of(node).runs_externally(); }
  /// The carrier of a node without a tuning of its own: radio.carrier_hz.
  double carrier_hz() const {
    return radio ? radio->carrier_hz : channel::RadioSettings{}.carrier_hz;
  }
  /// Node `node`'s frequencies, bandwidth and duplex.
  NodeBand band_of(std::size_t node) const {
    return scenario::band_of(nodes[node].tuning, spectrum, carrier_hz(), timing.sample_rate_hz);
  }
  /// True when some node has a tuning of its own: the channel then works out
  /// each link's offset and leakage; otherwise every node shares one band.
  bool tuned() const {
    for (const NodeConfig& n : nodes) {
      if (n.tuning) return true;
    }
    return false;
  }
  /// True when radio frames carry their kind (FrameKind) on the air: with IP
  /// or a MAC.
  bool typed_framing() const { return ip.enabled || mac.type != "none"; }
};

}  // namespace rfsitl::scenario
