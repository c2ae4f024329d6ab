#pragma once
// Every node's MAC, made from the scenario's mac: section once the
// transceivers exist (a MAC sizes its frames by its radio). Internal to the
// engine module.
#include <cstddef>
#include <vector>

#include "engine_node.hpp"
#include "rfsitl/scenario/scenario.hpp"

namespace rfsitl::engine {

/// Gives every node of `nodes` its MAC (node.mac), and to one that senses
/// the carrier its energy threshold (node.busy_power) in the units of its
/// receiver's input, which the front end scales by `front_end_gain`.
/// `counters` are the nodes' (by index); `tick_samples` and `rx_latency`
/// (samples from a frame's end to its decode, the largest of any receiver)
/// go to the MACs. Throws std::invalid_argument for an unknown MAC type.
void make_macs(std::vector<Node>& nodes, std::vector<NodeCounters>& counters,
               const scenario::Scenario& s, std::size_t tick_samples, std::size_t rx_latency,
               double front_end_gain);

}  // namespace rfsitl::engine
