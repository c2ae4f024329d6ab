#include "rfsitl/scenario/spectrum.hpp"

#include <charconv>

namespace rfsitl::scenario {

const config::Fields<SpectrumConfig>& spectrum_fields() {
  static const auto f = config::Fields<SpectrumConfig>().real(
      "duplexer_isolation_db", &SpectrumConfig::duplexer_isolation_db, "dB", {0.0, 200.0},
      "how far below its own transmit power a full-duplex node hears itself, on top of its "
      "spectral mask at its receive frequency");
  return f;
}

const config::ComponentInfo& spectrum_info() {
  static const config::ComponentInfo info = spectrum_fields().info(
      "spectrum", "spectrum",
      "the spectrum: section: named channel plans (plans: {NAME: plan}) and the duplexer");
  return info;
}

const config::Fields<ChannelPlan>& channel_plan_fields() {
  using P = ChannelPlan;
  static const auto f =
      config::Fields<P>()
          .real("first_hz", &P::first_hz, "Hz", {1e6, 1e11}, "centre of channel 1")
          .real("spacing_hz", &P::spacing_hz, "Hz", {1.0, 1e10},
                "from one channel's centre to the next")
          .integer("channels", &P::channels, "", 1, 100000, "how many channels, numbered from 1")
          .real("bandwidth_hz", &P::bandwidth_hz, "Hz", {1.0, 1e10},
                "each channel's width: its transmitters' occupied band and its receivers' "
                "filter (at most the emulator's sample rate)");
  return f;
}

const config::ComponentInfo& channel_plan_info() {
  static const config::ComponentInfo info = channel_plan_fields().info(
      "spectrum", "plan",
      "a named channel plan (spectrum.plans.NAME) that nodes pick with channel: NAME/N; the "
      "defaults are 802.11's 2.4 GHz channels 1-13");
  return info;
}

const config::Fields<NodeTuning>& node_tuning_fields() {
  using T = NodeTuning;
  static const auto f =
      config::Fields<T>()
          .text("channel", &T::channel,
                "PLAN/N: channel N of spectrum.plans.PLAN, both directions (instead of tx_hz)")
          .real("tx_hz", &T::tx_hz, "Hz", {0.0, 1e11},
                "centre frequency the node transmits on; 0: radio.carrier_hz")
          .real("rx_hz", &T::rx_hz, "Hz", {0.0, 1e11},
                "centre frequency the node receives on; 0: tx_hz (the same channel)")
          .real("bandwidth_hz", &T::bandwidth_hz, "Hz", {0.0, 1e10},
                "channel width; 0: the plan's, or the emulator's sample rate")
          .choice("duplex", &T::duplex, {{"half", Duplex::kHalf}, {"full", Duplex::kFull}},
                  "half: the receiver is deaf while the node transmits; full: both at once "
                  "(FDD)");
  return f;
}

const config::ComponentInfo& node_tuning_info() {
  static const config::ComponentInfo info = node_tuning_fields().info(
      "spectrum", "node",
      "a node's frequencies and duplex (keys of a nodes[] entry); without them a node is on "
      "radio.carrier_hz over the whole sample rate, half duplex");
  return info;
}

std::optional<ChannelRef> parse_channel_ref(const std::string& text) {
  const auto slash = text.rfind('/');
  if (slash == std::string::npos || slash == 0 || slash + 1 == text.size()) return std::nullopt;
  ChannelRef ref{text.substr(0, slash), 0};
  const char* first = text.data() + slash + 1;
  const char* last = text.data() + text.size();
  const auto [end, ec] = std::from_chars(first, last, ref.number);
  if (ec != std::errc() || end != last || ref.number == 0) return std::nullopt;
  return ref;
}

NodeBand band_of(const std::optional<NodeTuning>& t, const SpectrumConfig& spectrum,
                 double carrier_hz, double sample_rate_hz) {
  NodeBand b{carrier_hz, carrier_hz, sample_rate_hz, Duplex::kHalf};
  if (!t) return b;
  b.duplex = t->duplex;
  if (const auto ref = parse_channel_ref(t->channel)) {
    const ChannelPlan& plan = spectrum.plans.find(ref->plan)->second;
    b.tx_hz = b.rx_hz = plan.centre_hz(ref->number);
    b.bandwidth_hz = plan.bandwidth_hz;
  } else {
    if (t->tx_hz > 0.0) b.tx_hz = t->tx_hz;
    b.rx_hz = t->rx_hz > 0.0 ? t->rx_hz : b.tx_hz;
  }
  if (t->bandwidth_hz > 0.0) b.bandwidth_hz = t->bandwidth_hz;
  return b;
}

}  // namespace rfsitl::scenario
