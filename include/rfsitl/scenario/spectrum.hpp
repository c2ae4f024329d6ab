#pragma once
/// Radios on their own frequencies: the scenario's `spectrum:` section (named
/// channel plans) and each node's tuning (`channel: plan/N`, or `tx_hz`,
/// `rx_hz` and `bandwidth_hz`, and `duplex`). A node that gives none of them
/// is on radio.carrier_hz over the emulator's whole sample rate, half duplex,
/// as every node was before channel plans existed.
#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "rfsitl/config/fields.hpp"

namespace rfsitl::scenario {

/// A named channel plan (`spectrum.plans.NAME`): channel k = 1..channels is
/// centred at first_hz + (k - 1) spacing_hz and is bandwidth_hz wide. The
/// defaults are 802.11's 2.4 GHz plan (channels 1-13, 20 MHz).
struct ChannelPlan {
  double first_hz = 2.412e9;
  double spacing_hz = 5e6;
  std::uint32_t channels = 13;
  double bandwidth_hz = 20e6;

  double centre_hz(std::uint32_t channel) const {
    return first_hz + static_cast<double>(channel - 1) * spacing_hz;
  }
  bool operator==(const ChannelPlan&) const = default;
};

const config::Fields<ChannelPlan>& channel_plan_fields();
/// Kind "spectrum", name "plan": as `rfsitl describe` lists it.
const config::ComponentInfo& channel_plan_info();

/// Half: the T/R switch (the receiver is blanked while the node transmits).
/// Full: FDD, transmitting and receiving at once.
enum class Duplex { kHalf, kFull };

/// A node's tuning keys as written (NodeConfig::tuning); band_of() resolves
/// them. Either `channel` or tx_hz/rx_hz, not both (validate()).
struct NodeTuning {
  std::string channel;        ///< "plan/N", or empty
  double tx_hz = 0.0;         ///< 0: radio.carrier_hz
  double rx_hz = 0.0;         ///< 0: tx_hz
  double bandwidth_hz = 0.0;  ///< 0: the plan's, else the emulator's sample rate
  Duplex duplex = Duplex::kHalf;
  bool operator==(const NodeTuning&) const = default;
};

const config::Fields<NodeTuning>& node_tuning_fields();
/// Kind "spectrum", name "node": the keys a node may add.
const config::ComponentInfo& node_tuning_info();

/// `spectrum:`.
struct SpectrumConfig {
  std::map<std::string, ChannelPlan, std::less<>> plans;
  /// How far below its transmit power a full-duplex node hears itself in its
  /// receive band (the duplexer's, or in-band full duplex's cancellation).
  double duplexer_isolation_db = 60.0;
  bool operator==(const SpectrumConfig&) const = default;
};

/// The section's own settings (duplexer_isolation_db; the plans are read
/// one by one as channel_plan_info()).
const config::Fields<SpectrumConfig>& spectrum_fields();
/// Kind "spectrum", name "spectrum".
const config::ComponentInfo& spectrum_info();

/// Where a node's radio is, resolved: centre frequencies of each direction,
/// the channel's bandwidth (the transmitter's occupied band and the receiver's
/// filter alike) and the duplex.
struct NodeBand {
  double tx_hz = 0.0;
  double rx_hz = 0.0;
  double bandwidth_hz = 0.0;
  Duplex duplex = Duplex::kHalf;
  bool operator==(const NodeBand&) const = default;
};

/// "plan/N" split into its plan name and channel number; nullopt when the
/// text is not of that form (N a decimal number >= 1).
struct ChannelRef {
  std::string plan;
  std::uint32_t number = 0;
};
std::optional<ChannelRef> parse_channel_ref(const std::string& text);

/// The band of a node with tuning `t` (nullopt: none given) in a scenario
/// whose carrier is `carrier_hz` and sample rate `sample_rate_hz`.
/// Precondition: the tuning passed validate() (its plan and channel exist).
NodeBand band_of(const std::optional<NodeTuning>& t, const SpectrumConfig& spectrum,
                 double carrier_hz, double sample_rate_hz);

}  // namespace rfsitl::scenario
