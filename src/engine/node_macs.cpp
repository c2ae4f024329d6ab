#include "node_macs.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "rfsitl/common/xoshiro256.hpp"
#include "rfsitl/registry/mac_registry.hpp"

namespace rfsitl::engine {

void make_macs(std::vector<Node>& nodes, std::vector<NodeCounters>& counters,
               const scenario::Scenario& s, std::size_t tick_samples, std::size_t rx_latency,
               double front_end_gain) {
  const mac::MacComponent* component = mac::find_mac(s.mac.type);
  if (component == nullptr) {
    throw std::invalid_argument("mac: unknown type '" + s.mac.type + "'");
  }
  const config::Settings settings = s.mac.settings.size() == component->info.settings.size()
                                        ? s.mac.settings
                                        : component->info.defaults();
  for (Node& node : nodes) {
    phy::Transceiver* radio = node.radio.get();
    mac::MacContext c;
    c.id = node.id;
    c.index = node.index;
    c.num_nodes = nodes.size();
    c.sample_rate_hz = s.timing.sample_rate_hz;
    c.tick_samples = tick_samples;
    c.radio_max_payload = radio->max_payload();
    c.frame_samples = [radio](std::size_t bytes) { return radio->frame_samples(bytes); };
    c.rx_latency_samples = rx_latency;
    std::uint64_t mix = s.seed ^ (0x6D61630000000000ULL + node.id);
    c.seed = splitmix64(mix);
    c.counters = &counters[node.index].mac;
    node.mac = component->make(settings, c);
    if (const auto db = node.mac->carrier_sense_db()) {
      // The receiver's input is scaled by the front end's gain g = 1 / sigma:
      // the noise has unit power there (and so would a -120 dB floor
      // without noise, which g is set for).
      const double g = front_end_gain;
      const double sigma2 = s.channel.noise_variance;
      const double noise_in_y = sigma2 > 0.0 ? g * g * sigma2 : 1.0;
      node.busy_power = static_cast<float>(noise_in_y * std::pow(10.0, *db / 10.0));
    }
  }
}

}  // namespace rfsitl::engine
