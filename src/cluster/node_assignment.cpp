#include "rfsitl/cluster/node_assignment.hpp"

#include <algorithm>
#include <cstdio>
#include <numeric>
#include <string_view>

namespace rfsitl::cluster {

double expected_cost(const scenario::Scenario& s, std::size_t index) {
  // Receiver time per sample with frames, relative to our GMSK (README,
  // "Receiver throughput": 55.7 Msps gmsk, 6.7 gmsk-liquid, 11-33 ofdm, over
  // 170 dsss), plus 1 for what every node costs the channel (mixing its
  // input, its noise) whatever its PHY.
  const std::string_view type = s.phy_of(index).type;
  double phy = 1.0;
  if (type == "gmsk_liquid") phy = 8.0;
  if (type == "ofdm") phy = 4.0;
  if (type == "dsss") phy = 0.3;
  return 1.0 + phy;
}

std::vector<std::size_t> assign_nodes(const scenario::Scenario& s, std::size_t ranks) {
  const std::size_t n = s.nodes.size();
  std::vector<double> cost(n);
  for (std::size_t i = 0; i < n; ++i) cost[i] = expected_cost(s, i);
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return cost[a] > cost[b]; });
  std::vector<double> load(std::max<std::size_t>(ranks, 1), 0.0);
  std::vector<std::size_t> owner(n, 0);
  for (const std::size_t i : order) {
    const auto least = std::min_element(load.begin(), load.end());
    owner[i] = static_cast<std::size_t>(least - load.begin());
    *least += cost[i];
  }
  return owner;
}

std::string describe_assignment(const scenario::Scenario& s, const std::vector<std::size_t>& owner,
                                std::size_t ranks, const std::vector<std::string>& hosts) {
  std::string out;
  for (std::size_t r = 0; r < ranks; ++r) {
    std::string ids;
    double cost = 0.0;
    for (std::size_t i = 0; i < owner.size(); ++i) {
      if (owner[i] != r) continue;
      ids += " " + std::to_string(s.nodes[i].id);
      cost += expected_cost(s, i);
    }
    char line[64];
    std::snprintf(line, sizeof line, " (cost %.1f)", cost);
    out += "  rank " + std::to_string(r) + ": node(s)" + (ids.empty() ? " none" : ids) + line +
           (r < hosts.size() ? " on " + hosts[r] : std::string()) + "\n";
  }
  return out;
}

}  // namespace rfsitl::cluster
